"""A cheap picture of an episode for ``render_mode="rgb_array"``: one flat colour per cell, no drawing library.

The colours are the GIF frames' (:mod:`guardsim.render.palette`), one per meaning: wall, floor still
unseen, floor seen, a cell too tight for the guard to stand in, what a guard sees now (the cone's tint
over the floor), a guard.
"""

from __future__ import annotations

import numpy as np

from guardsim.render import palette
from guardsim.render.cells import tight_cells
from guardsim.scene import Scene
from guardsim.simulation import Simulation

__all__ = ["PALETTE", "TightCells", "rgb_frame"]

_WALL, _UNSEEN, _SEEN, _IN_VIEW_UNSEEN, _IN_VIEW_SEEN, _TIGHT, _GUARDS = range(7)

#: Cell colours, by label: wall, unseen floor, seen floor, in a guard's view now (over unseen, over seen
#: floor), too tight to stand in, then each guard's colour (as in the GIF).
PALETTE = np.array(
    [
        palette.COLOURS["wall"],
        palette.COLOURS["unseen"],
        palette.COLOURS["free"],
        palette.PALETTE[palette.Index.CONE_BASE + palette.Index.UNSEEN],
        palette.PALETTE[palette.Index.CONE_BASE + palette.Index.FREE],
        palette.COLOURS["tight"],
        *palette.GUARD_COLOURS,
    ],
    dtype=np.uint8,
)


class TightCells:
    """The cells of a scene too tight to stand in, found once per scene (the environment's level may change
    between episodes)."""

    def __init__(self) -> None:
        self._scene: Scene | None = None
        self._cells: np.ndarray | None = None

    def of(self, scene: Scene) -> np.ndarray:
        """``bool (rows, cols)``: ``scene``'s cells whose centre is floor but where the guard does not fit."""
        if self._cells is None or self._scene is not scene:
            self._scene = scene
            self._cells = tight_cells(scene.level, scene.grid.traversable, scene.grid.origin)
        return self._cells


def rgb_frame(simulation: Simulation, cell_pixels: int = 8, *, tight: np.ndarray | None = None) -> np.ndarray:
    """``uint8 (rows * cell_pixels, cols * cell_pixels, 3)``: the grid as the simulation stands now.

    ``tight`` (``bool (rows, cols)``, from :class:`TightCells`) marks the cells drawn as too tight to stand
    in; without it they are drawn as walls.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> simulation = Simulation(Scene.from_level(parse_level({"outer": [[0, 0], [3, 0], [3, 2], [0, 2]]})))
    >>> simulation.reset(starts=[(0, 0)], headings=[0])
    >>> frame = rgb_frame(simulation, cell_pixels=2)
    >>> frame.shape, frame[0, 0].tolist()
    ((4, 6, 3), [214, 40, 40])
    """
    grid = simulation.scene.grid
    traversable = grid.traversable
    labels = np.where(traversable, _UNSEEN, _WALL).astype(np.uint8)
    if tight is not None:
        labels[tight] = _TIGHT
    seen = traversable & simulation.seen
    labels[seen] = _SEEN
    in_view = np.zeros(grid.size, dtype=bool)
    for (col, row), heading in zip(simulation.cells, simulation.headings):
        in_view[simulation.vision(col, row, heading)] = True
    in_view = traversable & in_view.reshape(grid.shape)
    labels[in_view] = np.where(seen[in_view], _IN_VIEW_SEEN, _IN_VIEW_UNSEEN)
    for guard, (col, row) in enumerate(simulation.cells):
        labels[row, col] = _GUARDS + guard % len(palette.GUARD_COLOURS)
    return np.repeat(np.repeat(PALETTE[labels], cell_pixels, axis=0), cell_pixels, axis=1)
