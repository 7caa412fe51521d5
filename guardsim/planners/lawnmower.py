"""Lawnmower routes: boustrophedon lanes one cone's swath apart, as viewpoint routes for the tour planner.

On open ground a guard whose cone reaches ``w`` cells to each side sees a band ``2 w + 1`` cells wide as
it walks straight ahead; lanes that far apart, walked back and forth (the boustrophedon of coverage
path planning, H. Choset, "Coverage of known spaces: the boustrophedon cellular decomposition",
Autonomous Robots 9, 2000), see an open level with few wasted steps, where viewpoint tours and
frontier walks wander. A route here is the states along the lanes (every :data:`WAYPOINT_GAP` cells,
heading along the lane); the tour planner's walk (:mod:`guardsim.planners.route_walk`) skips those
that see nothing new by then, so obstacles, walls and what the first look saw are taken care of there.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import state_of
from guardsim.vision.table import ViewTable

__all__ = ["WAYPOINT_GAP", "lane_routes", "swath_half_width"]

#: Cells between two states of a lane.
WAYPOINT_GAP = 4


def swath_half_width(table: ViewTable, goal: np.ndarray, cols: int) -> int:
    """How far sideways a guard walking right sees: the largest row offset between a goal cell and a
    cell it sees heading right (the other headings see the same cone turned)."""
    cells = np.flatnonzero(goal)
    states = state_of(cells, np.zeros_like(cells))
    lengths = table.sight_start[states + 1] - table.sight_start[states]
    if lengths.sum() == 0:
        return 0
    index = np.repeat(table.sight_start[states] - np.cumsum(lengths) + lengths, lengths) + np.arange(lengths.sum())
    return int(np.abs(table.sight[index] // cols - np.repeat(cells, lengths) // cols).max())


def _lanes(mask: np.ndarray, spacing: int) -> list[tuple[int, list[np.ndarray]]]:
    """The lanes over the rows of ``mask`` (2-D), evenly spread at most ``spacing`` apart, each row and
    its runs of ``mask`` cells (column numbers, ascending)."""
    rows = np.flatnonzero(mask.any(axis=1))
    if rows.size == 0:
        return []
    low, extent = int(rows[0]), int(rows[-1] - rows[0] + 1)
    count = -(-extent // spacing)
    lanes = []
    for lane in range(count):
        row = low + (2 * lane + 1) * extent // (2 * count)
        columns = np.flatnonzero(mask[row])
        runs = np.split(columns, np.flatnonzero(np.diff(columns) > 1) + 1) if columns.size else []
        lanes.append((row, runs))
    return lanes


def lane_routes(goal: np.ndarray, shape: tuple[int, int], entry: np.ndarray, spacing: int) -> list[np.ndarray]:
    """Eight boustrophedon routes over the goal: rows or columns as lanes, from either end, first lane
    walked either way; each as state numbers (states no step can enter are left out).

    Parameters
    ----------
    goal
        ``bool (rows * cols,)``: the cells to see.
    shape
        ``(rows, cols)`` of the grid.
    entry
        ``int64 (states,)``: the cell a step into each state comes from, -1 for none (the view table's).
    spacing
        Most cells between two lanes (the swath's width).
    """
    rows, cols = shape
    grid = np.asarray(goal, dtype=bool).reshape(rows, cols)
    routes = []
    for vertical in (False, True):
        lanes = _lanes(grid.T if vertical else grid, max(1, spacing))
        for order in (lanes, lanes[::-1]):
            for first_forward in (True, False):
                cells: list[int] = []
                headings: list[int] = []
                forward = first_forward
                for lane, runs in order:
                    heading = (1 if forward else 3) if vertical else (0 if forward else 2)
                    for run in runs if forward else runs[::-1]:
                        along = run if forward else run[::-1]
                        stops = along[::WAYPOINT_GAP].tolist()
                        if stops[-1] != along[-1]:
                            stops.append(int(along[-1]))
                        cells.extend(stop * cols + lane if vertical else lane * cols + stop for stop in stops)
                        headings.extend([heading] * len(stops))
                    forward = not forward
                states = state_of(np.array(cells, dtype=np.int64), np.array(headings, dtype=np.int64))
                routes.append(states[entry[states] >= 0] if states.size else states)
    return routes
