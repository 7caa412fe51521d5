"""Wall rings for a trace whose level is not at hand, rebuilt from its grid.

A saved trace carries the grid (which cells the guard could stand on) but not the level's polygons.
Without the level, the viewer draws the cells the guard could not stand on as walls: the outline is
then cell-aligned and a little fatter than the real walls (cells too near a wall for the guard's body
count as wall), so the cone drawn from it can fall slightly short of what the guard saw.
"""

from __future__ import annotations

import numpy as np
import shapely

from guardsim.trace import Trace

__all__ = ["rings_from_grid"]


def rings_from_grid(trace: Trace) -> list[list[tuple[float, float]]]:
    """The grid's bounding box and the outlines of its blocked cells, as world-coordinate rings.

    Examples
    --------
    >>> from guardsim.trace import Trace
    >>> free = np.ones((3, 3), dtype=bool)
    >>> free[1, 1] = False
    >>> trace = Trace("t", "p", 0, 1.0, (0.0, 0.0), (3, 3), ((0, 0),), (0,), (0.0,), "covered", 8, 0,
    ...               np.zeros((3, 3), dtype=int), free, free)
    >>> [len(ring) for ring in rings_from_grid(trace)]
    [4, 4]
    """
    rows, cols = trace.shape
    size, (x0, y0) = trace.cell_size, trace.origin
    boxes = []
    for row in range(rows):
        blocked = np.concatenate([[False], ~trace.traversable[row], [False]])
        changes = np.flatnonzero(blocked[1:] != blocked[:-1])
        for start, stop in zip(changes[::2], changes[1::2]):
            boxes.append(shapely.box(x0 + start * size, y0 + row * size, x0 + stop * size, y0 + (row + 1) * size))
    outer = [(x0, y0), (x0 + cols * size, y0), (x0 + cols * size, y0 + rows * size), (x0, y0 + rows * size)]
    rings = [outer]
    if not boxes:
        return rings
    merged = shapely.union_all(boxes)
    for polygon in getattr(merged, "geoms", [merged]):
        for ring in (polygon.exterior, *polygon.interiors):
            rings.append([(float(x), float(y)) for x, y in list(ring.simplify(0).coords)[:-1]])
    return rings
