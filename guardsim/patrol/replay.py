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
    unseen_percent = tuple(round(100.0 * (goal_count - int(count)) / max(goal_count, 1), 4) for count in seen_so_far)
    cols = grid.shape[1]
    paths = [tuple(zip((cell_of_state(row) % cols).tolist(), (cell_of_state(row) // cols).tolist())) for row in states]
    headings = [tuple(heading_of_state(row).tolist()) for row in states]
    single = patrol.guards == 1
    level = scene.level
    covered = bool(np.all(np.asarray(seen_any)[goal]))
    return Trace(
        level=level.name,
        planner=label or f"patrol: {patrol.strategy}",
        seed=None,
        cell_size=grid.cell_size,
        origin=grid.origin,
        shape=grid.shape,
        path=paths[0],
        headings=headings[0],
        unseen_percent=unseen_percent,
        outcome="covered" if covered else "step_limit",
        reachable=goal_count,
        unreachable=int(grid.traversable.sum()) - goal_count,
        first_seen=np.where(goal, first_seen, -1).reshape(grid.shape),
        goal=goal.reshape(grid.shape).copy(),
        traversable=grid.traversable.copy(),
        guard_paths=() if single else tuple(paths),
        guard_headings=() if single else tuple(headings),
        guard_radius=level.guard.radius,
        view_range=scene.cone.view_range,
        fov_degrees=scene.cone.fov_degrees,
        line_of_sight=scene.line_of_sight.value,
    )
