"""The compiled twin of :func:`guardsim.vision.cone.cone_targets`, for the compiled vision fills."""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["cone_target"]


@jit
def cone_target(
    col: int, row: int, offsets: np.ndarray, index: int, rows: int, cols: int, traversable: np.ndarray
) -> int:
    """Compiled twin of :func:`cone_targets` for one offset: the flat index of the traversable cell
    ``offsets[index]`` away from ``(col, row)``, or -1 if it is off the grid, a wall or the guard's own cell."""
    target_col = col + offsets[index, 0]
    target_row = row + offsets[index, 1]
    if target_col < 0 or target_col >= cols or target_row < 0 or target_row >= rows:
        return -1
    if target_col == col and target_row == row:
        return -1
    flat = target_row * cols + target_col
    return flat if traversable[flat] else -1
