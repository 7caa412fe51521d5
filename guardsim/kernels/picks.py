"""The cluster bound's farthest-first picks over one area's watchers, and the distances between them.

:class:`AreaWatchers` is built once per area by :func:`guardsim.bounds.area.area_watchers`; these
functions read it, and fill its lazy matrices, for each start.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.arrays import true_indices
from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import fill_distances

__all__ = ["UNKNOWN", "AreaWatchers", "pick_matrix", "spread_picks", "start_edges"]


class AreaWatchers(NamedTuple):
    """The start-independent part of the cluster bound for one connected area (see the module text).

    The pool's matrices are filled on first use: a row (``opened``) when its cell is first picked, an
    entry when first needed (``UNKNOWN`` until then).
    """

    usable: np.ndarray
    """``bool (states,)``: states whose entry cell is in the area."""
    order: np.ndarray
    """``int64``: the area's cells with a usable watcher, fewest usable watchers first (ties by cell)."""
    entry_start: np.ndarray
    """``int64 (len(order) + 1,)``: ``order[i]``'s usable watchers' distinct entry cells are
    ``entry_cells[entry_start[i]:entry_start[i + 1]]``."""
    entry_cells: np.ndarray
    position: np.ndarray
    """``int64 (cells,)``: each cell's position in ``order`` (any value for cells not in it)."""
    greedy: np.ndarray
    """Positions in ``order`` of the cells the fewest-watchers-first greedy choice keeps over all of it."""
    greedy_tree: int
    """The minimum spanning tree over the greedy clusters."""
    pool: np.ndarray
    """The first cells of ``order``: enough that a start's candidates, the first ``candidates`` cells
    not seen from it, are among them."""
    pool_start: np.ndarray
    """``int64 (len(pool) + 1,)``: ``pool[i]``'s usable watchers are
    ``pool_states[pool_start[i]:pool_start[i + 1]]``, with their cells and entry cells alongside."""
    pool_states: np.ndarray
    pool_cells: np.ndarray
    pool_entries: np.ndarray
    member_start: np.ndarray
    """``int64 (states + 1,)``: state ``s`` watches the pool positions ``members[member_start[s]:member_start[s + 1]]``."""
    members: np.ndarray
    radius: np.ndarray
    """``int64 (pool,)``: largest distance between cells from a pool cell to its watchers' cells."""
    gaps: np.ndarray
    """``int32 (pool, cells)``, by opened row: distances between cells from the row's watchers' cells."""
    separation: np.ndarray
    """``int32 (pool, pool)``, by opened row: least ``gaps[row]`` over the cells of column's watchers."""
    ahead: np.ndarray
    """``int32 (pool, pool)``, by opened row: fewest steps from a watcher of row's cell to one of column's, -1: none."""
    opened: np.ndarray
    """``bool (pool,)``: rows computed so far."""


#: Not yet computed, in :attr:`AreaWatchers.separation` and :attr:`AreaWatchers.ahead`.
UNKNOWN = -2


@jit
def _least_gap(gap: np.ndarray, cells: np.ndarray, begin: int, end: int, far: int) -> int:
    least = far
    for k in range(begin, end):
        if 0 <= gap[cells[k]] < least:
            least = gap[cells[k]]
    return least


@jit
def _lazy_least(
    row: int, column: int, matrix: np.ndarray, gaps: np.ndarray, start: np.ndarray, cells: np.ndarray, plus: int
) -> int:
    """``matrix[row, column]``, computed first if :data:`UNKNOWN`: ``plus`` + the least ``gaps[row]``
    over ``cells[start[column]:start[column + 1]]`` (-1: none). Arrays, not the whole
    :class:`AreaWatchers`: compiled code passes tuples by value, which costs more than the work here."""
    if matrix[row, column] == UNKNOWN:
        least = _least_gap(gaps[row], cells, start[column], start[column + 1], 1 << 30)
        matrix[row, column] = least + plus if least < (1 << 30) else -1
    return matrix[row, column]


