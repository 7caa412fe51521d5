"""Vision from a continuous pose: the eye anywhere, the cone along any heading.

The rule is the grid's (:mod:`guardsim.vision.rays`) with the eye at the body's position: a traversable
cell is seen when its centre is within ``view_range`` of the eye, within ``fov_degrees / 2`` of the
heading, and the segment from the eye to the centre touches no wall; the cell the eye stands in is always
seen. At a cell centre facing one of the four headings it sees what the grid guard sees there. Under the
Bresenham rule (:mod:`guardsim.vision.bresenham`, a grid rule) the cone is the same, taken from the pose,
and the segment test is replaced by the grid line from the cell the eye is in to the target cell.

:func:`pose_visible_cells` is the reference: numpy for the cone and one pymunk ray per cell.
:class:`PoseVision` is the fast path: a compiled kernel finds the cells in the cone and screens their rays
against nearby walls (:func:`guardsim.kernels.screen.screen`), and pymunk is asked only about close calls,
so the verdict on every ray is the same. Both are compared tick for tick in ``tests/test_motion.py``.
"""

from __future__ import annotations

import math

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.kernels.compiler import jit
from guardsim.kernels.screen import CLEAR, CLOSE_CALL, WallIndex, screen
from guardsim.vision.bresenham import bresenham_clear, bresenham_line
from guardsim.vision.cone import VisionCone
from guardsim.vision.rules import LineOfSight
from guardsim.world import World

__all__ = ["PoseVision", "pose_visible_cells"]

# The grid cone's tolerance (guardsim.vision.cone), in cells and in cosine.
_EDGE_TOLERANCE = 1e-9


def _cone_terms(cone: VisionCone, heading_degrees: float) -> tuple[float, float, float, bool, float]:
    """``(hx, hy, cos_half, full, reach)`` of a cone along ``heading_degrees``; reach in cells."""
    angle = math.radians(heading_degrees)
    return (
        math.cos(angle),
        math.sin(angle),
        math.cos(math.radians(cone.fov_degrees) / 2),
        cone.fov_degrees >= 360,
        cone.view_range / cone.cell_size,
    )


def _cell_span(eye: float, origin: float, cell_size: float, reach: float, count: int) -> tuple[int, int]:
    """First and last cell index whose centre may lie within ``reach`` cells of ``eye`` along one axis."""
    middle = (eye - origin) / cell_size - 0.5
    return max(0, math.ceil(middle - reach - _EDGE_TOLERANCE)), min(
        count - 1, math.floor(middle + reach + _EDGE_TOLERANCE)
    )


def pose_visible_cells(
    world: World,
    grid: CoverageGrid,
    cone: VisionCone,
    x: float,
    y: float,
    heading_degrees: float,
    *,
    rule: LineOfSight = LineOfSight.PYMUNK,
) -> np.ndarray:
    """Flat indices of the cells seen from ``(x, y)`` facing ``heading_degrees``, ascending: the reference.

    One pymunk segment query per traversable cell in the cone; under ``LineOfSight.BRESENHAM``, one
    Bresenham line (in Python) from the eye's cell instead.
    """
    rows, cols = grid.shape
    hx, hy, cos_half, full, reach = _cone_terms(cone, heading_degrees)
    first_col, last_col = _cell_span(x, grid.origin[0], grid.cell_size, reach, cols)
    first_row, last_row = _cell_span(y, grid.origin[1], grid.cell_size, reach, rows)
    seen = []
    own = grid.cell_of((x, y))
    if own is not None and grid.traversable[own[1], own[0]]:
        seen.append(grid.flat(*own))
    if first_col <= last_col and first_row <= last_row:
        col_grid, row_grid = np.meshgrid(np.arange(first_col, last_col + 1), np.arange(first_row, last_row + 1))
        target_cols, target_rows = col_grid.ravel(), row_grid.ravel()
        centre_x = grid.origin[0] + (target_cols + 0.5) * grid.cell_size
        centre_y = grid.origin[1] + (target_rows + 0.5) * grid.cell_size
        dx = (centre_x - x) / grid.cell_size
        dy = (centre_y - y) / grid.cell_size
        distance = np.sqrt(dx * dx + dy * dy)
        inside = distance <= reach + _EDGE_TOLERANCE
        if not full:
            inside &= (distance == 0) | (dx * hx + dy * hy >= (cos_half - _EDGE_TOLERANCE) * distance)
        inside &= grid.traversable[target_rows, target_cols]
        for col, row, target_x, target_y in zip(
            target_cols[inside].tolist(),
            target_rows[inside].tolist(),
            centre_x[inside].tolist(),
            centre_y[inside].tolist(),
        ):
            if rule is LineOfSight.BRESENHAM:
                clear = own is not None and all(
                    grid.traversable[r, c] for c, r in bresenham_line(own[0], own[1], col, row)[1:]
                )
            else:
                clear = world.line_of_sight((x, y), (target_x, target_y))
            if clear:
                seen.append(row * cols + col)
    return np.unique(np.asarray(seen, dtype=np.int64))


