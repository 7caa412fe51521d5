"""Minimum spanning trees over clusters of guard states, with distances between the clusters as weights.

A cluster is a set of states (the watchers of one cell), given as a label per state: the cluster's
number, or -1 for none; clusters are disjoint. The distance between clusters ``A`` and ``B`` is
``min(d(A -> B), d(B -> A))``, ``d`` being the fewest steps from any state of one to any state of the
other. Two ways to weigh the tree:

- :func:`spanning_tree_weight`, for any number of clusters: two searches over the state graph in all;
- :func:`cluster_distances` then :func:`subset_tree_weight`, for a few clusters and many subsets of them:
  one search per cluster, then each subset's tree from the matrix in microseconds.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.arrays import largest, upto
from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import spread, spread_states
from guardsim.kernels.steps import cell_of_state, heading_of_state, state_of
from guardsim.kernels.subsets import subset_path_bound

__all__ = ["cluster_distances", "path_bound", "spanning_tree_weight", "subset_tree_weight"]


@jit
def _spread(neighbours: np.ndarray, label: np.ndarray, clusters: int, backward: bool) -> tuple[np.ndarray, np.ndarray]:
    """Search from all clusters at once: each state's distance from (or, ``backward``, to) the nearest
    cluster, and that cluster's number; -1 where none is connected."""
    states = label.shape[0]
    distance = np.empty(states, dtype=np.int32)
    distance[:] = -1
    nearest = np.empty(states, dtype=np.int32)
    nearest[:] = -1
    queue = np.empty(states, dtype=np.int64)
    tail = 0
    for state in range(states):
        if 0 <= label[state] < clusters:
            distance[state] = 0
            nearest[state] = label[state]
            queue[tail] = state
            tail += 1
    spread_states(neighbours, queue, tail, -1, distance, backward, nearest)
    return distance, nearest


@jit
def _root(parent: np.ndarray, node: int) -> int:
    """Union-find root, halving the path on the way."""
    while parent[node] != node:
        parent[node] = parent[parent[node]]
        node = parent[node]
    return node


@jit
def spanning_tree_weight(neighbours: np.ndarray, label: np.ndarray, clusters: int) -> int:
    """Weight of the minimum spanning tree over clusters ``0 .. clusters - 1`` of ``label``.

    One search forward from all clusters and one backward to them give, for each state ``p`` reached,
    a walk from the nearest cluster behind ``p`` to the nearest cluster ahead of it, and for each move
    ``p -> q`` one through that move. Every such walk is at least the distance between its two clusters,
    and the spanning tree over these walks weighs exactly as much as over the true distances (Mehlhorn
    1988 for undirected graphs; the directed case is argued in ``docs/bounds.md``).
    """
    ahead, ahead_label = _spread(neighbours, label, clusters, False)
    behind, behind_label = _spread(neighbours, label, clusters, True)
    states = label.shape[0]
    source = np.empty(5 * states, dtype=np.int32)
    target = np.empty(5 * states, dtype=np.int32)
    weight = np.empty(5 * states, dtype=np.int64)
    count = 0
    for state in range(states):
        if ahead[state] < 0:
            continue
        here = ahead_label[state]
        if behind[state] >= 0 and behind_label[state] != here:
            source[count], target[count], weight[count] = here, behind_label[state], ahead[state] + behind[state]
            count += 1
        cell = cell_of_state(state)
        for direction in range(4):
            there = neighbours[cell, direction]
            if there < 0:
                continue
            other = state_of(there, direction)
            if behind[other] >= 0 and behind_label[other] != here:
                source[count], target[count] = here, behind_label[other]
                weight[count] = ahead[state] + 1 + behind[other]
                count += 1
    # Kruskal, the walks ordered by a counting sort on their lengths (small whole numbers).
    heaviest = largest(weight, count) if count else 0
    slot = np.zeros(heaviest + 2, dtype=np.int64)
    for index in range(count):
        slot[weight[index] + 1] += 1
    for value in range(heaviest + 1):
        slot[value + 1] += slot[value]
    order = np.empty(count, dtype=np.int64)
    for index in range(count):
        order[slot[weight[index]]] = index
        slot[weight[index]] += 1
    parent = upto(clusters)
    total = 0
    joined = 0
    for edge in order:
        if joined == clusters - 1:
            break
        a = _root(parent, source[edge])
        b = _root(parent, target[edge])
        if a != b:
            parent[a] = b
            total += int(weight[edge])
            joined += 1
    return total


