"""Array chores in compiled code by plain loops, which numba compiles in a fraction of the time its own
versions take on first use (measured in a fresh process: slice assignment ``a[i:j] = b`` 2.4 s, for
its error message alone; the first reduction such as ``a.max()`` 1.3 s; ``np.flatnonzero`` 0.4 s;
``np.arange`` 0.3 s; a loop 0.01-0.05 s)."""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["copy_into", "count_true", "largest", "smallest", "true_indices", "upto"]


@jit(inline="always")
def copy_into(target: np.ndarray, begin: int, source: np.ndarray) -> None:
    """``target[begin:begin + len(source)] = source`` for one-dimensional arrays (the caller ensures room).

    Examples
    --------
    >>> target = np.zeros(5, dtype=np.int64)
    >>> copy_into(target, 1, np.array([7, 8]))
    >>> target.tolist()
    [0, 7, 8, 0, 0]
    """
    for index in range(source.shape[0]):
        target[begin + index] = source[index]


@jit
def count_true(values: np.ndarray) -> int:
    """How many of ``values`` are true (``values.sum()`` for a one-dimensional bool array).

    >>> count_true(np.array([True, False, True]))
    2
    """
    count = 0
    for index in range(values.shape[0]):
        if values[index]:
            count += 1
    return count


@jit
def largest(values: np.ndarray, count: int) -> int:
    """The largest of ``values[:count]`` (``count`` at least 1).

    >>> largest(np.array([3, 9, 4, 12]), 3)
    9
    """
    best = values[0]
    for index in range(1, count):
        if values[index] > best:
            best = values[index]
    return best


@jit
def smallest(values: np.ndarray, count: int) -> int:
    """The smallest of ``values[:count]`` (``count`` at least 1).

    >>> smallest(np.array([3, 9, 1]), 2)
    3
    """
    best = values[0]
    for index in range(1, count):
        if values[index] < best:
            best = values[index]
    return best


@jit
def true_indices(values: np.ndarray) -> np.ndarray:
    """``int64``: the indices where ``values`` is true, ascending (``np.flatnonzero`` of a 1-D array).

    >>> true_indices(np.array([False, True, True, False])).tolist()
    [1, 2]
    """
    found = np.empty(count_true(values), dtype=np.int64)
    count = 0
    for index in range(values.shape[0]):
        if values[index]:
            found[count] = index
            count += 1
    return found


@jit
def upto(count: int) -> np.ndarray:
    """``int64``: ``0, 1, ..., count - 1`` (``np.arange(count)``).

    >>> upto(3).tolist()
    [0, 1, 2]
    """
    values = np.empty(count, dtype=np.int64)
    for index in range(count):
        values[index] = index
    return values
