"""The node store of the exact searches: nodes in flat arrays, found again through an open-addressing hash
table, with a chain per label for the dominance checks.

A node is a label (one or more small integers: the position, or the guard, position and walk before it)
and the set of goal cells seen so far (a bitset of 64-bit words, ``seen_rows[node]``). The hash table's
slots hold ``node + 1`` (0: empty); linear probing from :func:`guardsim.kernels.frontier.node_hash`'s
value. Each chain (a position, or a guard's position) links its nodes newest first through ``latest`` and
``earlier``, so a dominance check reads the last few nodes of the same chain. The one-guard search
(``guardsim.search.astar``) and the team search (``guardsim.search.team``) both keep their nodes here;
each adds its own fields (steps, parent, estimate) beside these arrays.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import numpy as np

from guardsim.kernels.arrays import copy_into
from guardsim.kernels.compiler import jit

__all__ = ["find_node", "is_dominated", "new_table", "store_node"]

#: The counters slot that holds the number of nodes stored (the searches' ``NODES``).
STORED = 0


@contextlib.contextmanager
def _small_pages() -> Iterator[None]:
    """numpy asks Linux for huge pages on large arrays; the hash table is touched sparsely, so each probe
    would zero a whole 2 MB page: a 3 GB budget on a tiny level cost 1.4 GB and 15 s instead of 0.2 GB
    and 2 s. Pages are then zeroed one small page at a time, as touched."""
    try:
        from numpy._core.multiarray import _set_madvise_hugepage  # type: ignore[attr-defined]
    except ImportError:  # another numpy: its default pages
        yield
        return
    before = _set_madvise_hugepage(False)
    try:
        yield
    finally:
        _set_madvise_hugepage(before)


def new_table(capacity: int) -> np.ndarray:
    """An empty hash table for at most ``capacity`` nodes (a power of two, at least twice as many slots;
    probed at random, so it gets small pages)."""
    slots = 1 << max(4, int(2 * capacity - 1).bit_length())
    with _small_pages():
        return np.zeros(slots, dtype=np.int64)


@jit
def find_node(
    table: np.ndarray, value: np.uint64, labels: tuple, label: tuple, seen_rows: np.ndarray, seen: np.ndarray
) -> tuple[int, int]:
    """(node, slot): the node whose labels (``labels[k][node] == label[k]`` for each k) and seen set are
    these, or -1 and the empty slot where it would go; ``value`` is the node's hash."""
    mask = table.shape[0] - 1
    slot = np.int64(value >> np.uint64(1)) & mask
    words = seen.shape[0]
    while True:
        entry = table[slot]
        if entry == 0:
            return -1, slot
        node = entry - 1
        same = True
        for k in range(len(labels)):
            if labels[k][node] != label[k]:
                same = False
                break
        if same:
            for word in range(words):
                if seen_rows[node, word] != seen[word]:
                    same = False
                    break
            if same:
                return node, slot
        slot = (slot + 1) & mask


@jit
def is_dominated(
    latest: np.ndarray,
    earlier: np.ndarray,
    chain: int,
    costs: tuple,
    cost: tuple,
    seen_rows: np.ndarray,
    seen: np.ndarray,
    checks: int,
    itself: int,
) -> bool:
    """Whether one of the last ``checks`` nodes of ``chain`` (other than ``itself``) saw at least ``seen``
    at no greater cost in every measure (``costs[k][node] <= cost[k]``): whatever the node could still do,
    that one can do no later."""
    node = latest[chain]
    words = seen.shape[0]
    while node >= 0 and checks > 0:
        checks -= 1
        if node != itself:
            cheaper = True
            for k in range(len(costs)):
                if costs[k][node] > cost[k]:
                    cheaper = False
                    break
            if cheaper:
                covers = True
                for word in range(words):
                    if seen[word] & ~seen_rows[node, word]:
                        covers = False
                        break
                if covers:
                    return True
        node = earlier[node]
    return False


@jit
def store_node(
    counters: np.ndarray,
    table: np.ndarray,
    latest: np.ndarray,
    earlier: np.ndarray,
    seen_rows: np.ndarray,
    slot: int,
    chain: int,
    seen: np.ndarray,
) -> int:
    """Store a new node with ``seen`` in the empty ``slot`` found by :func:`find_node`, at the head of
    ``chain``; returns its number (the caller fills its other fields)."""
    node = counters[STORED]
    counters[STORED] += 1
    copy_into(seen_rows[node], 0, seen)
    table[slot] = node + 1
    earlier[node] = latest[chain]
    latest[chain] = node
    return node
