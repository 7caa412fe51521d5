"""The Bresenham line-of-sight rule of grid watchman-route solvers, for comparison with their optima.

Under this rule a cell sees a target cell when every cell of the integer Bresenham line from the viewer's
cell to the target's (traced viewer → target, both ends included) is traversable. It replaces the pymunk
rays only; the cone's angle and range still apply (with ``fov_degrees`` 360 and an unlimited range it is
the rule of the optimal solver MWRP-CP3 on Moving AI maps).

The line is the classic all-octant integer form: error ``e = dx - dy``; at each step, ``2e > -dy``
moves in x and ``2e < dx`` moves in y (both on a diagonal step).
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.targets import cone_target

__all__ = ["bresenham_clear", "bresenham_line", "bresenham_visible"]


def bresenham_line(col: int, row: int, target_col: int, target_row: int) -> list[tuple[int, int]]:
    """Cells ``(col, row)`` of the Bresenham line from the first cell to the second, both included.

    Examples
    --------
    >>> bresenham_line(0, 0, 3, 1)
    [(0, 0), (1, 0), (2, 1), (3, 1)]
    >>> bresenham_line(2, 2, 0, 0)
    [(2, 2), (1, 1), (0, 0)]
    """
    dx, dy = abs(target_col - col), abs(target_row - row)
    step_x = 1 if target_col > col else -1
    step_y = 1 if target_row > row else -1
    error = dx - dy
    cells = [(col, row)]
    while (col, row) != (target_col, target_row):
        doubled = 2 * error
        if doubled > -dy:
            error -= dy
            col += step_x
        if doubled < dx:
            error += dx
            row += step_y
        cells.append((col, row))
    return cells


def bresenham_visible(traversable: np.ndarray, col: int, row: int, offsets: np.ndarray) -> np.ndarray:
    """Reference: flat indices, ascending, of the cells in ``offsets`` seen from ``(col, row)``.

    Plain Python, one line per target; :func:`bresenham_clear` is the compiled twin the cache uses.
    """
    rows, cols = traversable.shape
    seen = {row * cols + col}
    for dcol, drow in offsets.tolist():
        target_col, target_row = col + dcol, row + drow
        if not (0 <= target_col < cols and 0 <= target_row < rows) or not traversable[target_row, target_col]:
            continue
        if all(traversable[r, c] for c, r in bresenham_line(col, row, target_col, target_row)):
            seen.add(target_row * cols + target_col)
    return np.array(sorted(seen), dtype=np.int64)


@jit
def bresenham_clear(
    traversable: np.ndarray, rows: int, cols: int, col: int, row: int, offsets: np.ndarray, out: np.ndarray
) -> int:
    """Write the flat indices seen from ``(col, row)`` (itself included, unsorted) into ``out``; return the count."""
    count = 0
    out[count] = row * cols + col
    count += 1
    for index in range(offsets.shape[0]):
        flat = cone_target(col, row, offsets, index, rows, cols, traversable)
        if flat < 0:
            continue
        target_col = flat % cols
        target_row = flat // cols
        dx = abs(target_col - col)
        dy = abs(target_row - row)
        step_x = 1 if target_col > col else -1
        step_y = 1 if target_row > row else -1
        error = dx - dy
        x = col
        y = row
        clear = True
        while x != target_col or y != target_row:
            doubled = 2 * error
            if doubled > -dy:
                error -= dy
                x += step_x
            if doubled < dx:
                error += dx
                y += step_y
            if not traversable[y * cols + x]:
                clear = False
                break
        if clear:
            out[count] = target_row * cols + target_col
            count += 1
    return count
