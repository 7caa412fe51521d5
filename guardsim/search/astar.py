"""A* over (position, cells seen so far), with macro moves from one newly seeing position to the next.

A node is a position and the set of goal cells seen on the way there. Its successors are the positions
that would see an unseen cell ("frontier" positions) and can be reached without passing another one,
each at its breadth-first distance, found by a search from the node that stops at frontier positions.
Any covering walk splits at the steps where it sees something new; between two such steps it sees
nothing new, so it can be replaced by a shortest path through positions that see nothing new, and the
split walk is a path of these macro moves no longer than the walk. So the search misses no optimum.

Nodes are kept in flat arrays (position, steps, parent, seen bitset), found again through the node
store's hash table on (position, seen) (:mod:`guardsim.kernels.nodes`), and ordered by a binary heap on ``f = g + h`` (ties:
the deeper node first). The estimate ``h`` is :func:`guardsim.kernels.estimate.estimate`, with
pathmax. A greedy walk (nearest frontier first) gives the first incumbent; nodes whose ``f`` reaches the
incumbent are never stored. The search runs in chunks of expansions, so the caller can stop it between
chunks; everything it needs lives in the :class:`SearchState` arrays.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba.extending import register_jitable

from guardsim.kernels.compiler import jit
from guardsim.kernels.estimate import Heuristic, eccentricity, estimate, estimate_work, pattern_value
from guardsim.kernels.frontier import drop_shadowed, frontier, frontier_work, node_hash
from guardsim.kernels.heap import heap_pop, heap_push
from guardsim.kernels.nodes import find_node, is_dominated, new_table, store_node

__all__ = ["FULL", "PROVED", "RUNNING", "SearchState", "greedy_walk", "new_search_state", "run_search", "start_search"]

#: Status codes in ``counters[STATUS]``.
RUNNING, PROVED, FULL = 0, 1, 2
# Counter slots.
NODES, HEAP, EXPANSIONS, GENERATED, INCUMBENT, INCUMBENT_NODE, STATUS, FLOOR = range(8)
_KEY_SHIFT = 1 << 16


class SearchState(NamedTuple):
    """Everything an interrupted search needs to go on."""

    position: np.ndarray
    """``int32 (capacity,)``: each node's position."""
    steps: np.ndarray
    """``int32 (capacity,)``: each node's best known steps from the start (g)."""
    parent: np.ndarray
    """``int32 (capacity,)``: the node it was reached from (-1 for the root)."""
    estimate: np.ndarray
    """``int32 (capacity,)``: its estimate h."""
    exact: np.ndarray
    """``bool (capacity,)``: whether h is the full estimate (else only the cheap one, until popped)."""
    seen: np.ndarray
    """``uint64 (capacity, words)``: the goal cells it has seen."""
    heap_key: np.ndarray
    """``int64``: heap entries' ``f * 65536 + (65535 - g)``."""
    heap_node: np.ndarray
    """``int32``: heap entries' nodes."""
    table: np.ndarray
    """``int64 (power of two,)``: hash slots, node + 1, 0 for empty."""
    counters: np.ndarray
    """``int64 (8,)``: nodes, heap size, expansions, generated, incumbent steps, incumbent node, status,
    and the proved floor (the least f left when the search stopped)."""
    latest: np.ndarray
    """``int32 (positions,)``: the node stored last at each position, -1 for none."""
    earlier: np.ndarray
    """``int32 (capacity,)``: the node stored before it at the same position, -1 for none."""


def new_search_state(capacity: int, words: int, positions: int) -> SearchState:
    """Empty arrays for at most ``capacity`` nodes (the node arrays fill in order; the hash table is
    probed at random, so it gets small pages)."""
    return SearchState(
        np.zeros(capacity, dtype=np.int32),
        np.zeros(capacity, dtype=np.int32),
        np.zeros(capacity, dtype=np.int32),
        np.zeros(capacity, dtype=np.int32),
        np.zeros(capacity, dtype=np.bool_),
        np.zeros((capacity, words), dtype=np.uint64),
        np.zeros(2 * capacity, dtype=np.int64),
        np.zeros(2 * capacity, dtype=np.int32),
        new_table(capacity),
        np.zeros(8, dtype=np.int64),
        np.full(positions, -1, dtype=np.int32),
        np.full(capacity, -1, dtype=np.int32),
    )


