"""The fast vision path: each state's visible cells, computed once and shared by every episode.

A state is a cell and one of the four headings (:func:`guardsim.grid.state_of`). (With
:attr:`LineOfSight.BRESENHAM` the states are filled by the compiled Bresenham rule of
:mod:`guardsim.vision.bresenham` instead.) The first time a state is asked for, its cells are computed
with the reference rule (:func:`guardsim.vision.rays.visible_cells`): each ray is first screened
against the walls near the eye (:mod:`guardsim.sight_screen`), which settles clear misses and clear
crossings, and pymunk casts only the close calls. The result is stored in flat arrays (CSR layout) that
the compiled episode loop reads directly.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.kernels.compiler import jit
from guardsim.kernels.steps import cell_of_state, heading_of_state, state_of
from guardsim.vision.bresenham import bresenham_clear
from guardsim.vision.cone import VisionCone
from guardsim.vision.rules import LineOfSight
from guardsim.vision.screen import CLEAR, CLOSE_CALL, WallIndex, index_walls, screen
from guardsim.vision.targets import cone_target
from guardsim.world import World

__all__ = ["FillArrays", "VisionCache", "try_fill"]



class FillArrays(NamedTuple):
    """What :func:`try_fill` needs to fill a state from compiled code: the cone, the grid and the walls."""

    offsets: np.ndarray
    """``int64 (n, 2)``: every heading's cone offsets, one heading after another."""
    offsets_start: np.ndarray
    """``int64 (5,)``: heading ``h``'s offsets are ``offsets[offsets_start[h]:offsets_start[h + 1]]``."""
    traversable: np.ndarray
    """``bool (cells,)``."""
    rows: int
    cols: int
    origin_x: float
    origin_y: float
    cell_size: float
    walls: WallIndex
    stamp: np.ndarray
    """``int64 (walls + 1,)``: scratch for the screen (which walls a ray was tested against)."""
    candidates: np.ndarray
    """``int64 (widest cone,)``: scratch, the cells in the cone."""
    targets: np.ndarray
    """``float64 (widest cone, 2)``: scratch, their centres."""
    verdicts: np.ndarray
    """``int8 (widest cone,)``: scratch, the screen's verdict per ray."""


