"""Where game guards head: pure functions over the grid's arrays that the episode's rules call.

- :func:`escape_path` and :func:`cut_off_cell`: the intruder's likely escape from a chaser and the cell
  of it a second guard reaches first (cutting off instead of following);
- :func:`search_cell`: the cell a searcher commits to among those its strategy wants looked at, leaning
  the intruder's way and away from the other searchers' cells.

The rules themselves are in :mod:`guardsim.alert.episode`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.kernels.distances import FAR

__all__ = [
    "CLAIM_CELLS",
    "CLAIM_COST",
    "ESCAPE_CELLS",
    "LEAN_COST",
    "STEPS",
    "cut_off_cell",
    "escape_path",
    "search_cell",
]

#: Extra cost, in steps, of a search cell per cell it lies behind the last known cell.
LEAN_COST = 2.0
#: Extra cost, in steps, of a search cell within :data:`CLAIM_CELLS` of another searcher's cell.
CLAIM_COST = 8.0
#: Steps (4-connected) within which another searcher's cell makes a search cell cost more.
CLAIM_CELLS = 3
#: Cells of the intruder's likely escape a cutting-off guard considers.
ESCAPE_CELLS = 32
#: Heading numbers' steps (column, row): right, down, left, up.
STEPS = ((1, 0), (0, 1), (-1, 0), (0, -1))


def escape_path(neighbours: np.ndarray, start: int, travel: int, away: np.ndarray) -> list[int]:
    """The intruder's likely escape from ``start``: each step to the neighbour farthest from the chaser
    (``away``: steps from it), never nearer to it, straight on (``travel``, a heading number) on ties;
    at most :data:`ESCAPE_CELLS` steps.

    >>> corridor = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> escape_path(corridor, 1, 0, np.array([0, 1, 2, 3]))
    [1, 2, 3]
    """
    path, here, heading = [start], start, travel
    seen = {start}
    for _ in range(ESCAPE_CELLS):
        best, best_key, best_direction = -1, (0, 0), -1
        for direction in range(4):
            there = int(neighbours[here, direction])
            if there < 0 or there in seen or away[there] < away[here]:
                continue
            key = (int(away[there]), 1 if direction == heading else 0)
            if best < 0 or key > best_key:
                best, best_key, best_direction = there, key, direction
        if best < 0:
            break
        path.append(best)
        seen.add(best)
        here, heading = best, best_direction
    return path


def cut_off_cell(path: Sequence[int], own: np.ndarray, run: float, walk: float) -> int:
    """The first cell of ``path`` (the escape, one cell per intruder move) that a guard ``own`` steps from
    each cell, running ``run`` cells a tick, reaches no later than the intruder moving ``walk`` cells a
    tick; the path's last cell when there is none.

    >>> cut_off_cell([5, 6, 7, 8], np.array([9, 9, 9, 9, 9, 9, 4, 3, 2]), 1.5, 1.0)
    7
    """
    walk = max(walk, 1e-9)
    for index, cell in enumerate(path):
        if own[cell] < FAR and own[cell] / run <= index / walk:
            return int(cell)
    return int(path[-1])


def search_cell(
    goal: np.ndarray,
    steps: np.ndarray,
    columns: int,
    *,
    last_known: int,
    travel: int,
    claimed: Sequence[int],
) -> int:
    """Among ``goal`` (flat cells a strategy wants looked at), the one with the fewest ``steps`` (from the
    searcher, per goal cell) plus :data:`LEAN_COST` per cell it lies behind ``last_known`` against
    ``travel`` (a heading number; -1: none) plus :data:`CLAIM_COST` within :data:`CLAIM_CELLS` of a cell
    in ``claimed`` (the other searchers'); -1 when none is reachable.

    >>> search_cell(np.array([0, 4]), np.array([2, 2]), 5, last_known=2, travel=0, claimed=[])
    4
    >>> search_cell(np.array([0, 4]), np.array([2, 2]), 5, last_known=2, travel=0, claimed=[4])
    0
    """
    if goal.size == 0:
        return -1
    cost = steps.astype(np.float64)
    cost[steps >= FAR] = np.inf
    rows, cols = np.divmod(goal, columns)
    if travel >= 0 and last_known >= 0:
        known_row, known_col = divmod(last_known, columns)
        dx, dy = STEPS[travel]
        ahead = (cols - known_col) * dx + (rows - known_row) * dy
        cost += LEAN_COST * np.maximum(0, -ahead)
    for cell in claimed:
        claimed_row, claimed_col = divmod(cell, columns)
        cost[np.abs(rows - claimed_row) + np.abs(cols - claimed_col) <= CLAIM_CELLS] += CLAIM_COST
    if not np.isfinite(cost).any():
        return -1
    return int(goal[int(np.argmin(cost))])
