"""Which kind each cell is drawn as, beyond what the coverage grid records: no drawing library needed."""

from __future__ import annotations

import numpy as np
import shapely

from guardsim.level import Level

__all__ = ["tight_cells"]


def tight_cells(level: Level, traversable: np.ndarray, origin: tuple[float, float]) -> np.ndarray:
    """``bool (rows, cols)``: cells whose centre is in the free area but where the guard does not fit.

    They are floor, but never a goal: every picture draws them in the palette's ``tight`` colour, apart
    from walls and from floor still to be seen.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> level = parse_level({"outer": [[0, 0], [4, 0], [4, 3], [0, 3]], "guard": {"radius": 0.8}})
    >>> grid = Scene.from_level(level).grid
    >>> tight_cells(level, grid.traversable, grid.origin).astype(int).tolist()
    [[1, 1, 1, 1], [1, 0, 0, 1], [1, 1, 1, 1]]
    """
    rows, cols = traversable.shape
    centre_x = origin[0] + (np.arange(cols) + 0.5) * level.cell_size
    centre_y = origin[1] + (np.arange(rows) + 0.5) * level.cell_size
    free = shapely.contains_xy(level.free_area(), *np.meshgrid(centre_x, centre_y))
    return free & ~traversable
