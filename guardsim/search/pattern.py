"""A pattern database for the exact search: the fewest steps to see a few chosen goal cells, stored
for every position and every subset of them already seen.

Seeing every goal cell includes seeing the *picks*, ``k`` chosen goal cells: the fewest steps from a
position, with some of the picks already seen, until a watcher of each of the others has been visited is
a lower bound on the steps left (an abstraction of the search's state, as pattern databases are in
puzzle search: Culberson and Schaeffer 1998). Unlike the pivots of :mod:`guardsim.search.heuristic`,
whose watcher sets must be apart and whose distances are taken between sets, the table holds the exact
walk through the picks' watchers, whatever they share: on issue 28's random-32-32-20 from (0, 0) 17
picks give 93 at the start where the pivots give 69 (``docs/optimum.md``).

The table is filled backwards, largest subset first (a move only adds picks to the subset), and within a
subset by breadth-first relaxation from the values its moves into larger subsets give. The picks are
chosen one at a time against the table so far: the walk the table calls shortest from the start is
followed, and the next pick is the goal cell it leaves unseen whose watchers are farthest from it, so
each pick makes that walk fall short (the idea of counterexample-guided abstraction refinement).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.csr import predecessors, watcher_csr
from guardsim.kernels.distances import FAR, fill_distances
from guardsim.kernels.estimate import Heuristic
from guardsim.search.graph import SearchGraph

__all__ = [
    "PATTERN_ENTRIES",
    "PATTERN_MOST_PICKS",
    "PATTERN_TABLES",
    "build_pattern",
    "build_patterns",
    "pattern_table",
    "with_pattern",
]

#: Most entries (bytes) of one table: 128 MB; its fill takes about 2-6 s at this size (17 picks on the
#: 682-position room-32-32-4, 16 on the 2,054-position arena at range 8).
PATTERN_ENTRIES = 1 << 27
#: Tables a search builds (:func:`build_patterns`): room-32-32-4 from (3, 0) reaches 193 in 300 s with
#: two, 191 with one.
PATTERN_TABLES = 2
#: Most picks whatever the size (the subset of seen picks is an ``int64`` bit mask).
PATTERN_MOST_PICKS = 24
#: The table's values saturate (``uint8``): 254 stands for "254 or more", 255 for "255 or more, or no
#: walk at all" (never met in a connected goal). Both stay lower bounds, so a walk longer than 254
#: steps (a large level) only weakens the table.
_UNREACHED = 255
_LONGEST = 254


@jit
def _cover(views: np.ndarray, bits: np.ndarray) -> np.ndarray:
    """``int64 (positions,)``: the picks (bit ``i`` for ``bits[i]``) each position sees."""
    cover = np.zeros(views.shape[0], dtype=np.int64)
    for index in range(bits.shape[0]):
        word, shift = bits[index] >> 6, np.uint64(bits[index] & 63)
        for position in range(views.shape[0]):
            if (views[position, word] >> shift) & np.uint64(1):
                cover[position] |= np.int64(1) << index
    return cover


@jit
def pattern_table(successors: np.ndarray, cover: np.ndarray, picks: int) -> np.ndarray:
    """``uint8 (2**picks, positions)``: at ``[seen, position]`` the fewest steps from ``position``, the picks
    of the bit mask ``seen`` already seen, until a watcher of every pick has been visited (``cover``: the
    picks each position sees); 254 stands for 254 or more, 255 for 255 or more, or never.

    The entries whose mask lacks what their position sees are never read by the search and hold values
    of no meaning.

    Examples
    --------
    A corridor of four positions; the one pick is seen from position 3 only: from 0 it takes 3 steps
    (position 3 with the pick unseen is one of the entries never read).

    >>> successors = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> pattern_table(successors, np.array([0, 0, 0, 1]), 1)[0, :3].tolist()
    [3, 2, 1]
    """
    positions = successors.shape[0]
    subsets = 1 << picks
    everything = subsets - 1
    table = np.empty((subsets, positions), dtype=np.uint8)
    table[everything, :] = 0
    before_start, before = predecessors(successors)
    counts = np.zeros(_UNREACHED + 2, dtype=np.int64)
    order = np.empty(positions, dtype=np.int64)
    queue = np.empty(positions * 4 + 1, dtype=np.int64)
    queued = np.empty(positions * 4 + 1, dtype=np.int64)
    for seen in range(everything - 1, -1, -1):
        row = table[seen]
        # A move that sees a new pick leads into a larger subset, whose row is final.
        for position in range(positions):
            best = _UNREACHED
            for direction in range(4):
                there = successors[position, direction]
                if there >= 0:
                    more = seen | cover[there]
                    if more != seen:
                        best = min(best, int(table[more, there]) + 1)
            row[position] = min(best, _LONGEST) if best < _UNREACHED else _UNREACHED
        # Moves that see no new pick stay in this row: breadth first from the values so far, taken in
        # increasing order (a counting sort), merged with the queue of values they improve.
        counts[:] = 0
        for position in range(positions):
            counts[row[position] + 1] += 1
        for value in range(1, counts.shape[0]):
            counts[value] += counts[value - 1]
        for position in range(positions):
            order[counts[row[position]]] = position
            counts[row[position]] += 1
        taken, head, tail = 0, 0, 0
        while taken < positions or head < tail:
            if head < tail and (taken >= positions or queued[head] <= row[order[taken]]):
                here, value = queue[head], queued[head]
                head += 1
            else:
                here = order[taken]
                value = np.int64(row[here])
                taken += 1
            if row[here] != value or value >= _LONGEST or (seen | cover[here]) != seen:
                continue
            for index in range(before_start[here], before_start[here + 1]):
                back = before[index]
                if row[back] > value + 1:
                    row[back] = value + 1
                    queue[tail], queued[tail] = back, value + 1
                    tail += 1
    return table


@jit
def _shortest_walk(successors: np.ndarray, cover: np.ndarray, table: np.ndarray, start: int) -> np.ndarray:
    """The positions of a walk from ``start`` that the table calls shortest (the first best move each step)."""
    everything = table.shape[0] - 1
    seen = cover[start]
    here = start
    walk = [here]
    while seen != everything and table[seen, here] < _UNREACHED:
        value = table[seen, here]
        best, best_value = -1, _UNREACHED + 1
        for direction in range(4):
            there = successors[here, direction]
            if there >= 0 and table[seen | cover[there], there] < best_value:
                best, best_value = there, int(table[seen | cover[there], there])
        if best < 0 or (value < _LONGEST and best_value != value - 1):
            break  # only past the stored range (or in a disconnected goal) can no move go one lower
        here = best
        seen |= cover[here]
        walk.append(here)
    return np.array(walk, dtype=np.int64)


@jit
def _next_pick(
    graph_views: np.ndarray,
    successors: np.ndarray,
    full: np.ndarray,
    walk: np.ndarray,
    counts: np.ndarray,
    watchers: np.ndarray,
) -> int:
    """The goal cell ``walk`` leaves unseen whose nearest watcher is farthest from it (ties: fewer
    watchers, then the lower bit); -1 when the walk sees everything."""
    words = full.shape[0]
    seen = np.zeros(words, dtype=np.uint64)
    for position in walk:
        for word in range(words):
            seen[word] |= graph_views[position, word]
    distance = np.empty(successors.shape[0], dtype=np.int32)
    fill_distances(successors, walk, FAR, distance)
    best, best_far, best_count = -1, -1, 0
    for word in range(words):
        left = full[word] & ~seen[word]
        for shift in range(64):
            if not (left >> np.uint64(shift)) & np.uint64(1):
                continue
            bit = word * 64 + shift
            near = np.iinfo(np.int32).max
            for index in range(counts[bit], counts[bit + 1]):
                near = min(near, distance[watchers[index]])
            many = counts[bit + 1] - counts[bit]
            if near > best_far or (near == best_far and many < best_count):
                best, best_far, best_count = bit, near, many
    return best


def build_pattern(
    graph: SearchGraph,
    *,
    most_entries: int | None = None,
    deadline: float | None = None,
    report: Callable[[int, int], None] | None = None,
    walk: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Picks and their table for ``graph`` (``int64`` goal bits, ``uint8 (2**k, positions)``), and the
    walk (positions) the table calls shortest from the start.

    Picks are added one at a time (see the module text) while the table stays within ``most_entries``
    entries (:data:`PATTERN_ENTRIES` by default) and :data:`PATTERN_MOST_PICKS`; ``report(picks, value at the start)`` is called after each.
    The work is counted in picks: the same graph gives the same table, unless ``deadline`` (a
    :func:`time.perf_counter` reading) passes first, which stops adding picks. ``walk``: the positions
    of a walk to pick the first pick against (the start alone by default).
    """
    counts, watchers = watcher_csr(graph.views, int(graph.goal_cells.size))
    successors = np.ascontiguousarray(graph.successors, dtype=np.int64)
    positions = graph.positions
    bits: list[int] = []
    table = np.zeros((1, positions), dtype=np.uint8)
    cover = np.zeros(positions, dtype=np.int64)
    walk = np.array([graph.start], dtype=np.int64) if walk is None else walk
    most = PATTERN_ENTRIES if most_entries is None else most_entries
    while len(bits) < PATTERN_MOST_PICKS and (2 << len(bits)) * positions <= most:
        if deadline is not None and time.perf_counter() > deadline:
            break
        bit = _next_pick(graph.views, successors, graph.full, walk, counts, watchers)
        if bit < 0:
            break  # the table's walk sees every goal cell: no pick can make it fall short
        bits.append(bit)
        cover = _cover(graph.views, np.array(bits, dtype=np.int64))
        table = pattern_table(successors, cover, len(bits))
        walk = _shortest_walk(successors, cover, table, graph.start)
        if report is not None:
            report(len(bits), int(table[cover[graph.start], graph.start]))
    return np.array(bits, dtype=np.int64), table, walk


