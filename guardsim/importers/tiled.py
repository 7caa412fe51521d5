"""Tiled maps (TMX and Tiled JSON) into levels: floor minus walls, the spawns, and what was guessed.

One tile is one world unit. The roles of the map's layers, tiles and objects come from
:func:`guardsim.importers.tiled_roles.assign_roles`; this module turns them into geometry:

* the **free area** is the boundary objects if there are any, else the cells of the floor layers, minus
  every wall (wall tiles as whole cells, tile collision shapes and wall objects as drawn);
* vertices within ``snap_tolerance`` of the half-tile grid are snapped onto it, so hand-placed walls
  that were meant to meet do; the outer ring is the free area's bounding box on whole tiles;
* when the map has guard spawns, parts of the free area that hold none (the painted void around a
  dungeon, a closed room) are left out, so the guard walks the level its author drew;
* size limits are checked on the tile grid before any geometry is built.

Every guess is named in the summary, and a result that looks wrong (no walls, a free area open to the
map edge all round, a start area much smaller than the free area) is a warning.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry

from guardsim.errors import LevelError
from guardsim.importers.imported import (
    ImportedLevel,
    check_raster_limits,
    counted,
    level_from_walls,
    listed,
    with_tile_pixels,
)
from guardsim.importers.source import display_name
from guardsim.importers.tiled_checks import check_floor_is_ground, check_view, look_warnings
from guardsim.importers.tiled_data import TileLayer
from guardsim.importers.tiled_geometry import TileGeometry, blocked_mask
from guardsim.importers.tiled_heights import walker_layers
from guardsim.importers.tiled_read import read_tiled
from guardsim.importers.tiled_roles import Guesses, RoleOptions, assign_roles, names, parse_wall_property
from guardsim.importers.tiled_spawns import (
    keep_spawn_areas,
    player_starts,
    spawn_points,
    unguarded_players,
    usable_starts,
)
from guardsim.importers.watchers import tiled_watchers, with_watchers
from guardsim.level import (
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_FILE_BYTES,
    DEFAULT_MAX_VERTICES,
    level_to_data,
    parse_level,
)

__all__ = ["DEFAULT_SNAP_STEP", "DEFAULT_SNAP_TOLERANCE", "import_tiled", "read_tiled"]

#: Vertices are snapped to multiples of this many tiles...
DEFAULT_SNAP_STEP = 0.5
#: ...when they are this close (in tiles: 2.56 pixels on 64-pixel tiles).
DEFAULT_SNAP_TOLERANCE = 0.04
#: A tile filling the map's edge is the void when walls lie within this many tiles of this share of its
#: border with the other tiles.
VOID_WALL_DISTANCE = 0.5
VOID_WALLED_SHARE = 0.8


def import_tiled(
    path: str | os.PathLike[str],
    *,
    cell_size: float = 1.0,
    spawn_tiles: Iterable[int] = (),
    wall_layers: Iterable[str] = (),
    floor_layers: Iterable[str] = (),
    wall_tiles: Iterable[int] = (),
    wall_properties: Iterable[str] = (),
    wall_classes: Iterable[str] = (),
    view: str = "auto",
    snap_step: float = DEFAULT_SNAP_STEP,
    snap_tolerance: float = DEFAULT_SNAP_TOLERANCE,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Convert a Tiled map to a level (one tile = one world unit; see the module notes).

    Parameters
    ----------
    spawn_tiles
        Global tile ids that mark a guard spawn, for maps whose tilesets do not say which tile that is.
    wall_layers, floor_layers
        Layer names (or ``group/layer`` paths) that replace the guesses of which layers are walls and floor.
    wall_tiles
        Global tile ids that are walls wherever they are drawn.
    wall_properties
        ``NAME`` or ``NAME=VALUE``: tiles and objects whose property ``NAME`` reads true (or equals
        ``VALUE``) are walls; replaces the guess from property names.
    wall_classes
        Tile and object classes (any case) that are walls.
    view
        ``"auto"`` refuses a map that looks drawn from the side (a platformer: layers named platforms or
        ladders, a gravity property); ``"top-down"`` imports it as seen from above.
    snap_step, snap_tolerance
        Wall and boundary vertices within ``snap_tolerance`` tiles of a multiple of ``snap_step`` tiles are
        moved onto it.
    """
    source = display_name(path)
    try:
        parsed = tuple(parse_wall_property(text) for text in wall_properties)
    except ValueError as error:
        raise LevelError(f"{source}: --wall-property {error}") from None
    classes = tuple(wall_classes)
    if any(not kind.strip() for kind in classes):
        raise LevelError(f"{source}: --wall-class must name a class, not an empty text")
    options = RoleOptions(
        tuple(wall_layers), tuple(floor_layers), tuple(wall_tiles), tuple(spawn_tiles), parsed, classes
    )
    tiled = read_tiled(path, max_file_bytes=max_file_bytes, max_cells=max_cells, cells_per_tile=cell_size**-2)
    view_note = check_view(source, tiled, view)
    roles = assign_roles(tiled, options)
    geometry = TileGeometry(tiled, snap_step, snap_tolerance)
    changes: list[str] = [view_note] if view_note else []
    warnings = list(roles.warnings) + list(tiled.warnings)

    # The tiles a walker meets: the top-most at its height decides each cell (tiled_heights).
    walked, heights_phrase = walker_layers(tiled, roles)
    if heights_phrase:
        changes.append(heights_phrase)
    wall_tiles_found = [
        (layer, gids)
        for original, layer in zip(tiled.tile_layers, walked, strict=True)
        if (gids := _wall_gids_in(layer, roles, original)) is None or gids.size
    ]
    # Image-collection tiles bigger or smaller than a map tile stand on their cell at their own size.
    wall_boxes = [
        piece for layer, gids in wall_tiles_found for piece in geometry.tile_boxes(layer, gids, skip=geometry.images)
    ]
    image_walls = [piece for layer, gids in wall_tiles_found for piece in geometry.image_tiles(layer, gids)]
    drawn_walls: set[int] = set()
    for layer, gids in wall_tiles_found:
        drawn_walls |= set(np.unique(layer.gids if gids is None else gids).tolist())
    unsized = sorted(drawn_walls & geometry.unsized)
    if unsized:
        shown = ", ".join(map(str, unsized[:8])) + (" ..." if len(unsized) > 8 else "")
        warnings.append(
            f"wall tiles {shown} are images whose size the tileset does not give (no width and height): "
            "each is taken as one map tile"
        )
    # Collision shapes drawn in a layer that opts out are not walls (unless the tile marks itself).
    shape_walls = [
        shape
        for layer in walked
        for shape in geometry.tile_shapes(
            layer, roles.shaped_gids & roles.marked_gids if _layer_opts_out(layer) else roles.shaped_gids
        )
    ]
    wall_objects = [item for _, item in roles.wall_objects]
    object_walls = [wall for item in wall_objects if item.closed and (wall := geometry.object_wall(item)) is not None]
    open_walls = sum(1 for item in wall_objects if not item.closed)
    walls: list[BaseGeometry] = [*object_walls, *shape_walls, *image_walls, *wall_boxes]

    free, floor_boxes = _free_area(source, roles, geometry, walls, changes)
    bounds = _tile_bounds(free.bounds if free is not None else shapely.total_bounds(floor_boxes))
    width, height = bounds[2] - bounds[0], bounds[3] - bounds[1]
    cells = width * height / cell_size**2
    if cells > max_cells:
        raise LevelError(
            f"{source}: the level spans {width:g} x {height:g} tiles = {cells:.0f} cells at cell size {cell_size:g}, "
            f"over the limit of {max_cells} (raise it with --max-cells)"
        )
    check_raster_limits(
        blocked_mask(bounds, floor_boxes if free is None else [], wall_boxes),
        source=source,
        max_vertices=max_vertices,
    )

    if free is None:
        free = shapely.union_all(floor_boxes)
    if free.is_empty or not free.difference(shapely.union_all(walls) if walls else Polygon()).area > 0:
        raise LevelError(f"{source}: the walls cover the whole floor: no free area")
    changes.append(
        _walls_phrase(roles, wall_tiles_found, len(object_walls), len(shape_walls), len(wall_boxes), len(image_walls))
    )
    if not walls:
        warnings.append(
            "no walls found: no collision objects, no collision-marked tiles, no layer named like walls; "
            "mark a layer with a `collision` property or pass --wall-layer"
        )

    off_floor = box(*bounds).difference(free)
    level, report = level_from_walls(
        [*walls, *([] if off_floor.is_empty else [off_floor])],
        bounds,
        name=Path(path).stem,
        source=source,
        cell_size=cell_size,
        cut_step=snap_step,
        max_cells=max_cells,
        max_vertices=max_vertices,
    )
    changes.append(report.describe("wall pieces"))
    if geometry.snapped:
        changes.append(f"snapped {geometry.snapped} vertices to the {snap_step:g}-tile grid")
    if open_walls:
        changes.append(f"ignored {counted(open_walls, 'open wall polyline')} or points (walls must be closed shapes)")

    spawns, spawn_source = spawn_points(tiled, roles, geometry)
    if options.spawn_tiles:
        drawn = {int(gid) for layer in tiled.tile_layers for gid in np.unique(layer.gids)}
        for gid in sorted(set(options.spawn_tiles) - drawn):
            warnings.append(f"--spawn-tile {gid} matches no tile in the map: no spawns from it")
    starts, dropped = usable_starts(level, spawns)
    changes.append(f"{counted(len(starts), 'guard spawn')}" + (f" from {spawn_source}" if spawn_source else ""))
    changes += [f"dropped spawn ({x:g}, {y:g}): {why}" for (x, y), why in dropped[:5]]
    if len(dropped) > 5:
        changes.append(f"dropped {len(dropped) - 5} more spawns")
    if spawns and not starts:
        warnings.append(f"none of the {len(spawns)} spawns is a place the guard fits: the start is left to the command")
    changes += list(tiled.notes)

    # Parts holding a guard spawn are kept, and so are parts where the player starts (found on the
    # uncropped level: a player start is an anchor too, never dropped with its part).
    # With no guard spawn, the parts where the player starts are kept: the guard starts where the player
    # is, not on the ground round a house the player never leaves.
    before = player_starts(level, roles, geometry)[0]
    anchors = [*starts, *before]
    what = "spawn" if not before else "player start" if not starts else "spawn or player start"
    level, left_out = keep_spawn_areas(
        level, anchors, source=source, max_cells=max_cells, max_vertices=max_vertices, what=what
    )
    if left_out:
        changes.append(left_out)
    check_floor_is_ground(source, level, roles, roles.void_gid)
    warnings += look_warnings(level, bool(starts), tiled.size)
    _name_missing_tilesets(warnings, tiled.missing_tilesets)
    players, player_phrase = player_starts(level, roles, geometry)
    if player_phrase:
        changes.append(player_phrase)
    lonely = unguarded_players(level, starts, players)
    if lonely:
        warnings.append(lonely)
    # The level keeps the player starts a player can stand on: sneak's and alert's default --from.
    area = level.free_area()
    standing = [point for point in players if shapely.contains_xy(area, *point)]
    if starts or standing:
        data = level_to_data(level)
        if starts:
            data["guard"]["start"] = list(starts[0])
            data["starts"] = [list(point) for point in starts]
        if standing:
            data["player_starts"] = [list(point) for point in standing]
        level = parse_level(data, source=source, max_cells=max_cells, max_vertices=max_vertices)
    level, watchers = with_watchers(
        level, tiled_watchers(tiled), source=source, max_cells=max_cells, max_vertices=max_vertices
    )
    changes += [watchers] if watchers else []
    level = with_tile_pixels(level, tiled.tile_width, tiled.tile_height)
    # The map's own size, as Tiled shows it; the grid cropped to the level says where it sits (summary).
    declared = tiled.size
    inside = bounds[0] >= 0 and bounds[1] >= 0 and bounds[2] <= declared[0] and bounds[3] <= declared[1]
    size = declared if inside else (int(width), int(height))
    return ImportedLevel(level, "Tiled map", size, tuple(changes), tuple(warnings), tuple(players))


