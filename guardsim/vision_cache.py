"""The fast vision path: each state's visible cells, computed once and shared by every episode.

A state is a cell and one of the four headings. (With ``line_of_sight="bresenham"`` the states are filled
by the compiled Bresenham rule of :mod:`guardsim.bresenham` instead.) The first time a state is asked for, its cells are
computed with the reference rule (:func:`guardsim.vision.visible_cells`): each ray is first screened
against the walls near the eye (:mod:`guardsim.sight_screen`), which settles clear misses and clear
crossings, and pymunk casts only the close calls. The result is stored in flat arrays (CSR layout) that
the compiled episode loop reads directly.
"""

from __future__ import annotations

import numba
import numpy as np

from guardsim.bresenham import bresenham_clear
from guardsim.grid import CoverageGrid
from guardsim.sight_screen import CLEAR, CLOSE_CALL, WallIndex, screen
from guardsim.vision import VisionCone, cone_target
from guardsim.world import World

__all__ = ["LINES_OF_SIGHT", "VisionCache"]

#: The line-of-sight rules: pymunk rays against the walls (the default), or Bresenham lines on the grid.
LINES_OF_SIGHT = ("pymunk", "bresenham")


@numba.njit(cache=True, nogil=True)
def _screen_state(
    col: int,
    row: int,
    offsets: np.ndarray,
    traversable: np.ndarray,
    rows: int,
    cols: int,
    origin_x: float,
    origin_y: float,
    cell_size: float,
    segments: np.ndarray,
    bucket_start: np.ndarray,
    bucket_walls: np.ndarray,
    bucket_x: float,
    bucket_y: float,
    bucket: float,
    bucket_columns: int,
    bucket_rows: int,
    margin: float,
    stamp: np.ndarray,
    candidates: np.ndarray,
    targets: np.ndarray,
    verdicts: np.ndarray,
) -> int:
    """The traversable cells in the cone (the guard's own excluded), their centres and ray verdicts."""
    count = 0
    for index in range(offsets.shape[0]):
        flat = cone_target(col, row, offsets, index, rows, cols, traversable)
        if flat < 0:
            continue
        target_col = flat % cols
        target_row = flat // cols
        candidates[count] = flat
        targets[count, 0] = origin_x + (target_col + 0.5) * cell_size
        targets[count, 1] = origin_y + (target_row + 0.5) * cell_size
        count += 1
    if count and bucket_walls.shape[0]:
        screen(
            origin_x + (col + 0.5) * cell_size,
            origin_y + (row + 0.5) * cell_size,
            targets[:count],
            segments,
            bucket_start,
            bucket_walls,
            bucket_x,
            bucket_y,
            bucket,
            bucket_columns,
            bucket_rows,
            margin,
            stamp,
            verdicts[:count],
        )
    return count


@numba.njit(cache=True, nogil=True)
def try_fill(
    state: int,
    offsets_all: np.ndarray,
    offsets_start: np.ndarray,
    traversable: np.ndarray,
    dims: np.ndarray,
    geometry: np.ndarray,
    segments: np.ndarray,
    bucket_start: np.ndarray,
    bucket_walls: np.ndarray,
    stamp: np.ndarray,
    candidates: np.ndarray,
    targets: np.ndarray,
    verdicts: np.ndarray,
    data: np.ndarray,
    used: int,
    start: np.ndarray,
    length: np.ndarray,
) -> int:
    """Fill ``state`` without leaving compiled code when the screen settles every ray.

    Returns how many cells were stored at ``data[used:]``; -1 when a ray is a close call (pymunk must
    decide: fill it from Python) and -2 when ``data`` has no room (grow it from Python).
    """
    cell = state // 4
    heading = state % 4
    rows, cols = dims[0], dims[1]
    offsets = offsets_all[offsets_start[heading] : offsets_start[heading + 1]]
    count = _screen_state(
        cell % cols, cell // cols, offsets, traversable, rows, cols, geometry[0], geometry[1], geometry[2],
        segments, bucket_start, bucket_walls, geometry[3], geometry[4], geometry[5], dims[2], dims[3],
        geometry[6], stamp, candidates, targets, verdicts,
    )  # fmt: skip
    visible = 1
    for index in range(count):
        if verdicts[index] == CLOSE_CALL:
            return -1
        if verdicts[index] == CLEAR:
            visible += 1
    if used + visible > data.shape[0]:
        return -2
    data[used] = cell
    position = used + 1
    for index in range(count):
        if verdicts[index] == CLEAR:
            data[position] = candidates[index]
            position += 1
    data[used : used + visible] = np.sort(data[used : used + visible])
    start[state] = used
    length[state] = visible
    return visible


