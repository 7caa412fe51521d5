"""The cluster bound: cells with disjoint watcher sets, and the spanning tree they force a walk to span.

Any walk from the start that sees every goal cell passes through a watcher of each chosen cell; with
pairwise disjoint watcher sets ("clusters") it meets them one after another, so it is at least as long
as the distance from the start to the nearest cluster plus a minimum spanning tree over the clusters
(``docs/bounds.md``). Every choice of clusters gives a valid bound; this module searches for a good one.
"""

from __future__ import annotations

import numpy as np

from guardsim.bounds.area import choose_clusters
from guardsim.bounds.watchers import state_distances
from guardsim.kernels.arrays import count_true, largest, smallest, upto
from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import new_fill
from guardsim.kernels.picks import AreaWatchers, pick_matrix, spread_picks, start_edges
from guardsim.kernels.steps import cell_of_state
from guardsim.kernels.trees import path_bound, prim_weight, spanning_tree_weight
from guardsim.vision.table import ViewTable

__all__ = [
    "MOST_CLUSTERS",
    "MOST_TRIALS",
    "PATH_CLUSTERS",
    "SPREAD_CANDIDATES",
    "choose_clusters",
    "cluster_bound",
]

#: Most clusters the farthest-first choice picks.
MOST_CLUSTERS = 48
#: Candidates of the farthest-first picks: the cells with the fewest reachable watchers.
SPREAD_CANDIDATES = 1000
#: Farthest-first picks the path bound orders (its work grows as ``2**n * n**2``).
PATH_CLUSTERS = 10
#: Most subsets of the picks the local search weighs per start.
MOST_TRIALS = 20_000


@jit
def _subset_bound(matrix: np.ndarray, start_edge: np.ndarray, chosen: np.ndarray) -> int:
    """The cluster bound of the chosen clusters: their tree plus the shortest start edge among them."""
    size = chosen.shape[0]
    return _chosen_bound(
        matrix, start_edge, chosen, np.empty(size, np.int64), np.empty(size, np.int64), np.empty(size, np.bool_)
    )


@jit
def _chosen_bound(
    matrix: np.ndarray,
    start_edge: np.ndarray,
    chosen: np.ndarray,
    members: np.ndarray,
    link: np.ndarray,
    inside: np.ndarray,
) -> int:
    """:func:`_subset_bound` in the scratch arrays ``members``, ``link`` and ``inside`` (the local search
    weighs thousands of small subsets and must not allocate for each)."""
    count = 0
    for cluster in range(chosen.shape[0]):
        if chosen[cluster]:
            members[count] = cluster
            count += 1
    if count == 0:
        return 0
    nearest = start_edge[members[0]]
    for k in range(count):
        nearest = min(nearest, start_edge[members[k]])
    return prim_weight(matrix, members, count, link, inside) + nearest


@jit
def _local_search(matrix: np.ndarray, start_edge: np.ndarray, chosen: np.ndarray, most_trials: int) -> tuple[int, int]:
    """Add, drop or swap one cluster while that raises the bound: first improvement, at most
    ``most_trials`` subsets weighed. Returns the bound and the number of clusters."""
    clusters = matrix.shape[0]
    chosen = chosen.copy()
    members = np.empty(clusters, dtype=np.int64)
    link = np.empty(clusters, dtype=np.int64)
    inside = np.empty(clusters, dtype=np.bool_)
    value = _chosen_bound(matrix, start_edge, chosen, members, link, inside)
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
                trial = _chosen_bound(matrix, start_edge, chosen, members, link, inside)
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
    return value, count_true(chosen)


@jit
def _eccentricity(
    order: np.ndarray, entry_start: np.ndarray, entry_cells: np.ndarray, gap: np.ndarray, seen: np.ndarray, lower: int
) -> int:
    """The largest nearest-watcher distance over the cells of ``order`` not ``seen`` (at least
    ``lower``): a cell stops being scanned as soon as one watcher is known to be no farther than the
    largest so far, which is all the maximum needs."""
    largest = lower
    for index in range(order.shape[0]):
        if seen[order[index]]:
            continue
        nearest = -1
        for k in range(entry_start[index], entry_start[index + 1]):
            here = gap[entry_cells[k]]
            if here >= 0 and (nearest < 0 or here + 1 < nearest):
                nearest = here + 1
                if nearest <= largest:
                    break
        largest = max(largest, nearest)
    return largest


@jit
def _best_subset(
    matrix: np.ndarray, start_edge: np.ndarray, most_trials: int, path_clusters: int
) -> tuple[int, int, int]:
    """The best prefix of the picks, improved by :func:`_local_search`, and the path bound of the first
    ``path_clusters``: (cluster bound, its clusters, path bound)."""
    size = matrix.shape[0]
    best_count, best_value = 1, -1
    chosen = np.zeros(size, dtype=np.bool_)
    members = np.empty(size, dtype=np.int64)
    link = np.empty(size, dtype=np.int64)
    inside = np.empty(size, dtype=np.bool_)
    for count in range(1, size + 1):
        chosen[count - 1] = True
        value = _chosen_bound(matrix, start_edge, chosen, members, link, inside)
        if value > best_value:
            best_count, best_value = count, value
    first = np.zeros(size, dtype=np.bool_)
    for count in range(best_count):
        first[count] = True
    value, clusters = _local_search(matrix, start_edge, first, most_trials)
    path = path_bound(matrix, start_edge, upto(min(size, path_clusters)))
    return value, clusters, path