#: The warnings that say walls may be missing; a missing tileset is named in the first of them.
_MISSING_WALLS = ("no walls found", "the free area runs along more than half of every edge")


def _name_missing_tilesets(warnings: list[str], missing: Iterable[str]) -> None:
    """Name the tileset files that were not found in the warning that says walls may be missing (one of its
    own if no other says so): their tiles' collision marks, classes and shapes are unknown."""
    files = list(dict.fromkeys(missing))
    if not files:
        return
    phrase = (
        f"tileset{'s' if len(files) > 1 else ''} {listed(map(repr, files))} not found, so walls "
        f"{'their' if len(files) > 1 else 'its'} tiles mark are missing"
    )
    for index, warning in enumerate(warnings):
        if warning.startswith(_MISSING_WALLS):
            warnings[index] = f"{warning}; {phrase}"
            return
    warnings.append(f"walls may be missing: {phrase}")


def _tile_bounds(bounds: Iterable[float]) -> tuple[float, float, float, float]:
    min_x, min_y, max_x, max_y = (float(value) for value in bounds)
    if not all(math.isfinite(value) for value in (min_x, min_y, max_x, max_y)):
        raise LevelError("the map's free area is empty")
    return float(math.floor(min_x)), float(math.floor(min_y)), float(math.ceil(max_x)), float(math.ceil(max_y))


