"""One episode of a batch: what to run (:class:`EpisodeSpec`), what came of it (:class:`EpisodeRecord`).

:func:`run_spec` is the function workers run. It needs nothing but its argument, so it runs the same in
this process, in a local process pool or on a Dask worker on another machine, and gives the same record
(apart from the wall-time columns) wherever it runs.
"""

from __future__ import annotations

import functools
import threading
import time
import traceback
from typing import NamedTuple

from guardsim.bounds import Bounds, lower_bounds
from guardsim.errors import ArgumentError
from guardsim.level import HEADINGS, Level
from guardsim.motion import GuardMotion, run_episode
from guardsim.motion.measures import RECORD_COLUMNS, record_columns
from guardsim.simulation import Scene
from guardsim.vision.table import view_table

__all__ = [
    "CSV_COLUMNS",
    "FRACTIONS",
    "LOOK_AHEAD",
    "TIMED_COLUMNS",
    "EpisodeRecord",
    "EpisodeSpec",
    "bounds_of",
    "error_record",
    "error_text",
    "forget_scenes",
    "run_spec",
    "run_spec_logged",
    "scene_of",
    "wants_bounds",
]

#: Coverage fractions whose first tick is recorded as T50, T90 and T99.
FRACTIONS = (0.5, 0.9, 0.99)

#: Planners that read the whole view table (see :func:`guardsim.vision.table.view_table`).
LOOK_AHEAD = frozenset({"frontier", "tour"})

#: Heading names by heading number (0 right, 1 down, 2 left, 3 up).
HEADING_NAMES = tuple(HEADINGS)


class EpisodeSpec(NamedTuple):
    """Everything a worker needs to run one episode of a batch."""

    level: Level
    """The validated level (small, so it travels with each episode; workers need no copy of the file),
    its guard already carrying the batch's field of view and view range."""
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
    guards: int = 1
    """Guards in the team, all running ``planner``."""
    line_of_sight: str = "pymunk"
    """``pymunk`` or ``bresenham``, as :meth:`Scene.from_level`'s ``line_of_sight``."""
    bounds: bool = True
    """Compute the start's lower bounds (one guard only)."""
    motion: str = "grid"
    """``grid`` or ``continuous`` (``docs/motion.md``)."""
    move_speed: float | None = None
    """Continuous motion: walking speed; ``None`` for the level guard's, else the default."""
    turn_speed: float | None = None
    """Continuous motion: turning speed; ``None`` for the level guard's, else the default."""
    tick_hz: float | None = None
    """Continuous motion: physics ticks per second; ``None`` for the level guard's, else the default."""
    max_seconds: float | None = None
    """Continuous motion: game-time limit; ``None`` for the default."""

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
    guards: int
    """Guards in the team."""
    seed: int
    """Seed of the batch."""
    episode: int
    """Episode index within the batch."""
    start_col: int | None
    """Column of the start cell (guard 0's, for a team)."""
    start_row: int | None
    """Row of the start cell."""
    start_heading: str | None
    """First heading: ``right``, ``down``, ``left`` or ``up``."""
    steps: int | None
    """Steps taken: ticks until covered or stopped, a team's makespan."""
    total_moves: int | None
    """Moves summed over the guards (a tick on which a guard stays is no move)."""
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
    best_bound: int | None
    """The larger of the two lower bounds on one guard's steps from this start (``None`` for a team)."""
    eccentricity_bound: int | None
    """The eccentricity bound (:func:`guardsim.bounds.lower_bounds`); ``None`` for a team."""
    cluster_bound: int | None
    """The cluster bound; ``None`` for a team."""
    seconds: float
    """Wall time of the episode in its worker. Not deterministic: leave it out when comparing runs."""
    plan_us_per_step: float | None
    """``seconds`` per step in microseconds: planning, vision and the loop's bookkeeping. Not deterministic;
    ``None`` for an episode of no steps."""
    error: str
    """For ``error``: the exception's type and message on one line; otherwise empty."""
    motion: str = "grid"
    """``grid`` or ``continuous``; with ``continuous``, ``steps`` and the T columns count physics ticks."""
    game_seconds: float | None = None
    """Continuous motion: game time of the episode (to cover, when covered)."""
    t50_s: float | None = None
    """Continuous motion: T50 in game seconds."""
    t90_s: float | None = None
    """Continuous motion: T90 in game seconds."""
    t99_s: float | None = None
    """Continuous motion: T99 in game seconds."""
    distance: float | None = None
    """World units walked (on the grid: moves times the cell size)."""
    turning_degrees: float | None = None
    """Degrees turned in all."""
    in_place_s: float | None = None
    """Continuous motion: seconds spent turning in place."""
    turns: int | None = None
    """Turns (on the grid: ticks whose heading changed)."""
    u_turns: int | None = None
    """Turns of 135 degrees or more."""
    turns_per_minute: float | None = None
    """Continuous motion: turns per minute of game time."""

    @property
    def key(self) -> tuple[str, str, int, int]:
        """``(level_file, planner, seed, episode)``, as :attr:`EpisodeSpec.key`."""
        return (self.level_file, self.planner, self.seed, self.episode)

    @property
    def sort_key(self) -> tuple[str, str, int]:
        """``(level_file, planner, episode)``: the order of rows in a finished ``results.csv``."""
        return (self.level_file, self.planner, self.episode)

    @property
    def bound_ratio(self) -> float | None:
        """``steps / best_bound``: at least how many times the shortest covering walk this episode took.

        ``None`` for a team, an episode that raised, or a bound of 0 (the start sees every cell).
        """
        if self.steps is None or not self.best_bound:
            return None
        return self.steps / self.best_bound

    def to_row(self) -> list[str]:
        """The record as CSV fields: ``None`` as an empty field, times to the microsecond (per step, to a
        thousandth of one)."""
        return [_field(name, value) for name, value in zip(CSV_COLUMNS, self)]

    @classmethod
    def from_row(cls, row: list[str]) -> EpisodeRecord:
        """Parse :meth:`to_row` output; raises ``ValueError`` naming the bad field."""
        if len(row) not in (len(CSV_COLUMNS), len(CSV_COLUMNS) - len(RECORD_COLUMNS)):
            raise ArgumentError(f"expected {len(CSV_COLUMNS)} fields, found {len(row)}")
        # A row written before the motion columns existed is a grid row.
        values = dict(zip(CSV_COLUMNS, row)) | ({} if len(row) == len(CSV_COLUMNS) else {"motion": "grid"})
        parsed: dict[str, object] = {}
        for name, text in values.items():
            kind = _FIELD_TYPES[name]
            try:
                parsed[name] = None if text == "" and name not in _ALWAYS_TEXT else kind(text)
            except ValueError:
                raise ArgumentError(f"{name} is not a number: {text!r}") from None
        return cls(**parsed)  # type: ignore[arg-type]