class VisionCache:
    """Visible cells per state, filled on first use.

    Attributes
    ----------
    start
        ``int64 (cells * 4,)``: where state ``cell * 4 + heading`` begins in :attr:`data`.
    length
        ``int64 (cells * 4,)``: how many cells the state sees; -1 while not computed.
    data
        ``int32 (capacity,)``: the flat indices of the cells seen, state after state, each ascending.
    """

    def __init__(self, world: World, grid: CoverageGrid, cone: VisionCone, *, line_of_sight: str = "pymunk") -> None:
        if line_of_sight not in LINES_OF_SIGHT:
            raise ValueError(f"unknown line of sight {line_of_sight!r}; known: {', '.join(LINES_OF_SIGHT)}")
        self.world = world
        self.grid = grid
        self.cone = cone
        self.line_of_sight = line_of_sight
        states = grid.size * 4
        self.start = np.zeros(states, dtype=np.int64)
        self.length = np.full(states, -1, dtype=np.int64)
        self.data = np.zeros(max(1024, 16 * len(cone.offsets[0])), dtype=np.int32)
        self.used = 0
        self.rays_cast = 0
        """Rays pymunk was asked about (the close calls)."""
        self.rays_screened = 0
        """Rays settled by the screen alone."""
        longest = max(float(np.hypot(*offsets.T).max()) if len(offsets) else 0.0 for offsets in cone.offsets)
        rows, cols = grid.shape
        self._walls = WallIndex(
            np.array([(*wall.a, *wall.b) for wall in world.walls], dtype=np.float64).reshape(-1, 4),
            grid.origin,
            (cols * grid.cell_size, rows * grid.cell_size),
            longest * grid.cell_size,
        )
        self._stamp = np.zeros(len(world.walls) + 1, dtype=np.int64)
        self._traversable = np.ascontiguousarray(grid.traversable.ravel())
        walls = self._walls
        widest = max(len(offsets) for offsets in cone.offsets)
        # What try_fill needs, packed so that the compiled loop can fill states itself.
        self.compiled_fill = line_of_sight == "pymunk"
        self.fill_arrays = (
            np.ascontiguousarray(np.concatenate(cone.offsets).astype(np.int64).reshape(-1, 2)),
            np.cumsum([0, *(len(offsets) for offsets in cone.offsets)]).astype(np.int64),
            self._traversable,
            np.array([rows, cols, walls.columns, walls.rows], dtype=np.int64),
            np.array([*grid.origin, grid.cell_size, *walls.origin, walls.bucket, walls.margin], dtype=np.float64),
            walls.segments,
            walls.start,
            walls.walls,
            self._stamp,
            np.zeros(widest, dtype=np.int64),
            np.zeros((widest, 2), dtype=np.float64),
            np.zeros(widest, dtype=np.int8),
        )

    @property
    def computed(self) -> int:
        """Number of states computed so far."""
        return int((self.length >= 0).sum())

    def fill(self, state: int) -> None:
        """Compute and store the cells seen from ``state`` (``cell * 4 + heading``) if not yet known."""
        if self.length[state] >= 0:
            return
        cell, heading = divmod(state, 4)
        col, row = self.grid.unflat(cell)
        rows, cols = self.grid.shape
        offsets = self.cone.offsets[heading]
        if self.line_of_sight == "bresenham":
            out = np.zeros(len(offsets) + 1, dtype=np.int64)
            count = bresenham_clear(self._traversable, rows, cols, col, row, offsets, out)
            self._store(state, np.sort(out[:count]))
            return
        walls = self._walls
        candidates = np.zeros(len(offsets), dtype=np.int64)
        targets = np.zeros((len(offsets), 2), dtype=np.float64)
        verdicts = np.zeros(len(offsets), dtype=np.int8)
        count = _screen_state(
            col,
            row,
            offsets,
            self._traversable,
            rows,
            cols,
            self.grid.origin[0],
            self.grid.origin[1],
            self.grid.cell_size,
            walls.segments,
            walls.start,
            walls.walls,
            walls.origin[0],
            walls.origin[1],
            walls.bucket,
            walls.columns,
            walls.rows,
            walls.margin,
            self._stamp,
            candidates,
            targets,
            verdicts,
        )
        candidates, targets, verdicts = candidates[:count], targets[:count], verdicts[:count]
        visible = verdicts == CLEAR
        eye = self.grid.centre(col, row)
        for index in np.flatnonzero(verdicts == CLOSE_CALL).tolist():
            visible[index] = self.world.line_of_sight(eye, (float(targets[index, 0]), float(targets[index, 1])))
            self.rays_cast += 1
        self.rays_screened += count
        self._store(state, np.sort(np.append(candidates[visible], cell)))

    def _store(self, state: int, cells: np.ndarray) -> None:
        needed = self.used + len(cells)
        if needed > len(self.data):
            self.data = np.concatenate([self.data, np.zeros(max(needed, len(self.data)), dtype=np.int32)])
        self.data[self.used : needed] = cells
        self.start[state] = self.used
        self.length[state] = len(cells)
        self.used = needed

    def fill_all(self) -> None:
        """Compute every state of every traversable cell (for benchmarks and equality tests)."""
        for cell in np.flatnonzero(self.grid.traversable.ravel()):
            for heading in range(4):
                self.fill(int(cell) * 4 + heading)

    def __call__(self, col: int, row: int, heading: int) -> np.ndarray:
        """Flat indices of the cells seen from ``(col, row)`` facing ``heading``, ascending."""
        state = self.grid.flat(col, row) * 4 + heading
        self.fill(state)
        begin = self.start[state]
        return self.data[begin : begin + self.length[state]].astype(np.int64)