@jit(inline="always")
def _find(state: SearchState, position: int, seen: np.ndarray) -> tuple[int, int]:
    """(node, slot): the node of (position, seen), or -1 and the empty slot where it would go."""
    return find_node(state.table, node_hash(position, seen), (state.position,), (np.int64(position),), state.seen, seen)


@jit
def greedy_walk(successors: np.ndarray, views: np.ndarray, full: np.ndarray, start: int) -> tuple[np.ndarray, int]:
    """The nearest-frontier walk: its macro-move positions (the start first) and its steps.

    Ties go to the position seeing the most unseen cells, then to the one found first.
    """
    positions = successors.shape[0]
    words = full.shape[0]
    distance, queue, found, found_steps = frontier_work(positions)
    seen = views[start].copy()
    route = [start]
    steps = 0
    here = start
    while True:
        done = True
        for word in range(words):
            if seen[word] != full[word]:
                done = False
        if done:
            break
        count = frontier(successors, views, here, seen, distance, queue, found, found_steps)
        if count == 0:
            return np.zeros(0, dtype=np.int64), -1
        best, best_steps, best_gain = -1, 0, -1
        for index in range(count):
            gain = 0
            for word in range(words):
                left = views[found[index], word] & ~seen[word]
                while left:
                    left &= left - np.uint64(1)
                    gain += 1
            if best < 0 or found_steps[index] < best_steps or (found_steps[index] == best_steps and gain > best_gain):
                best, best_steps, best_gain = index, found_steps[index], gain
        here = found[best]
        steps += best_steps
        for word in range(words):
            seen[word] |= views[here, word]
        route.append(here)
    result = np.empty(len(route), dtype=np.int64)
    for index in range(len(route)):
        result[index] = route[index]
    return result, steps


@jit
def _add(state: SearchState, slot: int, position: int, steps: int, parent: int, h: int, seen: np.ndarray) -> int:
    node = store_node(state.counters, state.table, state.latest, state.earlier, state.seen, slot, position, seen)
    state.position[node] = position
    state.steps[node] = steps
    state.parent[node] = parent
    state.estimate[node] = h
    return node


@jit(inline="always")
def _dominated(state: SearchState, position: int, steps: int, seen: np.ndarray, checks: int, itself: int) -> bool:
    """Whether one of the last ``checks`` nodes stored at ``position`` (other than ``itself``) saw at
    least ``seen`` in at most ``steps``."""
    return is_dominated(
        state.latest, state.earlier, position, (state.steps,), (np.int64(steps),), state.seen, seen, checks, itself
    )


@register_jitable(inline="always")
def _f(g: int, h: int, weight: float) -> int:
    """The heap's key: ``g + h``, or ``g + floor(weight * h)`` for a weighted search."""
    return g + h if weight == 1.0 else g + int(weight * h)


@jit
def start_search(
    state: SearchState,
    heuristic: Heuristic,
    views: np.ndarray,
    full: np.ndarray,
    start: int,
    incumbent: int,
    weight: float = 1.0,
) -> None:
    """Put the root in the heap; ``incumbent`` is the steps of a known covering walk; ``weight`` as in
    :func:`run_search`."""
    counters = state.counters
    counters[:] = 0
    counters[INCUMBENT] = incumbent
    counters[INCUMBENT_NODE] = -1
    kept, link, gap, order = estimate_work(heuristic)
    seen = views[start].copy()
    h = estimate(heuristic, start, seen, full, kept, link, gap, order)
    _, slot = _find(state, start, seen)
    node = _add(state, slot, start, 0, -1, h, seen)
    state.exact[node] = True
    counters[FLOOR] = h
    done = True
    for word in range(full.shape[0]):
        if seen[word] != full[word]:
            done = False
    if done:
        counters[INCUMBENT] = 0
        counters[INCUMBENT_NODE] = node
        counters[STATUS] = PROVED
        counters[FLOOR] = 0
        return
    if _f(0, h, weight) < incumbent:
        counters[HEAP] = heap_push(
            state.heap_key, state.heap_node, counters[HEAP], _f(0, h, weight) * _KEY_SHIFT + (_KEY_SHIFT - 1), node
        )


