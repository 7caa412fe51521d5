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

import itertools

import numpy as np

from guardsim.grid import state_of
from guardsim.vision.table import ViewTable

__all__ = ["WAYPOINT_GAP", "lane_routes", "spiral_rings", "spiral_routes", "swath_half_width"]

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


def _ring(top: int, bottom: int, left: int, right: int) -> list[tuple[int, int, int]]:
    """``(row, col, heading)`` stops once around a rectangle clockwise (on screen, rows growing
    downward) from its top-left corner; a new side starts a stop past its corner, which the walk
    reaches already facing the side's way."""
    if top == bottom or left == right:
        down = left == right
        first, last = (top, bottom) if down else (left, right)
        ahead = [*range(first, last + 1, WAYPOINT_GAP), last]
        back = [*range(last - WAYPOINT_GAP, first - 1, -WAYPOINT_GAP), first]
        if down:
            return [(row, left, 1) for row in ahead] + [(row, left, 3) for row in back]
        return [(top, col, 0) for col in ahead] + [(top, col, 2) for col in back]
    stops = [(top, col, 0) for col in [*range(left, right, WAYPOINT_GAP), right]]
    stops += [(row, right, 1) for row in [*range(top + WAYPOINT_GAP, bottom, WAYPOINT_GAP), bottom]]
    stops += [(bottom, col, 2) for col in [*range(right - WAYPOINT_GAP, left, -WAYPOINT_GAP), left]]
    stops += [(row, left, 3) for row in range(bottom - WAYPOINT_GAP, top, -WAYPOINT_GAP)]
    return stops


def spiral_rings(goal: np.ndarray, shape: tuple[int, int], spacing: int) -> list[list[tuple[int, int, int]]]:
    """Nested rectangles over the goal's bounding box, a swath apart, the outermost half a swath in from
    its edges, each as :func:`_ring`'s stops, until their swaths leave no middle; where the middle left is
    narrower than a swath, one line (or point) there."""
    rows, cols = shape
    grid = np.asarray(goal, dtype=bool).reshape(rows, cols)
    used_rows, used_cols = np.flatnonzero(grid.any(axis=1)), np.flatnonzero(grid.any(axis=0))
    if used_rows.size == 0:
        return []
    spacing = max(1, spacing)
    rings = []
    for ring in itertools.count():
        inset = spacing // 2 + ring * spacing
        top, bottom = int(used_rows[0]) + inset, int(used_rows[-1]) - inset
        left, right = int(used_cols[0]) + inset, int(used_cols[-1]) - inset
        # Its swaths (half a swath to each side) see the middle too when its sides are this close.
        last = bottom - top <= spacing or right - left <= spacing
        if top > bottom:
            top = bottom = (top + bottom) // 2
        if left > right:
            left = right = (left + right) // 2
        rings.append(_ring(top, bottom, left, right))
        if last:
            return rings
    raise AssertionError("unreachable")


def spiral_routes(
    rings: list[list[tuple[int, int, int]]], cols: int, entry: np.ndarray, start: int
) -> list[np.ndarray]:
    """Four spirals through ``rings`` (:func:`spiral_rings`): outside in or inside out, clockwise or not,
    each ring entered at its stop nearest the guard's cell ``start`` or the previous ring's last stop,
    and walked once around; as state numbers (states no step can enter are left out)."""
    routes = []
    for inward in (True, False):
        for clockwise in (True, False):
            order = rings if inward else rings[::-1]
            row, col = divmod(start, cols)
            cells: list[int] = []
            headings: list[int] = []
            for ring in order:
                stops = ring if clockwise else [(r, c, (h + 2) % 4) for r, c, h in ring[::-1]]
                nearest = min(range(len(stops)), key=lambda i: abs(stops[i][0] - row) + abs(stops[i][1] - col))
                # Once around, and on to the first stops again: what was behind the guard as it set off.
                turn = stops[nearest:] + stops[:nearest] + stops[nearest : nearest + 2]
                cells.extend(r * cols + c for r, c, _ in turn)
                headings.extend(h for _, _, h in turn)
                row, col = turn[-1][0], turn[-1][1]
            states = state_of(np.array(cells, dtype=np.int64), np.array(headings, dtype=np.int64))
            routes.append(states[entry[states] >= 0] if states.size else states)
    return routes
