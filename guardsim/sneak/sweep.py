"""The exact sneak searches without a node per (lap tick, cell): sets of lap ticks as bitsets, and one entry
tick searched with a sparse node store.

The searches of :mod:`~guardsim.sneak.search` and :mod:`~guardsim.sneak.graded` keep an entry (a parent,
a label chain) for each of the ``period x cells`` nodes: 578 million for one guard's lap of a 256 x 256
map. Here the answer is split in two.

:func:`sweep` runs every entry tick at once, breadth first over the time since entering, and keeps for
each cell only the set of lap ticks at which a player got there with every meter empty (a bitset, one
bit per node, ``reached``) and, apart, the labels whose meters are not empty (a hash table of nodes, from
:mod:`guardsim.kernels.nodes`). The items of a layer are the words of those bitsets that gained bits: a
cell out of every guard's sight gains most of its lap ticks in one layer and the rest a few at a time,
so the work grows with the cells and the ticks near the guards' sight, not with their product. It
answers what does not depend on the order of the search: the fewest ticks to the target, the entry
ticks that manage them, the cells a player can reach, and, backwards from the target, the nodes from
which it is reached unseen.

:func:`entry_search` is the search of :mod:`~guardsim.sneak.graded` (and, ``graded=False``, the
breadth-first search of :mod:`~guardsim.sneak.search`) from one entry tick, its nodes in the same hash
table, pruned to the nodes that can still reach the target within a bound. The path those searches
return is the least, in the order (entry tick, first move, second move, ...), of the fastest paths: two
labels at one node in one layer entered at the same tick, a label dropped for a dominating one is
matched by that one's continuation, and the breadth-first order is that lexicographic order. So the
fastest path from the least entry tick :func:`sweep` finds, searched alone, is the same path, node for
node, as the search of every entry tick at once finds.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.detection.sight import LapSight
from guardsim.errors import ArgumentError, LimitError
from guardsim.kernels.compiler import jit
from guardsim.kernels.frontier import node_hash
from guardsim.kernels.meter import DETECTED, meter_after
from guardsim.kernels.nodes import find_node, store_node

__all__ = ["EntryPath", "Sweep", "entry_search", "sweep"]

_ONE = np.uint64(1)


class Sweep(NamedTuple):
    """What a search of every entry tick at once found."""

    ticks: int
    """Fewest ticks from entering to the target; -1 when it is not reached."""
    entry: int
    """The least entry lap tick that reaches the target in :attr:`ticks`; -1 when none."""
    reached: np.ndarray
    """``uint64 (cells, words)``: the (lap tick, cell) nodes reached with every meter empty (as bits)."""
    cells: np.ndarray
    """``bool (cells,)``: the cells reached at all."""
    labels: int
    """Labels with some meter not empty that the search kept."""


class EntryPath(NamedTuple):
    """The path of a search from one entry tick."""

    found: bool
    """Whether a goal node was reached."""
    cells: np.ndarray
    """``int64 (ticks + 1,)``: the flat cell at each tick (empty when not found)."""
    labels: int
    """Labels the search kept."""


@jit
def _grow_int(array: np.ndarray, needed: int) -> np.ndarray:
    if needed <= array.shape[0]:
        return array
    grown = np.empty(max(needed, 2 * array.shape[0]), dtype=array.dtype)
    for index in range(array.shape[0]):
        grown[index] = array[index]
    return grown


@jit
def _grow_rows(array: np.ndarray, needed: int) -> np.ndarray:
    if needed <= array.shape[0]:
        return array
    grown = np.empty((max(needed, 2 * array.shape[0]), array.shape[1]), dtype=array.dtype)
    for row in range(array.shape[0]):
        for column in range(array.shape[1]):
            grown[row, column] = array[row, column]
    return grown


class _Nodes(NamedTuple):
    """The hash table of nodes ((lap tick, cell) as ``tick * cells + cell``) and each node's label chain."""

    table: np.ndarray
    key: np.ndarray
    head: np.ndarray
    settled: np.ndarray
    earlier: np.ndarray
    latest: np.ndarray
    counters: np.ndarray
    rows: np.ndarray


@jit
def _copy_row(rows: np.ndarray, row: int, values: np.ndarray) -> None:
    for column in range(values.shape[0]):
        rows[row, column] = values[column]


