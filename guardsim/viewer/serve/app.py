"""``guardsim watch``: a local server whose one page redraws the level's analysis on each save.

A starlette application on uvicorn serves the page (:func:`~guardsim.viewer.serve.page.live_page`) and a
stream of server-sent events; watchfiles watches the level's folder. Each save is read, analysed
(:func:`guardsim.design.analyse`, reusing what the edit left valid) and sent in two steps: the analysis
with its report, then the report again with the distinct ways through counted (the slowest measure).

- A save that cannot be read (half written, invalid) sends its one-line error; the page keeps the last
  analysis drawn.
- Saves coalesce: the watcher waits :data:`DEBOUNCE_MS` for a burst to end, and a save during an
  analysis cancels it at its next step, so a burst costs one analysis.
- Only 127.0.0.1 is listened on unless another host is given.

Needs ``pip install 'guardsim[watch]'`` (starlette, uvicorn, watchfiles).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import socket
import threading
import time
from collections.abc import AsyncIterator, Callable, Sequence
from pathlib import Path
from typing import Any

from guardsim.errors import GuardsimError

__all__ = ["DEBOUNCE_MS", "LiveAnalyser", "watch"]

#: How long the watcher waits for a burst of file events to end before analysing, in milliseconds.
DEBOUNCE_MS = 40
#: Files beside a map that it may read: a save of one re-analyses the map (tilesets saved after it).
COMPANION_SUFFIXES = (".tsx", ".tsj", ".tx", ".png", ".ldtkl")
#: Seconds between keep-alive comments on an idle event stream.
KEEPALIVE_SECONDS = 10.0

Point = tuple[float, float]


class Superseded(Exception):
    """A newer save (or the server stopping) made this analysis pointless."""


class LiveAnalyser:
    """The latest analysis of a watched level and the messages the pages are sent.

    :meth:`run` analyses the file as it is now (in a worker thread); :meth:`messages` are the events a
    page that connects now needs (the last analysis, then the error of a later save if any).
    """

    def __init__(
        self,
        path: str,
        *,
        patrol: str | None = None,
        guards: int = 1,
        pairs: Sequence[tuple[Point, Point]] | None = None,
        planner: str = "cover",
        seed: int = 0,
        echo: Callable[[str], None] = print,
    ) -> None:
        self.path = path
        self.patrol = patrol
        self.guards = guards
        self.pairs = None if pairs is None else list(pairs)
        self.planner = planner
        self.seed = seed
        self.echo = echo
        self.generation = 0
        """Saves seen so far (an analysis of an older generation is cancelled)."""
        self.stopping = False
        self.analyses = 0
        """Analyses finished."""
        self.cancelled = 0
        self.version = 0
        """Bumped whenever :meth:`messages` changes."""
        self._last: Any = None
        self._analysis: dict[str, Any] | None = None
        self._failure: dict[str, Any] | None = None
        self._waiters: set[asyncio.Event] = set()
        self._delivered: dict[asyncio.Event, int] = {}
        """The version each page's stream has sent."""
        self._lock = threading.Lock()

    # --- what the pages are sent ---

    def messages(self) -> list[tuple[str, str]]:
        """``(event, data)`` pairs for a page: the last analysis, then a later failure."""
        with self._lock:
            out = []
            if self._analysis is not None:
                out.append(("analysis", json.dumps(self._analysis, separators=(",", ":"))))
            if self._failure is not None:
                out.append(("failure", json.dumps(self._failure)))
            return out

    def subscribe(self) -> asyncio.Event:
        event = asyncio.Event()
        self._waiters.add(event)
        return event

    def unsubscribe(self, event: asyncio.Event) -> None:
        self._waiters.discard(event)
        self._delivered.pop(event, None)

    def delivered(self, event: asyncio.Event, version: int) -> None:
        """A page's stream has sent everything up to ``version``."""
        self._delivered[event] = version

    async def _deliver(self) -> None:
        """Publish, then wait (a moment at most) until every page's stream has sent it: the compiled
        searches of the next step hold the interpreter, and the page should not wait for them."""
        self._publish()
        target = self.version
        loop = asyncio.get_running_loop()
        deadline = loop.time() + 1.0
        while loop.time() < deadline and any(self._delivered.get(e, -1) < target for e in self._waiters):
            await asyncio.sleep(0.002)

    def _publish(self) -> None:
        self.version += 1
        for event in list(self._waiters):
            event.set()

    # --- analysing ---

    def saved(self) -> None:
        """A watched file changed: later analyses supersede the running one."""
        self.generation += 1

    def _check(self, generation: int) -> None:
        if self.stopping or generation != self.generation:
            raise Superseded

    def analyse_now(self, generation: int, publish: Callable[[dict[str, Any]], None]) -> None:
        """Read and analyse the level (worker thread); ``publish`` each payload; :class:`Superseded` when
        a newer save arrives first, :class:`~guardsim.errors.GuardsimError` when the save is unusable."""
        from guardsim.design import analyse, report_data, report_of
        from guardsim.importers import ImportedLevel, load_level
        from guardsim.viewer.serve.payload import analysis_payload

        began = time.perf_counter()
        records: list[ImportedLevel] = []
        level = load_level(self.path, report=records.append)
        # What the import says is probably not what the author drew (a tileset not saved yet, no walls).
        warnings = [" ".join(warning.split()) for record in records for warning in record.warnings]
        self._check(generation)

        def step(line: str) -> None:
            self._check(generation)
            # A long analysis (a big map) is not silent: each step is a line.
            self.echo(f"analysing: {line}")

        analysis = analyse(
            level,
            patrol=self.patrol,
            guards=self.guards,
            pairs=self.pairs,
            planner=self.planner,
            seed=self.seed,
            reuse=self._last,
            progress=step,
        )
        self._check(generation)
        number = self.analyses + 1
        header = {"number": number, "file": os.path.basename(self.path), "warnings": warnings}
        fast = report_data(report_of(analysis, ways=False))
        fast["provisional"] = True
        for pair in fast["pairs"]:
            pair["ways"] = None
        first = analysis_payload(analysis, fast)
        first["seconds"] = round(time.perf_counter() - began, 3)
        publish({**first, **header, "phase": "analysis"})
        self._last = analysis
        self.analyses = number
        self._check(generation)
        full = analysis_payload(analysis, report_data(report_of(analysis, progress=step)))
        full["seconds"] = round(time.perf_counter() - began, 3)
        publish({**full, **header, "phase": "report"})

    async def run(self) -> None:
        """Analyse the file as it is now, unless a newer save supersedes it; publish what comes out."""
        generation = self.generation
        loop = asyncio.get_running_loop()

        def publish(payload: dict[str, Any]) -> None:
            with self._lock:
                self._analysis, self._failure = payload, None
            if payload["phase"] == "analysis":
                asyncio.run_coroutine_threadsafe(self._deliver(), loop).result()
            else:
                loop.call_soon_threadsafe(self._publish)
                # The report's last step (the ways through) ends here: said, so its line stops ticking.
                self.echo(f"report {payload['number']}: {payload['seconds']:.2f} s")
            if payload["phase"] == "analysis":
                reused = f", reused {' and '.join(payload['reused'])}" if payload["reused"] else ""
                self.echo(f"analysis {payload['number']}: {payload['seconds']:.2f} s{reused}")
                for warning in payload["warnings"]:
                    self.echo(f"warning: {payload['file']}: {warning}")

        try:
            await asyncio.to_thread(self.analyse_now, generation, publish)
        except Superseded:
            self.cancelled += 1
        except GuardsimError as error:
            self._fail(" ".join(str(error).split()), generation)
        except Exception as error:
            self._fail(
                f"{self.path}: internal error: {type(error).__name__}: {' '.join(str(error).split())}", generation
            )

    def _fail(self, message: str, generation: int) -> None:
        if generation != self.generation:
            return
        with self._lock:
            self._failure = {"message": message, "number": self.analyses}
        self.echo(f"error: {message} (the page keeps analysis {self.analyses})")
        self._publish()


