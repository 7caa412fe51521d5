"""Breadth-first distances over the grid's connected cells and over its states: every fill in guardsim.

A fill marks the cells (or states) no source reaches with the caller's ``far``: :data:`FAR` wherever the
field feeds the greedy step (farther than any real distance, so a minimum never picks it); the bounds
pass -1, which their own tests read as "unreached".

Moves cost one step each and connectivity is symmetric, so the distance from a set of cells to a cell
is also the distance from that cell to the set. Heading does not constrain moves (a guard may step in
any of the four directions), so the steps from a cell to a state ``(cell b, heading h)`` are one more
than the steps to the cell behind ``b`` in heading ``h`` (the one a guard steps from to arrive facing
``h``): see :attr:`guardsim.grid.CoverageGrid.entry_cells`.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.steps import cell_of_state, heading_of_state, state_of

__all__ = [
    "FAR",
    "distance_fields",
    "distances_between",
    "distances_from",
    "fill_distances",
    "fill_states",
    "new_fill",
    "spread",
    "spread_states",
]

#: Distance of a cell no source reaches: farther than any real distance, with room to add to it.
FAR = np.int32(np.iinfo(np.int32).max // 2)


@jit
def fill_distances(neighbours: np.ndarray, sources: np.ndarray, far: int, distance: np.ndarray) -> None:
    """Fill ``distance`` with steps to the nearest source; ``far`` where no source is reachable.

    The compiled kernel behind :func:`distances_from`, for other compiled loops.
    """
    cells = neighbours.shape[0]
    queue = np.empty(cells, dtype=np.int64)
    for cell in range(cells):
        distance[cell] = far
    tail = 0
    for source in sources:
        if distance[source] != 0:
            distance[source] = 0
            queue[tail] = source
            tail += 1
    spread(neighbours, queue, tail, far, distance, -1)


@jit
def new_fill(neighbours: np.ndarray, far: int, sources: np.ndarray) -> np.ndarray:
    """A new ``int32`` field of :func:`fill_distances`."""
    distance = np.empty(neighbours.shape[0], dtype=np.int32)
    fill_distances(neighbours, sources, far, distance)
    return distance


@jit
def spread(neighbours: np.ndarray, queue: np.ndarray, tail: int, far: int, distance: np.ndarray, stop: int) -> int:
    """Breadth-first on from the cells ``queue[:tail]`` (their distances set, every other cell ``far``),
    until every reachable cell has its distance or ``stop`` (a cell, -1 for none) has one; returns how
    many cells ``queue`` then holds, which are all the cells given a distance."""
    head = 0
    while head < tail:
        cell = queue[head]
        head += 1
        step = distance[cell] + 1
        for direction in range(4):
            other = neighbours[cell, direction]
            if other >= 0 and distance[other] == far:
                distance[other] = step
                queue[tail] = other
                tail += 1
                if other == stop:
                    return tail
    return tail


@jit
def spread_states(
    neighbours: np.ndarray,
    queue: np.ndarray,
    tail: int,
    far: int,
    distance: np.ndarray,
    backward: bool,
    label: np.ndarray,
) -> int:
    """Breadth-first over states (``cell * 4 + heading``; a step goes from ``(c, h)`` to
    ``(neighbours[c, d], d)``) from the states ``queue[:tail]``, their distances set and every other
    state at ``far``; ``backward`` follows the steps the other way (the steps into ``(c, h)`` come from
    every state of the cell behind ``c`` along ``h``). Each state reached takes the ``label`` of the state
    it was reached from, when ``label`` is not empty. Returns how many states ``queue`` then holds."""
    carry = label.shape[0] > 0
    head = 0
    while head < tail:
        state = queue[head]
        head += 1
        step = distance[state] + 1
        cell = cell_of_state(state)
        for direction in range(4):
            if backward:
                behind = neighbours[cell, (heading_of_state(state) + 2) % 4]
                if behind < 0:
                    break
                other = state_of(behind, direction)
            else:
                there = neighbours[cell, direction]
                if there < 0:
                    continue
                other = state_of(there, direction)
            if distance[other] == far:
                distance[other] = step
                if carry:
                    label[other] = label[state]
                queue[tail] = other
                tail += 1
    return tail


@jit
def fill_states(neighbours: np.ndarray, start_state: int, far: int, distance: np.ndarray) -> None:
    """Fill ``distance`` (``cells * 4``) with steps from ``start_state`` to every state; ``far`` where
    none reaches."""
    states = distance.shape[0]
    queue = np.empty(states, dtype=np.int64)
    for state in range(states):
        distance[state] = far
    distance[start_state] = 0
    queue[0] = start_state
    spread_states(neighbours, queue, 1, far, distance, False, np.empty(0, dtype=np.int32))


@jit
def _fields(neighbours: np.ndarray, sources: np.ndarray, far: int, out: np.ndarray) -> None:
    single = np.empty(1, dtype=np.int64)
    for index in range(sources.shape[0]):
        single[0] = sources[index]
        fill_distances(neighbours, single, far, out[index])


@jit
def _between(neighbours: np.ndarray, sources: np.ndarray, targets: np.ndarray, far: int, out: np.ndarray) -> None:
    # Each search stops once every target has its distance (a breadth-first label is final when given),
    # and only the cells it labelled are cleared for the next: sources and targets close together (a
    # region's viewpoints on a big map) cost their neighbourhood, not the level.
    cells = neighbours.shape[0]
    field = np.empty(cells, dtype=np.int32)
    field[:] = far
    wanted = np.zeros(cells, dtype=np.bool_)
    distinct = 0
    for column in range(targets.shape[0]):
        if not wanted[targets[column]]:
            wanted[targets[column]] = True
            distinct += 1
    queue = np.empty(cells, dtype=np.int64)
    for index in range(sources.shape[0]):
        source = sources[index]
        field[source] = 0
        queue[0] = source
        tail = 1
        found = 1 if wanted[source] else 0
        head = 0
        while head < tail and found < distinct:
            cell = queue[head]
            head += 1
            step = field[cell] + 1
            for direction in range(4):
                other = neighbours[cell, direction]
                if other >= 0 and field[other] == far:
                    field[other] = step
                    queue[tail] = other
                    tail += 1
                    if wanted[other]:
                        found += 1
        for column in range(targets.shape[0]):
            out[index, column] = field[targets[column]]
        for at in range(tail):
            field[queue[at]] = far


def distances_from(neighbours: np.ndarray, sources: np.ndarray) -> np.ndarray:
    """Steps from every cell to the nearest of ``sources`` through connected moves.

    Parameters
    ----------
    neighbours
        ``int64 (n, 4)``: connected neighbour per direction, -1 where none (``CoverageGrid.neighbours``).
    sources
        ``bool (n,)`` mask or integer flat indices of the source cells.

    Returns
    -------
    numpy.ndarray
        ``int32 (n,)``: 0 on sources, :data:`FAR` where no source is
        reachable (so the field can be fed to the same greedy rule as RippleFront's).

    Examples
    --------
    A corridor of four cells, the right-most one the source:

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> distances_from(neighbours, np.array([3])).tolist()
    [3, 2, 1, 0]
    """
    indices = np.flatnonzero(sources) if sources.dtype == np.bool_ else np.asarray(sources, dtype=np.int64)
    distance = np.empty(neighbours.shape[0], dtype=np.int32)
    fill_distances(np.ascontiguousarray(neighbours, dtype=np.int64), indices.astype(np.int64), int(FAR), distance)
    return distance


def distance_fields(neighbours: np.ndarray, sources: np.ndarray) -> np.ndarray:
    """One field per source cell: ``int32 (len(sources), n)``, row ``k`` the steps to ``sources[k]``."""
    sources = np.asarray(sources, dtype=np.int64)
    out = np.empty((sources.size, neighbours.shape[0]), dtype=np.int32)
    _fields(np.ascontiguousarray(neighbours, dtype=np.int64), sources, int(FAR), out)
    return out


def distances_between(neighbours: np.ndarray, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Steps from each source cell to each target cell: ``int32 (len(sources), len(targets))``.

    Needs one field at a time, so memory grows with the pairs asked for, not with sources times cells.
    """
    sources = np.asarray(sources, dtype=np.int64)
    targets = np.asarray(targets, dtype=np.int64)
    out = np.empty((sources.size, targets.size), dtype=np.int32)
    neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
    if sources.size * neighbours.shape[0] < SPLIT_BETWEEN_WORK:
        _between(neighbours, sources, targets, int(FAR), out)
        return out
    # Each row is one search of its own: two halves of the sources searched at once (the kernel releases
    # the interpreter) fill the same rows as one call, on two cores in half the time.
    half = sources.size // 2
    with ThreadPoolExecutor(max_workers=1) as pool:
        other = pool.submit(_between, neighbours, sources[half:], targets, int(FAR), out[half:])
        _between(neighbours, sources[:half], targets, int(FAR), out[:half])
        other.result()
    return out


#: Sources times cells from which :func:`distances_between` searches two halves of the sources at once.
SPLIT_BETWEEN_WORK = 20_000_000
