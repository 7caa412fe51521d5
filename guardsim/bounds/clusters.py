"""The cluster bound: cells with disjoint watcher sets, and the spanning tree they force a walk to span.

Any walk from the start that sees every goal cell passes through a watcher of each chosen cell; with
pairwise disjoint watcher sets ("clusters") it meets them one after another, so it is at least as long
as the distance from the start to the nearest cluster plus a minimum spanning tree over the clusters
(``docs/bounds.md``). Every choice of clusters gives a valid bound; this module searches for a good one.
"""

from __future__ import annotations

import numba
import numpy as np

from guardsim.bounds.trees import cluster_distances, path_bound, spanning_tree_weight, subset_tree_weight
from guardsim.vision.table import ViewTable

__all__ = [
    "FAR_FRACTIONS",
    "MOST_CLUSTERS",
    "MOST_TRIALS",
    "PATH_CLUSTERS",
    "SPREAD_CANDIDATES",
    "choose_clusters",
    "cluster_bound",
    "spread_picks",
]

#: Most clusters the farthest-first choice picks.
MOST_CLUSTERS = 48
#: Candidates of the farthest-first picks: the cells with the fewest reachable watchers.
SPREAD_CANDIDATES = 1000
#: Farthest-first picks the path bound orders (its work grows as ``2**n * n**2``).
PATH_CLUSTERS = 10
#: Most subsets of the picks the local search weighs per start.
MOST_TRIALS = 20_000
#: The fewest-watchers-first choices keep only cells whose nearest watcher is at least this fraction of
#: the eccentricity bound away (far cells spread the clusters out).
FAR_FRACTIONS: tuple[float, ...] = (0.0,)


@numba.njit(cache=True, nogil=True)
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


@numba.njit(cache=True, nogil=True)
def _relax(gap: np.ndarray, queue: np.ndarray, neighbours: np.ndarray, tail: int) -> None:
    """Lower the cell distances ``gap`` by a breadth-first search from the ``tail`` cells queued."""
    head = 0
    while head < tail:
        cell = queue[head]
        head += 1
        for direction in range(4):
            other = neighbours[cell, direction]
            if other >= 0 and gap[other] > gap[cell] + 1:
                gap[other] = gap[cell] + 1
                queue[tail] = other
                tail += 1


