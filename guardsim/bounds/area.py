"""What the bounds of every start in one connected area share, computed once per area.

From any start in a connected area the guard can reach every cell of it, and from a cell step into each
neighbour, so the states a covering walk can use are the start state and the **usable** states: those
whose entry cell (the cell a guard steps from to arrive in them) lies in the area. The start state only
watches cells seen at step 0, which the cluster bound leaves out. So for the cells the bound chooses
from, the reachable watchers, their counts, the fewest-watchers-first order, the greedy clusters with
their spanning tree, and the distances between the watcher sets of candidate cells do not depend on the
start: :class:`AreaWatchers` keeps them, the distance rows filled on first use (``guardsim bench`` asks
200 starts per level; issue 15 made the bounds of a start on a shipped level 5 ms -> well under 1 ms).

Distances from the start state follow from distances between cells: the start state can step in any
direction, so the fewest steps to a usable state ``s`` are one more than the fewest steps between cells
from the start cell to ``s``'s entry cell.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.bounds.trees import spanning_tree_weight
from guardsim.grid import CoverageGrid
from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import spread
from guardsim.kernels.steps import cell_of_state
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import ViewTable, level_memo

__all__ = [
    "UNKNOWN",
    "AreaWatchers",
    "area_watchers",
    "cell_distances",
    "choose_clusters",
    "pick_matrix",
    "spread_picks",
    "start_edges",
]


@jit
def choose_clusters(
    order: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, distance: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Greedy: keep each cell of ``order`` none of whose reachable watchers a cell kept before holds.

    Only watchers with ``distance >= 0`` (reachable from the start) count. Returns the cluster number of
    every state (-1 for none) and the kept cells, cluster by cluster.
    """
    label = np.full(distance.shape[0], -1, dtype=np.int32)
    kept = np.empty(order.shape[0], dtype=np.int64)
    clusters = 0
    for cell in order:
        free = True
        for k in range(watch_start[cell], watch_start[cell + 1]):
            state = watchers[k]
            if distance[state] >= 0 and label[state] >= 0:
                free = False
                break
        if free:
            for k in range(watch_start[cell], watch_start[cell + 1]):
                state = watchers[k]
                if distance[state] >= 0:
                    label[state] = clusters
            kept[clusters] = cell
            clusters += 1
    return label, kept[:clusters]


@jit
def cell_distances(neighbours: np.ndarray, sources: np.ndarray) -> np.ndarray:
    """``int32 (cells,)``: fewest steps between cells from the nearest of ``sources``, -1 where unreachable."""
    size = neighbours.shape[0]
    gap = np.full(size, -1, dtype=np.int32)
    queue = np.empty(size, dtype=np.int64)
    tail = 0
    for cell in sources:
        if gap[cell] < 0:
            gap[cell] = 0
            queue[tail] = cell
            tail += 1
    spread(neighbours, queue, tail, -1, gap, -1)
    return gap


