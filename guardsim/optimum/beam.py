"""Beam search over the exact search's macro moves: a short covering walk in bounded, deterministic work.

The search space is that of :mod:`guardsim.optimum.search` (a node is a position and the cells seen;
a move goes to a position that sees something new, along a shortest path through positions that do
not). Layer ``k`` holds nodes ``k`` macro moves from the start; each layer keeps the ``width`` nodes of
least ``g + h`` (ties: fewer steps, then the order found), ``h`` being the exact search's estimate, and
duplicate (position, seen) pairs are merged. The best complete node found is the walk. Work grows
with ``width`` times the number of macro moves, never with time.
"""

from __future__ import annotations

import numba
import numpy as np

from guardsim.optimum.graph import SearchGraph
from guardsim.optimum.heuristic import Heuristic, estimate, estimate_work
from guardsim.optimum.search import _frontier, _hash, frontier_work

__all__ = ["beam_route"]


@numba.njit(cache=True, nogil=True)
def _beam(
    heuristic: Heuristic,
    successors: np.ndarray,
    views: np.ndarray,
    full: np.ndarray,
    start: int,
    known: np.ndarray,
    width: int,
) -> tuple[np.ndarray, int]:
    positions = successors.shape[0]
    words = full.shape[0]
    most_layers = positions * 4 + 4
    # Nodes of all layers kept: position, steps, parent, seen.
    room = width * 4 + 16
    node_position = np.empty(room, dtype=np.int64)
    node_steps = np.empty(room, dtype=np.int64)
    node_parent = np.empty(room, dtype=np.int64)
    node_seen = np.empty((room, words), dtype=np.uint64)
    count = 0
    distance, queue, found, found_steps = frontier_work(positions)
    kept, link, gap, order = estimate_work(heuristic)
    node_position[0] = start
    node_steps[0] = 0
    node_parent[0] = -1
    node_seen[0] = views[start] | known
    count = 1
    layer = np.zeros(1, dtype=np.int64)
    best_node, best_steps = -1, 1 << 40
    done = True
    for word in range(words):
        if node_seen[0, word] != full[word]:
            done = False
    if done:
        return np.array([start], dtype=np.int64), 0
    seen = np.empty(words, dtype=np.uint64)
    for _ in range(most_layers):
        if layer.shape[0] == 0:
            break
        # Children of the layer, merged on (position, seen) through a small hash table.
        child_position: list[int] = []
        child_steps: list[int] = []
        child_parent: list[int] = []
        child_key: list[int] = []
        child_seen: list[np.ndarray] = []
        slots = 1 << 4
        while slots < 2 * layer.shape[0] * positions and slots < (1 << 22):
            slots <<= 1
        table = np.full(slots, -1, dtype=np.int64)
        for node in layer:
            here = node_position[node]
            found_count = _frontier(successors, views, here, node_seen[node], distance, queue, found, found_steps)
            for index in range(found_count):
                there = int(found[index])
                steps = int(node_steps[node] + found_steps[index])
                if steps >= best_steps:
                    continue
                complete = True
                for word in range(words):
                    seen[word] = node_seen[node, word] | views[there, word]
                    if seen[word] != full[word]:
                        complete = False
                slot = np.int64(_hash(there, seen) >> np.uint64(1)) & (slots - 1)
                merged = False
                while table[slot] >= 0:
                    other = table[slot]
                    if child_position[other] == there:
                        same = True
                        for word in range(words):
                            if child_seen[other][word] != seen[word]:
                                same = False
                                break
                        if same:
                            if steps < child_steps[other]:
                                child_steps[other] = steps
                                child_parent[other] = int(node)
                            merged = True
                            break
                    slot = (slot + 1) & (slots - 1)
                if merged:
                    continue
                if len(child_position) * 2 >= slots:
                    continue  # the table is full: a deterministic, rare truncation
                table[slot] = len(child_position)
                child_position.append(there)
                child_steps.append(steps)
                child_parent.append(int(node))
                child_seen.append(seen.copy())
                child_key.append(-1 if complete else 0)
        total = len(child_position)
        if total == 0:
            break
        scores = np.empty(total, dtype=np.int64)
        for index in range(total):
            if child_key[index] < 0:
                scores[index] = child_steps[index]
            else:
                scores[index] = child_steps[index] + estimate(
                    heuristic, child_position[index], child_seen[index], full, kept, link, gap, order
                )
        # Least g + h first; ties to fewer steps, then the order found (a stable sort).
        ranks = np.argsort(scores * (1 << 20) + np.array(child_steps), kind="mergesort")
        if count + width + 1 > room:
            # Keep the arrays bounded: drop nothing needed, since parents are only read back at the end.
            grow = max(room * 2, count + width + 1)
            node_position = _grow(node_position, grow)
            node_steps = _grow(node_steps, grow)
            node_parent = _grow(node_parent, grow)
            wider = np.empty((grow, words), dtype=np.uint64)
            wider[:room] = node_seen
            node_seen = wider
            room = grow
        next_layer: list[int] = []
        for rank in ranks:
            if len(next_layer) >= width:
                break
            if scores[rank] >= best_steps:
                break
            kept_node = count
            count += 1
            node_position[kept_node] = child_position[rank]
            node_steps[kept_node] = child_steps[rank]
            node_parent[kept_node] = child_parent[rank]
            node_seen[kept_node] = child_seen[rank]
            if child_key[rank] < 0:
                if child_steps[rank] < best_steps:
                    best_node, best_steps = kept_node, child_steps[rank]
            else:
                next_layer.append(kept_node)
        layer = np.array(next_layer, dtype=np.int64) if next_layer else np.zeros(0, dtype=np.int64)
    if best_node < 0:
        return np.zeros(0, dtype=np.int64), -1
    route: list[int] = []
    back = best_node
    while back >= 0:
        route.append(node_position[back])
        back = node_parent[back]
    result = np.empty(len(route), dtype=np.int64)
    for index in range(len(route)):
        result[index] = route[len(route) - 1 - index]
    return result, best_steps


@numba.njit(cache=True, nogil=True)
def _grow(array: np.ndarray, size: int) -> np.ndarray:
    wider = np.empty(size, dtype=array.dtype)
    wider[: array.shape[0]] = array
    return wider


def beam_route(
    graph: SearchGraph, heuristic: Heuristic, width: int, known: np.ndarray | None = None
) -> tuple[np.ndarray, int]:
    """The macro-move positions (the start first) and steps of the best covering walk a beam of
    ``width`` finds; an empty route and -1 if it finds none (some goal cell no position sees).

    ``known`` (a goal bitset, :func:`~guardsim.optimum.graph.goal_bits`) marks cells seen before the start.
    """
    if known is None:
        known = np.zeros_like(graph.full)
    route, steps = _beam(heuristic, graph.successors, graph.views, graph.full, graph.start, known, width)
    return route, int(steps)