@jit
def _find(nodes: _Nodes, key: int) -> tuple[int, int]:
    # A node is its key alone: its row of seen words (``rows[0]``) is empty.
    none = nodes.rows[0]
    return find_node(nodes.table, node_hash(key, none), (nodes.key,), (np.int64(key),), nodes.rows, none)


@jit
def _add(nodes: _Nodes, key: int) -> tuple[_Nodes, int]:
    """The node of ``key``, stored if new (its chain empty); the table grows as nodes come."""
    node, slot = _find(nodes, key)
    if node >= 0:
        return nodes, node
    stored = nodes.counters[0]
    if 2 * (stored + 1) > nodes.table.shape[0] or stored + 1 > nodes.key.shape[0]:
        size = 2 * nodes.table.shape[0]
        table = np.zeros(size, dtype=np.int64)
        mask = size - 1
        for index in range(stored):
            place = np.int64(node_hash(nodes.key[index], nodes.rows[0]) >> _ONE) & mask
            while table[place] != 0:
                place = (place + 1) & mask
            table[place] = index + 1
        capacity = size // 2
        nodes = _Nodes(
            table, _grow_int(nodes.key, capacity), _grow_int(nodes.head, capacity),
            _grow_int(nodes.settled, capacity), _grow_int(nodes.earlier, capacity), nodes.latest, nodes.counters,
            np.zeros((capacity, 0), dtype=np.uint64),
        )  # fmt: skip
        node, slot = _find(nodes, key)
    # One chain for every node (``latest``): the searches walk label chains, not node chains.
    node = store_node(nodes.counters, nodes.table, nodes.latest, nodes.earlier, nodes.rows, slot, 0, nodes.rows[0])
    nodes.key[node] = key
    nodes.head[node] = -1
    nodes.settled[node] = False
    return nodes, node


class _Labels(NamedTuple):
    """The labels kept (states whose meters are not all empty), numbered as kept: each one's node key, parent
    label, meters, and the label kept before it at its node (the chain starts at ``nodes.head``)."""

    key: np.ndarray
    parent: np.ndarray
    meters: np.ndarray
    after: np.ndarray
    nodes: _Nodes


@jit
def _no_labels(watchers: int) -> _Labels:
    nodes = _Nodes(
        np.zeros(1024, dtype=np.int64), np.zeros(512, dtype=np.int64), np.zeros(512, dtype=np.int64),
        np.zeros(512, dtype=np.bool_), np.zeros(512, dtype=np.int64), np.full(1, -1, dtype=np.int64),
        np.zeros(8, dtype=np.int64), np.zeros((512, 0), dtype=np.uint64),
    )  # fmt: skip
    return _Labels(
        np.empty(1024, dtype=np.int64), np.empty(1024, dtype=np.int64), np.empty((1024, watchers), dtype=np.float64),
        np.empty(1024, dtype=np.int64), nodes,
    )  # fmt: skip


@jit
def _dominated(labels: _Labels, key: int, meters: np.ndarray) -> bool:
    """Whether a label kept at node ``key`` has no meter above ``meters``."""
    node, _ = _find(labels.nodes, key)
    stored = labels.nodes.head[node] if node >= 0 else -1
    while stored >= 0:
        dominated = True
        for guard in range(meters.shape[0]):
            if labels.meters[stored, guard] > meters[guard]:
                dominated = False
                break
        if dominated:
            return True
        stored = labels.after[stored]
    return False


@jit
def _keep(labels: _Labels, count: int, key: int, parent: int, meters: np.ndarray) -> tuple[_Labels, int]:
    """``labels`` with label number ``count`` (node ``key``, ``parent``, ``meters``) kept first at its node;
    and the node."""
    nodes, node = _add(labels.nodes, key)
    labels = _Labels(
        _grow_int(labels.key, count + 1), _grow_int(labels.parent, count + 1), _grow_rows(labels.meters, count + 1),
        _grow_int(labels.after, count + 1), nodes,
    )  # fmt: skip
    labels.key[count] = key
    labels.parent[count] = parent
    _copy_row(labels.meters, count, meters)
    labels.after[count] = nodes.head[node]
    nodes.head[node] = count
    return labels, node


@jit
def _append(array: np.ndarray, count: int, value: int) -> np.ndarray:
    array = _grow_int(array, count + 1)
    array[count] = value
    return array


