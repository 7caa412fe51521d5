"""The reference vision: one pymunk ray per traversable cell in the cone, every time it is asked.

A traversable cell is seen when its centre is within ``view_range`` of the eye, within
``fov_degrees / 2`` of the heading, and the segment from the eye to the centre touches no wall
(:meth:`guardsim.world.World.line_of_sight`). The guard's own cell is always seen. The cache
(:mod:`guardsim.vision.cache`) gives the same cells, faster; this is what it is checked against.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.vision.cone import VisionCone, cone_targets
from guardsim.world import World

__all__ = ["visible_cells"]


def visible_cells(world: World, grid: CoverageGrid, cone: VisionCone, col: int, row: int, heading: int) -> np.ndarray:
    """Flat indices of the cells seen from cell ``(col, row)`` facing ``heading``, sorted ascending.

    This is the reference: one pymunk segment query per traversable cell in the cone.
    """
    cols = grid.shape[1]
    target_cols, target_rows = cone_targets(grid, cone, col, row, heading)
    eye = grid.centre(col, row)
    seen = [row * cols + col]
    for target_col, target_row in zip(target_cols.tolist(), target_rows.tolist()):
        if target_col == col and target_row == row:
            continue
        if world.line_of_sight(eye, grid.centre(target_col, target_row)):
            seen.append(target_row * cols + target_col)
    return np.unique(np.asarray(seen, dtype=np.int64))
