"""A cheap picture of an episode for ``render_mode="rgb_array"``: one flat colour per cell, no drawing library."""

from __future__ import annotations

import numpy as np

from guardsim.simulation import Simulation

__all__ = ["PALETTE", "rgb_frame"]

#: Cell colours: wall or unreachable by the guard's circle, not yet seen, seen, in a guard's view now, a guard.
PALETTE = np.array(
    [[40, 40, 48], [120, 120, 132], [232, 232, 222], [250, 212, 90], [200, 40, 40]],
    dtype=np.uint8,
)


def rgb_frame(simulation: Simulation, cell_pixels: int = 8) -> np.ndarray:
    """``uint8 (rows * cell_pixels, cols * cell_pixels, 3)``: the grid as the simulation stands now.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> simulation = Simulation(Scene.from_level(parse_level({"outer": [[0, 0], [3, 0], [3, 2], [0, 2]]})))
    >>> simulation.reset(starts=[(0, 0)], headings=[0])
    >>> frame = rgb_frame(simulation, cell_pixels=2)
    >>> frame.shape, frame[0, 0].tolist()
    ((4, 6, 3), [200, 40, 40])
    """
    grid = simulation.scene.grid
    traversable = grid.traversable
    labels = traversable.astype(np.uint8)
    labels[traversable & simulation.seen] = 2
    in_view = np.zeros(grid.size, dtype=bool)
    for (col, row), heading in zip(simulation.cells, simulation.headings):
        in_view[simulation.vision(col, row, heading)] = True
    labels[traversable & in_view.reshape(grid.shape)] = 3
    for col, row in simulation.cells:
        labels[row, col] = 4
    return np.repeat(np.repeat(PALETTE[labels], cell_pixels, axis=0), cell_pixels, axis=1)
