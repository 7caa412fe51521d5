"""Best-first search for a team's makespan: the fewest ticks until K guards together have seen the goal.

The guards move at once, a cell a tick each, or wait. What they have seen at the end is the union of
what each saw on its own walk, whenever it saw it, so the makespan of a team is the longest of K walks
that together see every goal cell: the ticks line up by themselves (a guard done early waits). The
search therefore builds the walks one guard after the other, in the order of the starts:

- a node is (the guard ``k`` now walking, its position, its steps ``g``, the longest walk ``G`` of the
  guards before it, the cells seen by all of them so far, the starts' views included);
- its successors are guard ``k``'s macro moves (:func:`guardsim.kernels.frontier.frontier`: the nearest
  positions that see something unseen, at their shortest distance) and, unless ``k`` is the last guard,
  *handing over*: guard ``k`` stops there and guard ``k + 1`` sets off from its start, ``G`` becoming
  ``max(G, g)``;
- the bound of a node is ``max(G, g, max over unseen cells c of min(g + d_k(c), min over later guards
  j of d_j(c)))``, ``d(c)`` being the steps from a guard's position (or start) to the nearest position
  that sees ``c``: each unseen cell must still be seen by guard ``k`` or by a later guard, and none of
  them walks less than that to see it. For the last guard it is also ``g`` plus the one-guard estimate
  (:func:`guardsim.kernels.estimate.estimate`, pivots and all), taken when the node reaches the top of
  the heap, as the one-guard search does. A child's bound is at least its parent's (pathmax).

*Why no optimum is lost.* Take K walks of an optimal team. Walk 1, split where it sees something new
(new to the starts' views and to what it saw itself), is a chain of guard 1's macro moves, each no
longer than its stretch of the walk; then guard 1 hands over, and walk 2 splits the same way against
everything seen so far, and so on; a guard whose walk adds nothing hands over at once. That chain of
nodes reaches a complete node whose makespan is at most the optimal one. A node is dropped only when an
earlier node of the same guard and position has seen at least its cells with no more steps and no
longer walks before it, which can then finish no later.

Nodes live in flat arrays like :mod:`guardsim.search.astar`'s, found again through a hash table on
(guard, position, ``G``, seen); the heap (:mod:`guardsim.kernels.heap`) is ordered on the bound, ties
to the later guard and then the longer walk. The search runs in chunks of expansions.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.arrays import copy_into
from guardsim.kernels.compiler import jit
from guardsim.kernels.estimate import Heuristic, estimate, estimate_work
from guardsim.kernels.frontier import drop_shadowed, frontier, frontier_work, node_hash
from guardsim.kernels.heap import heap_pop, heap_push
from guardsim.kernels.nodes import find_node, is_dominated, new_table, store_node
from guardsim.kernels.team_estimate import split_bound, team_bound
from guardsim.search.astar import (
    EXPANSIONS,
    FLOOR,
    FULL,
    GENERATED,
    HEAP,
    INCUMBENT,
    INCUMBENT_NODE,
    NODES,
    PROVED,
    RUNNING,
    STATUS,
)

__all__ = ["TeamSearchState", "new_team_state", "run_team", "start_team", "team_routes"]

_KEY_SHIFT = 1 << 16
#: Steps of one guard's walk that the heap's tie-break tells apart.
_TIE_STEPS = 4096


class TeamSearchState(NamedTuple):
    """Everything an interrupted team search needs to go on."""

    guard: np.ndarray
    """``int32 (capacity,)``: the guard walking at each node (its index among the starts)."""
    position: np.ndarray
    """``int32 (capacity,)``: that guard's position."""
    steps: np.ndarray
    """``int32 (capacity,)``: that guard's steps so far (g)."""
    before: np.ndarray
    """``int32 (capacity,)``: the longest walk of the guards before it (G)."""
    parent: np.ndarray
    """``int32 (capacity,)``: the node it was reached from (-1 for the root)."""
    bound: np.ndarray
    """``int32 (capacity,)``: the node's lower bound on the makespan."""
    exact: np.ndarray
    """``bool (capacity,)``: whether the bound includes the one-guard estimate (last guard only)."""
    seen: np.ndarray
    """``uint64 (capacity, words)``: the goal cells seen by the team so far."""
    heap_key: np.ndarray
    """``int64``: heap entries' ``bound * 65536 + tie``."""
    heap_node: np.ndarray
    """``int32``: heap entries' nodes."""
    table: np.ndarray
    """``int64 (power of two,)``: hash slots, node + 1, 0 for empty."""
    counters: np.ndarray
    """``int64 (8,)``: as :class:`guardsim.search.astar.SearchState`'s (the incumbent is a makespan)."""
    latest: np.ndarray
    """``int32 (guards * positions,)``: the node stored last for each (guard, position), -1 for none."""
    earlier: np.ndarray
    """``int32 (capacity,)``: the node stored before it for the same (guard, position), -1 for none."""