@jit
def cluster_distances(neighbours: np.ndarray, label: np.ndarray, clusters: int) -> np.ndarray:
    """``int64 (clusters, clusters)``: ``min(d(A -> B), d(B -> A))`` between clusters of ``label``.

    Any step is allowed from any heading, so the steps from state ``a`` to another state ``b`` are one
    more than the steps between cells from ``a``'s cell to ``b``'s entry cell (the cell behind it). One
    breadth-first search over cells per cluster, from its states' cells, then gives ``d(A -> B)`` as one
    plus the least distance of a ``B`` state's entry cell: four times fewer nodes than over states.
    """
    cells = neighbours.shape[0]
    states = label.shape[0]
    ahead = np.empty((clusters, clusters), dtype=np.int64)
    ahead[:] = -1
    distance = np.empty(cells, dtype=np.int32)
    distance[:] = -1
    queue = np.empty(cells, dtype=np.int64)
    members_start = np.zeros(clusters + 1, dtype=np.int64)
    for state in range(states):
        if 0 <= label[state] < clusters:
            members_start[label[state] + 1] += 1
    for cluster in range(clusters):
        members_start[cluster + 1] += members_start[cluster]
    members = np.empty(members_start[clusters], dtype=np.int64)
    fill = members_start[:clusters].copy()
    for state in range(states):
        if 0 <= label[state] < clusters:
            members[fill[label[state]]] = state
            fill[label[state]] += 1
    for source in range(clusters):
        distance[:] = -1
        tail = 0
        for k in range(members_start[source], members_start[source + 1]):
            cell = cell_of_state(members[k])
            if distance[cell] < 0:
                distance[cell] = 0
                queue[tail] = cell
                tail += 1
        spread(neighbours, queue, tail, -1, distance, -1)
        for target in range(clusters):
            if target == source:
                continue
            best = -1
            for k in range(members_start[target], members_start[target + 1]):
                state = members[k]
                behind = neighbours[cell_of_state(state), (heading_of_state(state) + 2) % 4]
                if behind >= 0 and distance[behind] >= 0:
                    steps = distance[behind] + 1
                    if best < 0 or steps < best:
                        best = steps
            ahead[source, target] = best
    both = np.zeros((clusters, clusters), dtype=np.int64)
    for a in range(clusters):
        for b in range(clusters):
            if a == b:
                continue
            forward, backward = ahead[a, b], ahead[b, a]
            if forward >= 0 and backward >= 0:
                both[a, b] = min(forward, backward)
            else:
                # A walk covering both clusters joins them one way or the other, so one is always
                # known; zero keeps the tree a lower bound should neither be.
                both[a, b] = max(forward, backward, 0)
    return both


@jit
def subset_tree_weight(matrix: np.ndarray, members: np.ndarray) -> int:
    """Weight of the minimum spanning tree over the clusters ``members`` of a :func:`cluster_distances`
    matrix (Prim's algorithm on the dense matrix)."""
    count = members.shape[0]
    return prim_weight(matrix, members, count, np.empty(count, dtype=np.int64), np.empty(count, dtype=np.bool_))


@jit
def prim_weight(matrix: np.ndarray, members: np.ndarray, count: int, link: np.ndarray, inside: np.ndarray) -> int:
    """Prim's algorithm over ``members[:count]`` of a dense distance matrix, in the caller's scratch
    arrays ``link`` and ``inside`` (at least ``count`` long): the local search weighs thousands of small
    subsets and must not allocate for each."""
    if count < 2:
        return 0
    for k in range(count):
        link[k] = matrix[members[0], members[k]]
        inside[k] = k == 0
    total = 0
    for _ in range(count - 1):
        best = -1
        for k in range(count):
            if not inside[k] and (best < 0 or link[k] < link[best]):
                best = k
        inside[best] = True
        total += link[best]
        for k in range(count):
            if not inside[k] and matrix[members[best], members[k]] < link[k]:
                link[k] = matrix[members[best], members[k]]
    return total


@jit
def path_bound(matrix: np.ndarray, start_edge: np.ndarray, members: np.ndarray) -> int:
    """The largest, over subsets of ``members``, of the shortest walk order from the start through
    every cluster of the subset: start edge to the first, then ``matrix`` between consecutive ones.

    :func:`~guardsim.kernels.subsets.subset_path_bound`, ``2**n * n**2`` steps for ``n`` members.
    """
    size = members.shape[0]
    start = np.empty(size, dtype=np.int64)
    for k in range(size):
        start[k] = start_edge[members[k]]
    order = np.empty((1 << size) * size, dtype=np.int64)
    return subset_path_bound(start, matrix, members, size, order, np.iinfo(np.int64).max // 4)
