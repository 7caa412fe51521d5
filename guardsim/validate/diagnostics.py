"""Designer warnings: things that make a valid level play differently from how it looks.

* **Unreachable pockets**: traversable cells the guard cannot walk to from the start (or, with no
  start, from the largest connected area), grouped by connected area, each with its size and a cell
  centre inside it.
* **Narrow passages**: places where the free area goes on but the guard's circle does not fit, so that
  traversable cells on either side end up in different connected areas: free-area cells where the
  guard does not fit whose traversable neighbours belong to two or more areas, and neighbouring
  traversable cells with a clear line between their centres that the guard's circle cannot slide along.
* **Hidden areas**: free-area cells no vision cone sees from any cell the guard can reach, with any
  heading. Reachable cells are always seen (the guard sees its own cell), so these are cells in
  unreachable pockets or too tight for the guard: places an intruder could stand unseen forever.

Hidden areas cost one ray per (cell, candidate eye) pair, nearest eyes first and stopping at the first
that sees the cell; ``max_rays`` bounds the total (scanning a cell counts as 16 rays, plus one per 32
candidate eyes), and a warning says so when the bound cut it short.
"""

from __future__ import annotations

from collections import deque
from typing import NamedTuple

import numpy as np
import shapely

from guardsim.errors import LevelError
from guardsim.grid import DIRECTIONS, CoverageGrid
from guardsim.level import Level
from guardsim.scene import Scene
from guardsim.starts import choose_start

__all__ = ["DEFAULT_MAX_RAYS", "DesignerWarning", "free_cells", "level_warnings", "scene_and_reachable"]

#: Rays the hidden-area search may cast before it stops (a few seconds of pymunk queries).
DEFAULT_MAX_RAYS = 1_000_000


class DesignerWarning(NamedTuple):
    """One thing a designer should look at; not an error."""

    kind: str
    """``unreachable pocket``, ``narrow passage``, ``hidden area`` or ``not checked for hidden areas``."""
    cells: int
    """How many cells it covers."""
    where: tuple[float, float] | None
    """World coordinates of a cell centre in it (the cell nearest its middle)."""

    def __str__(self) -> str:
        if self.where is None:
            return f"{self.cells} cells {self.kind} (the ray budget ran out)"
        return f"{self.kind} of {self.cells} cell{'s' if self.cells != 1 else ''} around ({self.where[0]:g}, {self.where[1]:g})"


def free_cells(scene: Scene) -> np.ndarray:
    """``bool (rows, cols)``: cells whose centre lies in the free area, whether or not the guard fits."""
    grid = scene.grid
    rows, cols = grid.shape
    xs = grid.origin[0] + (np.arange(cols) + 0.5) * grid.cell_size
    ys = grid.origin[1] + (np.arange(rows) + 0.5) * grid.cell_size
    return np.asarray(shapely.contains_xy(scene.level.free_area(), *np.meshgrid(xs, ys)), dtype=bool)


def level_warnings(scene: Scene, reachable: np.ndarray, *, max_rays: int = DEFAULT_MAX_RAYS) -> list[DesignerWarning]:
    """Every designer warning for a scene whose guard can reach the ``bool (rows, cols)`` ``reachable`` cells.

    Pockets and passages come largest first; hidden areas last.
    """
    grid = scene.grid
    areas = grid.component_labels.reshape(grid.shape)
    free = free_cells(scene)
    warnings = _pockets(grid, areas, reachable)
    warnings += _narrow_passages(scene, areas, free)
    warnings += _hidden_areas(scene, reachable, free, max_rays)
    return warnings


def _clusters(mask: np.ndarray) -> list[np.ndarray]:
    """4-connected groups of ``True`` cells of a mask, each as ``int (n, 2)`` ``(row, col)``, in row order."""
    seen = np.zeros_like(mask, dtype=bool)
    rows, cols = mask.shape
    groups = []
    for row, col in zip(*np.nonzero(mask), strict=True):
        if seen[row, col]:
            continue
        seen[row, col] = True
        members = [(int(row), int(col))]
        queue = deque(members)
        while queue:
            r, c = queue.popleft()
            for dc, dr in DIRECTIONS:
                rr, cc = r + dr, c + dc
                if 0 <= rr < rows and 0 <= cc < cols and mask[rr, cc] and not seen[rr, cc]:
                    seen[rr, cc] = True
                    members.append((rr, cc))
                    queue.append((rr, cc))
        groups.append(np.array(members))
    return groups


def _middle(grid: CoverageGrid, members: np.ndarray) -> tuple[float, float]:
    """The centre of the member cell nearest the group's mean position (so it lies inside the group)."""
    mean = members.mean(axis=0)
    row, col = members[int(np.argmin(((members - mean) ** 2).sum(axis=1)))]
    return grid.centre(int(col), int(row))


def _by_size(warnings: list[DesignerWarning]) -> list[DesignerWarning]:
    return sorted(warnings, key=lambda w: (-w.cells, w.where or (0.0, 0.0)))