@numba.njit(cache=True, nogil=True)
def _separation(
    cell: int,
    watch_start: np.ndarray,
    watchers: np.ndarray,
    distance: np.ndarray,
    gap: np.ndarray,
    taken: np.ndarray,
    far: int,
) -> int:
    """The smallest ``gap`` over the cells of ``cell``'s reachable watchers; -1 if one is taken."""
    separation = far
    for k in range(watch_start[cell], watch_start[cell + 1]):
        state = watchers[k]
        if distance[state] >= 0:
            if taken[state]:
                return -1
            separation = min(separation, gap[state // 4])
    return separation


@numba.njit(cache=True, nogil=True)
def _sift_down(keys: np.ndarray, size: int, index: int) -> None:
    """Restore the min-heap order of ``keys[:size]`` below ``index``."""
    key = keys[index]
    while True:
        child = 2 * index + 1
        if child >= size:
            break
        if child + 1 < size and keys[child + 1] < keys[child]:
            child += 1
        if keys[child] >= key:
            break
        keys[index] = keys[child]
        index = child
    keys[index] = key


@numba.njit(cache=True, nogil=True)
def spread_picks(
    cells: np.ndarray,
    watch_start: np.ndarray,
    watchers: np.ndarray,
    distance: np.ndarray,
    neighbours: np.ndarray,
    start_cell: int,
    most: int,
) -> np.ndarray:
    """Up to ``most`` cells picked farthest first, their reachable watcher sets pairwise disjoint.

    Each pick is the candidate whose reachable watchers' cells lie farthest, in steps between cells,
    from the start cell and from the watchers of earlier picks (its separation), among candidates
    sharing no watcher with them; ties go to the earlier in ``cells``. Separations only shrink as picks
    are added, so stale ones in the heap are upper bounds and only the top needs recomputing (lazy greedy).
    The heap is one ``int64`` key per candidate, ``(far - separation) * 2**24 + position``.
    """
    size = neighbours.shape[0]
    far = np.iinfo(np.int32).max // 2
    gap = np.full(size, far, dtype=np.int32)
    taken = np.zeros(distance.shape[0], dtype=np.bool_)
    queue = np.empty(size * 4 + 1, dtype=np.int64)
    gap[start_cell] = 0
    queue[0] = start_cell
    _relax(gap, queue, neighbours, 1)
    shift = np.int64(1) << 24
    keys = np.empty(cells.shape[0], dtype=np.int64)
    heap = 0
    for position in range(cells.shape[0]):
        # A guard sees its own cell, so a cell's separation is at most its own distance: an upper
        # bound, which is all the lazy greedy needs, and far cheaper than the exact value for all.
        keys[heap] = (far - gap[cells[position]]) * shift + position
        heap += 1
    for index in range(heap // 2 - 1, -1, -1):
        _sift_down(keys, heap, index)
    picks = np.empty(most, dtype=np.int64)
    count = 0
    while count < most and heap > 0:
        stale = far - keys[0] // shift
        position = keys[0] % shift
        cell = cells[position]
        separation = _separation(cell, watch_start, watchers, distance, gap, taken, far)
        if separation < 0:
            heap -= 1
            keys[0] = keys[heap]
            _sift_down(keys, heap, 0)
            continue
        if separation < stale:
            keys[0] = (far - separation) * shift + position
            _sift_down(keys, heap, 0)
            continue
        heap -= 1
        keys[0] = keys[heap]
        _sift_down(keys, heap, 0)
        picks[count] = cell
        count += 1
        tail = 0
        for k in range(watch_start[cell], watch_start[cell + 1]):
            state = watchers[k]
            if distance[state] >= 0:
                taken[state] = True
                if gap[state // 4] > 0:
                    gap[state // 4] = 0
                    queue[tail] = state // 4
                    tail += 1
        _relax(gap, queue, neighbours, tail)
    return picks[:count]


@numba.njit(cache=True, nogil=True)
def _subset_bound(matrix: np.ndarray, start_edge: np.ndarray, chosen: np.ndarray) -> int:
    """The cluster bound of the chosen clusters: their tree plus the shortest start edge among them."""
    members = np.flatnonzero(chosen)
    if members.shape[0] == 0:
        return 0
    return subset_tree_weight(matrix, members) + start_edge[members].min()


@numba.njit(cache=True, nogil=True)
def _local_search(matrix: np.ndarray, start_edge: np.ndarray, chosen: np.ndarray, most_trials: int) -> tuple[int, int]:
    """Add, drop or swap one cluster while that raises the bound: first improvement, at most
    ``most_trials`` subsets weighed. Returns the bound and the number of clusters."""
    clusters = matrix.shape[0]
    chosen = chosen.copy()
    value = _subset_bound(matrix, start_edge, chosen)
    trials = 0
    improved = True
    while improved and trials < most_trials:
        improved = False
        # Leave ``out`` (-1: none) and enter ``into`` (-1: none): adds first, then per ``out`` drop and swaps.
        for out in range(-1, clusters):
            if improved or trials >= most_trials:
                break
            if out >= 0 and not chosen[out]:
                continue
            for into in range(-1, clusters):
                if (out < 0 and into < 0) or (into >= 0 and chosen[into]):
                    continue
                if out >= 0:
                    chosen[out] = False
                if into >= 0:
                    chosen[into] = True
                trial = _subset_bound(matrix, start_edge, chosen)
                trials += 1
                if trial > value:
                    value = trial
                    improved = True
                    break
                if out >= 0:
                    chosen[out] = True
                if into >= 0:
                    chosen[into] = False
                if trials >= most_trials:
                    break
    return value, int(chosen.sum())


def cluster_bound(
    neighbours: np.ndarray,
    table: ViewTable,
    goal_cells: np.ndarray,
    nearest: np.ndarray,
    reachable: np.ndarray,
    distance: np.ndarray,
    start_cell: int,
) -> tuple[int, int, int]:
    """The cluster bound, its number of clusters, and the path bound: the best over several choices.

    Every choice keeps goal cells not seen from the start whose reachable watcher sets are pairwise
    disjoint, and is worth the minimum spanning tree over them plus the distance from the start to the
    nearest of them. Any such choice gives a valid bound, so the largest found is returned. The choices:

    - fewest reachable watchers first, among cells at least each of :data:`FAR_FRACTIONS` of the
      eccentricity away (any number of clusters, each tree weighed by
      :func:`~guardsim.bounds.trees.spanning_tree_weight`); on the shipped levels and the six Moving AI
      starts of ``docs/bounds.md`` the fractions 1/2 and 3/4 and a farthest-nearest-watcher-first order
      never raised the best bound, so they are no longer tried (issue 15: 1.5 ms of 9 per start);
    - up to :data:`MOST_CLUSTERS` cells picked farthest first (:func:`spread_picks`) among the
      :data:`SPREAD_CANDIDATES` cells with the fewest reachable watchers: every prefix of the
      picks, then a local search over their subsets. More clusters do not always give more: a cluster
      between two others can shorten the tree.

    The **path bound** orders the first :data:`PATH_CLUSTERS` farthest-first picks instead of spanning
    them: the shortest order from the start through a subset of them, the largest over the subsets
    (:func:`~guardsim.bounds.trees.path_bound`). A walk is a path, so this is never below the tree of
    the same clusters and often well above it (a maze's dead ends, visited one after another).

    Parameters
    ----------
    neighbours
        The grid's connectivity.
    table
        The level's visible cells per state and watchers per cell.
    goal_cells, nearest, reachable
        Goal cells, the distance from the start to their nearest reachable watcher, and how many of their
        watchers are reachable (:func:`~guardsim.bounds.watchers.nearest_watchers`).
    distance, start_cell
        State distances from the start state, and the start cell.
    """
    unseen = nearest > 0
    cells, nearest, reachable = goal_cells[unseen], nearest[unseen], reachable[unseen]
    start_edge_of = np.zeros(neighbours.shape[0], dtype=np.int64)
    start_edge_of[cells] = nearest
    by_watchers = cells[np.lexsort((cells, reachable))]
    farthest = int(nearest.max(initial=0))
    choices = [by_watchers[start_edge_of[by_watchers] >= fraction * farthest] for fraction in FAR_FRACTIONS]
    best = (0, 0)
    for choice in choices:
        label, kept = choose_clusters(choice, table.watch_start, table.watchers, distance)
        if len(kept):
            tree = int(spanning_tree_weight(neighbours, label, len(kept)))
            best = max(best, (tree + int(start_edge_of[kept].min()), len(kept)))
    picks = spread_picks(
        by_watchers[:SPREAD_CANDIDATES],
        table.watch_start,
        table.watchers,
        distance,
        neighbours,
        start_cell,
        MOST_CLUSTERS,
    )
    if len(picks) < 2:
        return (*best, best[0])
    # The picks share no watcher, so every subset of them is a valid choice.
    label, _ = choose_clusters(picks, table.watch_start, table.watchers, distance)
    matrix = cluster_distances(neighbours, label, len(picks))
    start_edge = start_edge_of[picks]
    prefixes = [np.arange(len(picks)) < count for count in range(1, len(picks) + 1)]
    values = [_subset_bound(matrix, start_edge, prefix) for prefix in prefixes]
    value, count = _local_search(matrix, start_edge, prefixes[int(np.argmax(values))], MOST_TRIALS)
    path = int(path_bound(matrix, start_edge, np.arange(min(len(picks), PATH_CLUSTERS))))
    return (*max(best, (int(value), int(count))), path)
