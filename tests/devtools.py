"""A real headless Chromium driven over the DevTools protocol (a websocket on 127.0.0.1): for pages that
change while they are open (``guardsim watch``), where ``--dump-dom`` sees only one moment."""

from __future__ import annotations

import json
import shutil
import subprocess
import time
import urllib.request
from pathlib import Path
from typing import Any

CHROMIUM = next((path for path in map(shutil.which, ("chromium", "chromium-browser")) if path), None)


class LivePage:
    """One Chromium tab showing ``url``; :meth:`evaluate` runs JavaScript in it."""

    def __init__(self, url: str, profile: Path, *, timeout: float = 30.0) -> None:
        from websockets.sync.client import connect

        assert CHROMIUM is not None
        profile.mkdir(parents=True, exist_ok=True)
        self.process = subprocess.Popen(
            [
                CHROMIUM,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--remote-debugging-address=127.0.0.1",
                "--remote-debugging-port=0",
                f"--user-data-dir={profile}",
                "--window-size=1100,900",
                url,
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        port_file = profile / "DevToolsActivePort"
        deadline = time.monotonic() + timeout
        while not (port_file.exists() and port_file.read_text().strip()):
            if time.monotonic() > deadline or self.process.poll() is not None:
                self.close()
                raise RuntimeError("chromium did not open its DevTools port")
            time.sleep(0.05)
        port = int(port_file.read_text().split()[0])
        socket_url = None
        while socket_url is None:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=5) as answer:
                tabs = json.load(answer)
            socket_url = next((tab["webSocketDebuggerUrl"] for tab in tabs if tab.get("type") == "page"), None)
            if socket_url is None:
                if time.monotonic() > deadline:
                    self.close()
                    raise RuntimeError("chromium opened no tab")
                time.sleep(0.05)
        # Entered by hand: the connection lives as long as this object, not one block.
        self.socket = connect(socket_url, max_size=None, open_timeout=timeout).__enter__()
        self.calls = 0

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression in the page."""
        self.calls += 1
        ident = self.calls
        params = {"expression": expression, "returnByValue": True}
        self.socket.send(json.dumps({"id": ident, "method": "Runtime.evaluate", "params": params}))
        while True:
            message = json.loads(self.socket.recv(timeout=30))
            if message.get("id") == ident:
                return message.get("result", {}).get("result", {}).get("value")

    def wait_for(self, expression: str, *, timeout: float = 60.0, every: float = 0.02) -> Any:
        """Poll ``expression`` until it is truthy; its value."""
        deadline = time.monotonic() + timeout
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise TimeoutError(f"waited {timeout} s for {expression}")
            time.sleep(every)

    def close(self) -> None:
        if getattr(self, "socket", None) is not None:
            self.socket.close()
        self.process.terminate()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