def new_team_state(capacity: int, words: int, positions: int, guards: int) -> TeamSearchState:
    """Empty arrays for at most ``capacity`` nodes."""
    return TeamSearchState(
        np.zeros(capacity, dtype=np.int32),
        np.zeros(capacity, dtype=np.int32),
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
        np.full(guards * positions, -1, dtype=np.int32),
        np.full(capacity, -1, dtype=np.int32),
    )


@jit(inline="always")
def _key(bound: int, guard: int, steps: int) -> int:
    tie = min(guard * _TIE_STEPS + min(steps, _TIE_STEPS - 1), _KEY_SHIFT - 1)
    return bound * _KEY_SHIFT + (_KEY_SHIFT - 1 - tie)


@jit(inline="always")
def _find(
    state: TeamSearchState, guard: int, position: int, before: int, seen: np.ndarray, positions: int
) -> tuple[int, int]:
    """(node, slot): the node of (guard, position, G, seen), or -1 and the empty slot where it would go."""
    value = node_hash(guard * positions + position, seen) ^ (np.uint64(before) * np.uint64(0x94D049BB133111EB))
    labels = (state.position, state.guard, state.before)
    label = (np.int64(position), np.int64(guard), np.int64(before))
    return find_node(state.table, value, labels, label, state.seen, seen)


@jit(inline="always")
def _dominated(
    state: TeamSearchState, chain: int, steps: int, before: int, seen: np.ndarray, checks: int, itself: int
) -> bool:
    """Whether one of the last ``checks`` nodes of the same (guard, position) saw at least ``seen`` with
    no more steps and no longer walks before it."""
    costs = (state.steps, state.before)
    cost = (np.int64(steps), np.int64(before))
    return is_dominated(state.latest, state.earlier, chain, costs, cost, state.seen, seen, checks, itself)


@jit
def _add(
    state: TeamSearchState,
    slot: int,
    chain: int,
    guard: int,
    position: int,
    steps: int,
    before: int,
    parent: int,
    bound: int,
    seen: np.ndarray,
) -> int:
    node = store_node(state.counters, state.table, state.latest, state.earlier, state.seen, slot, chain, seen)
    state.guard[node] = guard
    state.position[node] = position
    state.steps[node] = steps
    state.before[node] = before
    state.parent[node] = parent
    state.bound[node] = bound
    state.exact[node] = False
    return node


@jit
def start_team(
    state: TeamSearchState,
    heuristic: Heuristic,
    later: np.ndarray,
    starts: np.ndarray,
    views: np.ndarray,
    full: np.ndarray,
    incumbent: int,
) -> None:
    """Put the root (the first guard at its start, the starts' views seen) in the heap; ``incumbent`` is
    the makespan of a known covering team walk."""
    counters = state.counters
    counters[:] = 0
    counters[INCUMBENT] = incumbent
    counters[INCUMBENT_NODE] = -1
    positions = views.shape[0]
    guards = starts.shape[0]
    seen = np.zeros(full.shape[0], dtype=np.uint64)
    for k in range(guards):
        for word in range(full.shape[0]):
            seen[word] |= views[starts[k], word]
    bound = team_bound(heuristic, later, 0, starts[0], 0, 0, seen, full)
    work = estimate_work(heuristic)
    kept, link, gap, order = work
    if guards == 1:
        bound = max(bound, estimate(heuristic, starts[0], seen, full, kept, link, gap, order))
    else:
        need = np.empty(heuristic.to_watchers.shape[1], dtype=np.int16)
        cost = np.empty((guards, 1 << heuristic.pivots), dtype=np.int64)
        combined = np.empty((2, 1 << heuristic.pivots), dtype=np.int64)
        bound = max(bound, split_bound(heuristic, later, starts, 0, starts[0], 0, seen, need, work, cost, combined))
    _, slot = _find(state, 0, starts[0], 0, seen, positions)
    node = _add(state, slot, starts[0], 0, starts[0], 0, 0, -1, bound, seen)
    state.exact[node] = True
    counters[FLOOR] = bound
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
    if bound < incumbent:
        counters[HEAP] = heap_push(state.heap_key, state.heap_node, counters[HEAP], _key(bound, 0, 0), node)


