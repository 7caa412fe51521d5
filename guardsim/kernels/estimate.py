"""The exact search's per-node lower bound, shared by the search and the beam that seeds it (and so by
the ``tour`` planner's exact seed).

A node is a position and the set of goal cells already seen (a bit set of 64-bit words). The estimate
is the larger of the eccentricity (the farthest unseen goal cell's nearest watcher) and the longest
shortest order through a few spread-out unseen "pivots" (:mod:`guardsim.kernels.subsets`), and, when
the search has one, a pattern database's value (:mod:`guardsim.search.pattern`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.subsets import subset_path_bound

__all__ = ["UNREACHABLE", "Heuristic", "eccentricity", "estimate", "estimate_work", "pattern_value", "pick_pivots"]

#: Distance to a target the position cannot reach; fits int16 with room to add a few steps.
UNREACHABLE = 30000


class Heuristic(NamedTuple):
    """What the per-node estimate reads; a NamedTuple of arrays, so compiled code takes it whole."""

    to_watchers: np.ndarray
    """``int16 (positions, goal)``: steps from a position to the nearest watcher of a goal cell (one row
    per position, so a node's estimate reads one contiguous row)."""
    pool: np.ndarray
    """``int64 (pool,)``: goal bits of the pivot candidates, fewest watchers first."""
    between: np.ndarray
    """``int16 (pool, pool)``: steps between the watcher sets of two candidates, the shorter way round."""
    pivots: int
    """Most pivots per node (the work grows as ``2**pivots * pivots**2``)."""
    pattern_bits: np.ndarray
    """``int64 (tables, k)``: goal bits of the picks of pattern databases (:mod:`guardsim.search.pattern`);
    none by default."""
    pattern: np.ndarray
    """``uint8 (tables, 2**k, positions)``: their tables, the fewest steps to see the picks left from each
    position and subset of picks seen (one row of zeros when there are no picks)."""


@jit
def estimate_work(heuristic: Heuristic) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The work arrays ``kept, link, gap, order`` of :func:`estimate`, allocated once per search."""
    pool = heuristic.pool.shape[0]
    return (
        np.empty(heuristic.pivots, dtype=np.int64),
        np.empty(pool, dtype=np.int64),
        np.empty(pool, dtype=np.int64),
        np.empty((1 << heuristic.pivots) * heuristic.pivots, dtype=np.int64),
    )


@jit(inline="always")
def _unseen(seen: np.ndarray, bit: int) -> bool:
    return ((seen[bit >> 6] >> np.uint64(bit & 63)) & np.uint64(1)) == 0


@jit
def eccentricity(heuristic: Heuristic, position: int, seen: np.ndarray, full: np.ndarray) -> int:
    """The steps from ``position`` to the farthest unseen goal cell's nearest watcher (cheap)."""
    row = heuristic.to_watchers[position]
    farthest = 0
    for word in range(full.shape[0]):
        left = full[word] & ~seen[word]
        while left:
            low = left & (~left + np.uint64(1))
            steps = row[word * 64 + _bit_index(low)]
            if steps > farthest:
                farthest = steps
            left ^= low
    return farthest


@jit
def pattern_value(heuristic: Heuristic, position: int, seen: np.ndarray) -> int:
    """The pattern databases' bound at ``position`` with ``seen`` seen: the largest of their values (0
    without one)."""
    bits, tables = heuristic.pattern_bits, heuristic.pattern
    best = 0
    for table in range(bits.shape[0]):
        subset = 0
        for index in range(bits.shape[1]):
            if not _unseen(seen, bits[table, index]):
                subset |= 1 << index
        best = max(best, int(tables[table, subset, position]))
    return best


@jit
def estimate(
    heuristic: Heuristic,
    position: int,
    seen: np.ndarray,
    full: np.ndarray,
    kept: np.ndarray,
    link: np.ndarray,
    gap: np.ndarray,
    order: np.ndarray,
) -> int:
    """Lower bound on the steps from ``position`` to see every goal cell not in ``seen``.

    ``kept`` is a work array of at least ``heuristic.pivots`` entries, ``link`` and ``gap`` of at least
    the pool's size, ``order`` of ``2**pivots * pivots``.
    """
    row = heuristic.to_watchers[position]
    pool, between = heuristic.pool, heuristic.between
    count = pick_pivots(heuristic, row, seen, kept, link, gap)
    farthest = max(eccentricity(heuristic, position, seen, full), pattern_value(heuristic, position, seen))
    if count == 0:
        return farthest
    # The pivots' distances from the agent, in the scratch ``gap`` (done with it).
    for k in range(count):
        gap[k] = row[pool[kept[k]]]
    return max(farthest, subset_path_bound(gap, between, kept, count, order, UNREACHABLE))


@jit
def pick_pivots(
    heuristic: Heuristic, need: np.ndarray, seen: np.ndarray, kept: np.ndarray, link: np.ndarray, gap: np.ndarray
) -> int:
    """Up to ``heuristic.pivots`` unseen pool cells spread out, farthest first; returns how many, their
    pool indices in ``kept``. ``need[bit]`` is how far the agents are from goal cell ``bit`` (the steps
    to its nearest watcher); ``link`` and ``gap`` are work arrays of the pool's size.

    Each pivot is the unseen candidate farthest from the agents and from the pivots already taken, among
    those sharing no watcher with them (the k-centre rule, which spreads the pivots out).
    """
    pool, between = heuristic.pool, heuristic.between
    candidates = 0
    for candidate in range(pool.shape[0]):
        if _unseen(seen, pool[candidate]):
            link[candidates] = candidate
            gap[candidates] = need[pool[candidate]]
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
    return count


@jit(inline="always")
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
