"""``guardsim watch`` against real headless Chromium: the test rewrites the level while the page is open
and reads what the page shows over DevTools. Also: a port in use, a file that disappears and comes back,
a client that disconnects, Ctrl-C. Servers listen on 127.0.0.1 only."""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from click.testing import CliRunner

from guardsim.cli import main
from tests.design_levels import NEW, OLD, POST
from tests.devtools import CHROMIUM, LivePage

pytest.importorskip("starlette")
pytest.importorskip("watchfiles")

REPO = Path(__file__).resolve().parent.parent
STATUS = "document.getElementById('status').dataset"
ERROR = "document.getElementById('error').textContent"
OUTCOME = "Array.from(document.querySelectorAll('td.outcome')).map(e => e.textContent).join()"


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def save(path: Path, data: object) -> None:
    """Write as an editor does: to a temporary file, renamed over the level."""
    temporary = path.with_name(path.name + ".tmp~")
    temporary.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    os.replace(temporary, path)


class Watch:
    """``guardsim watch`` as a real process; its output lines collected."""

    def __init__(self, folder: Path, *args: str) -> None:
        self.port = free_port()
        self.out = folder / "watch.out"
        env = {**os.environ, "PYTHONPATH": str(REPO)}
        command = [sys.executable, "-m", "guardsim.cli", "watch", *args, "--port", str(self.port)]
        with self.out.open("w") as sink:
            self.process = subprocess.Popen(command, cwd=folder, stdout=sink, stderr=subprocess.STDOUT, env=env)
        self.url = f"http://127.0.0.1:{self.port}/"

    def lines(self) -> list[str]:
        return self.out.read_text().splitlines()

    def wait_line(self, text: str, count: int = 1, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while sum(text in line for line in self.lines()) < count:
            assert self.process.poll() is None, self.out.read_text()
            assert time.monotonic() < deadline, self.out.read_text()
            time.sleep(0.02)

    def stop(self) -> int:
        self.process.send_signal(signal.SIGINT)
        return self.process.wait(timeout=30)


def first_analysis(url: str) -> str:
    """The data of the first analysis event a page connecting now is sent."""
    with urllib.request.urlopen(url + "events", timeout=10) as stream:
        for line in stream:
            if line.startswith(b"data: {"):
                return line.decode()
    raise AssertionError("no analysis event")


@pytest.fixture
def level(tmp_path: Path) -> Path:
    path = tmp_path / "live.json"
    save(path, OLD)
    (tmp_path / "post.json").write_text(json.dumps(POST))
    return path


@pytest.mark.skipif(CHROMIUM is None, reason="no chromium on PATH: apt-get install -y chromium")
def test_the_page_shows_each_new_analysis_and_a_bad_save_keeps_the_last(level: Path, tmp_path: Path) -> None:
    """Saved old -> new -> half-written -> old: the page shows analyses 1, 2, the error line with analysis
    2 still drawn, then 3, each without a reload; the sneak outcome on the page follows the edit."""
    watch = Watch(tmp_path, level.name, "--patrol", "post.json", "--from", "0.5,6.5", "--to", "19.5,6.5")
    page = None
    try:
        watch.wait_line("serving http://127.0.0.1:")
        page = LivePage(watch.url, tmp_path / "profile")
        assert page.wait_for(f"{STATUS}.number == '1' && {OUTCOME}") == "detected"
        page.evaluate("window.loaded = 'this page'")
        save(level, NEW)
        assert page.wait_for(f"{STATUS}.number == '2' && {OUTCOME}") == "unseen"
        save(level, '{"name": "Side passage", "outer": [[0, 0], [20')
        error = page.wait_for(ERROR)
        assert "live.json" in error and "JSON" in error and "\n" not in error
        assert page.evaluate(f"{STATUS}.number") == "2" and page.evaluate(OUTCOME) == "unseen"
        assert page.evaluate("document.getElementById('level').width") > 0
        save(level, OLD)
        assert page.wait_for(f"{STATUS}.number == '3' && {OUTCOME}") == "detected"
        assert page.evaluate(ERROR) == ""
        # The same page all along: no reload happened.
        assert page.evaluate("window.loaded") == "this page"
        # The report arrives with the ways counted, and the score with its formula.
        page.wait_for(f"{STATUS}.phase == 'report'")
        assert page.evaluate("document.getElementById('formula').textContent").startswith("score = 100 x (")
    finally:
        if page is not None:
            page.close()
        assert watch.stop() == 0
    assert "stopped after 3 analyses" in watch.out.read_text()


def test_port_in_use_is_one_line(level: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        done = CliRunner().invoke(main, ["watch", str(level), "--port", str(port)])
    assert done.exit_code == 2
    assert done.output == f"guardsim: error: port {port} on 127.0.0.1 is in use: give another with --port N\n"


@pytest.mark.slow
def test_a_vanishing_file_a_disconnecting_client_and_ctrl_c(level: Path, tmp_path: Path) -> None:
    """The file removed: one error line, the server stays up; back again: a new analysis. A client that
    reads half an event and hangs up: no traceback. Ctrl-C: exit 0 and a last line."""
    watch = Watch(tmp_path, level.name, "--patrol", "post.json")
    try:
        watch.wait_line("analysis 1:")
        level.unlink()
        watch.wait_line("error: ")
        assert any("live.json" in line and "error:" in line for line in watch.lines())
        save(level, NEW)
        watch.wait_line("analysis 2:")
        with urllib.request.urlopen(watch.url + "events", timeout=10) as stream:
            assert stream.read(20).startswith(b"event: analysis")
        save(level, OLD)
        watch.wait_line("analysis 3:")
        with urllib.request.urlopen(watch.url, timeout=10) as answer:
            assert b"live analysis" in answer.read()
        # A burst of three saves: one analysis, of the last.
        for data in (NEW, OLD, NEW):
            save(level, data)
        watch.wait_line("analysis 4:")
        time.sleep(1.5)
        assert not any("analysis 5:" in line for line in watch.lines())
        assert '"number":4' in first_analysis(watch.url) and "[14.0,3.0]" in first_analysis(watch.url)
    finally:
        status = watch.stop()
    text = watch.out.read_text()
    assert status == 0 and "Traceback" not in text and text.splitlines()[-1] == "guardsim: stopped after 4 analyses"


TILED = shutil.which("tiled")
ROOM_TMX = """<?xml version="1.0" encoding="UTF-8"?>
<map version="1.8" orientation="orthogonal" renderorder="right-down" width="12" height="7" tilewidth="16"
 tileheight="16" infinite="0" nextlayerid="2" nextobjectid="1">
 <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2">
  <tile id="1"><properties><property name="collision" type="bool" value="true"/></properties></tile>
 </tileset>
 <layer id="1" name="Ground" width="12" height="7">
  <data encoding="csv">
2,2,2,2,2,2,2,2,2,2,2,2,
2,1,1,1,1,1,1,1,1,1,1,2,
2,1,1,1,1,PILLAR,1,1,1,1,1,2,
2,1,1,1,1,PILLAR,1,1,1,1,1,2,
2,1,1,1,1,PILLAR,1,1,1,1,1,2,
2,1,1,1,1,1,1,1,1,1,1,2,
2,2,2,2,2,2,2,2,2,2,2,2
</data>
 </layer>
</map>
"""


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None or TILED is None, reason="needs chromium and tiled on PATH")
def test_the_page_follows_real_tiled_re_exporting_a_map(tmp_path: Path) -> None:
    """Tiled's command line exports the map (a room with a pillar) to JSON; the pillar is removed and
    Tiled exports again over the watched file: the page shows the second analysis, with more floor."""
    runtime = tmp_path / "runtime"
    runtime.mkdir(mode=0o700)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(tmp_path), XDG_RUNTIME_DIR=str(runtime))
    source, exported = tmp_path / "room.tmx", tmp_path / "room.tmj"

    def export(pillar: str) -> None:
        source.write_text(ROOM_TMX.replace("PILLAR", pillar))
        done = subprocess.run(
            [TILED, "--export-map", "json", str(source), str(exported)], env=env, capture_output=True, timeout=120
        )
        assert done.returncode == 0, done.stderr

    export("2")
    watch = Watch(tmp_path, exported.name)
    page = None
    floor = "Array.from(atob(JSON.parse(window.lastPayload).kinds)).filter(c => c.charCodeAt(0) > 0).length"
    try:
        watch.wait_line("serving http://127.0.0.1:")
        page = LivePage(watch.url, tmp_path / "profile")
        page.wait_for(f"{STATUS}.number == '1'")
        page.evaluate(
            "window.events = new EventSource('events'); window.events.addEventListener('analysis', e => { window.lastPayload = e.data; })"
        )
        before = page.wait_for(f"window.lastPayload && {floor}")
        export("1")
        page.wait_for(f"{STATUS}.number == '2'")
        page.wait_for("JSON.parse(window.lastPayload).number == 2")
        assert page.evaluate(floor) == before + 3
        assert page.evaluate(ERROR) == ""
    finally:
        if page is not None:
            page.close()
        assert watch.stop() == 0


