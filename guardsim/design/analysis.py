"""One analysis of a level under a patrol, shared by ``report``, ``diff`` and ``watch``.

:func:`analyse` builds the scene and its view table, reads or plans the patrol, scores its idleness,
applies the detection model (exposure, time to detection) and runs the sneak check for each entry-goal
pair. Given the analysis of an earlier version of the level (``reuse``), it keeps what the edit left
valid: the scene and view table when the walls, the grid and the guards' sight did not change (else the
view table of every state out of reach of the edit, :mod:`guardsim.design.reuse`); the planned patrol
when, in addition, the guards' start and team did not, and with it the exposure of a lap counted in
slices; and each sneak check's backward sweep when the grid, the seen lap ticks and the goal are equal
(:class:`~guardsim.sneak.SneakMemo`). Each gives what a fresh analysis gives.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple

import numpy as np

from guardsim.design.reuse import reused_view_table
from guardsim.detection import GuardDetection, PatrolGains, exposure_map, patrol_gains
from guardsim.detection.exposure import MAX_DENSE_NODES
from guardsim.errors import LimitError
from guardsim.kernels.distances import FAR, distances_from
from guardsim.level import Level
from guardsim.patrol import Patrol, PatrolScore, PatrolSetup, plan_loop, read_patrol, score_patrol, seen_timeline
from guardsim.scene import Scene
from guardsim.sneak import SneakMemo, SneakResult, sneak_check
from guardsim.starts import episode_start, team_starts
from guardsim.vision.table import ViewTable, view_table

__all__ = ["Analysis", "PairResult", "analyse", "default_pairs", "geometry_key", "outcome_of"]

Point = tuple[float, float]

#: The sneak outcomes, hardest last: an unseen path exists; only an undetected one (seen briefly, no meter
#: fills); none (the closest call is detected); the goal cannot be reached at all; the search was over a
#: size limit (:data:`guardsim.sneak.MAX_SNEAK_NODES`), so the pair was not checked.
OUTCOMES = ("unseen", "undetected", "detected", "unreachable", "unchecked")


class PairResult(NamedTuple):
    """The sneak check of one entry-goal pair."""

    source: Point
    target: Point
    source_cell: int | None
    """Flat cell of the entry; ``None`` when the point is outside the floor of this version."""
    target_cell: int | None
    sneak: SneakResult | None
    """The undetected sneak check (:func:`guardsim.sneak.sneak_check`); ``None`` when unreachable."""
    note: str = ""
    """Why the pair could not be checked, for a designer."""
    checked: bool = True
    """False when the search was over a size limit (the note says which)."""

    @property
    def outcome(self) -> str:
        """One of :data:`OUTCOMES`."""
        return outcome_of(self.sneak) if self.checked else "unchecked"


def outcome_of(result: SneakResult | None) -> str:
    """The outcome of an undetected sneak check (see :data:`OUTCOMES`)."""
    if result is None or result.path is None:
        return "unreachable"
    if not result.found:
        return "detected"
    return "unseen" if result.path.ticks_in_view == 0 else "undetected"


class Analysis(NamedTuple):
    """A level under a patrol: everything ``report``, ``diff`` and ``watch`` read."""

    level: Level
    scene: Scene
    table: ViewTable
    patrol: Patrol
    patrol_source: str
    """Where the patrol came from: the file read, or ``loop of K guard(s)``."""
    goal: np.ndarray
    """``bool (cells,)``: the floor the guards patrol (reachable from the guard's start)."""
    idleness: PatrolScore
    detection: GuardDetection
    gains: PatrolGains | None
    """The detection model applied to the lap; ``None`` when the lap times the cells is over
    :data:`guardsim.detection.exposure.MAX_DENSE_NODES` (the report then counts no distinct ways)."""
    exposure: np.ndarray
    """``float64 (cells,)``: fraction of the lap each cell is in some guard's view."""
    pairs: tuple[PairResult, ...]
    seconds: float
    """Wall time of this analysis."""
    reused: tuple[str, ...] = ()
    """What was taken from the earlier analysis (``scene``, ``sight away from the edit``, ``patrol``,
    ``exposure``, ``unseen reach``)."""
    memo: SneakMemo | None = None
    """The sneak checks' backward sweeps, for the next analysis to reuse (:class:`~guardsim.sneak.SneakMemo`)."""
    seed: int = 0
    """The seed the patrol was planned with."""

    @property
    def safe(self) -> np.ndarray:
        """``bool (cells,)``: floor cells no guard sees during the lap (safe spots, as ``check --safe``)."""
        return self.goal & (self.exposure == 0)


def geometry_key(level: Level) -> tuple[object, ...]:
    """What the scene and view table depend on: walls, cells, the guard's size and sight."""
    guard = level.guard
    return (level.outer, level.holes, level.cell_size, guard.radius, guard.view_range, guard.fov_degrees)


def _patrol_key(level: Level, guards: int, planner: str) -> tuple[object, ...]:
    return (*geometry_key(level), level.guard.start, level.guard.heading, level.starts, guards, planner)


def default_pairs(scene: Scene, goal: np.ndarray) -> tuple[tuple[Point, Point], ...]:
    """Entry-goal pairs when none is given: from each player start of the level to the floor cell farthest
    from it on foot; without player starts, across the patrolled floor: from the floor cell farthest on
    foot from its first cell (in row order) to the floor cell farthest from that one.

    >>> from guardsim.level import parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [5, 0], [5, 1], [0, 1]], "guard": {"start": [2.5, 0.5]}}))
    >>> default_pairs(scene, scene.grid.component(2, 0).ravel())
    (((4.5, 0.5), (0.5, 0.5)),)
    """
    grid = scene.grid
    neighbours = grid.neighbours

    def farthest(cell: int) -> int:
        distance = distances_from(neighbours, np.array([cell]))
        distance = np.where(goal & (distance < FAR), distance, -1)
        # Ties go to the lowest flat index, so the pair is fixed.
        return int(np.argmax(distance))

    def point(cell: int) -> Point:
        return grid.centre(*grid.unflat(cell))

    pairs = []
    for start in scene.level.player_starts:
        found = grid.cell_of(start)
        if found is not None and grid.traversable[found[1], found[0]]:
            pairs.append((tuple(start), point(farthest(grid.flat(*found)))))
    if pairs:
        return tuple(pairs)  # type: ignore[arg-type]
    cells = np.flatnonzero(goal)
    if cells.size == 0:
        return ()
    first = farthest(int(cells[0]))
    return ((point(first), point(farthest(first))),)


def _cell(scene: Scene, point: Point) -> int | None:
    grid = scene.grid
    found = grid.cell_of(point)
    if found is None or not grid.traversable[found[1], found[0]]:
        return None
    return grid.flat(*found)


def _pair(
    scene: Scene,
    table: ViewTable,
    patrol: Patrol,
    detection: GuardDetection,
    source: Point,
    target: Point,
    memo: SneakMemo | None = None,
) -> PairResult:
    start, goal = _cell(scene, source), _cell(scene, target)
    where = f"{source[0]:g},{source[1]:g} -> {target[0]:g},{target[1]:g}"
    if start is None or goal is None:
        which = "entry" if start is None else "goal"
        return PairResult(source, target, start, goal, None, f"{where}: the {which} is not floor a player fits on")
    labels = scene.grid.component_labels
    if labels[start] != labels[goal]:
        return PairResult(source, target, start, goal, None, f"{where}: the goal cannot be reached from the entry")
    try:
        result = sneak_check(scene.grid, table, patrol, start, goal, detection=detection, undetected=True, memo=memo)
    except LimitError as error:
        return PairResult(source, target, start, goal, None, f"{where}: not checked: {error}", checked=False)
    return PairResult(source, target, start, goal, result)


def analyse(
    level: Level,
    *,
    patrol: Patrol | str | None = None,
    guards: int = 1,
    pairs: Sequence[tuple[Point, Point]] | None = None,
    planner: str = "auto",
    seed: int = 0,
    reuse: Analysis | None = None,
    progress: Callable[[str], None] | None = None,
) -> Analysis:
    """Analyse ``level`` under ``patrol`` (a :class:`~guardsim.patrol.Patrol`, or a patrol.json path),
    else under the loop patrol of ``guards`` guards (:func:`guardsim.patrol.plan_loop` with ``planner``).

    ``pairs``: entry-goal points (world units) to run the undetected sneak check on; ``None`` takes
    :func:`default_pairs`. ``reuse``: an earlier analysis whose scene, view table and planned patrol are
    kept where the edit left them valid. ``progress`` receives a line before each long step.

    Raises
    ------
    PatrolError
        When the patrol does not fit the level, does not repeat, or is not a grid patrol.
    """
    began = time.perf_counter()
    tell = progress or (lambda line: None)
    reused: list[str] = []
    if reuse is not None and geometry_key(reuse.level) == geometry_key(level):
        scene = reuse.scene if reuse.scene.level is level else dataclasses.replace(reuse.scene, level=level)
        table = reuse.table
        reused.append("scene")
    else:
        tell("building the scene and its view table")
        scene = Scene.from_level(level)
        kept = None if reuse is None else reused_view_table(reuse.scene, reuse.table, scene)
        if kept is not None:
            table = kept
            reused.append("sight away from the edit")
        else:
            table = view_table(scene.grid, scene.vision())
    rng, cell, heading = episode_start(scene, seed=seed)
    goal = scene.grid.component(*cell).ravel()
    if isinstance(patrol, Patrol):
        chosen, source = patrol, "the patrol given"
    elif isinstance(patrol, str):
        chosen, source = read_patrol(patrol, scene.grid, level=level.name), patrol
    elif (
        reuse is not None
        and reuse.patrol_source == _loop_name(guards, planner)
        and reuse.seed == seed
        and _patrol_key(reuse.level, guards, planner) == _patrol_key(level, guards, planner)
    ):
        chosen, source = reuse.patrol, reuse.patrol_source
        reused.append("patrol")
    else:
        tell(f"planning the loop patrol of {guards} guard(s)")
        starts, headings = team_starts(scene, (cell, heading), guards, rng=rng)
        setup = PatrolSetup(scene, table, goal, starts, headings, seed)
        chosen, source = plan_loop(setup, guards, planner=planner)[0].patrol, _loop_name(guards, planner)
    period = chosen.require_repeating_grid(source, "the analysis")
    idleness = score_patrol(table, chosen, goal)
    detection = GuardDetection.of_level(level)
    grid = scene.grid
    if period * grid.size <= MAX_DENSE_NODES:
        found = patrol_gains(
            grid, table, chosen.states, detection.model, view_range=detection.view_range, dt=detection.dt
        )
        gains: PatrolGains | None = found
        exposure = exposure_map(found)
    elif "scene" in reused and "patrol" in reused and reuse is not None and reuse.gains is None:
        # The same view table and lap: the same share of it each cell is in view.
        gains, exposure = None, reuse.exposure
        reused.append("exposure")
    else:
        gains, exposure = None, None  # counted below
    asked = default_pairs(scene, goal) if pairs is None else tuple(pairs)
    memo = SneakMemo(None if reuse is None else reuse.memo)
    results = []
    with ThreadPoolExecutor(max_workers=1) as pool:
        # A lap too long to hold as one (ticks, cells) array: the exposure is counted a slice of it at a
        # time, beside the sneak checks (a core their sweeps leave free part of the time).
        counting = pool.submit(_exposure, table, chosen, grid.size) if exposure is None else None
        for source_point, target_point in asked:
            tell(f"sneak check {source_point[0]:g},{source_point[1]:g} -> {target_point[0]:g},{target_point[1]:g}")
            results.append(_pair(scene, table, chosen, detection, source_point, target_point, memo))
        exposure = exposure if counting is None else counting.result()
    assert exposure is not None
    memo.forget_earlier()
    if memo.hits:
        reused.append("unseen reach")
    return Analysis(
        level,
        scene,
        table,
        chosen,
        source,
        goal,
        idleness,
        detection,
        gains,
        exposure,
        tuple(results),
        time.perf_counter() - began,
        tuple(reused),
        memo,
        seed,
    )


#: Lap ticks per slice when the exposure of a long lap is counted.
EXPOSURE_SLICE = 256


def _exposure(table: ViewTable, patrol: Patrol, cells: int) -> np.ndarray:
    """``float64 (cells,)``: the share of the lap each cell is in some guard's view."""
    counts = np.zeros(cells, dtype=np.int64)
    for begin in range(0, patrol.ticks, EXPOSURE_SLICE):
        counts += seen_timeline(table, patrol.states[:, begin : begin + EXPOSURE_SLICE], cells).sum(axis=0)
    return counts / patrol.ticks


def _loop_name(guards: int, planner: str) -> str:
    return f"loop of {guards} guard(s)" + ("" if planner == "auto" else f" ({planner})")
