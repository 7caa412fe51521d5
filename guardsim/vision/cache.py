"""The fast vision path: each state's visible cells, computed once and shared by every episode.

A state is a cell and one of the four headings (:func:`guardsim.grid.state_of`). (With
:attr:`LineOfSight.BRESENHAM` the states are filled by the compiled Bresenham rule of
:mod:`guardsim.vision.bresenham` instead.) The first time a state is asked for, its cells are computed
with the reference rule (:func:`guardsim.vision.rays.visible_cells`): each ray is first screened
against the walls near the eye (:mod:`guardsim.kernels.screen`), which settles clear misses and clear
crossings, and pymunk casts only the close calls. The result is stored in flat arrays (CSR layout) that
the compiled episode loop reads directly.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.kernels.fill import FillArrays, fill_many, screen_state
from guardsim.kernels.screen import CLEAR, CLOSE_CALL, index_walls
from guardsim.kernels.steps import cell_of_state, heading_of_state, state_of
from guardsim.vision.bresenham import bresenham_clear
from guardsim.vision.cone import VisionCone
from guardsim.vision.rules import LineOfSight
from guardsim.world import World

__all__ = ["VisionCache"]


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
        """Whether compiled code may fill states itself with :func:`~guardsim.kernels.fill.try_fill` (pymunk rays only)."""
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
        count = screen_state(col, row, offsets, fill)
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
            self.used, stopped, close = fill_many(
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