def _pockets(grid: CoverageGrid, areas: np.ndarray, reachable: np.ndarray) -> list[DesignerWarning]:
    """One warning per connected area of traversable cells outside ``reachable``."""
    pocket = grid.traversable & ~reachable
    warnings = []
    for label in np.unique(areas[pocket]).tolist():
        members = np.argwhere(areas == label)
        warnings.append(DesignerWarning("unreachable pocket", len(members), _middle(grid, members)))
    return _by_size(warnings)


def _narrow_passages(scene: Scene, areas: np.ndarray, free: np.ndarray) -> list[DesignerWarning]:
    """Free cells too tight for the guard between different areas, and gaps between neighbouring cells."""
    grid, world = scene.grid, scene.world
    rows, cols = grid.shape
    warnings = []
    for members in _clusters(free & ~grid.traversable):
        touching = set()
        for row, col in members.tolist():
            for dc, dr in DIRECTIONS:
                if 0 <= row + dr < rows and 0 <= col + dc < cols and areas[row + dr, col + dc] >= 0:
                    touching.add(int(areas[row + dr, col + dc]))
        if len(touching) >= 2:
            warnings.append(DesignerWarning("narrow passage", len(members), _middle(grid, members)))
    for dcol, drow in DIRECTIONS[:2]:
        here = areas[: rows - drow, : cols - dcol]
        there = areas[drow:, dcol:]
        for row, col in zip(*np.nonzero((here >= 0) & (there >= 0) & (here != there)), strict=True):
            a = grid.centre(int(col), int(row))
            b = grid.centre(int(col) + dcol, int(row) + drow)
            if world.line_of_sight(a, b):
                middle = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
                warnings.append(DesignerWarning("narrow passage", 2, middle))
    return _by_size(warnings)


def _hidden_areas(scene: Scene, reachable: np.ndarray, free: np.ndarray, max_rays: int) -> list[DesignerWarning]:
    """Free cells outside ``reachable`` that no cone from a reachable cell sees, grouped; bounded by ``max_rays``."""
    grid, world = scene.grid, scene.world
    rows, cols = grid.shape
    # A target at eye + offset is in the cone of some heading exactly when offset is in one of the four.
    offsets = np.unique(np.concatenate(scene.cone.offsets), axis=0)
    offsets = offsets[np.argsort(np.hypot(offsets[:, 0], offsets[:, 1]), kind="stable")]
    offsets = offsets[(offsets != 0).any(axis=1)]
    hidden = np.zeros_like(free)
    rays = 0
    unchecked = 0
    for row, col in zip(*np.nonzero(free & ~reachable), strict=True):
        if rays >= max_rays:
            unchecked += 1
            continue
        # Scanning a cell costs about 16 rays, plus one per 32 candidate eyes: charged, so that a fine
        # grid (a million cells, half a million cone offsets) cannot spend minutes before the first ray.
        rays += 16 + len(offsets) // 32
        eye_cols, eye_rows = col - offsets[:, 0], row - offsets[:, 1]
        on_grid = (eye_cols >= 0) & (eye_cols < cols) & (eye_rows >= 0) & (eye_rows < rows)
        eye_cols, eye_rows = eye_cols[on_grid], eye_rows[on_grid]
        keep = reachable[eye_rows, eye_cols]
        target = grid.centre(int(col), int(row))
        seen = False
        for eye_col, eye_row in zip(eye_cols[keep].tolist(), eye_rows[keep].tolist(), strict=True):
            rays += 1
            if world.line_of_sight(grid.centre(eye_col, eye_row), target):
                seen = True
                break
        hidden[row, col] = not seen
    warnings = [DesignerWarning("hidden area", len(m), _middle(grid, m)) for m in _clusters(hidden)]
    if unchecked:
        warnings.append(DesignerWarning("not checked for hidden areas", unchecked, None))
    return _by_size(warnings)


def scene_and_reachable(level: Level) -> tuple[Scene, np.ndarray]:
    """The scene of ``level``, and the cells reachable from its guard's start (or the largest area
    without one): what :func:`level_warnings` takes, as ``guardsim validate`` finds them.

    Building the grid also finds what only it can: a start cell where the guard does not fit (a
    :class:`~guardsim.errors.GuardsimError`, as is a level where the guard fits nowhere).
    """
    scene = Scene.from_level(level)
    for point in ([level.guard.start] if level.guard.start else []) + list(level.starts):
        choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
    if level.guard.start is not None:
        cell, _ = choose_start(scene, rng=np.random.default_rng(0), point=level.guard.start, heading="right")
        return scene, scene.grid.component(*cell)
    largest = scene.grid.largest_component()
    if not largest.any():
        # Valid geometry, but a level no guard can stand in is not a level to ship.
        raise LevelError(
            f"{level.source}: no cell where the guard (radius {level.guard.radius:g}) fits; nothing to cover"
        )
    return scene, largest
