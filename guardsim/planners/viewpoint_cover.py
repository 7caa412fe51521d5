"""Greedy set cover: a small set of viewpoints whose visible cells together include every goal cell.

Candidates are the states a guard can arrive in by a step (the start state is the episode's own and
sees its cells at tick 0 anyway). The greedy rule (Chvátal 1979, "A greedy heuristic for the
set-covering problem") repeatedly takes the state that sees the most goal cells not yet covered, ties to
the lowest state number (found in a heap of the states by gain, updated lazily); it stays within a factor ``ln(max cells per state) + 1`` of the smallest cover.
A final pass drops any chosen viewpoint whose cells the others already cover, latest pick first.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.arrays import count_true
from guardsim.kernels.compiler import jit
from guardsim.kernels.heap import heap_pop, heap_push
from guardsim.vision.table import ViewTable

__all__ = ["greedy_cover"]


@jit
def _greedy_cover(
    sight_start: np.ndarray,
    sight: np.ndarray,
    watch_start: np.ndarray,
    watchers: np.ndarray,
    candidate: np.ndarray,
    goal: np.ndarray,
) -> np.ndarray:
    states = candidate.shape[0]
    gain = np.zeros(states, dtype=np.int64)
    for state in range(states):
        if candidate[state]:
            for index in range(sight_start[state], sight_start[state + 1]):
                gain[state] += goal[sight[index]]
    covered = ~goal
    chosen = []
    # The states by gain, most first, then by number (one key: -gain x states + state), kept lazily: gains
    # only fall, so a popped key whose gain has fallen is pushed again with its gain now, and the first
    # popped key that is still right is the state of most gain, the lowest such, as a full scan finds.
    keys = np.empty(states + 1, dtype=np.int64)
    items = np.empty(states + 1, dtype=np.int64)
    size = 0
    for state in range(states):
        if candidate[state] and gain[state] > 0:
            size = heap_push(keys, items, size, -gain[state] * states + state, state)
    while size > 0:
        key, best, size = heap_pop(keys, items, size)
        if -(key - best) // states != gain[best]:
            if gain[best] > 0:
                size = heap_push(keys, items, size, -gain[best] * states + best, best)
            continue
        chosen.append(best)
        for index in range(sight_start[best], sight_start[best + 1]):
            cell = sight[index]
            if not covered[cell]:
                covered[cell] = True
                for other in range(watch_start[cell], watch_start[cell + 1]):
                    gain[watchers[other]] -= 1
    # Redundancy pass: how many chosen viewpoints see each goal cell; drop those nobody needs.
    multiplicity = np.zeros(goal.shape[0], dtype=np.int64)
    for state in chosen:
        for index in range(sight_start[state], sight_start[state + 1]):
            multiplicity[sight[index]] += 1
    keep = np.ones(len(chosen), dtype=np.bool_)
    for position in range(len(chosen) - 1, -1, -1):
        state = chosen[position]
        needed = False
        for index in range(sight_start[state], sight_start[state + 1]):
            cell = sight[index]
            if goal[cell] and multiplicity[cell] == 1:
                needed = True
                break
        if not needed:
            keep[position] = False
            for index in range(sight_start[state], sight_start[state + 1]):
                multiplicity[sight[index]] -= 1
    result = np.empty(count_true(keep), dtype=np.int64)
    count = 0
    for position in range(len(chosen)):
        if keep[position]:
            result[count] = chosen[position]
            count += 1
    return result


def greedy_cover(table: ViewTable, goal: np.ndarray) -> np.ndarray:
    """Viewpoints (state numbers, in the order chosen) that together see every coverable goal cell.

    Parameters
    ----------
    table
        The level's :class:`~guardsim.vision.table.ViewTable`.
    goal
        ``bool (cells,)``: the cells to cover.

    Returns
    -------
    numpy.ndarray
        ``int64``: state numbers. A goal cell no arrivable state sees (only possible when the goal is a
        single cell, seen from the start) stays uncovered.
    """
    goal = np.ascontiguousarray(goal, dtype=np.bool_)
    if not goal.flags.writeable:
        goal = goal.copy()  # a read-only array is another type to numba: the kernel would compile twice
    candidate = (table.entry >= 0) & np.repeat(goal, 4)
    return _greedy_cover(table.sight_start, table.sight, table.watch_start, table.watchers, candidate, goal)