@jit
def _low_bit(word: np.uint64) -> int:
    """The index of the lowest set bit of ``word`` (not zero)."""
    low = word & (~word + _ONE)
    bit = 0
    while (low >> np.uint64(bit)) != _ONE:
        bit += 1
    return bit


@jit
def _gains_at(start: np.ndarray, tick: np.ndarray, watcher: np.ndarray, gain: np.ndarray, cell: int, phase: int,
              out: np.ndarray) -> None:  # fmt: skip
    """``out``: each watcher's gain at lap tick ``phase`` in ``cell`` (0 where it does not see it)."""
    for index in range(out.shape[0]):
        out[index] = 0.0
    low, high = start[cell], start[cell + 1]
    while low < high:
        middle = (low + high) >> 1
        if tick[middle] < phase:
            low = middle + 1
        else:
            high = middle
    while low < start[cell + 1] and tick[low] == phase:
        out[watcher[low]] = gain[low]
        low += 1


@jit
def _step(levels: np.ndarray, gains: np.ndarray, fall: float, out: np.ndarray) -> int:
    """``out``: the meters after a tick with ``gains``; 1 when one fills, 0 when all are empty, else 2."""
    empty = True
    for index in range(levels.shape[0]):
        out[index] = meter_after(levels[index], gains[index], fall)
        if out[index] >= DETECTED:
            return 1
        empty = empty and out[index] == 0.0
    return 0 if empty else 2


@jit
def _is_bit(bits: np.ndarray, cell: int, phase: int) -> bool:
    return ((bits[cell, phase >> 6] >> np.uint64(phase & 63)) & _ONE) != np.uint64(0)


@jit
def _shift(word: int, value: np.uint64, words: int, last: int, forward: bool, out_word: np.ndarray,
           out_bits: np.ndarray) -> int:  # fmt: skip
    """The lap ticks of ``value`` (bits of word ``word``) one tick later (``forward``) or earlier, round the
    lap of ``last + 1 + 64 * (words - 1)`` ticks: up to three (word, bits) pairs in ``out_*``; their count."""
    count = 0
    if forward:
        low = value << _ONE
        high = np.uint64(0)
        wrap = np.uint64(0)
        if word == words - 1:
            if last < 63:
                low &= (_ONE << np.uint64(last + 1)) - _ONE
            wrap = (value >> np.uint64(last)) & _ONE
        else:
            high = value >> np.uint64(63)
        if low:
            out_word[count], out_bits[count] = word, low
            count += 1
        if high:
            out_word[count], out_bits[count] = word + 1, high
            count += 1
        if wrap:
            out_word[count], out_bits[count] = 0, _ONE
            count += 1
    else:
        low = value >> _ONE
        high = np.uint64(0)
        wrap = np.uint64(0)
        if word == 0:
            wrap = value & _ONE
        else:
            high = (value & _ONE) << np.uint64(63)
        if low:
            out_word[count], out_bits[count] = word, low
            count += 1
        if high:
            out_word[count], out_bits[count] = word - 1, high
            count += 1
        if wrap:
            out_word[count], out_bits[count] = words - 1, _ONE << np.uint64(last)
            count += 1
    return count


@jit
def _runs(free: np.uint64, seeds: np.uint64, forward: bool) -> np.uint64:
    """The bits of ``free`` (a word, containing ``seeds``) reached from ``seeds`` by waiting: on through each
    run of free bits, towards the higher bits (``forward``) or the lower ones (an occluded fill, doubling
    its reach each step)."""
    reach = seeds
    through = free
    for step in (1, 2, 4, 8, 16, 32):
        shift = np.uint64(step)
        if forward:
            reach |= through & (reach << shift)
            through &= through << shift
        else:
            reach |= through & (reach >> shift)
            through &= through >> shift
    return reach & free


