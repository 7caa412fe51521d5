"""The Held–Karp subset DP behind the path bounds of ``bounds`` and of the exact search's estimate."""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["subset_path_bound"]


@jit
def subset_path_bound(
    start: np.ndarray, between: np.ndarray, members: np.ndarray, size: int, order: np.ndarray, far: int
) -> int:
    """The largest, over the non-empty subsets of ``members[:size]``, of the shortest walk order from
    the start through every member of the subset: ``start[k]`` to member ``k`` first, then
    ``between[members[a], members[b]]`` from one to the next.

    Dynamic programming over subsets (Held and Karp 1962), ``2**size * size**2`` steps. A covering walk
    enters the members (clusters, or watcher sets) in some order, each stretch at least the distance
    used here, so every subset's shortest order is a lower bound, hence the largest is. Distances of
    ``far`` or more count as unreachable; ``order`` is a work array of at least ``2**size * size``.

    Examples
    --------
    Two members, each 3 steps from the start and 4 apart: seeing both takes at least 3 + 4 steps.

    >>> between = np.array([[0, 4], [4, 0]])
    >>> subset_path_bound(np.array([3, 3]), between, np.array([0, 1]), 2, np.empty(8, dtype=np.int64), 1 << 30)
    7
    """
    subsets = 1 << size
    for mask in range(subsets * size):
        order[mask] = far
    for k in range(size):
        order[(1 << k) * size + k] = start[k]
    best = 0
    for mask in range(1, subsets):
        shortest = far
        for last in range(size):
            here = order[mask * size + last]
            if here >= far:
                continue
            if here < shortest:
                shortest = here
            for nxt in range(size):
                if mask & (1 << nxt):
                    continue
                value = here + between[members[last], members[nxt]]
                slot = (mask | (1 << nxt)) * size + nxt
                if value < order[slot]:
                    order[slot] = value
        if shortest > best:
            best = shortest
    return best