def _app(analyser: LiveAnalyser, title: str, stop: asyncio.Event) -> Any:
    from starlette.applications import Starlette
    from starlette.requests import Request
    from starlette.responses import HTMLResponse, StreamingResponse
    from starlette.routing import Route

    from guardsim.viewer.serve.page import live_page

    page = live_page(title)

    async def index(_request: Request) -> HTMLResponse:
        return HTMLResponse(page)

    async def events(request: Request) -> StreamingResponse:
        async def stream() -> AsyncIterator[str]:
            changed = analyser.subscribe()
            sent = -1
            try:
                while not stop.is_set():
                    if analyser.version != sent:
                        sent = analyser.version
                        changed.clear()
                        for name, data in analyser.messages():
                            yield f"event: {name}\ndata: {data}\n\n"
                        # Reached once the last message is sent (the next one is asked for).
                        analyser.delivered(changed, sent)
                    with contextlib.suppress(asyncio.TimeoutError):
                        await asyncio.wait_for(changed.wait(), KEEPALIVE_SECONDS)
                        continue
                    if await request.is_disconnected():
                        break
                    yield ": keep-alive\n\n"
            finally:
                analyser.unsubscribe(changed)

        return StreamingResponse(stream(), media_type="text/event-stream", headers={"Cache-Control": "no-cache"})

    return Starlette(routes=[Route("/", index), Route("/events", events)])