@jit
def _unique_keys(
    cells: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, usable: np.ndarray, key: np.ndarray, size: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per cell of ``cells``: the distinct ``key`` of its usable watchers (CSR start and values) and how
    many usable watchers it has."""
    stamp = np.full(size, -1, dtype=np.int64)
    start = np.zeros(cells.shape[0] + 1, dtype=np.int64)
    count = np.zeros(cells.shape[0], dtype=np.int64)
    flat = np.empty(16, dtype=np.int64)
    used = 0
    for index in range(cells.shape[0]):
        cell = cells[index]
        for k in range(watch_start[cell], watch_start[cell + 1]):
            state = watchers[k]
            if not usable[state]:
                continue
            count[index] += 1
            value = key[state]
            if stamp[value] == index:
                continue
            stamp[value] = index
            if used == flat.shape[0]:
                grown = np.empty(2 * used, dtype=np.int64)
                grown[:used] = flat
                flat = grown
            flat[used] = value
            used += 1
        start[index + 1] = used
    return start, flat[:used].copy(), count


@jit
def _pool_watchers(
    pool: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, usable: np.ndarray, entry: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The usable watchers of each pool cell as CSR start, states, their cells and their entry cells."""
    start = np.zeros(pool.shape[0] + 1, dtype=np.int64)
    for index in range(pool.shape[0]):
        cell = pool[index]
        count = 0
        for k in range(watch_start[cell], watch_start[cell + 1]):
            count += usable[watchers[k]]
        start[index + 1] = start[index] + count
    states = np.empty(start[-1], dtype=np.int32)
    cells = np.empty(start[-1], dtype=np.int32)
    entries = np.empty(start[-1], dtype=np.int32)
    used = 0
    for index in range(pool.shape[0]):
        cell = pool[index]
        for k in range(watch_start[cell], watch_start[cell + 1]):
            state = watchers[k]
            if usable[state]:
                states[used], cells[used], entries[used] = state, cell_of_state(state), entry[state]
                used += 1
    return start, states, cells, entries


@jit
def _members_of_states(pool_start: np.ndarray, pool_states: np.ndarray, states: int) -> tuple[np.ndarray, np.ndarray]:
    """The inverse of the pool's watcher lists: per state, the pool positions it watches (CSR)."""
    start = np.zeros(states + 1, dtype=np.int64)
    for k in range(pool_states.shape[0]):
        start[pool_states[k] + 1] += 1
    for state in range(states):
        start[state + 1] += start[state]
    fill = start[:states].copy()
    members = np.empty(pool_states.shape[0], dtype=np.int32)
    for position in range(pool_start.shape[0] - 1):
        for k in range(pool_start[position], pool_start[position + 1]):
            members[fill[pool_states[k]]] = position
            fill[pool_states[k]] += 1
    return start, members


@jit
def _reach_radius(
    pool: np.ndarray, pool_start: np.ndarray, pool_cells: np.ndarray, neighbours: np.ndarray
) -> np.ndarray:
    """Per pool cell: the largest distance between cells from it to one of its watchers' cells."""
    radius = np.zeros(pool.shape[0], dtype=np.int64)
    one = np.empty(1, dtype=np.int64)
    for position in range(pool.shape[0]):
        one[0] = pool[position]
        gap = cell_distances(neighbours, one)
        for k in range(pool_start[position], pool_start[position + 1]):
            radius[position] = max(radius[position], gap[pool_cells[k]])
    return radius


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


def area_watchers(
    grid: CoverageGrid, vision: VisionFunction, table: ViewTable, cell: int, candidates: int
) -> AreaWatchers:
    """The :class:`AreaWatchers` of the area around ``cell``, built once per grid, vision and area
    (``table`` is the view table of ``grid`` and ``vision``)."""
    label = int(grid.component_labels[cell])
    memo = level_memo(grid, vision)
    key = ("bounds area", label, candidates)
    if key not in memo:
        memo[key] = _build(grid, table, label, candidates)
    result: AreaWatchers = memo[key]
    return result


def _build(grid: CoverageGrid, table: ViewTable, label: int, candidates: int) -> AreaWatchers:
    area = grid.component_labels == label
    entry = table.entry
    usable = np.zeros(entry.size, dtype=np.bool_)
    has_entry = entry >= 0
    usable[has_entry] = area[entry[has_entry]]
    cells = np.flatnonzero(area)
    _, _, counts = _unique_keys(cells, table.watch_start, table.watchers, usable, entry, grid.size)
    watched = counts > 0
    cells, counts = cells[watched], counts[watched]
    order = cells[np.lexsort((cells, counts))]
    entry_start, entry_cells, _ = _unique_keys(order, table.watch_start, table.watchers, usable, entry, grid.size)
    neighbours = grid.neighbours
    # Only usable watchers count: the greedy labels exactly those (``distance >= 0`` in choose_clusters).
    reach = np.where(usable, 0, -1).astype(np.int32)
    cluster_of, kept = choose_clusters(order, table.watch_start, table.watchers, reach)
    position = np.empty(grid.size, dtype=np.int64)
    position[order] = np.arange(len(order))
    greedy = position[kept]
    tree = int(spanning_tree_weight(neighbours, cluster_of, len(kept))) if len(kept) else 0
    widest = int(np.diff(table.sight_start).max(initial=0))
    pool = order[: candidates + widest].copy()
    pool_start, pool_states, pool_cells, pool_entries = _pool_watchers(
        pool, table.watch_start, table.watchers, usable, entry
    )
    member_start, members = _members_of_states(pool_start, pool_states, entry.size)
    radius = _reach_radius(pool, pool_start, pool_cells, neighbours)
    size = len(pool)
    # np.empty leaves untouched rows unallocated by the system: only the rows used cost memory.
    return AreaWatchers(
        usable, order, entry_start, entry_cells, position, greedy, tree, pool, pool_start, pool_states,
        pool_cells, pool_entries, member_start, members, radius,
        np.empty((size, grid.size), dtype=np.int32), np.empty((size, size), dtype=np.int32),
        np.empty((size, size), dtype=np.int32), np.zeros(size, dtype=np.bool_),
    )  # fmt: skip


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
    near = np.where(gap >= 0, gap, far).astype(np.int32)
    alive = alive.copy()
    value = np.full(size, far, dtype=np.int64)
    # The live candidates, in order; dead ones are dropped as each pick's pass meets them.
    live = np.flatnonzero(alive)
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
            area.gaps[best, :] = cell_distances(neighbours, pool_cells[begin:end])
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
    :func:`~guardsim.bounds.trees.cluster_distances` would give (zero where neither way is known)."""
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
    out = np.full(positions.shape[0], -1, dtype=np.int64)
    for index in range(positions.shape[0]):
        least = _least_gap(
            gap, area.entry_cells, area.entry_start[positions[index]], area.entry_start[positions[index] + 1], 1 << 30
        )
        if least < (1 << 30):
            out[index] = least + 1
    return out
