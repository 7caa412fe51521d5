"""What ``report``, ``diff`` and ``watch`` share: repeatable entry-goal pairs, progress lines."""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Callable
from types import TracebackType
from typing import Any, TextIO, TypeVar

import click

from guardsim.cli.common import parse_point
from guardsim.cli.progress import PLAIN_EVERY_SECONDS, REDRAW_SECONDS, draw_line, duration
from guardsim.errors import GuardsimError

__all__ = ["StepLines", "check_outputs", "guards_option", "pair_options", "pairs_of", "progress_line"]

F = TypeVar("F", bound=Callable[..., Any])
Point = tuple[float, float]


def _each_point(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[Point, ...]:
    return tuple(point for point in (parse_point(ctx, param, value) for value in values) if point is not None)


def guards_option(command: F) -> F:
    """``--guards K``: the team size of the loop patrol made when no patrol file is given."""
    return click.option(
        "--guards",
        type=click.IntRange(min=1, max=64),
        default=1,
        show_default=True,
        help="Team size of the loop patrol made without a patrol file.",
    )(command)


def pair_options(command: F) -> F:
    """Repeatable ``--from X,Y`` and ``--to X,Y``: the k-th --from goes with the k-th --to."""
    command = click.option(
        "--to", "targets", multiple=True, callback=_each_point, metavar="X,Y", help="A goal (world units); repeatable."
    )(command)
    command = click.option(
        "--from",
        "sources",
        multiple=True,
        callback=_each_point,
        metavar="X,Y",
        help="An entry (world units), paired with the --to of the same rank; repeatable "
        "[default: each player start to the farthest floor, else across the patrolled floor].",
    )(command)
    return command


def pairs_of(sources: tuple[Point, ...], targets: tuple[Point, ...]) -> list[tuple[Point, Point]] | None:
    """The pairs given, or ``None`` (the default pairs) when neither option was."""
    if len(sources) != len(targets):
        raise GuardsimError(f"each --from needs its --to: {len(sources)} --from, {len(targets)} --to")
    return list(zip(sources, targets)) if sources else None


def progress_line(line: str) -> None:
    """A progress line on standard error, so that nothing sits silent."""
    click.echo(f"guardsim: {line}", err=True)


def check_outputs(**outputs: str | None) -> None:
    """Refuse, before any work, an output that cannot be written (``--json=path`` given as ``json=path``):
    a command that fails leaves none of its outputs behind, so each is checked before the first is written."""
    from guardsim.files.output import check_writable

    for name, target in outputs.items():
        if target is None:
            continue
        option = "--" + name.replace("_", "-")
        if not target.strip():
            raise click.BadParameter("an empty file name; give the file to write", param_hint=option)
        try:
            check_writable(target)
        except GuardsimError as error:
            raise GuardsimError(f"{option} {error}") from None


class StepLines:
    """:func:`progress_line` for each step as it starts, then, while a step runs on without news (a big
    map's patrol or scene), its line again with the time it has taken, every ``every`` seconds: drawn in
    place on a terminal, a plain line otherwise (``every``: :data:`~guardsim.cli.progress.PLAIN_EVERY_SECONDS`). Lines for which ``is_step`` is false (``watch``'s
    results and errors) end the step. Use as a context manager around the work, and pass the instance
    where a progress callback of lines is wanted."""

    def __init__(
        self,
        stream: TextIO | None = None,
        *,
        is_step: Callable[[str], bool] = lambda _line: True,
        every: float | None = None,
    ) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.is_step = is_step
        self.every = PLAIN_EVERY_SECONDS if every is None else every
        self.in_place = self.stream.isatty()
        self.silent = os.environ.get("GUARDSIM_PROGRESS", "1") == "0"
        self.step: str | None = None
        self.since = self.shown = time.monotonic()
        self._dangling = False
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._clock = threading.Thread(target=self._tick, name="guardsim-steps", daemon=True)

    def __call__(self, line: str) -> None:
        with self._lock:
            self._end_drawn_line()
            click.echo(f"guardsim: {line}", file=self.stream)
            self.step = line if self.is_step(line) else None
            self.since = self.shown = time.monotonic()

    def _end_drawn_line(self) -> None:
        if self._dangling:
            self.stream.write("\n")
            self._dangling = False

    def _tick(self) -> None:
        while not self._stop.wait(max(0.01, min(REDRAW_SECONDS, self.every))):
            with self._lock:
                now = time.monotonic()
                if self.silent or self.step is None or now - self.shown < self.every:
                    continue
                draw_line(self.stream, f"guardsim: {self.step} ({duration(now - self.since)})", in_place=self.in_place)
                self._dangling = self.in_place
                self.shown = now

    def start(self) -> StepLines:
        """Start the clock; :meth:`close` stops it."""
        if not self._clock.is_alive() and not self._stop.is_set():
            self._clock.start()
        return self

    def close(self) -> None:
        """Stop the clock and end a line drawn in place. Closing twice does nothing more."""
        self._stop.set()
        if self._clock.is_alive():
            self._clock.join()
        with self._lock:
            self._end_drawn_line()
            self.stream.flush()

    def __enter__(self) -> StepLines:
        return self.start()

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()
