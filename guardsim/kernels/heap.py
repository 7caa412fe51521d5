"""A binary min-heap of (key, item) pairs in two caller-owned arrays: the exact search's open list and
the sneak search's Dijkstra queue.

Equal keys come out in an order fixed by the pushes alone, so every search that uses it is
deterministic.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["heap_pop", "heap_push"]


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
