"""The vision cone: which cell offsets lie within a guard's view range and field of view, per heading."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from guardsim.grid import DIRECTIONS, CoverageGrid
from guardsim.level import GuardSpec

__all__ = ["VisionCone", "cone_targets"]

# Cells exactly on the cone's edge or range are in; this absorbs float noise in that comparison.
_EDGE_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class VisionCone:
    """The cone's cell offsets for each of the four headings.

    ``offsets[h]`` is an ``int (n, 2)`` array of ``(dcol, drow)`` whose cell centres lie inside the cone
    for heading ``h``, nearest first; ``(0, 0)`` is always the first row.
    """

    view_range: float
    fov_degrees: float
    cell_size: float
    offsets: tuple[np.ndarray, ...]

    @classmethod
    def from_guard(cls, guard: GuardSpec, cell_size: float, *, grid_shape: tuple[int, int] | None = None) -> VisionCone:
        """The cone of a guard on a grid of ``cell_size``.

        With ``grid_shape`` (``(rows, cols)``), offsets too long to land on such a grid are left out: the
        cells seen are the same, and the cone's size stays bounded by the grid's whatever the view range.

        Examples
        --------
        >>> cone = VisionCone.from_guard(GuardSpec(view_range=1.0, fov_degrees=90), 1.0)
        >>> cone.offsets[0].tolist()
        [[0, 0], [1, 0]]
        """
        reach = guard.view_range / cell_size
        half_angle = math.radians(guard.fov_degrees) / 2
        cos_half = math.cos(half_angle)
        span = math.floor(min(reach + _EDGE_TOLERANCE, math.inf if grid_shape is None else max(grid_shape) - 1))
        grid_cols, grid_rows = np.meshgrid(np.arange(-span, span + 1), np.arange(-span, span + 1))
        dcol, drow = grid_cols.ravel(), grid_rows.ravel()
        distance = np.hypot(dcol, drow)
        in_range = distance <= reach + _EDGE_TOLERANCE
        offsets = []
        for heading_col, heading_row in DIRECTIONS:
            if guard.fov_degrees >= 360:
                in_angle = np.ones_like(in_range)
            else:
                with np.errstate(invalid="ignore", divide="ignore"):
                    cosine = (dcol * heading_col + drow * heading_row) / distance
                in_angle = (distance == 0) | (cosine >= cos_half - _EDGE_TOLERANCE)
            keep = in_range & in_angle
            order = np.lexsort((dcol[keep], drow[keep], distance[keep]))
            offsets.append(np.stack([dcol[keep][order], drow[keep][order]], axis=1).astype(np.int64))
        return cls(guard.view_range, guard.fov_degrees, cell_size, tuple(offsets))


def cone_targets(
    grid: CoverageGrid, cone: VisionCone, col: int, row: int, heading: int
) -> tuple[np.ndarray, np.ndarray]:
    """``(cols, rows)`` of the traversable cells whose centres lie in the cone, nearest first."""
    rows, cols = grid.shape
    offsets = cone.offsets[heading]
    target_cols = col + offsets[:, 0]
    target_rows = row + offsets[:, 1]
    on_grid = (target_cols >= 0) & (target_cols < cols) & (target_rows >= 0) & (target_rows < rows)
    target_cols, target_rows = target_cols[on_grid], target_rows[on_grid]
    candidates = grid.traversable[target_rows, target_cols]
    return target_cols[candidates], target_rows[candidates]
