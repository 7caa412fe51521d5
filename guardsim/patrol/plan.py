"""Making and scoring a patrol of a level by strategy name: what ``guardsim patrol`` runs.

The goal is the cells reachable from the episode start (as in ``guardsim play``). The loop strategy's
lap sets the time scale of the others: a walked strategy runs ``warmup_laps + laps`` laps and is scored
on the last ``laps`` (a loop is scored exactly, over its lap in steady state).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

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
    "DEFAULT_WARMUP_LAPS",
    "LARGE_GOAL",
    "PatrolPlan",
    "PatrolSetup",
    "Progress",
    "auto_sources",
    "is_large",
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


def patrol_setup(scene: Scene, guards: int = 1, *, seed: int = 0) -> PatrolSetup:
    """The view table, goal and starts of a level's patrols."""
    if guards < 1:
        raise ValueError("a patrol needs at least one guard")
    rng, cell, heading = episode_start(scene, seed=seed)
    starts, headings = team_starts(scene, (cell, heading), guards, rng=rng)
    table = view_table(scene.grid, scene.vision())
    goal = scene.grid.component(*cell).ravel()
    return PatrolSetup(scene, table, goal, starts, headings, seed)


#: Where ``auto`` takes a loop's viewpoints from; the loop with the lowest worst idleness wins.
AUTO_SOURCES = ("cover", "tour", "frontier")
#: Goal cells above which a level is large. There the tour planner's full search (every seed, then
#: polishing) grows too fast (10 s of a 128 x 128 maze's 12 s patrol, minutes on a 256 x 256 city), so
#: ``auto`` takes :data:`LARGE_SOURCES`, and the viewpoints of a loop are cut to an irredundant cover of the
#: goal before they are ordered (:attr:`~guardsim.patrol.loops.LoopBuilder.thin`), which keeps ordering
#: small and makes the frontier walk's loop about as short as the full tour's. The shipped levels are far
#: below it, and are patrolled as before.
LARGE_GOAL = 10_000
LARGE_SOURCES = ("cover", "frontier")

#: ``progress(what, done, total)``: a stage of a long job, ``done`` of ``total`` of its steps.
Progress = Callable[[str, int, int], None]


def is_large(setup: PatrolSetup) -> bool:
    """Whether the level has more than :data:`LARGE_GOAL` goal cells."""
    return int(setup.goal.sum()) > LARGE_GOAL


def auto_sources(setup: PatrolSetup) -> tuple[str, ...]:
    """The sources ``auto`` tries on this level: :data:`AUTO_SOURCES`, or :data:`LARGE_SOURCES` on a large one."""
    return LARGE_SOURCES if is_large(setup) else AUTO_SOURCES


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
        plans = []
        for number, source in enumerate(sources):
            if progress is not None:
                progress(f"loop from {source} viewpoints", number, len(sources))
            plans.append(plan_loop(setup, guards, planner=source, progress=progress))
        return min(plans, key=lambda plan: score_rank(plan[0].score))
    builder = LoopBuilder(setup.scene.grid, setup.table, setup.goal, thin=is_large(setup))
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
    patrol, scores = team_loops(builder, viewpoints, guards, planner=planner)
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
        raise ValueError(f"unknown strategy {strategy!r}; known: {', '.join(STRATEGIES)}")
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
