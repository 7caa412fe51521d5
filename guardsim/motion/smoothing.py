"""A grid route pulled taut into straight segments the guard's circle can walk.

The planners answer on the grid: a route of 4-neighbour steps. Walked as it is, a diagonal is a
staircase. :func:`pull_route` replaces runs of route cells by one straight segment from the first to
the last when three things hold: the guard's circle slides along it without overlapping a wall
(:meth:`guardsim.world.World.sweep_clear`), every skipped cell centre lies within one cell of it, and the
skipped cells follow each other along it (their projections on it increase). The last two keep the walk
faithful to the route: a detour into a dead end and back, or a lane of a sweep, is kept, not cut off,
since the planner went there to look.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.world import World

__all__ = ["Waypoints", "pull_route"]


class Waypoints(NamedTuple):
    """A route pulled taut: the corners to walk through, in order."""

    points: np.ndarray
    """``float64 (n, 2)``: world positions of the corners (cell centres), the start first."""
    ticks: np.ndarray
    """``int64 (n,)``: the route tick at which the planner's guard first stood in each corner's cell."""


def pull_route(world: World, grid: CoverageGrid, cells: Sequence[int], radius: float) -> Waypoints:
    """The corners of route ``cells`` (flat indices, one per tick) pulled taut for a circle of ``radius``.

    Consecutive repeats (a planner that stays) are merged; the first corner is the first cell.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> from guardsim.grid import build_grid
    >>> level = parse_level({"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]})
    >>> world = World(level)
    >>> grid = build_grid(level, world)
    >>> route = [grid.flat(c, r) for c, r in [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (3, 2), (3, 3)]]
    >>> pull_route(world, grid, route, 0.3).points.tolist()
    [[0.5, 0.5], [3.5, 3.5]]
    """
    cols = grid.shape[1]
    route = np.asarray(cells, dtype=np.int64)
    if route.size == 0:
        return Waypoints(np.zeros((0, 2)), np.zeros(0, dtype=np.int64))
    keep = np.ones(route.size, dtype=bool)
    keep[1:] = route[1:] != route[:-1]
    ticks = np.flatnonzero(keep)
    route = route[keep]
    centres = np.stack(
        [
            grid.origin[0] + (route % cols + 0.5) * grid.cell_size,
            grid.origin[1] + (route // cols + 0.5) * grid.cell_size,
        ],
        axis=1,
    )
    corners = [0]
    anchor = 0
    last = len(route) - 1
    while anchor < last:
        reach = anchor + 1
        while reach < last and _taut(world, centres, anchor, reach + 1, radius, grid.cell_size):
            reach += 1
        corners.append(reach)
        anchor = reach
    chosen = np.asarray(corners, dtype=np.int64)
    return Waypoints(np.ascontiguousarray(centres[chosen]), ticks[chosen])


def _taut(world: World, centres: np.ndarray, anchor: int, end: int, radius: float, cell_size: float) -> bool:
    """Whether the straight segment from corner ``anchor`` to route cell ``end`` may replace the cells between."""
    start, stop = centres[anchor], centres[end]
    direction = stop - start
    length = float(np.hypot(*direction))
    if length == 0:
        return False
    unit = direction / length
    between = centres[anchor : end + 1] - start
    along = between @ unit
    across = np.abs(between[:, 0] * unit[1] - between[:, 1] * unit[0])
    if np.any(np.diff(along) <= 0) or np.any(across[1:-1] > cell_size * (1 + 1e-9)):
        return False
    return world.sweep_clear((float(start[0]), float(start[1])), (float(stop[0]), float(stop[1])), radius)
