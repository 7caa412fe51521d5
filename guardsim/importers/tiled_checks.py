"""What a Tiled map is refused for, or warned about, once its roles and level are known.

Two readings of a map are refused, each in one line that says what was guessed:

* a **side view** (a platformer: a layer named ``platforms`` or ``Ladders``, a ``gravity`` map property;
  :func:`~guardsim.importers.tiled_roles.side_view_sign`): its solid ground would be taken as the floor,
  the open air left out. ``--view top-down`` imports it anyway;
* a **floor of obstacles**: every tile of the floor layers is a wall or carries a collision shape and the
  guard fits on no cell, so the map draws obstacles on empty cells (which are outside the level), not
  ground (bevy_ecs_tiled's physics samples).

A level that imports but looks unlike a drawn level (no walls along the map's edges, the guard fitting
nowhere among walls drawn on real ground, a start in a small part) gets a warning.
"""

from __future__ import annotations

from typing import cast

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from guardsim.errors import LevelError
from guardsim.importers.imported import counted
from guardsim.importers.source import excerpt
from guardsim.importers.tiled_data import TiledMap
from guardsim.importers.tiled_roles import Guesses, names, side_view_sign
from guardsim.level import Level

__all__ = ["SMALL_START_SHARE", "VIEWS", "check_floor_is_ground", "check_view", "guard_fits", "look_warnings"]

#: A start area smaller than this share of the free area is a warning.
SMALL_START_SHARE = 0.5
#: The values of ``--view``: ``auto`` refuses a map that looks like a side view; ``top-down`` never does.
VIEWS = ("auto", "top-down")


def check_view(source: str, tiled: TiledMap, view: str) -> str:
    """Refuse a map that looks drawn from the side, unless ``view`` says it is drawn from above.

    Returns a phrase for the summary when ``--view top-down`` imports a map that looks like a side view.
    """
    if view not in VIEWS:
        raise LevelError(f"{source}: --view must be one of {', '.join(VIEWS)}, not {excerpt(view)}")
    sign = side_view_sign(tiled)
    if sign and view == "auto":
        raise LevelError(
            f"{source}: looks like a side view (a platformer), guessed from {sign}; guardsim walks guards over "
            "maps drawn from above: if this one is, import it with --view top-down"
        )
    return f"taken as drawn from above (--view top-down), though {sign} suggests a side view" if sign else ""


def check_floor_is_ground(source: str, level: Level, roles: Guesses, void_gid: int) -> None:
    """Refuse a floor made only of obstacles (each tile a wall or carrying a collision shape) on which the
    guard fits nowhere: the tiles drawn are what the guard walks around, not on."""
    if roles.boundary_objects or not roles.floor_layers or guard_fits(level):
        return
    solid = np.fromiter(roles.wall_gids | roles.shaped_gids | roles.marked_gids, dtype=np.int64)
    drawn = np.concatenate([layer.gids for layer in roles.floor_layers])
    drawn = drawn[drawn != void_gid] if void_gid else drawn
    if drawn.size and np.isin(drawn, solid).all():
        plural = "s" if len(roles.floor_layers) > 1 else ""
        raise LevelError(
            f"{source}: every tile of the floor layer{plural} {names(roles.floor_layers)} is an obstacle "
            f"({counted(int(drawn.size), 'tile')}, each a wall or carrying a collision shape) and the guard "
            f"(radius {level.guard.radius:g} tiles) fits on none: the map draws no ground (cells empty in every "
            "floor layer are outside the level); draw a ground layer under the obstacles, or name one with "
            "--floor-layer"
        )


def guard_fits(level: Level) -> bool:
    """Whether the guard's disc fits inside the free area on some cell centre (where the grid lets it stand)."""
    free = cast(BaseGeometry, level.free_area())
    if free.is_empty or free.area <= 0:
        return False
    radius = level.guard.radius
    rows, cols = level.grid_shape()
    left, top = level.bounds[:2]
    size = level.cell_size
    xs, ys = np.meshgrid(left + size * (np.arange(cols) + 0.5), top + size * (np.arange(rows) + 0.5))
    room = shapely.buffer(free, -radius * (1 - 1e-9)) if radius > 0 else free
    return bool(shapely.intersects_xy(room, xs.ravel(), ys.ravel()).any())


def look_warnings(level: Level, has_starts: bool, map_size: tuple[int, int]) -> list[str]:
    """Warnings about a level that looks unlike a drawn level (``map_size`` in tiles, one world unit each)."""
    warnings = []
    free = cast(BaseGeometry, level.free_area())
    if free.is_empty or free.area <= 0:
        return ["the free area is empty"]
    # The map's edges where the map declares them (a free area ending inside its wall border is drawn);
    # an infinite map's nominal size says nothing, so there the level's own bounds stand in.
    min_x, min_y, max_x, max_y = level.bounds
    if min_x >= 0 and min_y >= 0 and max_x <= map_size[0] and max_y <= map_size[1]:
        min_x, min_y, max_x, max_y = 0.0, 0.0, float(map_size[0]), float(map_size[1])
    edges = [
        shapely.LineString([(min_x, min_y), (max_x, min_y)]),
        shapely.LineString([(max_x, min_y), (max_x, max_y)]),
        shapely.LineString([(max_x, max_y), (min_x, max_y)]),
        shapely.LineString([(min_x, max_y), (min_x, min_y)]),
    ]
    boundary = free.boundary
    if all(boundary.intersection(edge).length > 0.5 * edge.length for edge in edges):
        warnings.append(
            "the free area runs along more than half of every edge of the map: walls may be missing "
            "(mark a layer with a `collision` property or pass --wall-layer)"
        )
    # Walls drawn so tight on real ground that only slivers are left: say that the guard fits on no cell
    # centre rather than report a level nobody can walk (a floor made only of obstacles is refused before:
    # check_floor_is_ground).
    if not guard_fits(level):
        warnings.append(
            f"the guard (radius {level.guard.radius:g} tiles) fits on no cell of the free area: every floor tile "
            "may carry a collision shape or a wall (check the wall layers and tile collision shapes, or pass "
            "--wall-layer)"
        )
        return warnings
    parts = sorted((part.area for part in shapely.get_parts(free)), reverse=True)
    if not has_starts and len(parts) > 1 and parts[0] < SMALL_START_SHARE * free.area:
        warnings.append(
            f"the free area is in {len(parts)} separate parts and the largest holds only "
            f"{100 * parts[0] / free.area:.0f}% of it: the guard starts in one part and never sees the others"
        )
    return warnings