@jit
def run_search(
    state: SearchState,
    heuristic: Heuristic,
    successors: np.ndarray,
    views: np.ndarray,
    full: np.ndarray,
    budget: int,
    checks: int,
    weight: float = 1.0,
    shadows: bool = False,
) -> None:
    """Expand at most ``budget`` nodes, or until the optimum is proved or the node arrays are full.

    A new node is dropped when one of the last ``checks`` nodes at its position dominates it. With
    ``weight`` W > 1 the heap is ordered on ``g + floor(W * h)`` (weighted A*): when its least key reaches
    the incumbent, the incumbent is at most W times the optimum (a node of an optimal walk waits in the
    heap with its optimal g, so its key is at most W times the optimum).
    """
    counters = state.counters
    positions = successors.shape[0]
    words = full.shape[0]
    capacity = state.position.shape[0]
    heap_room = state.heap_key.shape[0]
    distance, queue, found, found_steps = frontier_work(positions)
    kept, link, gap, order = estimate_work(heuristic)
    seen = np.empty(words, dtype=np.uint64)
    mark = np.zeros(positions if shadows else 0, dtype=np.int8)
    expanded = 0
    while counters[STATUS] == RUNNING and expanded < budget:
        if counters[HEAP] == 0:
            counters[STATUS] = PROVED
            counters[FLOOR] = counters[INCUMBENT]
            break
        key = state.heap_key[0]
        f = key // _KEY_SHIFT
        if f >= counters[INCUMBENT]:
            counters[STATUS] = PROVED
            counters[FLOOR] = counters[INCUMBENT]
            break
        if weight == 1.0:
            counters[FLOOR] = f  # a weighted key bounds nothing
        key, popped, counters[HEAP] = heap_pop(state.heap_key, state.heap_node, counters[HEAP])
        # As int64, like the walks start_search and the beam hand over: kernels called with a narrower
        # integer would be compiled a second time for it.
        node = np.int64(popped)
        g = _KEY_SHIFT - 1 - key % _KEY_SHIFT
        if g != state.steps[node]:
            continue  # a stale entry: the node was reached more cheaply since
        here = np.int64(state.position[node])
        if _dominated(state, here, g, state.seen[node], checks, node):
            continue
        if not state.exact[node]:
            # Lazy evaluation: the full estimate only for nodes that reach the top of the heap.
            state.exact[node] = True
            h = estimate(heuristic, here, state.seen[node], full, kept, link, gap, order)
            if h > state.estimate[node]:
                state.estimate[node] = h
                if _f(g, h, weight) > f:
                    if _f(g, h, weight) < counters[INCUMBENT]:
                        counters[HEAP] = heap_push(
                            state.heap_key,
                            state.heap_node,
                            counters[HEAP],
                            _f(g, h, weight) * _KEY_SHIFT + (_KEY_SHIFT - 1 - g),
                            node,
                        )
                    continue
        expanded += 1
        counters[EXPANSIONS] += 1
        parent_h = state.estimate[node]
        count = frontier(successors, views, here, state.seen[node], distance, queue, found, found_steps)
        if shadows:
            count = drop_shadowed(successors, here, found, found_steps, count, distance, queue, mark)
        for index in range(count):
            there = found[index]
            steps = g + found_steps[index]
            if steps >= counters[INCUMBENT]:
                continue
            complete = True
            for word in range(words):
                seen[word] = state.seen[node, word] | views[there, word]
                if seen[word] != full[word]:
                    complete = False
            counters[GENERATED] += 1
            other, slot = _find(state, there, seen)
            if other >= 0:
                if state.steps[other] <= steps:
                    continue
                state.steps[other] = steps
                state.parent[other] = node
                h = state.estimate[other]
            else:
                if _dominated(state, there, steps, seen, checks, -1):
                    continue
                if counters[NODES] >= capacity:
                    counters[STATUS] = FULL
                    break
                h = (
                    0
                    if complete
                    else max(eccentricity(heuristic, there, seen, full), pattern_value(heuristic, there, seen))
                )
                h = max(h, parent_h - found_steps[index])
                if _f(steps, h, weight) >= counters[INCUMBENT]:
                    continue
                other = _add(state, slot, there, steps, node, h, seen)
                state.exact[other] = complete
            if complete:
                counters[INCUMBENT] = steps
                counters[INCUMBENT_NODE] = other
                continue
            if counters[HEAP] >= heap_room:
                counters[STATUS] = FULL
                break
            counters[HEAP] = heap_push(
                state.heap_key,
                state.heap_node,
                counters[HEAP],
                _f(steps, h, weight) * _KEY_SHIFT + (_KEY_SHIFT - 1 - steps),
                other,
            )