def cluster_bound(
    neighbours: np.ndarray,
    table: ViewTable,
    area: AreaWatchers,
    start_state: int,
) -> tuple[int, int, int, int]:
    """The eccentricity bound, the cluster bound, its number of clusters, and the path bound.

    The cluster bound is the best over several choices. Every choice keeps goal cells not seen from
    the start whose reachable watcher sets are pairwise disjoint, and is worth the minimum spanning
    tree over them plus the distance from the start to the nearest of them. Any such choice gives a
    valid bound, so the largest found is returned. The choices:

    - fewest reachable watchers first, among the cells not seen from the start (any number of clusters,
      each tree weighed by :func:`~guardsim.kernels.trees.spanning_tree_weight`); when the start sees
      none of the cells this keeps over all of the area, it keeps the same cells, so the area's tree
      serves (:mod:`guardsim.bounds.area`). On the shipped levels and the six Moving AI starts of
      ``docs/bounds.md`` further orders (cells at least 1/2 or 3/4 of the eccentricity away,
      farthest nearest watcher first) never raised the best bound, so they are not tried (issue 15);
    - up to :data:`MOST_CLUSTERS` cells picked farthest first (:func:`~guardsim.kernels.picks.spread_picks`) among the
      :data:`SPREAD_CANDIDATES` cells with the fewest reachable watchers not seen from the start:
      every prefix of the picks, then a local search over their subsets. More clusters do not always
      give more: a cluster between two others can shorten the tree.

    The **path bound** orders the first :data:`PATH_CLUSTERS` farthest-first picks instead of spanning
    them: the shortest order from the start through a subset of them, the largest over the subsets
    (:func:`~guardsim.kernels.trees.path_bound`). A walk is a path, so this is never below the tree of
    the same clusters and often well above it (a maze's dead ends, visited one after another).

    Parameters
    ----------
    neighbours
        The grid's connectivity.
    table
        The level's visible cells per state and watchers per cell.
    area
        The start's area (:func:`~guardsim.bounds.area.area_watchers`, built with
        :data:`SPREAD_CANDIDATES`).
    start_state
        The start cell times 4 plus the first heading.
    """
    seen = np.zeros(neighbours.shape[0], dtype=np.bool_)
    seen[table.sees(start_state)] = True
    kept, tree = area.greedy, area.greedy_tree
    greedy_only = False
    if len(kept) and seen[area.order[kept]].any():
        if area.usable[start_state]:
            # The start state is a usable watcher, so it watches one kept cell at most: the walk enters
            # that cluster at step 0, the others later, and the tree alone is a bound (start edge 0).
            greedy_only = True
        else:
            # Choose again without the cells seen at step 0, as for one start alone.
            order = area.order[~seen[area.order]]
            distance = state_distances(neighbours, start_state)
            label, cells = choose_clusters(order, table.watch_start, table.watchers, distance)
            kept = area.position[cells]
            tree = int(spanning_tree_weight(neighbours, label, len(kept))) if len(kept) else 0
    eccentricity, greedy_edge, value, count, path, picks = _start_bounds(
        area,
        kept,
        seen,
        cell_of_state(start_state),
        neighbours,
        SPREAD_CANDIDATES,
        MOST_CLUSTERS,
        MOST_TRIALS,
        PATH_CLUSTERS,
    )
    best = (tree + (0 if greedy_only else int(greedy_edge)), len(kept)) if len(kept) else (0, 0)
    if picks < 2:
        return int(eccentricity), *best, best[0]
    return int(eccentricity), *max(best, (int(value), int(count))), int(path)


@jit
def _start_bounds(
    area: AreaWatchers,
    kept: np.ndarray,
    seen: np.ndarray,
    start_cell: int,
    neighbours: np.ndarray,
    candidates: int,
    most: int,
    most_trials: int,
    path_clusters: int,
) -> tuple[int, int, int, int, int, int]:
    """The per-start work in one compiled call (passing the area costs 0.1 ms a call): the eccentricity,
    the greedy clusters' start edge, the picks' cluster bound, its clusters, the path bound and the
    number of picks."""
    gap = new_fill(neighbours, -1, np.full(1, start_cell, dtype=np.int64))
    greedy_edge = smallest(start_edges(area, kept, gap), kept.shape[0]) if kept.shape[0] else 0
    alive = np.zeros(area.pool.shape[0], dtype=np.bool_)
    count = 0
    for position in range(area.pool.shape[0]):
        if not seen[area.pool[position]] and count < candidates:
            alive[position] = True
            count += 1
    picks = spread_picks(area, alive, gap, neighbours, most)
    edges = start_edges(area, picks, gap)
    lower = largest(edges, edges.shape[0]) if edges.shape[0] else 0
    eccentricity = _eccentricity(area.order, area.entry_start, area.entry_cells, gap, seen, lower)
    if picks.shape[0] < 2:
        return eccentricity, greedy_edge, 0, 0, 0, picks.shape[0]
    # The picks share no watcher, so every subset of them is a valid choice.
    value, clusters, path = _best_subset(pick_matrix(area, picks), edges, most_trials, path_clusters)
    return eccentricity, greedy_edge, value, clusters, path, picks.shape[0]