@jit
def spread_picks(
    area: AreaWatchers, alive: np.ndarray, gap: np.ndarray, neighbours: np.ndarray, most: int
) -> np.ndarray:
    """Up to ``most`` pool positions picked farthest first among the ``alive`` ones, their usable watcher
    sets pairwise disjoint.

    Each pick is the live candidate whose watchers' cells lie farthest, in steps between cells, from
    the start (``gap``, distances from the start cell) and from the watchers of earlier picks (its
    separation); ties go to the first. A pick's separation from a
    candidate is at least the pick's distance to the candidate's cell less the candidate's
    :attr:`~AreaWatchers.radius`; it is computed only when that could lower the candidate's value.
    """
    pool, pool_start, pool_states, pool_cells = area.pool, area.pool_start, area.pool_states, area.pool_cells
    member_start, members, radius = area.member_start, area.members, area.radius
    size = alive.shape[0]
    far = np.iinfo(np.int32).max // 2
    # Unreachable cells as ``far``: the least over a candidate's cells is then a plain minimum.
    near = np.empty(gap.shape[0], dtype=np.int32)
    for cell in range(gap.shape[0]):
        near[cell] = gap[cell] if gap[cell] >= 0 else far
    alive = alive.copy()
    value = np.empty(size, dtype=np.int64)
    value[:] = far
    # The live candidates, in order; dead ones are dropped as each pick's pass meets them.
    live = true_indices(alive)
    count_live = live.shape[0]
    best = -1
    for index in range(count_live):
        position = live[index]
        least = np.int32(far)
        for k in range(pool_start[position], pool_start[position + 1]):
            least = min(least, near[pool_cells[k]])
        value[position] = least
        if best < 0 or value[position] > value[best]:
            best = position
    picks = np.empty(most, dtype=np.int64)
    count = 0
    while count < most and best >= 0:
        picks[count] = best
        count += 1
        alive[best] = False
        begin, end = pool_start[best], pool_start[best + 1]
        for k in range(begin, end):
            state = pool_states[k]
            for m in range(member_start[state], member_start[state + 1]):
                alive[members[m]] = False
        if not area.opened[best]:
            # int64 sources, as every other fill passes them: an int32 slice compiled the fill again.
            sources = np.empty(end - begin, dtype=np.int64)
            for k in range(begin, end):
                sources[k - begin] = pool_cells[k]
            fill_distances(neighbours, sources, -1, area.gaps[best])
            area.separation[best, :] = UNKNOWN
            area.ahead[best, :] = UNKNOWN
            area.opened[best] = True
        row_gap = area.gaps[best]
        # One pass lowers the values and finds the next pick (the first of the largest value).
        kept = 0
        following = -1
        for index in range(count_live):
            position = live[index]
            if not alive[position]:
                continue
            live[kept] = position
            kept += 1
            # The triangle inequality: no watcher of the candidate is nearer to the pick than this.
            if row_gap[pool[position]] - radius[position] < value[position]:
                separation = area.separation[best, position]
                if separation == UNKNOWN:
                    separation = _lazy_least(best, position, area.separation, area.gaps, pool_start, pool_cells, 0)
                if separation >= 0:
                    value[position] = min(value[position], separation)
            if following < 0 or value[position] > value[following]:
                following = position
        count_live = kept
        best = following
    return picks[:count]


@jit
def pick_matrix(area: AreaWatchers, picks: np.ndarray) -> np.ndarray:
    """``min(d(A -> B), d(B -> A))`` between the picks' watcher sets, as
    :func:`~guardsim.kernels.trees.cluster_distances` would give (zero where neither way is known)."""
    size = picks.shape[0]
    ahead, gaps, start, entries = area.ahead, area.gaps, area.pool_start, area.pool_entries
    both = np.zeros((size, size), dtype=np.int64)
    for a in range(size):
        for b in range(a + 1, size):
            # Known entries are read here: a call per entry cost more than the reading.
            forward = ahead[picks[a], picks[b]]
            if forward == UNKNOWN:
                forward = _lazy_least(picks[a], picks[b], ahead, gaps, start, entries, 1)
            backward = ahead[picks[b], picks[a]]
            if backward == UNKNOWN:
                backward = _lazy_least(picks[b], picks[a], ahead, gaps, start, entries, 1)
            if forward >= 0 and backward >= 0:
                both[a, b] = both[b, a] = min(forward, backward)
            else:
                # A walk covering both clusters joins them one way or the other; zero keeps the bound.
                both[a, b] = both[b, a] = max(forward, backward, 0)
    return both


@jit
def start_edges(area: AreaWatchers, positions: np.ndarray, gap: np.ndarray) -> np.ndarray:
    """Fewest steps from the start state (``gap``: distances from its cell) to a usable watcher of each
    ``order`` position (-1: none)."""
    out = np.empty(positions.shape[0], dtype=np.int64)
    out[:] = -1
    for index in range(positions.shape[0]):
        least = _least_gap(
            gap, area.entry_cells, area.entry_start[positions[index]], area.entry_start[positions[index] + 1], 1 << 30
        )
        if least < (1 << 30):
            out[index] = least + 1
    return out