TILESET = """<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.8" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2">
 <tile id="1"><properties><property name="collision" type="bool" value="true"/></properties></tile>
</tileset>
"""


@pytest.mark.slow
def test_a_map_whose_tileset_is_saved_after_it(tmp_path: Path) -> None:
    """The map is saved first, naming a tileset not there yet: the analysis warns that the tileset was
    not found (its walls are missing); the tileset's save then brings a new analysis, without the warning."""
    inline = '<tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2">'
    text = ROOM_TMX.replace("PILLAR", "2")
    start, end = text.index(inline), text.index("</tileset>") + len("</tileset>")
    (tmp_path / "room.tmx").write_text(text[:start] + '<tileset firstgid="1" source="t.tsx"/>' + text[end:])
    watch = Watch(tmp_path, "room.tmx")
    try:
        watch.wait_line("analysis 1:")
        assert any("warning: room.tmx:" in line and "'t.tsx' not found" in line for line in watch.lines())
        save(tmp_path / "t.tsx", TILESET)
        # The warnings of analysis 2 would come between its line and its report's step.
        watch.wait_line("counting the distinct ways", count=2)
        lines = watch.lines()
        after = lines[next(k for k, line in enumerate(lines) if "analysis 2:" in line) :]
        assert not any("t.tsx" in line for line in after)
    finally:
        assert watch.stop() == 0
    assert "Traceback" not in watch.out.read_text()
