"""A stretch of a patrol as a :class:`~guardsim.trace.Trace`, so the GIF renderer and the viewer draw it.

Coverage in the trace starts afresh at the stretch's first tick: a cell counts as first seen at the tick
of the stretch a guard first sees it, so one lap of a loop ends with every goal cell seen.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import cell_of_state, heading_of_state
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import seen_timeline
from guardsim.scene import Scene
from guardsim.trace import Trace
from guardsim.vision.table import ViewTable

__all__ = ["patrol_trace"]


def patrol_trace(
    scene: Scene,
    table: ViewTable,
    patrol: Patrol,
    goal: np.ndarray,
    *,
    start: int = 0,
    ticks: int | None = None,
    label: str | None = None,
) -> Trace:
    """Ticks ``start .. start + ticks`` of the patrol (one lap and back to its first state by default)."""
    grid = scene.grid
    if ticks is None:
        ticks = patrol.ticks
    states = patrol.unrolled(start + ticks + 1)[:, start:]
    timeline = seen_timeline(table, states, grid.size)
    first_seen = np.full(grid.size, -1, dtype=np.int64)
    seen_any = timeline.any(axis=0)
    first_seen[seen_any] = np.argmax(timeline[:, seen_any], axis=0)
    goal_count = int(goal.sum())
    seen_so_far = np.logical_or.accumulate(timeline & goal[None, :], axis=0).sum(axis=1)
    covered = bool(np.all(np.asarray(seen_any)[goal]))
    return Trace.of_episode(
        scene,
        planner=label or f"patrol: {patrol.strategy}",
        seed=None,
        cells=cell_of_state(states),
        headings=heading_of_state(states),
        unseen=goal_count - seen_so_far,
        outcome="covered" if covered else "step_limit",
        first_seen=np.where(goal, first_seen, -1),
        goal=goal,
    )