def _free_area(
    source: str, roles: Guesses, geometry: TileGeometry, walls: list[BaseGeometry], changes: list[str]
) -> tuple[BaseGeometry | None, list[Polygon]]:
    """The boundary objects' area (and no floor boxes), or ``None`` and the floor layers' tile boxes."""
    if roles.boundary_objects:
        free = shapely.union_all([shapely.make_valid(geometry.polygon(item)) for _, item in roles.boundary_objects])
        changes.append(f"free area from {counted(len(roles.boundary_objects), 'boundary object')}")
        if free.is_empty:
            raise LevelError(f"{source}: the boundary objects enclose no area")
        return free, []
    if not roles.floor_layers:
        raise LevelError(
            f"{source}: no floor layer: every tile layer is named or marked as walls, spawns or drawn above "
            "the player; pass --floor-layer NAME or give a layer the boolean property 'floor'"
        )
    if not sum(layer.gids.size for layer in roles.floor_layers):
        raise LevelError(f"{source}: the floor layers {names(roles.floor_layers)} are empty")
    changes.append(f"floor from {names(roles.floor_layers)} ({roles.floor_rule})")
    void = roles.void_gid if roles.void_gid and _walled_void(roles.floor_layers[0], roles.void_gid, walls) else 0
    if void:
        changes.append(
            f"tile {void} fills the edge of {names(roles.floor_layers[:1])} up to the walls: taken as the void "
            "around the level, not floor"
        )
    boxes = [
        piece
        for index, layer in enumerate(roles.floor_layers)
        for piece in geometry.tile_boxes(layer, _not_void(layer, void if index == 0 else 0))
    ]
    return None, boxes