def _watched(path: Path, patrol: Path | None) -> Callable[[Any, str], bool]:
    level, companion = path.resolve(), path.suffix.lower() != ".json"

    def wanted(_change: Any, name: str) -> bool:
        changed = Path(name).resolve()
        if changed == level or (patrol is not None and changed == patrol):
            return True
        return companion and changed.parent == level.parent and changed.suffix.lower() in COMPANION_SUFFIXES

    return wanted


def _listen(host: str, port: int) -> socket.socket:
    from guardsim.files.reading import quoted

    if not host.strip():
        # An empty host binds every address of the machine: the page would be open to the network.
        raise GuardsimError("--host: an empty address listens on every network; give one (127.0.0.1 is this machine)")
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.bind((host, port))
    except (OSError, ValueError, TypeError) as error:
        # Not an address at all: a name IDNA cannot encode (TypeError), a NUL in it (ValueError).
        sock.close()
        shown = host if len(host) <= 60 and host.isprintable() else quoted(host, 60)
        if isinstance(error, OSError) and error.errno in (98, 48, 10048):
            raise GuardsimError(f"port {port} on {shown} is in use: give another with --port N") from None
        reason = error.strerror if isinstance(error, OSError) else "not an address"
        raise GuardsimError(
            f"port {port} on {shown} cannot be listened on ({reason}): give another --host or --port"
        ) from None
    sock.listen(64)
    sock.setblocking(False)
    return sock


async def _serve(analyser: LiveAnalyser, sock: socket.socket, title: str, open_browser: bool) -> None:
    import uvicorn
    from watchfiles import awatch

    stop = asyncio.Event()
    config = uvicorn.Config(
        _app(analyser, title, stop), log_level="critical", access_log=False, timeout_graceful_shutdown=1, lifespan="off"
    )
    server = uvicorn.Server(config)
    level = Path(analyser.path)
    patrol = Path(analyser.patrol).resolve() if analyser.patrol else None
    folders = {level.resolve().parent} | ({patrol.parent} if patrol else set())
    wanted = _watched(level, patrol)
    work: asyncio.Task[None] | None = None

    def analyse() -> None:
        nonlocal work
        analyser.saved()
        generation = analyser.generation

        async def follow(previous: asyncio.Task[None] | None) -> None:
            # One analysis at a time (each reuses the one before); a newer save supersedes this one.
            if previous is not None:
                await previous
            if generation == analyser.generation:
                await analyser.run()

        work = asyncio.create_task(follow(work))

    async def watching() -> None:
        analyse()
        async for changes in awatch(
            *folders, watch_filter=wanted, debounce=DEBOUNCE_MS, step=10, stop_event=stop, recursive=False
        ):
            for change, name in sorted(changes):
                analyser.echo(f"{Path(name).name} {change.name}")
            analyse()

    watcher = asyncio.create_task(watching())
    if open_browser:
        import webbrowser

        host, port = sock.getsockname()[:2]
        webbrowser.open(f"http://{host}:{port}/")
    try:
        await server.serve(sockets=[sock])
    finally:
        analyser.stopping = True
        stop.set()
        watcher.cancel()
        with contextlib.suppress(asyncio.CancelledError, Exception):
            await watcher
        if work is not None:
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await work


def watch(
    path: str,
    *,
    patrol: str | None = None,
    guards: int = 1,
    pairs: Sequence[tuple[Point, Point]] | None = None,
    host: str = "127.0.0.1",
    port: int = 8000,
    open_browser: bool = False,
    echo: Callable[[str], None] = print,
) -> None:
    """Serve the live page of the level (or map) at ``path`` on ``host:port`` until interrupted (Ctrl-C).

    ``patrol``: a patrol.json, re-read on each save; without it, the loop patrol of ``guards`` guards is
    planned (from the set cover's viewpoints, the quickest loop, and again only when the walls, the
    guards' sight or their start changed). ``pairs``: entry-goal points, else the default pairs.

    Raises
    ------
    GuardsimError
        When the port cannot be listened on, or the ``watch`` extra is not installed.
    """
    try:
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
        import watchfiles  # noqa: F401
    except ImportError as error:
        raise GuardsimError(f"guardsim watch needs {error.name}: pip install 'guardsim[watch]'") from None
    if not Path(path).parent.resolve().is_dir():
        raise GuardsimError(f"{path}: its folder does not exist, so there is nothing to watch")
    sock = _listen(host, port)
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead("report")  # each save is analysed as report analyses a level: its kernels, on two cores
    analyser = LiveAnalyser(path, patrol=patrol, guards=guards, pairs=pairs, echo=echo)
    bound = sock.getsockname()[1]
    echo(f"serving http://{host}:{bound}/ : the analysis of {path}, redrawn on each save (Ctrl-C stops)")
    try:
        asyncio.run(_serve(analyser, sock, f"{Path(path).name}: live analysis", open_browser))
    except KeyboardInterrupt:
        pass
    finally:
        sock.close()
    echo(f"stopped after {analyser.analyses} analyses")
