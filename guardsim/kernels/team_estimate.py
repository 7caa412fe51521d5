"""Lower bounds on a team's makespan, for the team search (:mod:`guardsim.search.team`).

A team node is (the guard ``k`` now walking, its position, its steps ``g``, the longest walk ``G`` of the
guards before it, the cells seen). :func:`team_bound` is the cheap bound every node gets;
:func:`split_bound` the stronger one taken before the last guard, when a node reaches the top of the heap.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.estimate import UNREACHABLE, Heuristic, pick_pivots
from guardsim.kernels.subsets import subset_path_bound

__all__ = ["later_distances", "split_bound", "team_bound"]


def later_distances(to_watchers: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """``int16 (guards, goal)``: row ``k``, the fewest steps from any later guard's start to a watcher of
    each goal cell (:data:`UNREACHABLE` for the last guard)."""
    guards = starts.size
    later = np.full((guards, to_watchers.shape[1]), UNREACHABLE, dtype=np.int16)
    for k in range(guards - 2, -1, -1):
        later[k] = np.minimum(later[k + 1], to_watchers[starts[k + 1]])
    return later


@jit
def team_bound(
    heuristic: Heuristic,
    later: np.ndarray,
    guard: int,
    position: int,
    steps: int,
    before: int,
    seen: np.ndarray,
    full: np.ndarray,
) -> int:
    """``max(G, g, max over unseen c of min(g + d_k(c), later guards' d(c)))``."""
    row = heuristic.to_watchers[position]
    rest = later[guard]
    best = max(before, steps)
    for word in range(full.shape[0]):
        left = full[word] & ~seen[word]
        bit = word * 64
        while left:
            if left & np.uint64(1):
                need = steps + row[bit]
                if rest[bit] < need:
                    need = rest[bit]
                if need > best:
                    best = need
            left >>= np.uint64(1)
            bit += 1
    return best


@jit
def split_bound(
    heuristic: Heuristic,
    later: np.ndarray,
    starts: np.ndarray,
    guard: int,
    position: int,
    steps: int,
    seen: np.ndarray,
    need: np.ndarray,
    work: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    cost: np.ndarray,
    combined: np.ndarray,
) -> int:
    """A lower bound on the makespan from pivots shared out among the guards still to walk.

    Up to ``heuristic.pivots`` unseen pivots (:func:`~guardsim.kernels.estimate.pick_pivots`, farthest
    from the team first). Each pivot is seen by one of guards ``guard ..``; a guard's walk enters the
    watcher sets of those it sees in some order, so it is at least its steps so far plus the shortest
    order through any subset of them (:func:`~guardsim.kernels.subsets.subset_path_bound`, from its
    position, or a later guard's start). The bound is the least, over the ways to share the pivots out,
    of the longest guard's bound (dynamic programming over subsets, ``3**pivots`` per guard).
    """
    kept, link, gap, order = work
    pool, between = heuristic.pool, heuristic.between
    guards = starts.shape[0]
    row = heuristic.to_watchers[position]
    for candidate in range(pool.shape[0]):
        bit = pool[candidate]
        need[bit] = min(steps + row[bit], later[guard, bit], UNREACHABLE)
    count = pick_pivots(heuristic, need, seen, kept, link, gap)
    if count == 0:
        return steps
    subsets = 1 << count
    never = 1 << 30
    for j in range(guard, guards):
        source = row if j == guard else heuristic.to_watchers[starts[j]]
        for k in range(count):
            gap[k] = source[pool[kept[k]]]
        subset_path_bound(gap, between, kept, count, order, UNREACHABLE)
        base = steps if j == guard else 0
        cost[j, 0] = base
        for mask in range(1, subsets):
            shortest = never
            for last in range(count):
                if order[mask * count + last] < shortest:
                    shortest = order[mask * count + last]
            value = base + shortest if shortest < UNREACHABLE else never
            # A shorter order through a subset would not bound the walk: the largest over subsets does.
            for k in range(count):
                if mask & (1 << k) and cost[j, mask ^ (1 << k)] > value:
                    value = cost[j, mask ^ (1 << k)]
            cost[j, mask] = value
    for mask in range(subsets):
        combined[0, mask] = cost[guards - 1, mask]
    for j in range(guards - 2, guard - 1, -1):
        for mask in range(subsets):
            best = never
            part = mask
            while True:
                value = max(cost[j, part], combined[0, mask ^ part])
                if value < best:
                    best = value
                if part == 0:
                    break
                part = (part - 1) & mask
            combined[1, mask] = best
        for mask in range(subsets):
            combined[0, mask] = combined[1, mask]
    return combined[0, subsets - 1]
