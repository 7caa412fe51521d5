"""Compressed sparse rows (CSR) and their inversion: one counting sort for every "who points at me" list.

A CSR list stores, for each of ``n`` rows, a run of items: row ``r`` holds
``items[start[r]:start[r + 1]]``. Inverting it lists, for each item value, the rows that hold it, in
ascending row order (the counting sort is stable). The vision table's watchers of each cell, the area
bound's states per pool position, the exact search's predecessors and the watchers of each goal bit are
all this one inversion.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["invert_csr", "predecessors", "watcher_csr"]


@jit
def invert_csr(start: np.ndarray, items: np.ndarray, values: int) -> tuple[np.ndarray, np.ndarray]:
    """The inverse of a CSR list whose items are in ``range(values)``: ``(inverse_start, rows)`` with value
    ``v`` held by rows ``rows[inverse_start[v]:inverse_start[v + 1]]``, ascending (``rows`` is int32).

    >>> start, rows = invert_csr(np.array([0, 2, 3, 5]), np.array([1, 2, 1, 0, 1]), 3)
    >>> start.tolist(), rows.tolist()
    ([0, 1, 4, 5], [2, 0, 1, 2, 0])
    """
    inverse_start = np.zeros(values + 1, dtype=np.int64)
    for index in range(items.shape[0]):
        inverse_start[items[index] + 1] += 1
    for value in range(values):
        inverse_start[value + 1] += inverse_start[value]
    fill = inverse_start[:values].copy()
    rows = np.empty(items.shape[0], dtype=np.int32)
    for row in range(start.shape[0] - 1):
        for index in range(start[row], start[row + 1]):
            value = items[index]
            rows[fill[value]] = row
            fill[value] += 1
    return inverse_start, rows


@jit
def predecessors(successors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reverse adjacency as CSR: the positions with a move into each position (``successors[p, d]`` is
    the position move ``d`` leads to from ``p``, -1 for none).

    >>> start, before = predecessors(np.array([[1, -1, -1, -1], [0, 2, -1, -1], [-1, -1, -1, -1]]))
    >>> start.tolist(), before.tolist()
    ([0, 1, 2, 3], [1, 0, 1])
    """
    positions = successors.shape[0]
    start = np.zeros(positions + 1, dtype=np.int64)
    for position in range(positions):
        for direction in range(4):
            other = successors[position, direction]
            if other >= 0:
                start[other + 1] += 1
    for position in range(positions):
        start[position + 1] += start[position]
    fill = start[:positions].copy()
    before = np.empty(start[positions], dtype=np.int64)
    for position in range(positions):
        for direction in range(4):
            other = successors[position, direction]
            if other >= 0:
                before[fill[other]] = position
                fill[other] += 1
    return start, before


@jit
def watcher_csr(views: np.ndarray, goal: int) -> tuple[np.ndarray, np.ndarray]:
    """The positions that see each goal bit, as CSR: bit ``i`` is seen from
    ``watchers[start[i]:start[i + 1]]`` (ascending); ``views[p]`` is position ``p``'s bitset of goal bits
    in 64-bit words.

    >>> start, watchers = watcher_csr(np.array([[0b011], [0b110]], dtype=np.uint64), 3)
    >>> start.tolist(), watchers.tolist()
    ([0, 1, 3, 4], [0, 0, 1, 1])
    """
    positions = views.shape[0]
    start = np.zeros(goal + 1, dtype=np.int64)
    for position in range(positions):
        for bit in range(goal):
            if (views[position, bit >> 6] >> np.uint64(bit & 63)) & np.uint64(1):
                start[bit + 1] += 1
    for bit in range(goal):
        start[bit + 1] += start[bit]
    watchers = np.empty(start[goal], dtype=np.int64)
    fill = start[:goal].copy()
    for position in range(positions):
        for bit in range(goal):
            if (views[position, bit >> 6] >> np.uint64(bit & 63)) & np.uint64(1):
                watchers[fill[bit]] = position
                fill[bit] += 1
    return start, watchers
