"""Sight from a point anywhere on the level, all around: what a camera or a lamp sees.

A guard's eye is always a cell centre; a camera's or a lamp's is any point of the free area or of a
wall's edge. :class:`PointSight` gives the traversable cells whose centres lie within a reach of such a
point with a clear line of sight by the level's rule, and their distances. With the pymunk rule each ray
is screened against the walls near the eye (:func:`guardsim.kernels.screen.screen`) and pymunk casts
only the close calls, from a point a hair along the ray (an eye on a wall's edge would otherwise hit
that wall at once). With the Bresenham rule the eye is the cell holding the point (a traversable one
when the point lies on a cell's side).
"""

from __future__ import annotations

import math

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.kernels.screen import BLOCKED, CLOSE_CALL, index_walls, screen
from guardsim.vision.bresenham import bresenham_clear
from guardsim.vision.rules import LineOfSight
from guardsim.world import World

__all__ = ["PointSight"]

# A cell centre exactly at the reach is in, as a guard's cone counts it.
_EDGE_TOLERANCE = 1e-9


class PointSight:
    """Cells in sight of points, for one level, grid and line-of-sight rule.

    Parameters
    ----------
    reach
        The longest reach that will be asked (it sizes the wall index's buckets; longer asks stay exact).

    Examples
    --------
    A 6 x 2 room with a block on its top edge; an eye on the block's right side sees right, not through it:

    >>> from guardsim.level import parse_level
    >>> from guardsim.grid import build_grid
    >>> level = parse_level({"outer": [[0, 0], [6, 0], [6, 2], [0, 2]], "holes": [[[2, 0], [3, 0], [3, 1], [2, 1]]]})
    >>> world = World(level)
    >>> cells, distances = PointSight(world, build_grid(level, world), reach=3.0).cells((3.0, 0.5), 3.0)
    >>> cells.tolist(), [round(float(d), 3) for d in distances]
    ([3, 4, 5, 9, 10, 11], [0.5, 1.5, 2.5, 1.118, 1.803, 2.693])
    """

    def __init__(self, world: World, grid: CoverageGrid, *, rule: LineOfSight | str = LineOfSight.PYMUNK, reach: float):
        self.world = world
        self.grid = grid
        self.rule = LineOfSight(rule)
        self._traversable = np.ascontiguousarray(grid.traversable.ravel())
        rows, cols = grid.shape
        self._walls = index_walls(
            np.array([(*wall.a, *wall.b) for wall in world.walls], dtype=np.float64).reshape(-1, 4),
            grid.origin,
            (cols * grid.cell_size, rows * grid.cell_size),
            max(float(reach), grid.cell_size),
        )
        self._stamp = np.zeros(len(world.walls) + 1, dtype=np.int64)

    def candidates(self, eye: tuple[float, float], reach: float) -> tuple[np.ndarray, np.ndarray]:
        """The traversable cells whose centres lie within ``reach`` of ``eye`` (walls not asked), and
        their distances."""
        grid = self.grid
        rows, cols = grid.shape
        size = grid.cell_size
        ox, oy = grid.origin
        first_col = max(0, math.floor((eye[0] - reach - ox) / size - 0.5))
        last_col = min(cols - 1, math.ceil((eye[0] + reach - ox) / size - 0.5))
        first_row = max(0, math.floor((eye[1] - reach - oy) / size - 0.5))
        last_row = min(rows - 1, math.ceil((eye[1] + reach - oy) / size - 0.5))
        if first_col > last_col or first_row > last_row:
            return np.zeros(0, dtype=np.int64), np.zeros(0)
        col_index = np.arange(first_col, last_col + 1)
        row_index = np.arange(first_row, last_row + 1)
        col_grid, row_grid = np.meshgrid(col_index, row_index)
        flat = (row_grid * cols + col_grid).ravel()
        xs = ox + (col_grid.ravel() + 0.5) * size
        ys = oy + (row_grid.ravel() + 0.5) * size
        distance = np.hypot(xs - eye[0], ys - eye[1])
        keep = (distance <= reach * (1 + _EDGE_TOLERANCE) + _EDGE_TOLERANCE) & self._traversable[flat]
        return flat[keep].astype(np.int64), distance[keep]

    def cells(self, eye: tuple[float, float], reach: float) -> tuple[np.ndarray, np.ndarray]:
        """``(cells, distances)``: the traversable cells, ascending, whose centres ``eye`` sees within
        ``reach`` (all around), and the distance to each centre."""
        flat, distance = self.candidates(eye, reach)
        if flat.size == 0:
            return flat, distance
        clear = self._bresenham(eye, flat) if self.rule is LineOfSight.BRESENHAM else self._rays(eye, flat)
        return flat[clear], distance[clear]

    def _centres(self, flat: np.ndarray) -> np.ndarray:
        cols = self.grid.shape[1]
        size = self.grid.cell_size
        return np.stack(
            [self.grid.origin[0] + (flat % cols + 0.5) * size, self.grid.origin[1] + (flat // cols + 0.5) * size],
            axis=1,
        ).astype(np.float64)

    def _rays(self, eye: tuple[float, float], flat: np.ndarray) -> np.ndarray:
        targets = np.ascontiguousarray(self._centres(flat))
        verdicts = np.zeros(flat.size, dtype=np.int8)
        screen(float(eye[0]), float(eye[1]), targets, self._walls, self._stamp, verdicts)
        clear = verdicts != BLOCKED
        hair = 1e-6 * self.grid.cell_size
        for index in np.flatnonzero(verdicts == CLOSE_CALL).tolist():
            tx, ty = float(targets[index, 0]), float(targets[index, 1])
            length = math.hypot(tx - eye[0], ty - eye[1])
            if length <= hair:
                continue
            start = (eye[0] + (tx - eye[0]) * hair / length, eye[1] + (ty - eye[1]) * hair / length)
            clear[index] = self.world.line_of_sight(start, (tx, ty))
        return clear

    def eye_cell(self, eye: tuple[float, float]) -> tuple[int, int]:
        """``(col, row)`` of the cell holding ``eye``: of the cells whose closure holds it, a traversable
        one when there is one (an eye on a wall's edge looks out of the wall)."""
        rows, cols = self.grid.shape
        size = self.grid.cell_size
        fx = (eye[0] - self.grid.origin[0]) / size
        fy = (eye[1] - self.grid.origin[1]) / size
        options = []
        for col in sorted({math.floor(fx), math.ceil(fx) - 1}):
            for row in sorted({math.floor(fy), math.ceil(fy) - 1}):
                options.append((min(max(col, 0), cols - 1), min(max(row, 0), rows - 1)))
        for col, row in options:
            if self.grid.traversable[row, col]:
                return col, row
        return options[0]

    def _bresenham(self, eye: tuple[float, float], flat: np.ndarray) -> np.ndarray:
        rows, cols = self.grid.shape
        col, row = self.eye_cell(eye)
        offsets = np.stack([flat % cols - col, flat // cols - row], axis=1).astype(np.int64)
        out = np.zeros(flat.size + 1, dtype=np.int64)
        count = bresenham_clear(self._traversable, rows, cols, col, row, offsets, out)
        seen = set(out[1:count].tolist())
        # The eye's own cell: clear when it is a candidate.
        seen.add(row * cols + col)
        return np.asarray([int(cell) in seen for cell in flat.tolist()], dtype=bool)