def _walled_void(layer: TileLayer, gid: int, walls: list[BaseGeometry]) -> bool:
    """Whether walls line the border between the cells of tile ``gid`` and the layer's other cells.

    A painted void meets the level at its walls; a grass tile that fills a town's edge meets paths and
    doors with no wall between, and stays floor.
    """
    if not walls:
        return False
    cols, rows = layer.cols, layer.rows
    grid = np.zeros((int(rows.max()) + 1, int(cols.max()) + 1), dtype=bool)
    grid[rows, cols] = layer.gids == gid
    across_rows, across_cols = np.nonzero(grid[:, :-1] != grid[:, 1:])
    down_rows, down_cols = np.nonzero(grid[:-1, :] != grid[1:, :])
    count = across_rows.size + down_rows.size
    if not count:
        return False
    points = shapely.points(np.r_[across_cols + 1.0, down_cols + 0.5], np.r_[across_rows + 0.5, down_rows + 1.0])
    hits = shapely.STRtree(walls).query(points, predicate="dwithin", distance=VOID_WALL_DISTANCE)
    return np.unique(hits[0]).size >= VOID_WALLED_SHARE * count


def _not_void(layer: TileLayer, void_gid: int) -> np.ndarray | None:
    """The layer's tile ids other than ``void_gid`` (``None``: all of them)."""
    if not void_gid:
        return None
    return np.setdiff1d(np.unique(layer.gids), [void_gid])


