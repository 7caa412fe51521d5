"""The coverage grid: a level's bounding box cut into square cells, 4-connected.

A cell is traversable when its centre lies in the free area and the guard's circle fits there; two
4-neighbours are connected when the guard's circle can slide between their centres without touching a
wall. Both questions are answered by the physics world's pymunk queries.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from guardsim.errors import LevelError, PointError
from guardsim.kernels.states import HEADINGS_PER_CELL, cell_of_state, heading_of_state, state_of
from guardsim.level import Level
from guardsim.world import World

__all__ = [
    "DIRECTIONS",
    "HEADINGS_PER_CELL",
    "CoverageGrid",
    "build_grid",
    "cell_of_state",
    "heading_of_state",
    "state_of",
]

#: The four moves as (dcol, drow), indexed by heading number: 0 right, 1 down, 2 left, 3 up.
#: Heading number k points at 90*k degrees with y down (clockwise on screen).
DIRECTIONS: tuple[tuple[int, int], ...] = ((1, 0), (0, 1), (-1, 0), (0, -1))


@dataclass(frozen=True, eq=False)
class CoverageGrid:
    """Cells, their traversability and their 4-connectivity.

    Cells are addressed as ``(col, row)`` or by flat index ``row * cols + col``.
    """

    origin: tuple[float, float]
    """World position of the grid's top-left corner."""
    cell_size: float
    """Side of a cell in world units."""
    traversable: np.ndarray
    """``bool (rows, cols)``: the guard can stand at the cell centre."""
    neighbours: np.ndarray
    """``int (rows * cols, 4)``: flat index of the connected neighbour in each direction, or -1."""

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``."""
        rows, cols = self.traversable.shape
        return rows, cols

    @property
    def size(self) -> int:
        """Number of cells."""
        return int(self.traversable.size)

    def centre(self, col: int, row: int) -> tuple[float, float]:
        """World position of a cell's centre."""
        return (
            self.origin[0] + (col + 0.5) * self.cell_size,
            self.origin[1] + (row + 0.5) * self.cell_size,
        )

    def cell_of(self, point: tuple[float, float]) -> tuple[int, int] | None:
        """``(col, row)`` of the cell containing ``point``, or ``None`` outside the grid."""
        col = int(np.floor((point[0] - self.origin[0]) / self.cell_size))
        row = int(np.floor((point[1] - self.origin[1]) / self.cell_size))
        rows, cols = self.shape
        if 0 <= col < cols and 0 <= row < rows:
            return col, row
        return None

    def floor_cell(self, point: tuple[float, float], what: str = "the point") -> int:
        """The flat index of the traversable cell holding the world point ``point``.

        Raises :class:`~guardsim.errors.PointError`, naming ``what`` (``"--from"``, ``"the goal"``), when
        the point lies off the grid or in a cell a guard-sized body does not fit in.

        Examples
        --------
        >>> from guardsim import Scene, load_level
        >>> grid = Scene.from_level(load_level("levels/square.json")).grid
        >>> grid.unflat(grid.floor_cell((2.5, 30.5)))
        (2, 30)
        >>> grid.floor_cell((-4, 30), "the goal")
        Traceback (most recent call last):
        ...
        guardsim.errors.PointError: the goal -4,30 lies outside the level
        """
        cell = self.cell_of(point)
        where = f"{what} {point[0]:g},{point[1]:g}"
        if cell is None:
            raise PointError(f"{where} lies outside the level")
        if not self.traversable[cell[1], cell[0]]:
            raise PointError(f"{where} is in cell [{cell[0]}, {cell[1]}], where a guard-sized intruder does not fit")
        return self.flat(*cell)

    def flat(self, col: int, row: int) -> int:
        """Flat index of ``(col, row)``."""
        return row * self.shape[1] + col

    def unflat(self, index: int) -> tuple[int, int]:
        """``(col, row)`` of a flat index."""
        row, col = divmod(int(index), self.shape[1])
        return col, row

    @cached_property
    def component_labels(self) -> np.ndarray:
        """``int64 (rows * cols,)``: connected-area number of each cell, -1 where not traversable.

        Areas are numbered in row-major order of their first cell. Computed once per grid.
        """
        labels = np.full(self.size, -1, dtype=np.int64)
        neighbours = self.neighbours
        next_label = 0
        for start in np.flatnonzero(self.traversable.ravel()).tolist():
            if labels[start] >= 0:
                continue
            labels[start] = next_label
            queue = deque([start])
            while queue:
                cell = queue.popleft()
                for other in neighbours[cell].tolist():
                    if other >= 0 and labels[other] < 0:
                        labels[other] = next_label
                        queue.append(other)
            next_label += 1
        return labels

    @cached_property
    def entry_cells(self) -> np.ndarray:
        """``int64 (rows * cols * 4,)``: per state, the cell a guard steps from to arrive in it (-1: none).

        That is the connected neighbour of the state's cell opposite its heading.

        Examples
        --------
        >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 2), dtype=bool), np.array([[1, -1, -1, -1], [-1, -1, 0, -1]]))
        >>> grid.entry_cells.reshape(2, 4).tolist()
        [[-1, -1, 1, -1], [0, -1, -1, -1]]
        """
        return np.asarray(self.neighbours, dtype=np.int64)[:, [2, 3, 0, 1]].ravel()

    def component(self, col: int, row: int) -> np.ndarray:
        """``bool (rows, cols)``: the cells reachable from ``(col, row)`` through connected moves."""
        label = self.component_labels[self.flat(col, row)]
        if label < 0:
            return np.zeros(self.shape, dtype=bool)
        return (self.component_labels == label).reshape(self.shape)

    def largest_component(self) -> np.ndarray:
        """``bool (rows, cols)``: the largest set of mutually reachable cells (ties: first in row order)."""
        labels = self.component_labels
        if labels.max(initial=-1) < 0:
            return np.zeros(self.shape, dtype=bool)
        largest = int(np.argmax(np.bincount(labels[labels >= 0])))
        return (labels == largest).reshape(self.shape)


