"""The view table of an edited level, rebuilt only where the edit can have changed what a guard sees.

A guard state's view reaches at most the view range. A state whose cell is farther than that (plus a
cell) from every cell the edit touched (floor added or removed, the bounding boxes of the walls moved,
added or removed) sees exactly what it saw before: none of its sight lines reaches the edit. Only the
other states are asked again, in bulk, from the new scene's vision.
"""

from __future__ import annotations

import math

import numpy as np

from guardsim.grid import HEADINGS_PER_CELL, state_of
from guardsim.kernels.csr import invert_csr
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable

__all__ = ["edited_cells", "reused_view_table"]


def edited_cells(old: Scene, new: Scene) -> np.ndarray:
    """``bool (rows, cols)``: cells whose floor changed or that a wall moved, added or removed covers."""
    grid = new.grid
    rows, cols = grid.shape
    touched = old.grid.traversable != grid.traversable
    for ring in set(old.level.holes) ^ set(new.level.holes):
        xs, ys = zip(*ring)
        first = [
            math.floor((min(xs) - grid.origin[0]) / grid.cell_size),
            math.floor((min(ys) - grid.origin[1]) / grid.cell_size),
        ]
        last = [
            math.floor((max(xs) - grid.origin[0]) / grid.cell_size),
            math.floor((max(ys) - grid.origin[1]) / grid.cell_size),
        ]
        touched[max(0, first[1]) : min(rows, last[1] + 1), max(0, first[0]) : min(cols, last[0] + 1)] = True
    return touched


def _near(mask: np.ndarray, radius: int) -> np.ndarray:
    """Cells within ``radius`` cells (square neighbourhood) of a cell of ``mask``, by a summed-area table."""
    rows, cols = mask.shape
    table = np.zeros((rows + 1, cols + 1), dtype=np.int64)
    table[1:, 1:] = mask.astype(np.int64).cumsum(axis=0).cumsum(axis=1)
    top = np.clip(np.arange(rows) - radius, 0, rows)
    bottom = np.clip(np.arange(rows) + radius + 1, 0, rows)
    left = np.clip(np.arange(cols) - radius, 0, cols)
    right = np.clip(np.arange(cols) + radius + 1, 0, cols)
    total = table[bottom][:, right] - table[top][:, right] - table[bottom][:, left] + table[top][:, left]
    return total > 0


def reused_view_table(old: Scene, old_table: ViewTable, new: Scene) -> ViewTable | None:
    """The view table of ``new``, copied from ``old_table`` where the edit cannot have changed it and
    asked again elsewhere; ``None`` when it must be built whole (the grids do not line up, the outer
    wall or the guards' sight changed, an unlimited range, or a vision that is not asked in bulk).

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> from guardsim.vision.table import build_view_table
    >>> room = {"outer": [[0, 0], [30, 0], [30, 10], [0, 10]], "guard": {"view_range": 4}}
    >>> old = Scene.from_level(parse_level({**room, "holes": [[[3, 3], [5, 3], [5, 5], [3, 5]]]}))
    >>> new = Scene.from_level(parse_level({**room, "holes": [[[3, 4], [5, 4], [5, 6], [3, 6]]]}))
    >>> reused = reused_view_table(old, build_view_table(old.grid, old.vision()), new)
    >>> whole = build_view_table(new.grid, new.vision())
    >>> all(np.array_equal(a, b) for a, b in zip(reused, whole))
    True
    """
    a, b = old.grid, new.grid
    same_grid = (a.shape, a.origin, a.cell_size) == (b.shape, b.origin, b.cell_size)
    cone_a, cone_b = old.cone, new.cone
    same_sight = (cone_a.view_range, cone_a.fov_degrees, cone_a.cell_size, old.rule) == (
        cone_b.view_range,
        cone_b.fov_degrees,
        cone_b.cell_size,
        new.rule,
    )
    sights = getattr(new.vision(), "sights", None)
    if not (same_grid and same_sight and old.level.outer == new.level.outer) or sights is None:
        return None
    if not math.isfinite(cone_b.view_range):
        return None
    radius = math.ceil(cone_b.view_range / b.cell_size) + 1
    again = _near(edited_cells(old, new), radius) & b.traversable
    count = b.size * HEADINGS_PER_CELL
    asked = state_of(np.flatnonzero(again)[:, None], np.arange(HEADINGS_PER_CELL)).ravel()
    lengths, cells = sights(asked) if asked.size else (np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int32))
    # Each state's cells come from one side: 1 copied from the old table, 2 asked again, 0 none (not floor).
    side = np.repeat(b.traversable.ravel().astype(np.int8), HEADINGS_PER_CELL)
    side[asked] = 2
    new_lengths = np.where(side == 1, np.diff(old_table.sight_start), 0)
    new_lengths[asked] = lengths
    sight_start = np.zeros(count + 1, dtype=np.int64)
    np.cumsum(new_lengths, out=sight_start[1:])
    asked_start = np.zeros(count + 1, dtype=np.int64)
    asked_start[asked + 1] = lengths
    np.cumsum(asked_start, out=asked_start)
    # States in runs of one side (few: the rows of the edit's neighbourhood), each run copied whole.
    bounds = np.flatnonzero(np.diff(side)) + 1
    firsts = np.concatenate([[0], bounds])
    lasts = np.concatenate([bounds, [count]])
    sight = np.empty(int(sight_start[-1]), dtype=np.int32)
    for first, last in zip(firsts.tolist(), lasts.tolist(), strict=True):
        which = side[first]
        if which == 0:
            continue
        into = sight[sight_start[first] : sight_start[last]]
        if which == 1:
            into[:] = old_table.sight[old_table.sight_start[first] : old_table.sight_start[last]]
        else:
            into[:] = cells[asked_start[first] : asked_start[last]]
    watch_start, watchers = invert_csr(sight_start, sight, b.size)
    return ViewTable(sight_start, sight, watch_start, watchers, b.entry_cells)
