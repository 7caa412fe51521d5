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

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.estimate import Heuristic
from guardsim.search.graph import FAR, SearchGraph, watcher_distances

__all__ = ["PIVOTS", "POOL", "Heuristic", "build_heuristic"]

#: Goal cells whose watcher-set distances are precomputed as pivot candidates.
POOL = 1024
#: Most pivots in one node's shortest path through pivots.
PIVOTS = 8


@jit
def _between(to_watchers: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, pool: np.ndarray) -> np.ndarray:
    size = pool.shape[0]
    ahead = np.empty((size, size), dtype=np.int16)
    for a in range(size):
        bit = pool[a]
        for b in range(size):
            row = to_watchers[pool[b]]
            best = row[watchers[watch_start[bit]]] if watch_start[bit + 1] > watch_start[bit] else FAR
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
    between = _between(to_watchers, watch_start, watchers, order)
    # No pattern database: no picks, and a row of zeros for the empty subset.
    no_picks, zeros = np.zeros((1, 0), dtype=np.int64), np.zeros((1, 1, graph.positions), dtype=np.uint8)
    return Heuristic(np.ascontiguousarray(to_watchers.T), order, between, pivots, no_picks, zeros)