@jit
def _push(
    reached: np.ndarray,
    cell: int,
    word: int,
    new: np.uint64,
    item_cell: np.ndarray,
    item_word: np.ndarray,
    item_bits: np.ndarray,
    count: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Mark ``new`` (unseen, unreached bits of word ``word`` of ``cell``) reached and queue them as an item."""
    reached[cell, word] |= new
    item_cell = _grow_int(item_cell, count + 1)
    item_word = _grow_int(item_word, count + 1)
    item_bits = _grow_int(item_bits, count + 1)
    item_cell[count], item_word[count], item_bits[count] = cell, word, new
    return item_cell, item_word, item_bits, count + 1


@jit
def _seed(
    reached: np.ndarray,
    bits: np.ndarray,
    pending: np.ndarray,
    cell: int,
    word: int,
    new: np.uint64,
    last: int,
    forward: bool,
) -> None:
    """Mark ``new`` (unseen, unreached bits of word ``word`` of ``cell``) reached, with every lap tick
    reached from them by waiting, and pending (to pass on to the neighbours)."""
    words = reached.shape[1]
    while True:
        free = ~bits[cell, word] & ~reached[cell, word]
        if word == words - 1 and last < 63:
            free &= (_ONE << np.uint64(last + 1)) - _ONE
        new = _runs(free | new, new, forward)
        reached[cell, word] |= new
        pending[cell, word] |= new
        # On past the word's edge (round the lap's end) while the run goes on.
        if forward:
            edge = last if word == words - 1 else 63
            if ((new >> np.uint64(edge)) & _ONE) == np.uint64(0):
                return
            word = 0 if word == words - 1 else word + 1
            new = _ONE
        else:
            if (new & _ONE) == np.uint64(0):
                return
            if word == 0:
                word = words - 1
                new = _ONE << np.uint64(last)
            else:
                word -= 1
                new = _ONE << np.uint64(63)
        if (bits[cell, word] | reached[cell, word]) & new:
            return


@jit
def _shift_row(row: np.ndarray, last: int, forward: bool, out: np.ndarray) -> None:
    """``out``: the lap ticks of ``row`` one tick later (``forward``) or earlier, round the lap."""
    words = row.shape[0]
    carry = np.uint64(0)
    if forward:
        for word in range(words):
            value = row[word]
            out[word] = (value << _ONE) | carry
            carry = value >> np.uint64(63)
        if last < 63:
            carry = (out[words - 1] >> np.uint64(last + 1)) & _ONE
            out[words - 1] &= (_ONE << np.uint64(last + 1)) - _ONE
        out[0] |= carry
    else:
        for word in range(words - 1, -1, -1):
            value = row[word]
            out[word] = (value >> _ONE) | (carry << np.uint64(63))
            carry = value & _ONE
        if carry:
            out[words - 1] |= _ONE << np.uint64(last)


@jit
def _flood(
    neighbours: np.ndarray,
    start: np.ndarray,
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    bits: np.ndarray,
    watchers: int,
    period: int,
    fall: float,
    source: int,
    entries: np.ndarray,
    graded: bool,
    forward: bool,
    max_labels: int,
    reached: np.ndarray,
    touched: np.ndarray,
) -> int:
    """Every node reached from the entry ticks ``entries`` at ``source``, in no particular order: a cell's
    newly reached ticks pass on to its neighbours a whole row of words at a time, each run of unseen ticks
    filled at once. Labels with some meter up (``graded``) are kept as :func:`_sweep` keeps them. Returns
    the labels kept (-1 past ``max_labels``)."""
    cells = neighbours.shape[0]
    words = reached.shape[1]
    last = (period - 1) & 63
    pending = np.zeros(reached.shape, dtype=np.uint64)
    queued = np.zeros(cells, dtype=np.bool_)
    queue = np.empty(cells + 1, dtype=np.int64)
    head = 0
    tail = 0
    shifted = np.empty(words, dtype=np.uint64)
    moved_words = np.empty(words, dtype=np.int64)
    kept = _no_labels(watchers)
    gains = np.zeros(watchers, dtype=np.float64)
    zero = np.zeros(watchers, dtype=np.float64)
    candidate = np.zeros(watchers, dtype=np.float64)
    labels = 0
    done = 0
    for phase in range(period):
        if not entries[phase]:
            continue
        if not _is_bit(bits, source, phase):
            if not _is_bit(reached, source, phase):
                _seed(reached, bits, pending, source, phase >> 6, _ONE << np.uint64(phase & 63), last, forward)
        elif graded:
            _gains_at(start, tick, watcher, gain, source, phase, gains)
            if _step(zero, gains, fall, candidate) == 1:
                continue
            kept, _ = _keep(kept, labels, phase * cells + source, -1, candidate)
            labels += 1
        touched[source] = True
    queue[tail] = source
    tail += 1
    queued[source] = True
    while head != tail or done < labels:
        while head != tail:
            cell = queue[head]
            head = (head + 1) % queue.shape[0]
            queued[cell] = False
            _shift_row(pending[cell], last, forward, shifted)
            # The words that moved, once (most pops move a few words of the row, not all of them), in the
            # direction waiting fills: one seed then fills a run across many words.
            count = 0
            for index in range(words):
                word = index if forward else words - 1 - index
                pending[cell, word] = 0
                if shifted[word]:
                    moved_words[count] = word
                    count += 1
            for move in range(5):
                other = cell if move == 4 else neighbours[cell, move]
                if other < 0:
                    continue
                grew = False
                for index in range(count):
                    word = moved_words[index]
                    moved = shifted[word]
                    fresh = moved & ~reached[other, word]
                    new = fresh & ~bits[other, word]
                    if new:
                        _seed(reached, bits, pending, other, word, new, last, forward)
                        grew = True
                    hit = fresh & bits[other, word] if graded else np.uint64(0)
                    while hit:
                        phase = word * 64 + _low_bit(hit)
                        hit &= hit - _ONE
                        _gains_at(start, tick, watcher, gain, other, phase, gains)
                        if _step(zero, gains, fall, candidate) == 1:
                            continue
                        key = phase * cells + other
                        if _dominated(kept, key, candidate):
                            continue
                        if labels >= max_labels:
                            return -1
                        kept, _ = _keep(kept, labels, key, -1, candidate)
                        labels += 1
                        touched[other] = True
                if grew:
                    touched[other] = True
                    if not queued[other]:
                        queued[other] = True
                        queue[tail] = other
                        tail = (tail + 1) % queue.shape[0]
        while done < labels:
            label = done
            done += 1
            key = kept.key[label]
            phase, cell = key // cells, key % cells
            if _is_bit(reached, cell, phase):
                continue
            after = (phase + 1) % period
            for move in range(5):
                other = cell if move == 4 else neighbours[cell, move]
                if other < 0 or _is_bit(reached, other, after):
                    continue
                _gains_at(start, tick, watcher, gain, other, after, gains)
                state = _step(kept.meters[label], gains, fall, candidate)
                if state == 1:
                    continue
                touched[other] = True
                if state == 0:
                    _seed(reached, bits, pending, other, after >> 6, _ONE << np.uint64(after & 63), last, forward)
                    if not queued[other]:
                        queued[other] = True
                        queue[tail] = other
                        tail = (tail + 1) % queue.shape[0]
                    continue
                key = after * cells + other
                if _dominated(kept, key, candidate):
                    continue
                if labels >= max_labels:
                    return -1
                kept, _ = _keep(kept, labels, key, -1, candidate)
                labels += 1
    return labels


@jit
def _sweep(
    neighbours: np.ndarray,
    start: np.ndarray,
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    bits: np.ndarray,
    watchers: int,
    period: int,
    fall: float,
    source: int,
    target: int,
    entries: np.ndarray,
    graded: bool,
    forward: bool,
    exhaustive: bool,
    bound: int,
    remaining: np.ndarray,
    max_labels: int,
    reached: np.ndarray,
    touched: np.ndarray,
) -> tuple[int, int, int]:
    """(fewest ticks to ``target``, least entry tick doing it, labels kept); -2 ticks past ``max_labels``.

    ``reached`` (zeros) receives the nodes reached with empty meters, ``touched`` (false) the cells
    reached at all. Backwards (``forward`` false, unseen only) the moves run from a node to those it
    is reached from. ``bound`` >= 0: leave out the nodes more than ``bound`` ticks from entering by
    ``remaining`` (steps to the target). :func:`_flood` reaches every node in no order, faster."""
    cells = neighbours.shape[0]
    words = reached.shape[1]
    last = (period - 1) & 63
    # The words gained in this layer and the next: (cell, word, bits).
    item_cell = np.empty(1024, dtype=np.int64)
    item_word = np.empty(1024, dtype=np.int64)
    item_bits = np.empty(1024, dtype=np.uint64)
    next_cell = np.empty(1024, dtype=np.int64)
    next_word = np.empty(1024, dtype=np.int64)
    next_bits = np.empty(1024, dtype=np.uint64)
    kept = _no_labels(watchers)
    # The labels of this layer and the next.
    frontier = np.empty(1024, dtype=np.int64)
    upcoming = np.empty(1024, dtype=np.int64)
    gains = np.zeros(watchers, dtype=np.float64)
    zero = np.zeros(watchers, dtype=np.float64)
    candidate = np.zeros(watchers, dtype=np.float64)
    shifted_word = np.empty(3, dtype=np.int64)
    shifted_bits = np.empty(3, dtype=np.uint64)
    labels = 0
    items = 0
    width = 0
    best = -1
    for phase in range(period):
        if not entries[phase] or (bound >= 0 and remaining[source] > bound):
            continue
        if not _is_bit(bits, source, phase):
            reached[source, phase >> 6] |= _ONE << np.uint64(phase & 63)
        elif graded:
            _gains_at(start, tick, watcher, gain, source, phase, gains)
            if _step(zero, gains, fall, candidate) == 1:
                continue
            kept, _ = _keep(kept, labels, phase * cells + source, -1, candidate)
            frontier = _append(frontier, width, labels)
            width += 1
            labels += 1
        else:
            continue
        touched[source] = True
        if source == target and best < 0:
            best = phase
    for word in range(words):
        if reached[source, word]:
            seeds = reached[source, word]
            reached[source, word] = 0
            item_cell, item_word, item_bits, items = _push(
                reached, source, word, seeds, item_cell, item_word, item_bits, items
            )
    layer = 0
    if best >= 0:
        return 0, best, labels
    found_ticks, found_entry = -1, -1
    while items > 0 or width > 0:
        following = 0
        upcoming_width = 0
        best = -1
        arrive = layer + 1
        for index in range(items):
            cell, word, value = item_cell[index], item_word[index], item_bits[index]
            count = _shift(word, value, words, last, forward, shifted_word, shifted_bits)
            for move in range(5):
                other = cell if move == 4 else neighbours[cell, move]
                if other < 0 or (bound >= 0 and arrive + remaining[other] > bound):
                    continue
                for part in range(count):
                    into, moved = shifted_word[part], shifted_bits[part]
                    fresh = moved & ~reached[other, into]
                    new = fresh & ~bits[other, into]
                    if new:
                        touched[other] = True
                        next_cell, next_word, next_bits, following = _push(
                            reached, other, into, new, next_cell, next_word, next_bits, following
                        )
                        left = new if other == target else np.uint64(0)
                        while left:
                            entry = (into * 64 + _low_bit(left) - arrive) % period
                            if best < 0 or entry < best:
                                best = entry
                            left &= left - _ONE
                    hit = fresh & bits[other, into] if graded else np.uint64(0)
                    while hit:
                        phase = into * 64 + _low_bit(hit)
                        hit &= hit - _ONE
                        _gains_at(start, tick, watcher, gain, other, phase, gains)
                        if _step(zero, gains, fall, candidate) == 1:
                            continue
                        key = phase * cells + other
                        if _dominated(kept, key, candidate):
                            continue
                        if labels >= max_labels:
                            return -2, -1, labels
                        kept, _ = _keep(kept, labels, key, -1, candidate)
                        upcoming = _append(upcoming, upcoming_width, labels)
                        upcoming_width += 1
                        labels += 1
                        touched[other] = True
                        if other == target:
                            entry = (phase - arrive) % period
                            if best < 0 or entry < best:
                                best = entry
        for index in range(width):
            label = frontier[index]
            key = kept.key[label]
            phase, cell = key // cells, key % cells
            if _is_bit(reached, cell, phase):
                # Met in its own layer by a label with every meter empty, which dominates it.
                continue
            after = (phase + 1) % period
            for move in range(5):
                other = cell if move == 4 else neighbours[cell, move]
                if other < 0 or _is_bit(reached, other, after):
                    continue
                if bound >= 0 and arrive + remaining[other] > bound:
                    continue
                _gains_at(start, tick, watcher, gain, other, after, gains)
                state = _step(kept.meters[label], gains, fall, candidate)
                if state == 1:
                    continue
                if state == 0:
                    touched[other] = True
                    next_cell, next_word, next_bits, following = _push(
                        reached, other, after >> 6, _ONE << np.uint64(after & 63), next_cell, next_word, next_bits,
                        following,
                    )  # fmt: skip
                else:
                    key = after * cells + other
                    if _dominated(kept, key, candidate):
                        continue
                    if labels >= max_labels:
                        return -2, -1, labels
                    kept, _ = _keep(kept, labels, key, -1, candidate)
                    upcoming = _append(upcoming, upcoming_width, labels)
                    upcoming_width += 1
                    labels += 1
                    touched[other] = True
                if other == target:
                    entry = (after - arrive) % period
                    if best < 0 or entry < best:
                        best = entry
        item_cell, next_cell = next_cell, item_cell
        item_word, next_word = next_word, item_word
        item_bits, next_bits = next_bits, item_bits
        items = following
        frontier, upcoming = upcoming, frontier
        width = upcoming_width
        layer = arrive
        if best >= 0 and found_ticks < 0:
            found_ticks, found_entry = layer, best
            if not exhaustive:
                break
    return found_ticks, found_entry, labels


def sweep(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    target: int,
    *,
    graded: bool,
    forward: bool = True,
    exhaustive: bool = False,
    flood: bool = False,
    bound: int = -1,
    remaining: np.ndarray | None = None,
    entries: np.ndarray | None = None,
    max_labels: int,
) -> Sweep:
    """Search from every entry tick at once (``entries``, ``bool (period,)``, default all) at ``source``
    for ``target`` (-1: none, with ``exhaustive``): unseen (``graded`` false) or undetected. Backwards
    (``forward=False``, unseen only): the nodes from which ``source`` is reached unseen. ``flood`` reaches
    every node (exhaustive; the fewest ticks are then not counted). ``bound`` (with ``remaining``, steps
    to the target) leaves out the nodes that cannot reach the target within ``bound`` ticks of entering:
    the fewest ticks and the entry stay exact when the target is reached within the bound.

    Raises
    ------
    LimitError
        When more than ``max_labels`` labels with some meter not empty are kept.
    """
    if not forward and graded:
        raise ArgumentError("the backward sweep is unseen only")
    period = sight.period
    reached = np.zeros(sight.bits.shape, dtype=np.uint64)
    touched = np.zeros(sight.cells, dtype=np.bool_)
    chosen = np.ones(period, dtype=np.bool_) if entries is None else np.ascontiguousarray(entries, dtype=np.bool_)
    if flood:
        labels = _flood(
            np.ascontiguousarray(neighbours, dtype=np.int64), sight.start, sight.tick, sight.watcher, sight.gain,
            sight.bits, sight.watchers, period, float(sight.fall), int(source), chosen, bool(graded), bool(forward),
            int(max_labels), reached, touched,
        )  # fmt: skip
        if labels < 0:
            raise LimitError(
                f"the undetected-path search passed {max_labels} labels ((cell, lap tick, meters) states kept); "
                "the level, lap or guards are too large for it"
            )
        return Sweep(-1, -1, reached, touched, labels)
    ticks, entry, labels = _sweep(
        np.ascontiguousarray(neighbours, dtype=np.int64), sight.start, sight.tick, sight.watcher, sight.gain,
        sight.bits, sight.watchers, period, float(sight.fall), int(source), int(target), chosen, bool(graded),
        bool(forward), bool(exhaustive), int(bound),
        np.zeros(sight.cells, dtype=np.int64) if remaining is None else np.ascontiguousarray(remaining, dtype=np.int64),
        int(max_labels), reached, touched,
    )  # fmt: skip
    if ticks == -2:
        raise LimitError(
            f"the undetected-path search passed {max_labels} labels ((cell, lap tick, meters) states kept); "
            "the level, lap or guards are too large for it"
        )
    return Sweep(ticks, entry, reached, touched, labels)


@jit
def _entry_search(
    neighbours: np.ndarray,
    start: np.ndarray,
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    bits: np.ndarray,
    watchers: int,
    period: int,
    fall: float,
    source: int,
    entry: int,
    target: int,
    goal: np.ndarray,
    graded: bool,
    bound: int,
    remaining: np.ndarray,
    max_labels: int,
) -> tuple[np.ndarray, np.ndarray, int, int]:
    """The search of :func:`guardsim.sneak.graded._label_search` from lap tick ``entry`` alone, stopping at
    the first label on ``target`` or on a node of ``goal`` (``uint64 (cells, words)``, or no rows): (label
    keys, label parents, labels kept, found label: -1 none, -2 past ``max_labels``). Unseen only when not
    ``graded``. With ``bound`` >= 0, a node whose cell is more than ``bound`` ticks from entering by
    ``remaining`` (steps to the target) is not searched."""
    cells = neighbours.shape[0]
    use_goal = goal.shape[0] > 0
    kept = _no_labels(watchers)
    frontier = np.empty(1024, dtype=np.int64)
    upcoming = np.empty(1024, dtype=np.int64)
    gains = np.zeros(watchers, dtype=np.float64)
    zero = np.zeros(watchers, dtype=np.float64)
    candidate = np.zeros(watchers, dtype=np.float64)
    seen = _is_bit(bits, source, entry)
    if seen and not graded:
        return kept.key, kept.parent, 0, -1
    _gains_at(start, tick, watcher, gain, source, entry, gains)
    state = _step(zero, gains, fall, candidate)
    if state == 1:
        return kept.key, kept.parent, 0, -1
    kept, node = _keep(kept, 0, entry * cells + source, -1, candidate)
    kept.nodes.settled[node] = state == 0
    frontier[0] = 0
    width = 1
    labels = 1
    if source == target or (use_goal and _is_bit(goal, source, entry)):
        return kept.key, kept.parent, labels, 0
    layer = 0
    while width > 0:
        upcoming_width = 0
        for index in range(width):
            label = frontier[index]
            key = kept.key[label]
            phase, cell = key // cells, key % cells
            after = (phase + 1) % period
            for move in range(5):
                other = cell if move == 4 else neighbours[cell, move]
                if other < 0:
                    continue
                if bound >= 0 and (remaining[other] < 0 or layer + 1 + remaining[other] > bound):
                    continue
                next_key = after * cells + other
                node, _ = _find(kept.nodes, next_key)
                if node >= 0 and kept.nodes.settled[node]:
                    continue
                if graded:
                    _gains_at(start, tick, watcher, gain, other, after, gains)
                    state = _step(kept.meters[label], gains, fall, candidate)
                    if state == 1:
                        continue
                elif _is_bit(bits, other, after):
                    continue
                else:
                    state = 0
                    candidate[:] = 0.0
                if _dominated(kept, next_key, candidate):
                    continue
                if labels >= max_labels:
                    return kept.key, kept.parent, labels, -2
                kept, node = _keep(kept, labels, next_key, label, candidate)
                kept.nodes.settled[node] = state == 0
                upcoming = _append(upcoming, upcoming_width, labels)
                upcoming_width += 1
                labels += 1
                if other == target or (use_goal and _is_bit(goal, other, after)):
                    return kept.key, kept.parent, labels, labels - 1
        frontier, upcoming = upcoming, frontier
        width = upcoming_width
        layer += 1
    return kept.key, kept.parent, labels, -1


def entry_search(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    entry: int,
    target: int,
    *,
    graded: bool,
    goal: np.ndarray | None = None,
    bound: int = -1,
    remaining: np.ndarray | None = None,
    max_labels: int,
) -> EntryPath:
    """The fastest path entering ``source`` at lap tick ``entry`` to ``target`` (or to a node of ``goal``,
    bits as :attr:`Sweep.reached`), unseen or (``graded``) undetected, least in move order among the
    fastest; ``bound`` (with ``remaining``, ``int (cells,)`` steps to the target, negative where it cannot
    be reached) skips nodes that cannot reach the target within ``bound`` ticks of entering.

    Raises
    ------
    LimitError
        When the search would keep more than ``max_labels`` labels.
    """
    cells = sight.cells
    rest = np.zeros(cells, dtype=np.int64) if remaining is None else np.ascontiguousarray(remaining, dtype=np.int64)
    keys, parents, labels, found = _entry_search(
        np.ascontiguousarray(neighbours, dtype=np.int64), sight.start, sight.tick, sight.watcher, sight.gain,
        sight.bits, sight.watchers, sight.period, float(sight.fall), int(source), int(entry), int(target),
        np.zeros((0, sight.bits.shape[1]), dtype=np.uint64) if goal is None else goal, bool(graded), int(bound),
        rest, int(max_labels),
    )  # fmt: skip
    if found == -2:
        raise LimitError(
            f"a sneak search from one entry tick passed {max_labels} labels; the level, lap or guards are too large for it"
        )
    if found < 0:
        return EntryPath(False, np.zeros(0, dtype=np.int64), labels)
    chain = [found]
    while parents[chain[-1]] >= 0:
        chain.append(int(parents[chain[-1]]))
    chain.reverse()
    return EntryPath(True, (keys[chain] % cells).astype(np.int64), labels)