@jit
def _cone_cells(
    eye_x: float,
    eye_y: float,
    hx: float,
    hy: float,
    cos_half: float,
    full: bool,
    reach: float,
    span: np.ndarray,
    origin_x: float,
    origin_y: float,
    cell_size: float,
    cols: int,
    traversable: np.ndarray,
    seen: np.ndarray,
    skip_seen: bool,
    candidates: np.ndarray,
    targets: np.ndarray,
) -> int:
    """Write the traversable cells whose centres lie in the cone (the eye's own cell left out, and with
    ``skip_seen`` the cells already seen) into ``candidates`` and their centres into ``targets``."""
    count = 0
    own_col = math.floor((eye_x - origin_x) / cell_size)
    own_row = math.floor((eye_y - origin_y) / cell_size)
    limit = reach + 1e-9
    slack = cos_half - 1e-9
    for row in range(span[2], span[3] + 1):
        for col in range(span[0], span[1] + 1):
            flat = row * cols + col
            if not traversable[flat] or (skip_seen and seen[flat]) or (col == own_col and row == own_row):
                continue
            target_x = origin_x + (col + 0.5) * cell_size
            target_y = origin_y + (row + 0.5) * cell_size
            dx = (target_x - eye_x) / cell_size
            dy = (target_y - eye_y) / cell_size
            distance = math.sqrt(dx * dx + dy * dy)
            if distance > limit:
                continue
            if not full and distance != 0 and dx * hx + dy * hy < slack * distance:
                continue
            candidates[count] = flat
            targets[count, 0] = target_x
            targets[count, 1] = target_y
            count += 1
    return count


class PoseVision:
    """The fast vision from continuous poses on one scene's world, grid and cone.

    Calls return the same cells as :func:`pose_visible_cells` with the same ``rule``.
    """

    def __init__(
        self,
        world: World,
        grid: CoverageGrid,
        cone: VisionCone,
        walls: WallIndex,
        *,
        rule: LineOfSight = LineOfSight.PYMUNK,
    ) -> None:
        self.rule = rule
        self.world = world
        self.grid = grid
        self.cone = cone
        self.walls = walls
        self._traversable = np.ascontiguousarray(grid.traversable.ravel())
        self._no_seen = np.zeros(grid.size, dtype=bool)
        rows, cols = grid.shape
        reach = cone.view_range / cone.cell_size
        side = 2 * min(math.ceil(reach) + 2, max(rows, cols)) + 1
        widest = min(grid.size, side * side)
        self._candidates = np.zeros(widest, dtype=np.int64)
        self._targets = np.zeros((widest, 2), dtype=np.float64)
        self._verdicts = np.zeros(widest, dtype=np.int8)
        self._stamp = np.zeros(walls.segments.shape[0] + 1, dtype=np.int64)
        self._span = np.zeros(4, dtype=np.int64)

    def __call__(self, x: float, y: float, heading_degrees: float) -> np.ndarray:
        """Flat indices of every cell seen from the pose, ascending."""
        return np.unique(self.unseen_visible(x, y, heading_degrees, self._no_seen))

    def unseen_visible(self, x: float, y: float, heading_degrees: float, seen: np.ndarray) -> np.ndarray:
        """Flat indices of the cells seen from the pose that ``seen`` (``bool (cells,)``) does not hold yet,
        in no particular order; the rays to cells already seen are not cast."""
        grid = self.grid
        rows, cols = grid.shape
        hx, hy, cos_half, full, reach = _cone_terms(self.cone, heading_degrees)
        span = self._span
        span[0], span[1] = _cell_span(x, grid.origin[0], grid.cell_size, reach, cols)
        span[2], span[3] = _cell_span(y, grid.origin[1], grid.cell_size, reach, rows)
        count = _cone_cells(
            x, y, hx, hy, cos_half, full, reach, span, grid.origin[0], grid.origin[1], grid.cell_size, cols,
            self._traversable, seen, seen is not self._no_seen, self._candidates, self._targets,
        )  # fmt: skip
        found: list[int] = []
        own = grid.cell_of((x, y))
        if own is not None:
            flat = grid.flat(*own)
            if self._traversable[flat] and not seen[flat]:
                found.append(flat)
        if count == 0:
            return np.asarray(found, dtype=np.int64)
        candidates, targets, verdicts = self._candidates[:count], self._targets[:count], self._verdicts[:count]
        if self.rule is LineOfSight.BRESENHAM:
            return np.concatenate([np.asarray(found, dtype=np.int64), self._bresenham(own, candidates)])
        if self.walls.walls.shape[0]:
            screen(x, y, targets, self.walls, self._stamp, verdicts)
        else:
            verdicts[:] = CLEAR
        visible = verdicts == CLEAR
        for index in np.flatnonzero(verdicts == CLOSE_CALL).tolist():
            visible[index] = self.world.line_of_sight((x, y), (float(targets[index, 0]), float(targets[index, 1])))
        clear = candidates[visible]
        return np.concatenate([np.asarray(found, dtype=np.int64), clear]) if found else clear.copy()

    def _bresenham(self, own: tuple[int, int] | None, candidates: np.ndarray) -> np.ndarray:
        """The candidates whose Bresenham line from the eye's cell ``own`` is clear (compiled)."""
        if own is None:
            return np.zeros(0, dtype=np.int64)
        rows, cols = self.grid.shape
        offsets = np.column_stack([candidates % cols - own[0], candidates // cols - own[1]])
        out = np.empty(len(candidates) + 1, dtype=np.int64)
        count = bresenham_clear(self._traversable, rows, cols, own[0], own[1], offsets, out)
        # The first entry is the eye's own cell, which the caller has already handled.
        return out[1:count].copy()