@jit
def _screen_state(col: int, row: int, offsets: np.ndarray, fill: FillArrays) -> int:
    """The traversable cells in the cone (the guard's own excluded), their centres and ray verdicts,
    written into ``fill``'s scratch arrays; returns how many."""
    count = 0
    candidates, targets = fill.candidates, fill.targets
    for index in range(offsets.shape[0]):
        flat = cone_target(col, row, offsets, index, fill.rows, fill.cols, fill.traversable)
        if flat < 0:
            continue
        candidates[count] = flat
        targets[count, 0] = fill.origin_x + (flat % fill.cols + 0.5) * fill.cell_size
        targets[count, 1] = fill.origin_y + (flat // fill.cols + 0.5) * fill.cell_size
        count += 1
    if count and fill.walls.walls.shape[0]:
        screen(
            fill.origin_x + (col + 0.5) * fill.cell_size,
            fill.origin_y + (row + 0.5) * fill.cell_size,
            targets[:count],
            fill.walls,
            fill.stamp,
            fill.verdicts[:count],
        )
    return count


@jit
def try_fill(state: int, fill: FillArrays, data: np.ndarray, used: int, start: np.ndarray, length: np.ndarray) -> int:
    """Fill ``state`` without leaving compiled code when the screen settles every ray.

    Returns how many cells were stored at ``data[used:]``; -1 when a ray is a close call (pymunk must
    decide: fill it from Python) and -2 when ``data`` has no room (grow it from Python).
    """
    cell = cell_of_state(state)
    heading = heading_of_state(state)
    offsets = fill.offsets[fill.offsets_start[heading] : fill.offsets_start[heading + 1]]
    count = _screen_state(cell % fill.cols, cell // fill.cols, offsets, fill)
    verdicts, candidates = fill.verdicts, fill.candidates
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


@jit
def _try_fill_many(
    states: np.ndarray, fill: FillArrays, data: np.ndarray, used: int, start: np.ndarray, length: np.ndarray
) -> tuple[int, int, np.ndarray]:
    """:func:`try_fill` over ``states`` in order, skipping known ones: returns the new ``used``, where it
    stopped (``len(states)`` when done; earlier when ``data`` is full) and the close calls passed over."""
    close = np.empty(states.shape[0], dtype=np.int64)
    closes = 0
    for index in range(states.shape[0]):
        state = states[index]
        if length[state] >= 0:
            continue
        stored = try_fill(state, fill, data, used, start, length)
        if stored == -2:
            return used, index, close[:closes]
        if stored == -1:
            close[closes] = state
            closes += 1
        else:
            used += stored
    return used, states.shape[0], close[:closes]


class VisionCache:
    """Visible cells per state, filled on first use.

    Attributes
    ----------
    start
        ``int64 (states,)``: where state :func:`~guardsim.grid.state_of` ``(cell, heading)`` begins in
        :attr:`data`.
    length
        ``int64 (states,)``: how many cells the state sees; -1 while not computed.
    data
        ``int32 (capacity,)``: the flat indices of the cells seen, state after state, each ascending.
    """

    def __init__(
        self,
        world: World,
        grid: CoverageGrid,
        cone: VisionCone,
        *,
        line_of_sight: LineOfSight | str = LineOfSight.PYMUNK,
    ) -> None:
        self.world = world
        self.grid = grid
        self.cone = cone
        self.line_of_sight = LineOfSight(line_of_sight)
        states = state_of(grid.size, 0)
        self.start = np.zeros(states, dtype=np.int64)
        self.length = np.full(states, -1, dtype=np.int64)
        self.data = np.zeros(max(1024, 16 * len(cone.offsets[0])), dtype=np.int32)
        self.used = 0
        longest = max(float(np.hypot(*offsets.T).max()) if len(offsets) else 0.0 for offsets in cone.offsets)
        rows, cols = grid.shape
        self._traversable = np.ascontiguousarray(grid.traversable.ravel())
        widest = max(len(offsets) for offsets in cone.offsets)
        self.compiled_fill = self.line_of_sight is LineOfSight.PYMUNK
        """Whether compiled code may fill states itself with :func:`try_fill` (pymunk rays only)."""
        self.fill_arrays = FillArrays(
            offsets=np.ascontiguousarray(np.concatenate(cone.offsets).astype(np.int64).reshape(-1, 2)),
            offsets_start=np.cumsum([0, *(len(offsets) for offsets in cone.offsets)]).astype(np.int64),
            traversable=self._traversable,
            rows=rows,
            cols=cols,
            origin_x=float(grid.origin[0]),
            origin_y=float(grid.origin[1]),
            cell_size=float(grid.cell_size),
            walls=index_walls(
                np.array([(*wall.a, *wall.b) for wall in world.walls], dtype=np.float64).reshape(-1, 4),
                grid.origin,
                (cols * grid.cell_size, rows * grid.cell_size),
                longest * grid.cell_size,
            ),
            stamp=np.zeros(len(world.walls) + 1, dtype=np.int64),
            candidates=np.zeros(widest, dtype=np.int64),
            targets=np.zeros((widest, 2), dtype=np.float64),
            verdicts=np.zeros(widest, dtype=np.int8),
        )

    @property
    def computed(self) -> int:
        """Number of states computed so far."""
        return int((self.length >= 0).sum())

    def fill(self, state: int) -> None:
        """Compute and store the cells seen from ``state`` if not yet known."""
        if self.length[state] >= 0:
            return
        cell, heading = cell_of_state(state), heading_of_state(state)
        col, row = self.grid.unflat(cell)
        rows, cols = self.grid.shape
        offsets = self.cone.offsets[heading]
        if self.line_of_sight is LineOfSight.BRESENHAM:
            out = np.zeros(len(offsets) + 1, dtype=np.int64)
            count = bresenham_clear(self._traversable, rows, cols, col, row, offsets, out)
            self._store(state, np.sort(out[:count]))
            return
        fill = self.fill_arrays
        count = _screen_state(col, row, offsets, fill)
        candidates, targets, verdicts = fill.candidates[:count], fill.targets[:count], fill.verdicts[:count]
        visible = verdicts == CLEAR
        eye = self.grid.centre(col, row)
        for index in np.flatnonzero(verdicts == CLOSE_CALL).tolist():
            visible[index] = self.world.line_of_sight(eye, (float(targets[index, 0]), float(targets[index, 1])))
        self._store(state, np.sort(np.append(candidates[visible], cell)))

    def fill_many(self, states: np.ndarray) -> None:
        """Compute every state of ``states`` not yet known, as :meth:`fill` would: in compiled code where
        the screen settles every ray (a whole level's table in a tenth of the time), the rest by :meth:`fill`."""
        states = np.asarray(states, dtype=np.int64)
        if not self.compiled_fill:
            for state in states.tolist():
                self.fill(state)
            return
        while states.size:
            self.used, stopped, close = _try_fill_many(
                states, self.fill_arrays, self.data, self.used, self.start, self.length
            )
            for state in close.tolist():
                self.fill(state)
            states = states[stopped:]
            if states.size:
                self.data = np.concatenate([self.data, np.zeros(len(self.data), dtype=np.int32)])

    def sights(self, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """How many cells each of ``states`` sees, and those cells one state after another (each ascending),
        all computed first by :meth:`fill_many`."""
        states = np.asarray(states, dtype=np.int64)
        self.fill_many(states)
        lengths = self.length[states]
        ends = np.cumsum(lengths)
        flat = self.data[
            np.repeat(self.start[states] - ends + lengths, lengths) + np.arange(int(ends[-1]) if ends.size else 0)
        ]
        return lengths, flat

    def _store(self, state: int, cells: np.ndarray) -> None:
        needed = self.used + len(cells)
        if needed > len(self.data):
            self.data = np.concatenate([self.data, np.zeros(max(needed, len(self.data)), dtype=np.int32)])
        self.data[self.used : needed] = cells
        self.start[state] = self.used
        self.length[state] = len(cells)
        self.used = needed

    def __call__(self, col: int, row: int, heading: int) -> np.ndarray:
        """Flat indices of the cells seen from ``(col, row)`` facing ``heading``, ascending."""
        state = state_of(self.grid.flat(col, row), heading)
        self.fill(state)
        begin = self.start[state]
        return self.data[begin : begin + self.length[state]].astype(np.int64)
