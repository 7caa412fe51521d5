"""Distances from a start state to every state, and from it to each cell's nearest watcher.

A state is ``cell * 4 + heading``; one step goes from ``(c, h)`` to ``(neighbours[c, d], d)`` for each
connected direction ``d``. The watchers of a cell are the states that see it, as listed by the level's
:class:`~guardsim.vision.table.ViewTable` (built once per grid and vision, shared with the planners).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["nearest_watchers", "state_distances"]


@numba.njit(cache=True, nogil=True)
def state_distances(neighbours: np.ndarray, start_state: int) -> np.ndarray:
    """``int32 (cells * 4,)``: steps from ``start_state`` to every state, -1 where unreachable.

    Breadth-first search over the state graph ``(c, h) -> (neighbours[c, d], d)``.
    """
    states = neighbours.shape[0] * 4
    distance = np.full(states, -1, dtype=np.int32)
    queue = np.empty(states, dtype=np.int64)
    distance[start_state] = 0
    queue[0] = start_state
    head, tail = 0, 1
    while head < tail:
        state = queue[head]
        head += 1
        cell = state // 4
        for direction in range(4):
            other = neighbours[cell, direction]
            if other >= 0:
                following = other * 4 + direction
                if distance[following] < 0:
                    distance[following] = distance[state] + 1
                    queue[tail] = following
                    tail += 1
    return distance


@numba.njit(cache=True, nogil=True)
def nearest_watchers(
    cells: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, distance: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per cell of ``cells``: the distance to its nearest reachable watcher (-1 if none), and how many
    of its watchers are reachable (``distance >= 0``)."""
    nearest = np.full(cells.shape[0], -1, dtype=np.int32)
    reachable = np.zeros(cells.shape[0], dtype=np.int64)
    for index in range(cells.shape[0]):
        cell = cells[index]
        for k in range(watch_start[cell], watch_start[cell + 1]):
            steps = distance[watchers[k]]
            if steps >= 0:
                reachable[index] += 1
                if nearest[index] < 0 or steps < nearest[index]:
                    nearest[index] = steps
    return nearest, reachable
