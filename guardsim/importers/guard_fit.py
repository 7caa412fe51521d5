"""Whether the guard can stand in an imported level, and whether its grid keeps the level whole.

Every importer's level passes here (on its way out of :func:`guardsim.load_level`): a level no guard fits in is
refused, since every command would refuse it; on a small level, a grid that cuts passages the guard's
circle can move along is a warning naming the finer cell size that keeps them whole.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np
import shapely

from guardsim.errors import LevelError
from guardsim.importers.imported import ImportedLevel
from guardsim.level import Level

if TYPE_CHECKING:
    from guardsim.grid import CoverageGrid

__all__ = ["FINER_CELLS", "FIT_CHECK_CELLS", "check_guard_fits"]


#: Grids up to this many cells are built to check that the guard fits somewhere (a second at most); larger
#: levels are checked on their geometry alone (some point of the free area clears the guard's radius).
FIT_CHECK_CELLS = 40_000


def check_guard_fits(imported: ImportedLevel) -> ImportedLevel:
    """Refuse a level no guard can stand in (a map narrower than the guard): every command would refuse it.
    On a small level, warn when the guard's grid cuts passages its circle can move along (see
    :func:`_grid_splits`).

    The same rule as ``guardsim validate``: a cell whose centre clears the guard's radius.
    """
    level = imported.level
    radius = level.guard.radius
    room = shapely.buffer(level.free_area(), -radius)
    fits = not room.is_empty
    rows, cols = level.grid_shape()
    if fits and rows * cols <= FIT_CHECK_CELLS:
        from guardsim.grid import build_grid
        from guardsim.world import World

        grid = build_grid(level, World(level))
        fits = bool(grid.traversable.any())
        note = _grid_splits(level, room, grid) if fits else ""
        if note:
            imported = dataclasses.replace(imported, warnings=(*imported.warnings, note))
    if fits:
        return imported
    # The reader may know why (every floor tile carries a collision shape): its warning is the reason.
    known = next((warning for warning in imported.warnings if "fits on no cell" in warning), None)
    if known is not None:
        raise LevelError(f"{level.source}: {known}")
    left, top, right, bottom = level.bounds
    raise LevelError(
        f"{level.source}: no cell where the guard (radius {radius:g}) fits in the imported level "
        f"({right - left:g} x {bottom - top:g} world units, cell size {level.cell_size:g}): nothing to cover"
    )


#: Finer cell sizes tried, as fractions of the level's, when the grid cuts the guard's passages.
FINER_CELLS = (2, 4)


def _grid_splits(level: Level, room: shapely.Geometry, grid: CoverageGrid) -> str:
    """A warning when the grid falls into more parts than the room the guard's centre can move in
    (``room``: the free area shrunk by its radius): a wall shape that leaves no room for the circle at a
    cell's centre (a diagonal half tile on a path one tile wide) cuts the path, and one of
    :data:`FINER_CELLS` keeps the parts whole: it is named, with a cut cell. ``""`` otherwise."""
    from guardsim.grid import build_grid
    from guardsim.world import World

    parts = int(grid.component_labels.max(initial=-1)) + 1
    whole = sum(1 for piece in shapely.get_parts(room) if piece.area > 1e-9)
    if parts <= whole:
        return ""
    size = level.cell_size
    rows, cols = level.grid_shape()
    # Said only when a finer grid is the cure: other splits (slivers the sweep between cell centres
    # cannot cross) are not a designer's to fix.
    advice = ""
    for finer in FINER_CELLS:
        if rows * cols * finer * finer > FIT_CHECK_CELLS:
            break
        trial = dataclasses.replace(level, cell_size=size / finer)
        found = int(build_grid(trial, World(trial)).component_labels.max(initial=-1)) + 1
        if found <= whole:
            advice = f"cell size {size / finer:g} keeps them whole (--cell-size {size / finer:g})"
            break
    if not advice:
        return ""
    cut = _cut_cell(grid, room)
    where = f", as the cell at ({cut[0]:g}, {cut[1]:g}) does" if cut is not None else ""
    return (
        f"at cell size {size:g} the guard's grid falls into {parts} parts where its circle can move in "
        f"{whole}: cells where a wall shape (a diagonal, a half tile) leaves no room for the guard's circle "
        f"(radius {level.guard.radius:g}) at their centre cut passages{where}; {advice}"
    )


def _cut_cell(grid: CoverageGrid, room: shapely.Geometry) -> tuple[float, float] | None:
    """The centre (world units) of the first cell, in row order, beside a cell of the grid, that the
    guard's circle can enter (``room``, where its centre may be, crosses the cell) but whose centre leaves
    it no room: a cell that cuts a passage. ``None`` when there is none."""
    rows, cols = grid.shape
    walk = np.zeros((rows + 2, cols + 2), dtype=bool)
    walk[1:-1, 1:-1] = grid.traversable
    beside = walk[:-2, 1:-1] | walk[2:, 1:-1] | walk[1:-1, :-2] | walk[1:-1, 2:]
    found = np.nonzero(beside & ~grid.traversable)
    if not found[0].size:
        return None
    size, (left, top) = grid.cell_size, grid.origin
    boxes = shapely.box(left + found[1] * size, top + found[0] * size, left + (found[1] + 1) * size,
                        top + (found[0] + 1) * size)  # fmt: skip
    # Crossed, not touched: the room's edge runs along every wall cell a radius away.
    crossed = np.flatnonzero(shapely.area(shapely.intersection(boxes, room)) > 1e-6 * size * size)
    if not crossed.size:
        return None
    return grid.centre(int(found[1][crossed[0]]), int(found[0][crossed[0]]))