@jit
def _offer(
    state: TeamSearchState,
    heuristic: Heuristic,
    later: np.ndarray,
    full: np.ndarray,
    guard: int,
    position: int,
    steps: int,
    before: int,
    parent: int,
    floor: int,
    seen: np.ndarray,
    checks: int,
) -> None:
    """Store (or improve) the child and push it, unless it is dominated or cannot beat the incumbent."""
    counters = state.counters
    positions = state.latest.shape[0] // later.shape[0]
    chain = guard * positions + position
    makespan = max(before, steps)
    if makespan >= counters[INCUMBENT]:
        return
    complete = True
    for word in range(full.shape[0]):
        if seen[word] != full[word]:
            complete = False
            break
    counters[GENERATED] += 1
    other, slot = _find(state, guard, position, before, seen, positions)
    if other >= 0:
        if state.steps[other] <= steps:
            return
        state.steps[other] = steps
        state.parent[other] = parent
        # Not the old bound: it counted the old steps.
        bound = max(floor, team_bound(heuristic, later, guard, position, steps, before, seen, full))
        state.bound[other] = bound
        state.exact[other] = complete
    else:
        if _dominated(state, chain, steps, before, seen, checks, -1):
            return
        if counters[NODES] >= state.position.shape[0]:
            counters[STATUS] = FULL
            return
        bound = (
            makespan
            if complete
            else max(floor, team_bound(heuristic, later, guard, position, steps, before, seen, full))
        )
        if bound >= counters[INCUMBENT]:
            return
        other = _add(state, slot, chain, guard, position, steps, before, parent, bound, seen)
        state.exact[other] = complete
    if complete:
        counters[INCUMBENT] = makespan
        counters[INCUMBENT_NODE] = other
        return
    if bound >= counters[INCUMBENT]:
        return
    if counters[HEAP] >= state.heap_key.shape[0]:
        counters[STATUS] = FULL
        return
    counters[HEAP] = heap_push(state.heap_key, state.heap_node, counters[HEAP], _key(bound, guard, steps), other)


@jit
def run_team(
    state: TeamSearchState,
    heuristic: Heuristic,
    later: np.ndarray,
    starts: np.ndarray,
    successors: np.ndarray,
    views: np.ndarray,
    full: np.ndarray,
    budget: int,
    checks: int,
) -> None:
    """Expand at most ``budget`` nodes, or until the optimum is proved or the node arrays are full."""
    counters = state.counters
    positions = successors.shape[0]
    words = full.shape[0]
    guards = starts.shape[0]
    distance, queue, found, found_steps = frontier_work(positions)
    mark = np.zeros(positions, dtype=np.int8)
    work = estimate_work(heuristic)
    kept, link, gap, order = work
    need = np.empty(heuristic.to_watchers.shape[1], dtype=np.int16)
    cost = np.empty((guards, 1 << heuristic.pivots), dtype=np.int64)
    combined = np.empty((2, 1 << heuristic.pivots), dtype=np.int64)
    seen = np.empty(words, dtype=np.uint64)
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
        counters[FLOOR] = f
        key, node, counters[HEAP] = heap_pop(state.heap_key, state.heap_node, counters[HEAP])
        guard, here, g, before = state.guard[node], state.position[node], state.steps[node], state.before[node]
        if key != _key(state.bound[node], guard, g):
            continue  # a stale entry: the node was reached more cheaply, or its bound rose, since
        if _dominated(state, guard * positions + here, g, before, state.seen[node], checks, node):
            continue
        if not state.exact[node]:
            # Once, at the heap's top: the last guard must see the rest alone (the one-guard estimate);
            # before it, the pivots shared out among the guards left.
            state.exact[node] = True
            if guard == guards - 1:
                raised = g + estimate(heuristic, here, state.seen[node], full, kept, link, gap, order)
            else:
                raised = split_bound(
                    heuristic, later, starts, guard, here, g, state.seen[node], need, work, cost, combined
                )
            if raised > state.bound[node]:
                state.bound[node] = raised
                if raised < counters[INCUMBENT]:
                    counters[HEAP] = heap_push(
                        state.heap_key, state.heap_node, counters[HEAP], _key(raised, guard, g), node
                    )
                continue
        expanded += 1
        counters[EXPANSIONS] += 1
        floor = state.bound[node]
        count = frontier(successors, views, here, state.seen[node], distance, queue, found, found_steps)
        # As for one guard (kernels.frontier.drop_shadowed): walking through a move's position to a
        # move it shadows is no longer for this guard and sees at least as much, the other guards'
        # walks unchanged, so some optimal team completion makes no shadowed move.
        count = drop_shadowed(successors, here, found, found_steps, count, distance, queue, mark)
        for index in range(count):
            there = found[index]
            for word in range(words):
                seen[word] = state.seen[node, word] | views[there, word]
            _offer(
                state, heuristic, later, full, guard, there, g + found_steps[index], before, node, floor, seen, checks
            )
            if counters[STATUS] == FULL:
                break
        if guard + 1 < guards and counters[STATUS] == RUNNING:
            copy_into(seen, 0, state.seen[node])
            _offer(
                state,
                heuristic,
                later,
                full,
                guard + 1,
                starts[guard + 1],
                0,
                max(before, g),
                node,
                floor,
                seen,
                checks,
            )


def team_routes(state: TeamSearchState, node: int, starts: np.ndarray) -> list[np.ndarray]:
    """Each guard's macro-move positions (its start first) on the way from the root to ``node``."""
    chain = []
    while node >= 0:
        chain.append(node)
        node = int(state.parent[node])
    routes: list[list[int]] = [[int(start)] for start in starts.tolist()]
    for node in reversed(chain[:-1]):
        guard, position = int(state.guard[node]), int(state.position[node])
        if int(state.steps[node]) > 0:
            routes[guard].append(position)
    return [np.array(route, dtype=np.int64) for route in routes]
