"""The residual goal: the goal cells a covering walk must still aim for, the others being seen on the way.

A goal cell can be dropped from the search's goal when seeing another goal cell, kept, implies seeing it:

- **seen at the start**: the start position sees it;
- **cell dominance**: every position that sees a kept cell ``a`` also sees ``b`` (``W(a) ⊆ W(b)``, the
  watcher sets), so a walk that sees ``a`` has seen ``b``;
- **path dominance**: every walk from the start to a watcher of a kept cell ``a`` passes a watcher of
  ``b`` (the watchers of ``a`` are unreachable from the start once ``b``'s are removed), so a walk that
  sees ``a`` has seen ``b`` on the way.

Cells are dropped one at a time, each for a cell still kept, so the reasons form chains that end at a
kept cell: a walk that sees every kept cell sees every goal cell, and the covering walks, hence the
optimum, are the same. The search over (position, cells seen) then tells apart far fewer seen sets, and
fewer positions are frontier positions. (The watchman-route solver MWRP-CP3, Gouru, Felner and Li,
"Scalable algorithms with provable optimality bounds for the multiple watchman route problem", 2026,
prunes cells by the same two kinds of dominance.)
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.search.graph import SearchGraph

__all__ = ["residual_goal"]


@jit
def _watcher_sets(views: np.ndarray, bits: np.ndarray) -> np.ndarray:
    """``uint64 (len(bits), position words)``: the positions that see each goal bit, as bitsets."""
    positions = views.shape[0]
    words = (positions + 63) // 64
    sets = np.zeros((bits.shape[0], words), dtype=np.uint64)
    for index in range(bits.shape[0]):
        bit = bits[index]
        word, shift = bit >> 6, np.uint64(bit & 63)
        for position in range(positions):
            if (views[position, word] >> shift) & np.uint64(1):
                sets[index, position >> 6] |= np.uint64(1) << np.uint64(position & 63)
    return sets


@jit(inline="always")
def _subset(sets: np.ndarray, a: int, b: int) -> bool:
    word = 0
    while word < sets.shape[1] and not sets[a, word] & ~sets[b, word]:
        word += 1
    return word == sets.shape[1]


@jit
def _cell_dominance(sets: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Which cells to keep: in ``order`` (fewest watchers first), a cell is dropped when a cell already
    kept has a watcher set inside its own."""
    keep = np.zeros(sets.shape[0], dtype=np.bool_)
    kept = np.empty(sets.shape[0], dtype=np.int64)
    count = 0
    for b in order:
        dominated = False
        for k in range(count):
            if _subset(sets, kept[k], b):
                dominated = True
                break
        if not dominated:
            keep[b] = True
            kept[count] = b
            count += 1
    return keep


@jit
def _path_dominance(successors: np.ndarray, start: int, sets: np.ndarray, keep: np.ndarray, order: np.ndarray) -> None:
    """Drop, in ``order``, each kept cell whose watchers every walk from the start to some other kept
    cell's watchers must pass (in place on ``keep``)."""
    positions = successors.shape[0]
    words = sets.shape[1]
    reached = np.zeros(words, dtype=np.uint64)
    queue = np.empty(positions, dtype=np.int64)
    for b in order:
        if not keep[b]:
            continue
        # Positions reachable from the start without entering a watcher of b.
        reached[:] = 0
        queue[0] = start
        reached[start >> 6] |= np.uint64(1) << np.uint64(start & 63)
        head, tail = 0, 1
        while head < tail:
            here = queue[head]
            head += 1
            for direction in range(4):
                there = successors[here, direction]
                if there < 0:
                    continue
                word, bit = there >> 6, np.uint64(1) << np.uint64(there & 63)
                if (reached[word] & bit) or (sets[b, word] & bit):
                    continue
                reached[word] |= bit
                queue[tail] = there
                tail += 1
        for a in range(sets.shape[0]):
            if a == b or not keep[a]:
                continue
            blocked = True
            for word in range(words):
                if sets[a, word] & reached[word]:
                    blocked = False
                    break
            if blocked:
                keep[b] = False
                break


