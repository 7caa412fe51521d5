"""Admissible estimates of the steps still needed from a position with some cells seen, compiled.

Both are the bounds of :mod:`guardsim.bounds` (``docs/bounds.md``), re-evaluated for every search node
over the cells it has not seen yet:

- **eccentricity**: the farthest unseen cell's nearest watcher;
- **pivot tree**: a minimum spanning tree over the agent and some unseen *pivot* cells, edge weights
  being the steps between their watcher sets (either way round, the smaller). A walk entering the
  pivots' watcher sets in some order is at least as long as that path through them, a spanning tree.
  Pivots are taken from a fixed *pool* (goal cells with the fewest watchers, whose pairwise distances
  are computed once), fewest watchers first, skipping any that shares a watcher with one taken.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from guardsim.optimum.graph import SearchGraph, watcher_distances

__all__ = ["PIVOTS", "POOL", "Heuristic", "build_heuristic", "estimate"]

#: Goal cells whose watcher-set distances are precomputed as pivot candidates.
POOL = 1024
#: Most pivots in one node's tree.
PIVOTS = 24


class Heuristic(NamedTuple):
    """What the per-node estimate reads; a NamedTuple of arrays, so compiled code takes it whole."""

    to_watchers: np.ndarray
    """``int16 (goal, positions)``: steps from a position to the nearest watcher of a goal cell."""
    pool: np.ndarray
    """``int64 (pool,)``: goal bits of the pivot candidates, fewest watchers first."""
    between: np.ndarray
    """``int16 (pool, pool)``: steps between the watcher sets of two candidates, the shorter way round."""
    pivots: int
    """Most pivots per node."""


@numba.njit(cache=True, nogil=True)
def _between(to_watchers: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, pool: np.ndarray) -> np.ndarray:
    size = pool.shape[0]
    ahead = np.empty((size, size), dtype=np.int16)
    for a in range(size):
        bit = pool[a]
        for b in range(size):
            row = to_watchers[pool[b]]
            best = row[watchers[watch_start[bit]]] if watch_start[bit + 1] > watch_start[bit] else 30000
            for k in range(watch_start[bit], watch_start[bit + 1]):
                if row[watchers[k]] < best:
                    best = row[watchers[k]]
            ahead[a, b] = best
    both = np.empty((size, size), dtype=np.int16)
    for a in range(size):
        for b in range(size):
            both[a, b] = min(ahead[a, b], ahead[b, a])
    return both


def build_heuristic(graph: SearchGraph, pool: int = POOL, pivots: int = PIVOTS) -> Heuristic:
    """Watcher distances of every goal cell and the pivot pool of a search graph."""
    to_watchers, watch_start, watchers = watcher_distances(graph)
    counts = np.diff(watch_start)
    order = np.lexsort((np.arange(counts.size), counts))[:pool].astype(np.int64)
    return Heuristic(to_watchers, order, _between(to_watchers, watch_start, watchers, order), pivots)


@numba.njit(cache=True, nogil=True, inline="always")
def _unseen(seen: np.ndarray, bit: int) -> bool:
    return ((seen[bit >> 6] >> np.uint64(bit & 63)) & np.uint64(1)) == 0


@numba.njit(cache=True, nogil=True)
def estimate(
    heuristic: Heuristic,
    position: int,
    seen: np.ndarray,
    full: np.ndarray,
    kept: np.ndarray,
    link: np.ndarray,
    gap: np.ndarray,
) -> int:
    """Lower bound on the steps from ``position`` to see every goal cell not in ``seen``.

    ``kept`` is a work array of at least ``heuristic.pivots`` entries, ``link`` and ``gap`` of at least
    the pool's size.
    """
    to_watchers = heuristic.to_watchers
    farthest = 0
    for word in range(full.shape[0]):
        left = full[word] & ~seen[word]
        while left:
            low = left & (~left + np.uint64(1))
            bit = word * 64 + _bit_index(low)
            steps = to_watchers[bit, position]
            if steps > farthest:
                farthest = steps
            left ^= low
    pool, between = heuristic.pool, heuristic.between
    # Farthest first: each pivot the unseen candidate farthest from the agent and the pivots taken,
    # among those sharing no watcher with them (the k-centre rule, which spreads the tree).
    candidates = 0
    for candidate in range(pool.shape[0]):
        if _unseen(seen, pool[candidate]):
            link[candidates] = candidate
            gap[candidates] = to_watchers[pool[candidate], position]
            candidates += 1
    count = 0
    while count < heuristic.pivots:
        best = -1
        for index in range(candidates):
            if gap[index] > 0 and (best < 0 or gap[index] > gap[best]):
                best = index
        if best < 0:
            break
        chosen = link[best]
        kept[count] = chosen
        count += 1
        gap[best] = 0
        for index in range(candidates):
            if gap[index] > 0:
                weight = between[link[index], chosen]
                if weight < gap[index]:
                    gap[index] = weight
    if count == 0:
        return farthest
    # More pivots can shorten the tree (one between two others), so every prefix of the picks counts.
    best_total = 0
    for size in range(1, count + 1):
        total = _tree_from_agent(to_watchers, pool, between, kept, size, position, link)
        if total > best_total:
            best_total = total
    return max(farthest, best_total)


@numba.njit(cache=True, nogil=True)
def _tree_from_agent(
    to_watchers: np.ndarray,
    pool: np.ndarray,
    between: np.ndarray,
    kept: np.ndarray,
    size: int,
    position: int,
    link: np.ndarray,
) -> int:
    """Prim's minimum spanning tree over the agent and the first ``size`` pivots of ``kept``."""
    for k in range(size):
        link[k] = to_watchers[pool[kept[k]], position]
    total = 0
    for _ in range(size):
        best = -1
        for k in range(size):
            if link[k] >= 0 and (best < 0 or link[k] < link[best]):
                best = k
        total += link[best]
        link[best] = -1
        for k in range(size):
            if link[k] >= 0:
                weight = between[kept[best], kept[k]]
                if weight < link[k]:
                    link[k] = weight
    return total


@numba.njit(cache=True, nogil=True, inline="always")
def _bit_index(low: np.uint64) -> int:
    """Index of the single set bit of ``low``."""
    index = 0
    if low >= np.uint64(1) << np.uint64(32):
        low >>= np.uint64(32)
        index += 32
    if low >= np.uint64(1) << np.uint64(16):
        low >>= np.uint64(16)
        index += 16
    if low >= np.uint64(1) << np.uint64(8):
        low >>= np.uint64(8)
        index += 8
    if low >= np.uint64(1) << np.uint64(4):
        low >>= np.uint64(4)
        index += 4
    if low >= np.uint64(1) << np.uint64(2):
        low >>= np.uint64(2)
        index += 2
    if low >= np.uint64(1) << np.uint64(1):
        index += 1
    return index