def build_patterns(
    graph: SearchGraph,
    tables: int | None = None,
    *,
    most_entries: int | None = None,
    deadline: float | None = None,
    report: Callable[[int, int], None] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``tables`` pattern databases (:data:`PATTERN_TABLES` by default) for ``graph``, stacked:
    ``int64 (tables, k)`` picks and ``uint8 (tables, 2**k, positions)`` tables.

    The first is :func:`build_pattern`'s; each next one starts picking against the walk the one before
    calls shortest, so its picks are cells that walk leaves unseen: the search reads the larger value,
    and where a node has gone the first table's cheap way, the next one still charges for what that way
    misses. A table that ends with fewer picks than the first (its walk saw everything, or
    ``deadline`` passed) is left out.
    """
    count = PATTERN_TABLES if tables is None else tables
    bits, table, walk = build_pattern(graph, most_entries=most_entries, deadline=deadline, report=report)
    all_bits, all_tables = [bits], [table]
    for _ in range(count - 1):
        more_bits, more_table, walk = build_pattern(
            graph, most_entries=most_entries, deadline=deadline, report=report, walk=walk
        )
        if more_bits.size != bits.size:
            break
        all_bits.append(more_bits)
        all_tables.append(more_table)
    return np.stack(all_bits), np.stack(all_tables)


def with_pattern(heuristic: Heuristic, bits: np.ndarray, table: np.ndarray) -> Heuristic:
    """``heuristic`` with pattern databases (:func:`build_patterns`) in its estimate."""
    return heuristic._replace(pattern_bits=bits, pattern=table)
