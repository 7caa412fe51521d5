"""Making and scoring a patrol of a level by strategy name: what ``guardsim patrol`` runs.

The goal is the cells reachable from the episode start (as in ``guardsim play``). The loop strategy's
lap sets the time scale of the others: a walked strategy runs ``warmup_laps + laps`` laps and is scored
on the last ``laps`` (a loop is scored exactly, over its lap in steady state).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from guardsim.errors import LimitError, PatrolError
from guardsim.grid import state_of
from guardsim.patrol.loops import LoopBuilder, team_loops
from guardsim.patrol.model import STRATEGIES, Patrol
from guardsim.patrol.scoring import PatrolScore, score_patrol, score_rank
from guardsim.patrol.strategies import run_strategy
from guardsim.scene import Scene
from guardsim.starts import episode_start, team_starts
from guardsim.vision.table import ViewTable, view_table

__all__ = [
    "DEFAULT_LAPS",
    "DEFAULT_PATROL_MEMORY",
    "DEFAULT_WARMUP_LAPS",
    "HUGE_CELLS",
    "LARGE_CELLS",
    "PatrolPlan",
    "PatrolSetup",
    "Progress",
    "auto_sources",
    "check_patrol_memory",
    "is_large",
    "patrol_memory",
    "patrol_setup",
    "plan_loop",
    "plan_patrol",
]

#: Laps a walked strategy is scored over, and laps of warm-up before them.
DEFAULT_LAPS = 10
DEFAULT_WARMUP_LAPS = 2
#: Fewest ticks a walked strategy is scored over (a post's lap is one tick).
MIN_SCORED_TICKS = 200


class PatrolSetup(NamedTuple):
    """What every strategy on a level shares."""

    scene: Scene
    table: ViewTable
    goal: np.ndarray
    """``bool (cells,)``: the cells to watch, reachable from the start."""
    starts: list[tuple[int, int]]
    """Start cell of each guard of a walked strategy (the first is ``play``'s start)."""
    headings: list[int]
    seed: int


class PatrolPlan(NamedTuple):
    """A patrol and its score."""

    patrol: Patrol
    score: PatrolScore
    warmup: int
    """Ticks walked before scoring (0 for a repeating patrol)."""


#: The memory a patrol may use, by default: ``guardsim patrol --memory-mb`` changes it.
DEFAULT_PATROL_MEMORY = 2 * 2**30
#: What a patrol holds besides its view table: the interpreter, numpy, the compiled kernels, the plot
#: library (measured: 270 MB on a 64 x 64 map).
PATROL_BASE_BYTES = 300 * 2**20
#: Bytes a patrol holds per (state, cell seen) pair of the view table: the table and its inverse, the
#: vision cache behind them, and the loops, legs, orderings and scores, which grow with the level like
#: the table (measured peaks: 28 bytes a pair on Berlin_1_256, 34 on AR0603SR and 55 on duskwood with 4
#: guards, whose long open views need many viewpoints and so a large ordering).
PATROL_BYTES_PER_ENTRY = 56


def patrol_memory(scene: Scene) -> int:
    """About how many bytes a loop patrol of ``scene`` needs at its peak (from the view table's size,
    estimated before it is built: :func:`guardsim.vision.table.estimate_entries`)."""
    from guardsim.vision.table import estimate_entries

    return PATROL_BASE_BYTES + PATROL_BYTES_PER_ENTRY * estimate_entries(scene.grid, scene.vision())


def check_patrol_memory(scene: Scene, memory_bytes: int = DEFAULT_PATROL_MEMORY) -> None:
    """Refuse, before any work, a level whose patrol would need more than ``memory_bytes``.

    Raises :class:`~guardsim.errors.LimitError` naming the budget (``memory_mb``) and what it would need.
    """
    needed = patrol_memory(scene)
    if needed > memory_bytes:
        rows, cols = scene.grid.shape
        raise LimitError(
            f"a patrol of this {rows} x {cols} grid would need about {-(-needed // 2**20)} MB, over the budget of "
            f"{memory_bytes // 2**20} MB (memory_mb)"
        )


def patrol_setup(
    scene: Scene, guards: int = 1, *, seed: int = 0, start: tuple[float, float] | None = None
) -> PatrolSetup:
    """The view table, goal and starts of a level's patrols: the first guard starts at ``start`` (world
    units), else at the level's ``guard.start``, else at a cell drawn from ``seed``, as in ``guardsim
    play`` (:func:`~guardsim.starts.episode_start`); the goal is the cells reachable from there."""
    if guards < 1:
        raise PatrolError("a patrol needs at least one guard")
    rng, cell, heading = episode_start(scene, seed=seed, point=start)
    starts, headings = team_starts(scene, (cell, heading), guards, rng=rng)
    table = view_table(scene.grid, scene.vision())
    goal = scene.grid.component(*cell).ravel()
    return PatrolSetup(scene, table, goal, starts, headings, seed)


#: Where ``auto`` takes a loop's viewpoints from; the loop with the lowest worst idleness wins.
AUTO_SOURCES = ("cover", "tour", "frontier")
#: Grid cells above which a level is large (the shipped levels are 60 x 60). There the tour planner's
#: full search (every seed, then polishing) grows too fast (10 s of a 128 x 128 maze's 12 s patrol,
#: minutes on a 256 x 256 city), so ``auto`` takes :data:`LARGE_SOURCES`, and the viewpoints of a loop are
#: cut to an irredundant cover of the goal before they are ordered
#: (:attr:`~guardsim.patrol.loops.LoopBuilder.thin`), which keeps ordering small and makes the frontier
#: walk's loop about as short as the full tour's (docs/performance.md has the figures).
LARGE_CELLS = 60 * 60
LARGE_SOURCES = ("cover", "frontier")
#: Grid cells above which a level is huge (a 512 x 512 game map): there the frontier walk alone took
#: over half of a 4-guard patrol, so ``auto`` builds the set cover's loop only.
HUGE_CELLS = 300 * 300
HUGE_SOURCES = ("cover",)

#: ``progress(what, done, total)``: a stage of a long job, ``done`` of ``total`` of its steps.
Progress = Callable[[str, int, int], None]


def is_large(setup: PatrolSetup) -> bool:
    """Whether the level's grid has more than :data:`LARGE_CELLS` cells."""
    return int(setup.scene.grid.size) > LARGE_CELLS


def auto_sources(setup: PatrolSetup) -> tuple[str, ...]:
    """The sources ``auto`` tries on this level: :data:`AUTO_SOURCES`, :data:`LARGE_SOURCES` on a large
    one, :data:`HUGE_SOURCES` above :data:`HUGE_CELLS` grid cells."""
    cells = int(setup.scene.grid.size)
    return HUGE_SOURCES if cells > HUGE_CELLS else LARGE_SOURCES if cells > LARGE_CELLS else AUTO_SOURCES


def plan_loop(
    setup: PatrolSetup, guards: int, *, planner: str = "auto", progress: Progress | None = None
) -> tuple[PatrolPlan, dict[str, PatrolScore]]:
    """The loop patrol: viewpoints from the set cover (``cover``), from a planner's coverage walk (a name
    of :data:`guardsim.planners.PLANNERS`), or the best of :func:`auto_sources` (``auto``).

    Also returns the score of each team strategy tried (``single`` for one guard, else ``shared`` and
    ``split``). ``progress`` hears of each source as it starts.
    """
    if planner == "auto":
        sources = auto_sources(setup)
        large = is_large(setup)
        plans = []
        for number, source in enumerate(sources):
            if progress is not None:
                progress(f"loop from {source} viewpoints", number, len(sources))
            # On a large level a team's loops are made once, from the source whose single loop is best.
            plans.append(plan_loop(setup, 1 if large else guards, planner=source, progress=progress))
        best = min(plans, key=lambda plan: score_rank(plan[0].score))
        if not large or guards == 1:
            return best
        builder = _builder(setup)
        lap = best[0].patrol.states[0]
        if progress is not None:
            progress(f"loops for a team of {guards} from {best[0].patrol.planner} viewpoints", 0, 0)
        return _team_plan(setup, builder, lap, guards, best[0].patrol.planner or "cover", lap)
    builder = _builder(setup)
    if planner == "cover":
        viewpoints = builder.cover_viewpoints()
    else:
        from guardsim.simulation import Simulation

        simulation = Simulation(setup.scene, planner)
        simulation.reset(starts=setup.starts[:1], headings=setup.headings[:1], seed=setup.seed)
        trace = simulation.run()
        grid = setup.scene.grid
        cells = np.array([grid.flat(col, row) for col, row in trace.path], dtype=np.int64)
        viewpoints = builder.walk_viewpoints(state_of(cells, np.asarray(trace.headings, dtype=np.int64)))
    if progress is not None and guards > 1:
        progress(f"loops for a team of {guards} from {planner} viewpoints", 0, 0)
    return _team_plan(setup, builder, viewpoints, guards, planner, None)


def _builder(setup: PatrolSetup) -> LoopBuilder:
    return LoopBuilder(setup.scene.grid, setup.table, setup.goal, thin=is_large(setup))


def _team_plan(
    setup: PatrolSetup, builder: LoopBuilder, viewpoints: np.ndarray, guards: int, planner: str, lap: np.ndarray | None
) -> tuple[PatrolPlan, dict[str, PatrolScore]]:
    patrol, scores = team_loops(builder, viewpoints, guards, planner=planner, lap=lap)
    chosen = scores.get(patrol.team or "single") or score_patrol(setup.table, patrol, setup.goal)
    return PatrolPlan(patrol, chosen, 0), scores


def plan_patrol(
    setup: PatrolSetup,
    strategy: str,
    *,
    planner: str = "auto",
    laps: int = DEFAULT_LAPS,
    warmup_laps: int = DEFAULT_WARMUP_LAPS,
    lap: int | None = None,
) -> PatrolPlan:
    """The patrol of ``strategy`` (one of :data:`~guardsim.patrol.model.STRATEGIES`) and its score.

    ``lap`` is the loop's period, which sets how long walked strategies run; it is computed when not
    given.
    """
    if strategy not in STRATEGIES:
        raise PatrolError(f"unknown strategy {strategy!r}; known: {', '.join(STRATEGIES)}")
    guards = len(setup.starts)
    if strategy == "loop":
        return plan_loop(setup, guards, planner=planner)[0]
    if lap is None:
        lap = int(plan_loop(setup, guards, planner=planner)[0].patrol.ticks)
    scored = max(laps * lap, MIN_SCORED_TICKS)
    warmup = warmup_laps * lap
    patrol = run_strategy(
        setup.scene, setup.table, setup.goal, strategy, setup.starts, setup.headings, warmup + scored, seed=setup.seed
    )
    return PatrolPlan(patrol, score_patrol(setup.table, patrol, setup.goal, warmup=warmup), warmup)