#: The header of ``results.csv``: the fields of :class:`EpisodeRecord`, in order.
CSV_COLUMNS: tuple[str, ...] = EpisodeRecord._fields

#: Columns measured in wall time, which differ from run to run; compare runs on the others.
TIMED_COLUMNS = ("seconds", "plan_us_per_step")

_TEXT_FIELDS = {"level", "level_file", "planner", "start_heading", "outcome", "error", "motion"}
_FLOAT_FIELDS = {"game_seconds", "t50_s", "t90_s", "t99_s", "distance", "turning_degrees", "in_place_s",
                 "turns_per_minute", *TIMED_COLUMNS}  # fmt: skip
#: Text fields that are never ``None`` (an empty ``error`` is no error, not a missing one).
_ALWAYS_TEXT = _TEXT_FIELDS - {"start_heading"}
_FIELD_TYPES = {name: str if name in _TEXT_FIELDS else float if name in _FLOAT_FIELDS else int for name in CSV_COLUMNS}
_DECIMALS = {"seconds": 6, "plan_us_per_step": 3}


def _field(name: str, value: object) -> str:
    if value is None:
        return ""
    if name in _DECIMALS:
        return f"{value:.{_DECIMALS[name]}f}"
    return str(value)


def scene_of(level: Level, line_of_sight: str = "pymunk") -> Scene:
    """The level's scene, built once per worker thread and shared by all the episodes it runs there.

    One per thread, not per process, because an episode moves the guard's body in the scene's pymunk
    space: a Dask worker with several threads must not run two episodes in one space. When the bounds
    or a look-ahead planner need the view table (what every state sees,
    :func:`guardsim.vision.table.view_table`), :func:`run_spec` builds it before its clock starts, so
    that no episode pays for the level's vision while another finds it cached.
    """
    return _scene_of_thread(level, line_of_sight, threading.get_ident())


def forget_scenes() -> None:
    """Drop this process's cached scenes and bounds (for timing a cold start, or to free memory)."""
    _scene_of_thread.cache_clear()
    _bounds_of_thread.cache_clear()


