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

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.kernels.arrays import copy_into
from guardsim.kernels.compiler import jit
from guardsim.kernels.csr import invert_csr
from guardsim.kernels.distances import new_fill
from guardsim.kernels.picks import AreaWatchers
from guardsim.kernels.steps import cell_of_state
from guardsim.kernels.trees import spanning_tree_weight
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import ViewTable, level_memo

__all__ = ["AreaWatchers", "area_watchers", "choose_clusters"]


@jit
def choose_clusters(
    order: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, distance: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Greedy: keep each cell of ``order`` none of whose reachable watchers a cell kept before holds.

    Only watchers with ``distance >= 0`` (reachable from the start) count. Returns the cluster number of
    every state (-1 for none) and the kept cells, cluster by cluster.
    """
    label = np.empty(distance.shape[0], dtype=np.int32)
    label[:] = -1
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
def _unique_keys(
    cells: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, usable: np.ndarray, key: np.ndarray, size: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per cell of ``cells``: the distinct ``key`` of its usable watchers (CSR start and values) and how
    many usable watchers it has."""
    stamp = np.empty(size, dtype=np.int64)
    stamp[:] = -1
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
                copy_into(grown, 0, flat[:used])
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
def _reach_radius(
    pool: np.ndarray, pool_start: np.ndarray, pool_cells: np.ndarray, neighbours: np.ndarray
) -> np.ndarray:
    """Per pool cell: the largest distance between cells from it to one of its watchers' cells."""
    radius = np.zeros(pool.shape[0], dtype=np.int64)
    one = np.empty(1, dtype=np.int64)
    for position in range(pool.shape[0]):
        one[0] = pool[position]
        gap = new_fill(neighbours, -1, one)
        for k in range(pool_start[position], pool_start[position + 1]):
            radius[position] = max(radius[position], gap[pool_cells[k]])
    return radius


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
    member_start, members = invert_csr(pool_start, pool_states, entry.size)
    radius = _reach_radius(pool, pool_start, pool_cells, neighbours)
    size = len(pool)
    # np.empty leaves untouched rows unallocated by the system: only the rows used cost memory.
    return AreaWatchers(
        usable, order, entry_start, entry_cells, position, greedy, tree, pool, pool_start, pool_states,
        pool_cells, pool_entries, member_start, members, radius,
        np.empty((size, grid.size), dtype=np.int32), np.empty((size, size), dtype=np.int32),
        np.empty((size, size), dtype=np.int32), np.zeros(size, dtype=np.bool_),
    )  # fmt: skip
