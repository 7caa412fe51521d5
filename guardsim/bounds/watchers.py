"""Distances from a start state to every state, and from it to each cell's nearest watcher.

A state is a cell and a heading (:mod:`guardsim.kernels.states`); one step goes from ``(c, h)`` to ``(neighbours[c, d], d)`` for each
connected direction ``d``. The watchers of a cell are the states that see it, as listed by the level's
:class:`~guardsim.vision.table.ViewTable` (built once per grid and vision, shared with the planners).
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import fill_states
from guardsim.kernels.steps import state_of

__all__ = ["nearest_watchers", "state_distances"]


@jit
def state_distances(neighbours: np.ndarray, start_state: int) -> np.ndarray:
    """``int32 (states,)``: steps from ``start_state`` to every state, -1 where unreachable.

    Breadth-first search over the state graph ``(c, h) -> (neighbours[c, d], d)``.
    """
    distance = np.empty(state_of(neighbours.shape[0], 0), dtype=np.int32)
    fill_states(neighbours, start_state, -1, distance)
    return distance


@jit
def nearest_watchers(
    cells: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, distance: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per cell of ``cells``: the distance to its nearest reachable watcher (-1 if none), and how many
    of its watchers are reachable (``distance >= 0``)."""
    nearest = np.empty(cells.shape[0], dtype=np.int32)
    nearest[:] = -1
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