def _wall_gids_in(layer: TileLayer, roles: Guesses, original: TileLayer | None = None) -> np.ndarray | None:
    """The wall tile ids drawn in this layer; ``None`` means every tile of it. ``original`` is the map's
    layer ``layer`` was cut from (the tiles a walker meets), for its role."""

    drawn = np.unique(layer.gids)
    original = layer if original is None else original
    if _layer_opts_out(layer):
        # A tile's own mark beats its layer's opt-out (as a game's physics reads it), nothing else does.
        return np.intersect1d(drawn, np.fromiter(roles.marked_gids, dtype=np.int64))
    if any(original is wall for wall in roles.wall_tile_layers):
        # Every tile of a wall layer but those whose own properties opt them out, and those with collision
        # shapes: they block where their shapes are (rule 4), not as whole tiles.
        out = roles.unmarked_gids | roles.shaped_gids
        if not out or not np.isin(drawn, list(out)).any():
            return None
        return np.setdiff1d(drawn[drawn != 0], np.fromiter(out, dtype=np.int64))
    return np.intersect1d(drawn, np.fromiter(roles.wall_gids, dtype=np.int64))


def _layer_opts_out(layer: TileLayer) -> bool:
    """Whether a tile layer's own collision property says its tiles are not walls."""
    from guardsim.importers.tiled_roles import flag

    return flag(layer.properties, "collision", "collides", "collidable", "solid") is False


def _walls_phrase(
    roles: Guesses,
    tiles: list[tuple[TileLayer, np.ndarray | None]],
    objects: int,
    shapes: int,
    boxes: int,
    images: int = 0,
) -> str:
    parts = []
    object_layers = {"/".join(layer.path) for layer, _ in roles.wall_objects}
    parts.append(
        f"{counted(objects, 'wall object')}" + (f" in {listed(map(repr, sorted(object_layers)))}" if objects else "")
    )
    whole = [layer for layer, gids in tiles if gids is None]
    if whole:
        parts.append(f"every tile of {names(whole)}")
    marked = sorted({int(gid) for _, gids in tiles if gids is not None for gid in gids})
    if marked:
        shown = ", ".join(map(str, marked[:8])) + (" ..." if len(marked) > 8 else "")
        parts.append(f"{counted(len(marked), 'collision-marked tile')} (gids {shown})")
    if shapes:
        parts.append(f"{counted(shapes, 'tile collision shape')}")
    if images:
        parts.append(f"{counted(images, 'image tile')} at image size")
    return f"walls from {', '.join(parts)} ({counted(boxes, 'wall tile run')})"
