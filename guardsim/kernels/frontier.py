"""The exact search's macro moves: from a position, the nearest positions that see something unseen,
and the node hash; shared by the search and its beam seed."""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["drop_shadowed", "frontier", "frontier_work", "node_hash"]


@jit(inline="always")
def node_hash(position: int, seen: np.ndarray) -> np.uint64:
    value = np.uint64(position) * np.uint64(0x9E3779B97F4A7C15)
    for word in range(seen.shape[0]):
        value ^= seen[word]
        value *= np.uint64(0xBF58476D1CE4E5B9)
        value ^= value >> np.uint64(31)
    return value


@jit
def frontier(
    successors: np.ndarray,
    views: np.ndarray,
    origin: int,
    seen: np.ndarray,
    distance: np.ndarray,
    queue: np.ndarray,
    found: np.ndarray,
    found_steps: np.ndarray,
) -> int:
    """Positions seeing something unseen, reached from ``origin`` without passing another such one, each
    with its shortest distance from ``origin``.

    Fills ``found[:n]`` and ``found_steps[:n]``, returns ``n``. ``distance`` must be all -1 on entry and
    is left so.

    The moves are those of the decomposition "walk until the first position that sees something new":
    every walk is a sequence of them, so the search over them is complete. Each is costed at its
    *shortest* distance, which may pass other frontier positions: a walk rebuilt along a shortest path
    (:func:`guardsim.search.graph.route_steps`) has exactly the steps counted and sees at least what the
    search assumed. Costing a move at the length of the avoiding path instead made the rebuilt walk
    shorter than the count (arena, range 8: "the walk has 272 steps, the search counted 276").
    """
    words = seen.shape[0]
    distance[origin] = 0
    queue[0] = origin
    head, tail, count = 0, 1, 0
    while head < tail:
        here = queue[head]
        head += 1
        step = distance[here] + 1
        for direction in range(4):
            there = successors[here, direction]
            if there < 0 or distance[there] >= 0:
                continue
            distance[there] = step
            queue[tail] = there
            tail += 1
            fresh = False
            for word in range(words):
                if views[there, word] & ~seen[word]:
                    fresh = True
                    break
            if fresh:
                found[count] = there
                found_steps[count] = step
                count += 1
                tail -= 1  # a frontier position ends the macro move: never expanded
    for index in range(head):
        distance[queue[index]] = -1
    # The unrestricted fill: shortest distances to the positions found (marked -2 - index).
    for index in range(count):
        distance[found[index]] = -2 - index
    distance[origin] = 0
    queue[0] = origin
    head, tail, left = 0, 1, count
    while head < tail and left > 0:
        here = queue[head]
        head += 1
        step = distance[here] + 1
        for direction in range(4):
            there = successors[here, direction]
            if there < 0:
                continue
            mark = distance[there]
            if mark >= 0:
                continue
            if mark < -1:
                found_steps[-2 - mark] = step
                left -= 1
            distance[there] = step
            queue[tail] = there
            tail += 1
    for index in range(tail):
        distance[queue[index]] = -1
    return count


@jit
def drop_shadowed(
    successors: np.ndarray,
    origin: int,
    found: np.ndarray,
    found_steps: np.ndarray,
    count: int,
    distance: np.ndarray,
    queue: np.ndarray,
    mark: np.ndarray,
) -> int:
    """Keep only the moves of :func:`frontier` that no shortest path from ``origin`` reaches through
    another move's position; returns how many are left, in their order, at the front of ``found`` and
    ``found_steps``.

    A move to ``b`` is *shadowed* when some move's position ``a`` lies on a shortest path to ``b``
    (``d(origin, a) + d(a, b) = d(origin, b)``): walking through ``a`` to ``b`` takes no more steps, sees
    at least as much, and sees ``a``'s new cells sooner. So among the optimal walks from the node, one
    that sees its cells as early as possible (the least sum over its steps of the cells not yet seen)
    never makes a shadowed move, and dropping them keeps an optimal walk from every node (the pruning of
    MWRP-CP3's expanding borders). ``distance`` must be all -1 and ``mark`` all 0 on entry; both are
    left so.

    One breadth-first search over the layers up to the farthest move: a position is marked *behind* when
    some position one layer nearer on a shortest path to it is a move's position or itself behind.
    """
    if count == 0:
        return 0
    farthest = 0
    for index in range(count):
        mark[found[index]] = 1
        if found_steps[index] > farthest:
            farthest = found_steps[index]
    distance[origin] = 0
    queue[0] = origin
    head, tail = 0, 1
    while head < tail:
        here = queue[head]
        head += 1
        step = distance[here] + 1
        if step > farthest:
            continue
        behind = mark[here] != 0
        for direction in range(4):
            there = successors[here, direction]
            if there < 0:
                continue
            if distance[there] < 0:
                distance[there] = step
                queue[tail] = there
                tail += 1
            if behind and distance[there] == step:
                mark[there] |= 2
    kept = 0
    for index in range(count):
        if mark[found[index]] & 2:
            continue
        found[kept] = found[index]
        found_steps[kept] = found_steps[index]
        kept += 1
    for index in range(tail):
        distance[queue[index]] = -1
        mark[queue[index]] = 0  # every move's position is within reach of the search
    return kept


@jit
def frontier_work(positions: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The work arrays ``distance, queue, found, found_steps`` of :func:`frontier` (``distance`` all -1)."""
    return (
        np.full(positions, -1, dtype=np.int32),
        np.empty(positions, dtype=np.int64),
        np.empty(positions, dtype=np.int64),
        np.empty(positions, dtype=np.int32),
    )
