"""Whether the guard can stand in an imported level, and whether its grid keeps the level whole.

Every importer's level passes here (on its way out of :func:`guardsim.load_level`): a level no guard fits in is
refused, since every command would refuse it; on a small level, a grid that cuts passages the guard's
circle can move along is a warning naming the finer cell size that keeps them whole.
"""

from __future__ import annotations

import dataclasses

import shapely

from guardsim.errors import LevelError
from guardsim.importers.imported import ImportedLevel
from guardsim.level import Level

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
        note = _grid_splits(level, room, int(grid.component_labels.max(initial=-1)) + 1) if fits else ""
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


def _grid_splits(level: Level, room: shapely.Geometry, parts: int) -> str:
    """A warning when the grid falls into more parts than the room the guard's centre can move in
    (``room``: the free area shrunk by its radius): a wall shape that leaves no room for the circle at a
    cell's centre (a diagonal half tile on a path one tile wide) cuts the path, and one of
    :data:`FINER_CELLS` keeps the parts whole: it is named. ``""`` otherwise."""
    from guardsim.grid import build_grid
    from guardsim.world import World

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
    return (
        f"at cell size {size:g} the guard's grid falls into {parts} parts where its circle can move in "
        f"{whole}: cells where a wall shape (a diagonal, a half tile) leaves no room for the guard at their "
        f"centre cut passages; {advice}"
    )
