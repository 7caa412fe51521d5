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

import numba
import numpy as np

__all__ = ["cluster_distances", "path_bound", "spanning_tree_weight", "subset_tree_weight"]


@numba.njit(cache=True, nogil=True)
def _spread(neighbours: np.ndarray, label: np.ndarray, clusters: int, backward: bool) -> tuple[np.ndarray, np.ndarray]:
    """Search from all clusters at once: each state's distance from (or, ``backward``, to) the nearest
    cluster, and that cluster's number; -1 where none is connected."""
    states = label.shape[0]
    distance = np.full(states, -1, dtype=np.int32)
    nearest = np.full(states, -1, dtype=np.int32)
    queue = np.empty(states, dtype=np.int64)
    tail = 0
    for state in range(states):
        if 0 <= label[state] < clusters:
            distance[state] = 0
            nearest[state] = label[state]
            queue[tail] = state
            tail += 1
    head = 0
    while head < tail:
        state = queue[head]
        head += 1
        cell, heading = state // 4, state % 4
        if backward:
            # The moves into (c, h) come from every state of the cell behind c along h.
            behind = neighbours[cell, (heading + 2) % 4]
            if behind < 0:
                continue
            for other in range(behind * 4, behind * 4 + 4):
                if distance[other] < 0:
                    distance[other] = distance[state] + 1
                    nearest[other] = nearest[state]
                    queue[tail] = other
                    tail += 1
        else:
            for direction in range(4):
                there = neighbours[cell, direction]
                if there >= 0 and distance[there * 4 + direction] < 0:
                    other = there * 4 + direction
                    distance[other] = distance[state] + 1
                    nearest[other] = nearest[state]
                    queue[tail] = other
                    tail += 1
    return distance, nearest


@numba.njit(cache=True, nogil=True)
def _root(parent: np.ndarray, node: int) -> int:
    """Union-find root, halving the path on the way."""
    while parent[node] != node:
        parent[node] = parent[parent[node]]
        node = parent[node]
    return node


@numba.njit(cache=True, nogil=True)
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
        cell = state // 4
        for direction in range(4):
            there = neighbours[cell, direction]
            if there < 0:
                continue
            other = there * 4 + direction
            if behind[other] >= 0 and behind_label[other] != here:
                source[count], target[count] = here, behind_label[other]
                weight[count] = ahead[state] + 1 + behind[other]
                count += 1
    # Kruskal, the walks ordered by a counting sort on their lengths (small whole numbers).
    heaviest = weight[:count].max() if count else 0
    slot = np.zeros(heaviest + 2, dtype=np.int64)
    for index in range(count):
        slot[weight[index] + 1] += 1
    for value in range(heaviest + 1):
        slot[value + 1] += slot[value]
    order = np.empty(count, dtype=np.int64)
    for index in range(count):
        order[slot[weight[index]]] = index
        slot[weight[index]] += 1
    parent = np.arange(clusters)
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


@numba.njit(cache=True, nogil=True)
def cluster_distances(neighbours: np.ndarray, label: np.ndarray, clusters: int) -> np.ndarray:
    """``int64 (clusters, clusters)``: ``min(d(A -> B), d(B -> A))`` between clusters of ``label``.

    Any step is allowed from any heading, so the steps from state ``a`` to another state ``b`` are one
    more than the steps between cells from ``a``'s cell to ``b``'s entry cell (the cell behind it). One
    breadth-first search over cells per cluster, from its states' cells, then gives ``d(A -> B)`` as one
    plus the least distance of a ``B`` state's entry cell: four times fewer nodes than over states.
    """
    cells = neighbours.shape[0]
    states = label.shape[0]
    ahead = np.full((clusters, clusters), -1, dtype=np.int64)
    distance = np.full(cells, -1, dtype=np.int32)
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
            cell = members[k] // 4
            if distance[cell] < 0:
                distance[cell] = 0
                queue[tail] = cell
                tail += 1
        spread_steps(neighbours, distance, queue, tail)
        for target in range(clusters):
            if target == source:
                continue
            best = -1
            for k in range(members_start[target], members_start[target + 1]):
                state = members[k]
                behind = neighbours[state // 4, (state % 4 + 2) % 4]
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


@numba.njit(cache=True, nogil=True)
def subset_tree_weight(matrix: np.ndarray, members: np.ndarray) -> int:
    """Weight of the minimum spanning tree over the clusters ``members`` of a :func:`cluster_distances`
    matrix (Prim's algorithm on the dense matrix)."""
    count = members.shape[0]
    return prim_weight(matrix, members, count, np.empty(count, dtype=np.int64), np.empty(count, dtype=np.bool_))


@numba.njit(cache=True, nogil=True)
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


@numba.njit(cache=True, nogil=True)
def spread_steps(neighbours: np.ndarray, distance: np.ndarray, queue: np.ndarray, tail: int) -> None:
    """Breadth-first search over cells, in place: ``queue[:tail]`` holds the sources, already at their
    ``distance`` (0); every cell they reach gets its fewest steps, the others keep -1."""
    head = 0
    while head < tail:
        cell = queue[head]
        head += 1
        for direction in range(4):
            other = neighbours[cell, direction]
            if other >= 0 and distance[other] < 0:
                distance[other] = distance[cell] + 1
                queue[tail] = other
                tail += 1


@numba.njit(cache=True, nogil=True)
def path_bound(matrix: np.ndarray, start_edge: np.ndarray, members: np.ndarray) -> int:
    """The largest, over subsets of ``members``, of the shortest walk order from the start through
    every cluster of the subset: start edge to the first, then ``matrix`` between consecutive ones.

    Dynamic programming over subsets (Held and Karp 1962), ``2**n * n**2`` steps for ``n`` members. A
    covering walk enters the clusters in some order, each stretch at least the distance used here, so
    every subset's shortest order is a lower bound, hence the largest is.
    """
    size = members.shape[0]
    if size == 0:
        return 0
    subsets = 1 << size
    far = np.iinfo(np.int64).max // 4
    distance = np.empty((size, size), dtype=np.int64)
    for a in range(size):
        for b in range(size):
            distance[a, b] = matrix[members[a], members[b]]
    # best_path[mask, last]: the shortest order through ``mask`` ending at ``last``, pulled from the
    # orders through ``mask`` less ``last`` (reads only: several times quicker than pushing forward).
    best_path = np.full((subsets, size), far, dtype=np.int64)
    best = 0
    for mask in range(1, subsets):
        shortest = far
        for last in range(size):
            bit = 1 << last
            if not mask & bit:
                continue
            rest = mask ^ bit
            if rest == 0:
                value = start_edge[members[last]]
            else:
                value = far
                for previous in range(size):
                    if rest & (1 << previous):
                        value = min(value, best_path[rest, previous] + distance[previous, last])
            best_path[mask, last] = value
            shortest = min(shortest, value)
        best = max(best, shortest)
    return best