def build_grid(level: Level, world: World) -> CoverageGrid:
    """Rasterise a level into a :class:`CoverageGrid` using the world's pymunk queries.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> level = parse_level({"outer": [[0, 0], [3, 0], [3, 2], [0, 2]]})
    >>> grid = build_grid(level, World(level))
    >>> grid.shape, int(grid.traversable.sum()), grid.neighbours[0].tolist()
    ((2, 3), 6, [1, 3, -1, -1])
    """
    min_x, min_y, _, _ = level.bounds
    rows, cols = level.grid_shape()
    size = level.cell_size
    origin = (min_x, min_y)
    xs = min_x + (np.arange(cols) + 0.5) * size
    ys = min_y + (np.arange(rows) + 0.5) * size
    centre_x, centre_y = np.meshgrid(xs, ys)
    inside = shapely.contains_xy(level.free_area(), centre_x, centre_y)
    radius = level.guard.radius
    # Cells farther than radius + one cell from every wall fit the guard and move freely to their
    # neighbours: only the cells near a wall need the world's queries (a 1000 x 1000 grid in seconds).
    deep = inside & ~_near_walls(world, centre_x, centre_y, radius + 1.5 * size)
    traversable = deep.copy()
    for row, col in zip(*np.nonzero(inside & ~deep)):
        traversable[row, col] = world.fits((float(centre_x[row, col]), float(centre_y[row, col])), radius)

    neighbours = np.full((rows * cols, 4), -1, dtype=np.int64)
    for direction, (dcol, drow) in enumerate(DIRECTIONS[:2]):
        # Test each pair once (rightward and downward) and record it in both directions.
        pair = traversable[: rows - drow, : cols - dcol] & traversable[drow:, dcol:]
        free = pair & deep[: rows - drow, : cols - dcol] & deep[drow:, dcol:]
        here_rows, here_cols = np.nonzero(free)
        here = here_rows * cols + here_cols
        there = (here_rows + drow) * cols + here_cols + dcol
        neighbours[here, direction] = there
        neighbours[there, direction + 2] = here
        for row, col in zip(*np.nonzero(pair & ~free)):
            a = (float(xs[col]), float(ys[row]))
            b = (float(xs[col + dcol]), float(ys[row + drow]))
            if world.sweep_clear(a, b, radius):
                here = row * cols + col
                there = (row + drow) * cols + col + dcol
                neighbours[here, direction] = there
                neighbours[there, direction + 2] = here
    return CoverageGrid(origin=origin, cell_size=size, traversable=traversable, neighbours=neighbours)


def _near_walls(world: World, xs: np.ndarray, ys: np.ndarray, distance: float) -> np.ndarray:
    """``bool`` like ``xs``: the points within ``distance`` of a wall segment (a margin of float noise
    included), found through an STRtree of the walls rather than one query per point."""
    near = np.zeros(xs.shape, dtype=bool)
    if not world.walls or not xs.size:
        return near
    walls = shapely.linestrings([[tuple(wall.a), tuple(wall.b)] for wall in world.walls])
    points = shapely.points(xs.ravel(), ys.ravel())
    margin = 1e-6 * max(1.0, float(np.abs(xs).max(initial=0)), float(np.abs(ys).max(initial=0)), distance)
    hits, _ = shapely.STRtree(walls).query(points, predicate="dwithin", distance=distance + margin)
    near.ravel()[hits] = True
    return near


def start_cell(level: Level, grid: CoverageGrid, point: tuple[float, float]) -> tuple[int, int]:
    """The traversable cell containing a start point, or a :class:`LevelError` saying why not."""
    cell = grid.cell_of(point)
    where = f"{level.source}: start ({point[0]:g}, {point[1]:g})"
    if cell is None:
        raise LevelError(f"{where} lies outside the level")
    if not grid.traversable[cell[1], cell[0]]:
        raise LevelError(
            f"{where} is in cell [{cell[0]}, {cell[1]}], where the guard (radius {level.guard.radius:g}) does not fit"
        )
    return cell
