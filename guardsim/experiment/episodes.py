"""One episode of a batch: what to run (:class:`EpisodeSpec`), what came of it (:class:`EpisodeRecord`).

:func:`run_spec` is the function workers run. It needs nothing but its argument, so it runs the same in
this process, in a local process pool or on a Dask worker on another machine, and gives the same record
(apart from the wall time) wherever it runs.
"""

from __future__ import annotations

import functools
import threading
import time
from typing import NamedTuple

from guardsim.level import HEADINGS, Level
from guardsim.simulation import Scene, run_batch_episode

__all__ = ["CSV_COLUMNS", "FRACTIONS", "EpisodeRecord", "EpisodeSpec", "forget_scenes", "run_spec", "scene_of"]

#: Coverage fractions whose first tick is recorded as T50, T90 and T99.
FRACTIONS = (0.5, 0.9, 0.99)

#: Heading names by heading number (0 right, 1 down, 2 left, 3 up).
HEADING_NAMES = tuple(HEADINGS)


class EpisodeSpec(NamedTuple):
    """Everything a worker needs to run one episode of a batch."""

    level: Level
    """The validated level (small, so it travels with each episode; workers need no copy of the file)."""
    level_file: str
    """The level's file as named on the command line (normalised), which identifies it in the results."""
    planner: str
    """Planner name, a key of :data:`guardsim.planners.PLANNERS`."""
    seed: int
    """Seed of the batch."""
    episode: int
    """Episode index; the episode's generator is ``episode_generator(seed, episode)``."""
    reference: bool = False
    """Use the reference vision instead of the fast path."""
    max_steps: int | None = None
    """Step limit; ``None`` for the simulation's default."""

    @property
    def key(self) -> tuple[str, str, int, int]:
        """``(level_file, planner, seed, episode)``: what makes an episode the same one on resume."""
        return (self.level_file, self.planner, self.seed, self.episode)


class EpisodeRecord(NamedTuple):
    """One row of ``results.csv``. Fields that an episode ending in ``error`` did not reach are ``None``."""

    level: str
    """Level name (from the file's ``name``)."""
    level_file: str
    """Level file, as in :attr:`EpisodeSpec.level_file`."""
    planner: str
    """Planner name."""
    seed: int
    """Seed of the batch."""
    episode: int
    """Episode index within the batch."""
    start_col: int | None
    """Column of the start cell."""
    start_row: int | None
    """Row of the start cell."""
    start_heading: str | None
    """First heading: ``right``, ``down``, ``left`` or ``up``."""
    steps: int | None
    """Steps taken."""
    outcome: str
    """``covered``, ``step_limit``, ``stuck``, or ``error`` when an exception escaped the episode."""
    t50: int | None
    """First tick at which 50 % of the reachable cells had been seen; ``None`` if never."""
    t90: int | None
    """The same for 90 %."""
    t99: int | None
    """The same for 99 %."""
    reachable: int | None
    """Cells reachable from the start: the episode's goal."""
    seconds: float
    """Wall time of the episode in its worker. Not deterministic: leave it out when comparing runs."""
    error: str
    """For ``error``: the exception's type and message on one line; otherwise empty."""

    @property
    def key(self) -> tuple[str, str, int, int]:
        """``(level_file, planner, seed, episode)``, as :attr:`EpisodeSpec.key`."""
        return (self.level_file, self.planner, self.seed, self.episode)

    @property
    def sort_key(self) -> tuple[str, str, int]:
        """``(level_file, planner, episode)``: the order of rows in a finished ``results.csv``."""
        return (self.level_file, self.planner, self.episode)

    def to_row(self) -> list[str]:
        """The record as CSV fields: ``None`` as an empty field, seconds to the microsecond."""
        return [
            "" if value is None else f"{value:.6f}" if name == "seconds" else str(value)
            for name, value in zip(CSV_COLUMNS, self)
        ]

    @classmethod
    def from_row(cls, row: list[str]) -> EpisodeRecord:
        """Parse :meth:`to_row` output; raises ``ValueError`` naming the bad field."""
        if len(row) != len(CSV_COLUMNS):
            raise ValueError(f"expected {len(CSV_COLUMNS)} fields, found {len(row)}")
        values = dict(zip(CSV_COLUMNS, row))
        parsed: dict[str, object] = {}
        for name, text in values.items():
            kind = _FIELD_TYPES[name]
            try:
                parsed[name] = None if text == "" and name not in _ALWAYS_TEXT else kind(text)
            except ValueError:
                raise ValueError(f"{name} is not a number: {text!r}") from None
        return cls(**parsed)  # type: ignore[arg-type]


#: The header of ``results.csv``: the fields of :class:`EpisodeRecord`, in order.
CSV_COLUMNS: tuple[str, ...] = EpisodeRecord._fields

_TEXT_FIELDS = {"level", "level_file", "planner", "start_heading", "outcome", "error"}
#: Text fields that are never ``None`` (an empty ``error`` is no error, not a missing one).
_ALWAYS_TEXT = _TEXT_FIELDS - {"start_heading"}
_FIELD_TYPES = {name: str if name in _TEXT_FIELDS else float if name == "seconds" else int for name in CSV_COLUMNS}


def scene_of(level: Level) -> Scene:
    """The level's scene, built once per worker thread and shared by all the episodes it runs there.

    One per thread, not per process, because an episode moves the guard's body in the scene's pymunk
    space: a Dask worker with several threads must not run two episodes in one space.
    """
    return _scene_of_thread(level, threading.get_ident())


def forget_scenes() -> None:
    """Drop this process's cached scenes (for timing a cold start, or to free memory)."""
    _scene_of_thread.cache_clear()


@functools.lru_cache(maxsize=16)
def _scene_of_thread(level: Level, _thread: int) -> Scene:
    return Scene.from_level(level)


def run_spec(spec: EpisodeSpec) -> EpisodeRecord:
    """Run one episode and record it; an exception from the episode becomes its ``error`` outcome.

    Only ``Exception`` is caught: Ctrl-C and the like still stop the run.
    """
    began = time.perf_counter()
    try:
        trace = run_batch_episode(
            scene_of(spec.level),
            seed=spec.seed,
            episode=spec.episode,
            planner=spec.planner,
            reference=spec.reference,
            max_steps=spec.max_steps,
        )
    except Exception as error:
        message = " ".join(f"{type(error).__name__}: {error}".split())
        return EpisodeRecord(
            spec.level.name, spec.level_file, spec.planner, spec.seed, spec.episode,
            None, None, None, None, "error", None, None, None, None,
            time.perf_counter() - began, message,
        )  # fmt: skip
    t50, t90, t99 = (trace.steps_to_fraction(fraction) for fraction in FRACTIONS)
    col, row = trace.start
    return EpisodeRecord(
        spec.level.name, spec.level_file, spec.planner, spec.seed, spec.episode,
        col, row, HEADING_NAMES[trace.headings[0]], trace.steps, trace.outcome, t50, t90, t99, trace.reachable,
        time.perf_counter() - began, "",
    )  # fmt: skip