@functools.lru_cache(maxsize=16)
def _scene_of_thread(level: Level, line_of_sight: str, _thread: int) -> Scene:
    return Scene.from_level(level, line_of_sight=line_of_sight)


def bounds_of(level: Level, line_of_sight: str, start: tuple[int, int], heading: int) -> Bounds:
    """:func:`guardsim.bounds.lower_bounds` of one start state, computed once per worker thread.

    The planners of a batch share their episodes' starts, so each start's bounds serve every planner.
    """
    return _bounds_of_thread(level, line_of_sight, start, heading, threading.get_ident())


@functools.lru_cache(maxsize=4096)
def _bounds_of_thread(level: Level, line_of_sight: str, start: tuple[int, int], heading: int, thread: int) -> Bounds:
    scene = _scene_of_thread(level, line_of_sight, thread)
    return lower_bounds(scene, start, heading, scene.vision())


def wants_bounds(spec: EpisodeSpec) -> bool:
    """Whether the episode's row gets its start's lower bounds: asked for, one guard, on the grid (bounds
    count grid steps; a continuous episode's steps are physics ticks)."""
    return spec.bounds and spec.guards == 1 and spec.motion == "grid"


def error_text(error: Exception) -> str:
    """``Type: message`` on one line, as the ``error`` column holds it."""
    return " ".join(f"{type(error).__name__}: {error}".split())


def error_record(spec: EpisodeSpec, message: str, seconds: float) -> EpisodeRecord:
    """The row of an episode that raised after ``seconds``: ``error`` outcome, ``message`` (from
    :func:`error_text`), and none of the fields it did not reach."""
    return EpisodeRecord(
        spec.level.name, spec.level_file, spec.planner, spec.guards, spec.seed, spec.episode,
        None, None, None, None, None, "error", None, None, None, None, None, None, None,
        seconds, None, message, spec.motion,
    )  # fmt: skip


def run_spec(spec: EpisodeSpec) -> EpisodeRecord:
    """Run one episode and record it; an exception from the episode becomes its ``error`` outcome.

    See :func:`run_spec_logged`, which also returns the traceback of such an exception.
    """
    return run_spec_logged(spec)[0]


def run_spec_logged(spec: EpisodeSpec) -> tuple[EpisodeRecord, str]:
    """Run one episode and record it, with the full traceback of an exception from the episode (which
    becomes its ``error`` outcome), or ``""``. The traceback is text, so it travels from any worker.

    Only the episode is timed: not the scene (built once per worker), nor the bounds (computed once per
    start, for one guard only: they do not bound a team's makespan). Only ``Exception`` is caught:
    Ctrl-C and the like still stop the run.
    """
    began = time.perf_counter()
    try:
        scene = scene_of(spec.level, spec.line_of_sight)
        if spec.bounds or spec.planner in LOOK_AHEAD:
            view_table(scene.grid, scene.vision())  # built once per scene, before the clock starts
        began = time.perf_counter()
        if spec.motion == "continuous":
            walk = GuardMotion.of_guard(spec.level.guard, move_speed=spec.move_speed, turn_speed=spec.turn_speed,
                                        tick_hz=spec.tick_hz)  # fmt: skip
            trace = run_episode(scene, spec.planner, seed=spec.seed, episode=spec.episode, motion=walk or "continuous", max_seconds=spec.max_seconds, max_steps=spec.max_steps, reference=spec.reference)  # fmt: skip
        else:
            trace = run_episode(
                scene,
                seed=spec.seed,
                episode=spec.episode,
                planner=spec.planner,
                guards=spec.guards,
                reference=spec.reference,
                max_steps=spec.max_steps,
            )
        seconds = time.perf_counter() - began
        col, row = trace.start
        wanted = wants_bounds(spec)
        bounds = bounds_of(spec.level, spec.line_of_sight, (col, row), trace.headings[0]) if wanted else None
    except Exception as error:
        return error_record(spec, error_text(error), time.perf_counter() - began), traceback.format_exc()
    t50, t90, t99 = (trace.steps_to_fraction(fraction) for fraction in FRACTIONS)
    return EpisodeRecord(
        spec.level.name, spec.level_file, spec.planner, spec.guards, spec.seed, spec.episode,
        col, row, HEADING_NAMES[trace.headings[0]], trace.steps, trace.total_moves, trace.outcome,
        t50, t90, t99, trace.reachable,
        bounds.best if bounds else None, bounds.eccentricity if bounds else None, bounds.cluster if bounds else None,
        seconds, 1e6 * seconds / trace.steps if trace.steps else None, "", **record_columns(trace),
    ), ""  # fmt: skip