@jit
def _restrict(views: np.ndarray, bits: np.ndarray) -> np.ndarray:
    """Each position's view over the kept bits only, renumbered ``0 .. len(bits) - 1``."""
    words = max(1, (bits.shape[0] + 63) // 64)
    out = np.zeros((views.shape[0], words), dtype=np.uint64)
    for index in range(bits.shape[0]):
        bit = bits[index]
        word, shift = bit >> 6, np.uint64(bit & 63)
        for position in range(views.shape[0]):
            if (views[position, word] >> shift) & np.uint64(1):
                out[position, index >> 6] |= np.uint64(1) << np.uint64(index & 63)
    return out


def _joined_starts(successors: np.ndarray, starts: Sequence[int]) -> tuple[np.ndarray, int]:
    """The moves with a chain of virtual positions (seeing nothing) that lead to every start, and the
    first of them: what a walk from the first virtual position reaches is what some start reaches."""
    positions = successors.shape[0]
    links = [list(starts[index : index + 3]) for index in range(0, len(starts), 3)]
    extra = np.full((len(links), 4), -1, dtype=np.int64)
    for index, group in enumerate(links):
        extra[index, : len(group)] = group
        if index + 1 < len(links):
            extra[index, 3] = positions + index + 1
    return np.concatenate([successors, extra]), positions


def residual_goal(graph: SearchGraph, also: Sequence[int] = ()) -> SearchGraph:
    """The same positions and moves, with the goal reduced to the cells a covering walk must aim for.

    Every walk from the start that sees each cell of the returned goal sees each cell of the original
    one, and conversely, so both have the same covering walks. ``goal_cells`` lists the kept cells. A
    goal cell that no position sees is always kept (the search then reports that it cannot be seen).

    ``also`` gives a team's other start positions: a cell is then dropped when some start sees it, or
    when *every* walk from *any* start to the watchers of a kept cell passes its watchers, so that walks
    of the team that together see every kept cell see the whole goal.

    Examples
    --------
    A corridor of 7 cells, a guard seeing its cell and the next, starting in the middle: only the two
    end cells remain, the others being seen on the way to them (or at the start).

    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> from guardsim.search.graph import build_search_graph
    >>> from guardsim.vision.table import view_table
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [7, 0], [7, 1], [0, 1]], "guard": {"view_range": 1.0}}))
    >>> graph = build_search_graph(scene.grid, view_table(scene.grid, scene.vision()), (3, 0), 0)
    >>> graph.goal_cells.tolist(), residual_goal(graph).goal_cells.tolist()
    ([0, 1, 2, 3, 4, 5, 6], [0, 6])
    """
    goal = int(graph.goal_cells.size)
    every = np.arange(goal, dtype=np.int64)
    at_start_words = graph.views[graph.start].copy()
    for position in also:
        at_start_words |= graph.views[position]
    at_start = (at_start_words[every >> 6] >> (every & 63).astype(np.uint64)) & np.uint64(1)
    bits = every[at_start == 0]
    if bits.size == 0:
        return graph._replace(
            views=np.zeros((graph.positions, 1), dtype=np.uint64),
            goal_cells=graph.goal_cells[:0],
            full=np.zeros(1, dtype=np.uint64),
        )
    sets = _watcher_sets(graph.views, bits)
    sizes = np.array([int(row.sum()) for row in np.unpackbits(sets.view(np.uint8), axis=1)], dtype=np.int64)
    order = np.lexsort((np.arange(bits.size), sizes)).astype(np.int64)
    keep = _cell_dominance(sets, order)
    # Most watchers first: a cell seen from many places is the likelier to be seen on the way.
    if also:
        successors, source = _joined_starts(graph.successors, [graph.start, *also])
        padded = np.zeros((sets.shape[0], (successors.shape[0] + 63) // 64), dtype=np.uint64)
        padded[:, : sets.shape[1]] = sets
        _path_dominance(successors, source, padded, keep, order[::-1].copy())
    else:
        _path_dominance(graph.successors, graph.start, sets, keep, order[::-1].copy())
    kept = bits[keep]
    full = np.zeros(max(1, (kept.size + 63) // 64), dtype=np.uint64)
    for index in range(kept.size):
        full[index >> 6] |= np.uint64(1) << np.uint64(index & 63)
    return graph._replace(views=_restrict(graph.views, kept), goal_cells=graph.goal_cells[kept], full=full)
