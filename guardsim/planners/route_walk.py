"""Walking viewpoint routes ahead of time: the whole team's episode, simulated with the level's view table.

The rule and the compiled walk are :mod:`guardsim.kernels.walk`; this module prepares its arrays.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.distances import FAR
from guardsim.kernels.walk import WalkLog, WalkTeam, descent, team_walk
from guardsim.vision.table import ViewTable

__all__ = ["RouteWalk", "descent_states", "walk_routes"]


class RouteWalk(NamedTuple):
    """A simulated team walk."""

    moves: np.ndarray
    """``int64 (guards, ticks)``: each guard's move per tick (a heading number, or -1 to stay)."""
    cells: np.ndarray
    """``int64 (guards, ticks + 1)``: each guard's cell per tick, the start included."""
    headings: np.ndarray
    """``int64 (guards, ticks + 1)``: each guard's heading per tick."""
    covered: bool
    """Whether every goal cell was seen before the limit."""
    visits: list[np.ndarray]
    """Per guard, the states it arrived in as its target (route viewpoints or frontier states), in order."""

    @property
    def steps(self) -> int:
        """Ticks until covered (the team's makespan)."""
        return int(self.moves.shape[1])

    @property
    def total_moves(self) -> int:
        """Moves made, summed over the guards."""
        return int((self.moves >= 0).sum())


def walk_routes(
    table: ViewTable,
    neighbours: np.ndarray,
    goal: np.ndarray,
    seen: np.ndarray,
    team: tuple[tuple[int, int], ...],
    routes: list[np.ndarray],
    *,
    limit: int,
) -> RouteWalk:
    """Simulate the team walking ``routes`` from ``team`` until every goal cell is seen or ``limit`` ticks.

    Parameters
    ----------
    table
        The level's view table (the loop's vision, state by state).
    neighbours
        The grid's connected neighbours.
    goal, seen
        ``bool (cells,)``: cells to see, and cells seen so far (the looks at the start included).
    team
        ``(cell, heading)`` of every guard at the start of the walk.
    routes
        Per guard, the state numbers of its viewpoints in order.
    limit
        Most ticks to simulate.
    """
    guards = len(team)
    longest = max((route.size for route in routes), default=0)
    padded = np.full((guards, max(longest, 1)), -1, dtype=np.int64)
    for guard, route in enumerate(routes):
        padded[guard, : route.size] = route
    moves = np.full((guards, limit), -1, dtype=np.int64)
    path = np.zeros((guards, limit + 1), dtype=np.int64)
    facing = np.zeros((guards, limit + 1), dtype=np.int64)
    visits = np.zeros((guards, limit), dtype=np.int64)
    visit_count = np.zeros(guards, dtype=np.int64)
    seen = seen.copy()
    ticks = team_walk(
        np.ascontiguousarray(neighbours, dtype=np.int64),
        table,
        np.ascontiguousarray(goal, dtype=np.bool_),
        seen,
        WalkTeam(
            np.array([cell for cell, _ in team], dtype=np.int64),
            np.array([heading for _, heading in team], dtype=np.int64),
            padded,
            np.array([route.size for route in routes], dtype=np.int64),
        ),
        limit,
        int(FAR),
        WalkLog(moves, path, facing, visits, visit_count, np.full_like(padded, -1)),
    )
    return RouteWalk(
        moves[:, :ticks],
        path[:, : ticks + 1],
        facing[:, : ticks + 1],
        bool((seen | ~goal).all()),
        [visits[guard, : visit_count[guard]].copy() for guard in range(guards)],
    )


def descent_states(
    table: ViewTable,
    neighbours: np.ndarray,
    goal: np.ndarray,
    seen: np.ndarray,
    cell: int,
    heading: int,
    *,
    limit: int,
    by_view: bool = False,
) -> np.ndarray:
    """The states of a walk that steps, every tick, down the distance to the nearest unseen goal cell
    (ties: keep the heading, then right, down, left, up, as ``ripplefront-exact`` does; with
    ``by_view``, first the step whose arrival state sees the most unseen goal cells); as a route, the
    tour planner's walk skips those of them that see nothing new by then."""
    return descent(
        np.ascontiguousarray(neighbours, dtype=np.int64),
        table.sight_start,
        table.sight,
        np.ascontiguousarray(goal, dtype=np.bool_),
        seen.copy(),
        cell,
        heading,
        limit,
        int(FAR),
        by_view,
    )
