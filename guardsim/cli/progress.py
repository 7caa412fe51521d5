"""Progress on standard error: one line redrawn in place on a terminal, plain lines otherwise.

:class:`ProgressLine` counts a batch's episodes (``bench``, ``alert``); :class:`StageLine` follows a long
job through its stages (``patrol``: the view table, each loop source, the team, the scoring), told by the
library's ``progress(what, done, total)`` callbacks. Both draw through :func:`draw_line`, so every
command's progress looks the same. A stage line keeps going on its own (a clock ticking beside the
stage's name) while a stage gives no news, so a command is never silent for more than two seconds; it
says nothing for a job that ends within :data:`QUIET_SECONDS`, and nothing at all with
``GUARDSIM_PROGRESS=0`` in the environment (the test suite sets it, as it silences the compile notice,
so that a slow machine adds no line to the messages tests read).
"""

from __future__ import annotations

import math
import os
import threading
import time
from types import TracebackType
from typing import TYPE_CHECKING, TextIO

import click

if TYPE_CHECKING:
    from guardsim.experiment import EpisodeRecord

__all__ = ["PLAIN_EVERY_SECONDS", "QUIET_SECONDS", "ProgressLine", "StageLine", "Throttle", "draw_line", "duration"]

#: A job that ends within this many seconds prints no progress at all.
QUIET_SECONDS = 2.0
#: Where standard error is not a terminal, a new plain line at most this often (and at each new stage).
PLAIN_EVERY_SECONDS = 2.0
#: Redraws of a line in place, at most this often.
REDRAW_SECONDS = 0.2


class Throttle:
    """At most one report every ``seconds``, the first once ``seconds`` have passed (quiet before), so a
    long search says where it is without flooding the terminal."""

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        self.began = time.perf_counter()
        self._next = self.began + seconds

    def due(self) -> bool:
        """Whether a report is due now (and, if so, the next one ``seconds`` from now)."""
        now = time.perf_counter()
        if now < self._next:
            return False
        self._next = now + self.seconds
        return True

    def elapsed(self) -> float:
        """Seconds since the throttle was made."""
        return time.perf_counter() - self.began


def duration(seconds: float) -> str:
    """``seconds`` for people: ``42s``, ``3m05s``, ``1h02m``."""
    minutes, second = divmod(round(seconds), 60)
    hours, minute = divmod(minutes, 60)
    return f"{hours}h{minute:02d}m" if hours else f"{minute}m{second:02d}s" if minute else f"{second}s"


def draw_line(stream: TextIO, text: str, *, in_place: bool) -> None:
    """Write ``text`` over the line drawn before (``in_place``, a terminal) or as a line of its own."""
    stream.write(f"\r{text}   " if in_place else f"{text}\n")
    stream.flush()


class ProgressLine:
    """Episodes done, rate and time left, redrawn in place on one line; silent unless ``stream`` is a terminal."""

    def __init__(self, total: int, stream: TextIO) -> None:
        self.total = total
        self.done = 0
        self.stream = stream
        self.active = stream.isatty()
        self.began = time.monotonic()
        self.drawn_at = -math.inf
        self.draw()

    def advance(self, _record: EpisodeRecord) -> None:
        """Count one episode done; redraw at most five times a second."""
        self.done += 1
        now = time.monotonic()
        if now - self.drawn_at >= REDRAW_SECONDS or self.done == self.total:
            self.draw()

    def draw(self) -> None:
        """Write the line over the previous one."""
        if not self.active:
            return
        self.drawn_at = time.monotonic()
        elapsed = self.drawn_at - self.began
        rate = self.done / elapsed if elapsed > 0 and self.done else 0.0
        left = f"{duration((self.total - self.done) / rate)} left" if rate else "time left unknown"
        draw_line(self.stream, f"{self.done}/{self.total} episodes  {rate:.1f}/s  {left}", in_place=True)

    def close(self) -> None:
        """End the line, so later messages start on their own."""
        if self.active:
            self.stream.write("\n")
            self.stream.flush()
            self.active = False


class StageLine:
    """A long job's stage, how far it is and the time taken, kept on standard error while the job runs.

    Use as a context manager around the job, and pass the instance as its ``progress`` callback::

        with StageLine(sys.stderr, "patrol") as progress:
            run_patrol(..., progress=progress)
    """

    def __init__(self, stream: TextIO, command: str) -> None:
        self.stream = stream
        self.command = command
        self.in_place = stream.isatty()
        self.silent = os.environ.get("GUARDSIM_PROGRESS", "1") == "0"
        self.began = time.monotonic()
        self.what = "starting"
        self.done = 0
        self.total = 0
        self._printed = ""
        self._drawn_at = -math.inf
        self._drawn = False
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._clock = threading.Thread(target=self._tick, name="guardsim-progress", daemon=True)

    def __call__(self, what: str, done: int, total: int) -> None:
        """The job is at step ``done`` of ``total`` of stage ``what`` (``total`` 0: not counted)."""
        with self._lock:
            self.what, self.done, self.total = what, done, total
        self._draw(force=False)

    def text(self) -> str:
        """The line as drawn now."""
        counted = f" {self.done}/{self.total}" if self.total else ""
        return f"guardsim: {self.command}: {self.what}{counted} ({duration(time.monotonic() - self.began)})"

    def _draw(self, *, force: bool) -> None:
        with self._lock:
            now = time.monotonic()
            if self.silent or now - self.began < QUIET_SECONDS:
                return
            text = self.text()
            if self.in_place:
                if now - self._drawn_at < REDRAW_SECONDS and not force:
                    return
            else:
                # A count that moves on (functions compiled, sources looped) is not a new stage: a plain
                # line for every step would flood a log.
                if self.what == self._printed and now - self._drawn_at < PLAIN_EVERY_SECONDS:
                    return
                self._printed = self.what
            self._drawn_at = now
            self._drawn = True
            draw_line(self.stream, text, in_place=self.in_place)

    def _tick(self) -> None:
        while not self._stop.wait(REDRAW_SECONDS):
            self._draw(force=False)

    def start(self) -> StageLine:
        """Start the clock that keeps the line going; :meth:`close` stops it (the click context too, when
        the command ends, should it stop early)."""
        if not self._clock.is_alive() and not self._stop.is_set():
            self._clock.start()
            context = click.get_current_context(silent=True)
            if context is not None:
                context.call_on_close(self.close)
        return self

    def close(self) -> None:
        """Stop the clock and end a line drawn in place, so that what the command prints next starts on
        its own line. Closing twice does nothing more."""
        self._stop.set()
        if self._clock.is_alive():
            self._clock.join()
        with self._lock:
            if self.in_place and self._drawn:
                self.stream.write("\n")
                self.stream.flush()
                self._drawn = False

    def __enter__(self) -> StageLine:
        return self.start()

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()
