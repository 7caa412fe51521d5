"""Copying between arrays in compiled code by a plain loop: numba's slice assignment (``a[i:j] = b``)
costs about two seconds to compile, for its error message alone."""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["copy_into"]


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
