"""Open travelling-salesman tours: a fixed first node, every other node once, no return.

Costs may be asymmetric (the steps from viewpoint a to viewpoint b differ from b to a, since arriving
in a viewpoint fixes the last step). The tour is built by the nearest-neighbour rule and improved by
local search until no move shortens it:

- 2-opt (Croes 1958): reverse a stretch of the tour;
- Or-opt (Or 1976): move a stretch of one to three nodes elsewhere, forwards or reversed.

Both are evaluated in constant time per move with prefix sums of the forward and backward leg costs,
and only moves that create a leg between near nodes are tried (neighbour lists, as in Johnson and
McGeoch 1997, "The travelling salesman problem: a case study in local optimization").
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["improve_tour", "nearest_neighbour_tour", "tour_cost"]


@jit
def nearest_neighbour_tour(cost: np.ndarray, first: int, nodes: np.ndarray) -> np.ndarray:
    """``first``, then repeatedly the cheapest node not yet visited (ties to the earliest in ``nodes``)."""
    tour = np.empty(nodes.shape[0] + 1, dtype=np.int64)
    tour[0] = first
    used = np.zeros(nodes.shape[0], dtype=np.bool_)
    here = first
    for position in range(1, tour.shape[0]):
        best = -1
        for index in range(nodes.shape[0]):
            if not used[index] and (best < 0 or cost[here, nodes[index]] < cost[here, nodes[best]]):
                best = index
        used[best] = True
        here = nodes[best]
        tour[position] = here
    return tour


@jit
def tour_cost(cost: np.ndarray, tour: np.ndarray) -> int:
    """Sum of the legs of an open tour."""
    total = 0
    for position in range(tour.shape[0] - 1):
        total += cost[tour[position], tour[position + 1]]
    return total


@jit
def _prefix(cost: np.ndarray, tour: np.ndarray, forward: np.ndarray, backward: np.ndarray) -> None:
    """``forward[k]``: cost of legs 0..k-1 as walked; ``backward[k]``: the same legs walked the other way."""
    forward[0] = 0
    backward[0] = 0
    for position in range(tour.shape[0] - 1):
        forward[position + 1] = forward[position] + cost[tour[position], tour[position + 1]]
        backward[position + 1] = backward[position] + cost[tour[position + 1], tour[position]]


@jit
def _leg(cost: np.ndarray, tour: np.ndarray, a: int, b: int) -> int:
    """Cost from position ``a`` to position ``b``; nothing when ``b`` is past the end (open tour)."""
    if b >= tour.shape[0]:
        return 0
    return cost[tour[a], tour[b]]


@jit
def _reposition(cost: np.ndarray, tour: np.ndarray, forward: np.ndarray, backward: np.ndarray, at: np.ndarray) -> None:
    """Refresh the prefix sums and ``at[node]``, the position of each node in the tour."""
    _prefix(cost, tour, forward, backward)
    for position in range(tour.shape[0]):
        at[tour[position]] = position


@jit
def _two_opt(
    cost: np.ndarray, tour: np.ndarray, forward: np.ndarray, backward: np.ndarray, at: np.ndarray, near: np.ndarray
) -> bool:
    """Reverse stretches ``tour[i..j]`` that shorten the tour, where ``tour[j]`` is near ``tour[i - 1]``."""
    length = tour.shape[0]
    improved = False
    for i in range(1, length - 1):
        for candidate in near[tour[i - 1]]:
            j = at[candidate]
            if j <= i:
                continue
            old = cost[tour[i - 1], tour[i]] + forward[j] - forward[i] + _leg(cost, tour, j, j + 1)
            new = cost[tour[i - 1], tour[j]] + backward[j] - backward[i]
            if j + 1 < length:
                new += cost[tour[i], tour[j + 1]]
            if new < old:
                for k in range((j + 1 - i) // 2):
                    tour[i + k], tour[j - k] = tour[j - k], tour[i + k]
                _reposition(cost, tour, forward, backward, at)
                improved = True
                break
    return improved


@jit
def _move_stretch(tour: np.ndarray, i: int, j: int, gap: int, flip: bool) -> None:
    """Move ``tour[i..j]`` (reversed if ``flip``) to between ``tour[gap]`` and ``tour[gap + 1]``."""
    size = j + 1 - i
    stretch = np.empty(size, dtype=np.int64)
    for k in range(size):
        stretch[k] = tour[j - k] if flip else tour[i + k]
    if gap < i:
        # The nodes gap+1 .. i-1 shift right by the stretch's size.
        for k in range(i - 1, gap, -1):
            tour[k + size] = tour[k]
        for k in range(size):
            tour[gap + 1 + k] = stretch[k]
    else:
        # The nodes j+1 .. gap shift left.
        for k in range(j + 1, gap + 1):
            tour[k - size] = tour[k]
        for k in range(size):
            tour[gap + 1 - size + k] = stretch[k]


@jit
def _or_opt(
    cost: np.ndarray, tour: np.ndarray, forward: np.ndarray, backward: np.ndarray, at: np.ndarray, near: np.ndarray
) -> bool:
    """Move stretches of 1-3 nodes, forwards or reversed, next to a node near their first one, when it helps."""
    length = tour.shape[0]
    improved = False
    for size in range(1, 4):
        i = 1
        while i <= length - size:
            j = i + size - 1
            # Taking tour[i..j] out joins tour[i - 1] to tour[j + 1].
            removed = (
                cost[tour[i - 1], tour[i]]
                + forward[j]
                - forward[i]
                + _leg(cost, tour, j, j + 1)
                - _leg(cost, tour, i - 1, j + 1)
            )
            moved = False
            for candidate in near[tour[i]]:
                for gap in (at[candidate], at[candidate] - 1):
                    # Insert between tour[gap] and tour[gap + 1], outside the stretch and its edges.
                    if gap < 0 or i - 1 <= gap <= j:
                        continue
                    after = _leg(cost, tour, gap, gap + 1)
                    for flip in (False, True):
                        head, tail = (tour[j], tour[i]) if flip else (tour[i], tour[j])
                        inner = backward[j] - backward[i] if flip else forward[j] - forward[i]
                        added = cost[tour[gap], head] + inner - after
                        if gap + 1 < length:
                            added += cost[tail, tour[gap + 1]]
                        if added < removed:
                            _move_stretch(tour, i, j, gap, flip)
                            _reposition(cost, tour, forward, backward, at)
                            moved = True
                            break
                    if moved:
                        break
                if moved:
                    break
            improved |= moved
            i += 1
    return improved


def improve_tour(cost: np.ndarray, tour: np.ndarray, neighbours: int = 12, max_rounds: int = 1000) -> np.ndarray:
    """2-opt and Or-opt until neither shortens the tour; ``tour[0]`` stays first.

    Only moves that create a leg between near nodes are tried (each node's ``neighbours`` nearest by
    the cost there and back), the usual neighbour-list restriction that keeps a pass close to linear.

    Parameters
    ----------
    cost
        ``int64 (nodes, nodes)``: cost of going from one node to another.
    tour
        ``int64``: node numbers, the fixed first node first. Not modified.
    neighbours
        Near nodes considered per node.
    max_rounds
        A safety limit on passes; each pass that changes the tour strictly shortens it.

    Returns
    -------
    numpy.ndarray
        The improved tour.
    """
    tour = np.array(tour, dtype=np.int64)
    count = min(neighbours, tour.shape[0] - 1)
    near = np.empty((cost.shape[0], max(count, 0)), dtype=np.int64)
    if count > 0:
        # Each member's nearest others there and back, ties in tour order (a stable sort).
        there_and_back = cost[np.ix_(tour, tour)] + cost[np.ix_(tour, tour)].T
        order = np.argsort(there_and_back, axis=1, kind="stable")
        ranked = tour[order]
        others = ranked[ranked != tour[:, None]].reshape(tour.shape[0], -1)
        near[tour] = others[:, :count]
    return _improve(cost, tour, near, max_rounds)


@jit
def _improve(cost: np.ndarray, tour: np.ndarray, near: np.ndarray, max_rounds: int) -> np.ndarray:
    length = tour.shape[0]
    forward = np.zeros(length, dtype=np.int64)
    backward = np.zeros(length, dtype=np.int64)
    at = np.empty(cost.shape[0], dtype=np.int64)
    at[:] = -1
    _reposition(cost, tour, forward, backward, at)
    for _ in range(max_rounds):
        changed = _two_opt(cost, tour, forward, backward, at, near)
        changed |= _or_opt(cost, tour, forward, backward, at, near)
        if not changed:
            break
    return tour
