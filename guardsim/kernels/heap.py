"""A binary min-heap of (key, item) pairs in two caller-owned arrays (the exact search's open list and
the sneak search's Dijkstra queue), and heapsort (a compiled vision fill's cells, the beam's ranking).

Equal keys come out in an order fixed by the pushes alone, so every search that uses it is
deterministic.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.arrays import upto
from guardsim.kernels.compiler import jit

__all__ = ["heap_pop", "heap_push", "heap_sort", "stable_order"]


@jit(inline="always")
def heap_push(keys: np.ndarray, items: np.ndarray, size: int, key: int, item: int) -> int:
    """Add ``(key, item)`` to the heap of ``size`` pairs; returns the new size (the arrays must have room)."""
    index = size
    while index > 0:
        parent = (index - 1) >> 1
        if keys[parent] <= key:
            break
        keys[index], items[index] = keys[parent], items[parent]
        index = parent
    keys[index], items[index] = key, item
    return size + 1


@jit(inline="always")
def heap_pop(keys: np.ndarray, items: np.ndarray, size: int) -> tuple[int, int, int]:
    """Remove the pair with the least key from the heap of ``size`` (> 0) pairs: ``(key, item, new size)``."""
    key, item = keys[0], items[0]
    size -= 1
    last_key, last_item = keys[size], items[size]
    index = 0
    while True:
        child = 2 * index + 1
        if child >= size:
            break
        if child + 1 < size and keys[child + 1] < keys[child]:
            child += 1
        if keys[child] >= last_key:
            break
        keys[index], items[index] = keys[child], items[child]
        index = child
    if size > 0:
        keys[index], items[index] = last_key, last_item
    return key, item, size


@jit(inline="always")
def _sift_down(values: np.ndarray, begin: int, root: int, size: int) -> None:
    """Restore the max-heap below ``root`` of ``values[begin:begin + size]``."""
    value = values[begin + root]
    while True:
        child = 2 * root + 1
        if child >= size:
            break
        if child + 1 < size and values[begin + child + 1] > values[begin + child]:
            child += 1
        if values[begin + child] <= value:
            break
        values[begin + root] = values[begin + child]
        root = child
    values[begin + root] = value


@jit
def heap_sort(values: np.ndarray, begin: int, end: int) -> None:
    """Sort ``values[begin:end]`` ascending, in place (heapsort: no allocation, ``n log n``; numba's own
    ``np.sort`` costs seconds to compile).

    Examples
    --------
    >>> values = np.array([9, 3, 1, 2, 7, 0])
    >>> heap_sort(values, 1, 5)
    >>> values.tolist()
    [9, 1, 2, 3, 7, 0]
    """
    size = end - begin
    for root in range(size // 2 - 1, -1, -1):
        _sift_down(values, begin, root, size)
    for last in range(size - 1, 0, -1):
        values[begin], values[begin + last] = values[begin + last], values[begin]
        _sift_down(values, begin, 0, last)


@jit(inline="always")
def _before(keys: np.ndarray, order: np.ndarray, a: int, b: int) -> bool:
    return keys[order[a]] < keys[order[b]] or (keys[order[a]] == keys[order[b]] and order[a] < order[b])


@jit
def stable_order(keys: np.ndarray) -> np.ndarray:
    """The indices that sort ``keys`` ascending, equal keys in index order: ``np.argsort(keys,
    kind="stable")`` by heapsort on (key, index), which compiles in a fraction of numba's merge sort.

    Examples
    --------
    >>> stable_order(np.array([3, 1, 3, 0])).tolist()
    [3, 1, 0, 2]
    """
    size = keys.shape[0]
    order = upto(size)
    for start in range(size // 2 - 1, -1, -1):
        _sift_order(keys, order, start, size)
    for last in range(size - 1, 0, -1):
        order[0], order[last] = order[last], order[0]
        _sift_order(keys, order, 0, last)
    return order


@jit(inline="always")
def _sift_order(keys: np.ndarray, order: np.ndarray, root: int, size: int) -> None:
    while True:
        child = 2 * root + 1
        if child >= size:
            return
        if child + 1 < size and _before(keys, order, child, child + 1):
            child += 1
        if not _before(keys, order, root, child):
            return
        order[root], order[child] = order[child], order[root]
        root = child
