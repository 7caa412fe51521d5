"""The fast vision path: each state's visible cells, computed once and shared by every episode.

A state is a cell and one of the four headings. The first time a state is asked for, its cells are
computed with the reference rule (:func:`guardsim.vision.visible_cells`) — except when no wall lies
within reach of the eye, where every traversable cell of the cone is visible without casting a ray —
and stored in flat arrays (CSR layout) that the compiled episode loop reads directly.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.vision import VisionCone, cone_cells, visible_cells
from guardsim.world import World

__all__ = ["VisionCache"]


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

    def __init__(self, world: World, grid: CoverageGrid, cone: VisionCone) -> None:
        self.world = world
        self.grid = grid
        self.cone = cone
        states = grid.size * 4
        self.start = np.zeros(states, dtype=np.int64)
        self.length = np.full(states, -1, dtype=np.int64)
        self.data = np.zeros(max(1024, 16 * len(cone.offsets[0])), dtype=np.int32)
        self.used = 0
        self.rays_skipped = 0
        # No ray is longer than the farthest cone offset; a wall farther than that cannot block one.
        longest = max(float(np.hypot(*offsets.T).max()) if len(offsets) else 0.0 for offsets in cone.offsets)
        self._clear_radius = longest * grid.cell_size * (1 + 1e-9) + 1e-9

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
        if self.world.wall_within(self.grid.centre(col, row), self._clear_radius):
            cells = visible_cells(self.world, self.grid, self.cone, col, row, heading)
        else:
            cells = cone_cells(self.grid, self.cone, col, row, heading)
            self.rays_skipped += len(cells) - 1
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
