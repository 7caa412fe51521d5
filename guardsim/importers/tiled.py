"""Tiled maps (TMX and Tiled JSON) into levels: which layers are floor, walls, boundary and spawns.

One tile is one world unit. What each part of a map means is marked in Tiled with custom properties,
and where a map has none (as most game maps do), with layer names (``docs/authoring.md``):

* **Floor**: tile layers with the boolean property ``floor``; else tile layers whose name contains
  "floor" or "ground"; else the first tile layer. Every non-empty tile of a floor layer is free area.
* **Boundary**: objects of class ``boundary`` or with the boolean property ``boundary`` (or in a layer
  with it, or named "boundary"). When a map has one, the free area is the boundary, not the floor.
* **Walls**: closed objects (rectangles, polygons, ellipses, tile objects) with the boolean property
  ``collision``, or in an object layer with it or whose name contains "wall" or "collision"
  (``collision: false`` opts one out); and tiles whose tileset tile has ``collision``, or every tile of
  a tile layer with it. The free area is floor (or boundary) minus walls.
* **Guard spawns**: objects of class ``guard`` or with the boolean property ``guard_spawn`` (or in a
  layer with it), tiles whose tileset tile has class ``guard`` or ``guard_spawn``, and tiles whose
  global id is passed as ``spawn_tiles`` (for maps whose tilesets carry no properties).

Vertices within ``snap_tolerance`` of the half-tile grid are snapped onto it, so hand-placed walls that
were meant to meet do. The outer ring is the free area's bounding box on whole tiles.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Point as ShapelyPoint
from shapely.geometry import Polygon, box

from guardsim.errors import LevelError
from guardsim.importers.imported import ImportedLevel, level_from_walls, read_source_bytes
from guardsim.importers.tiled_format import ObjectLayer, Properties, TiledMap, TiledObject, TileLayer
from guardsim.importers.tiled_json import JsonMapReader, parse_json, read_tsj_tiles
from guardsim.importers.tiled_tmx import TmxReader, parse_xml, read_tsx_tiles
from guardsim.importers.walls import snap_points
from guardsim.level import (
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_FILE_BYTES,
    DEFAULT_MAX_VERTICES,
    Level,
    level_to_data,
    parse_level,
)
from guardsim.world import World

__all__ = ["DEFAULT_SNAP_STEP", "DEFAULT_SNAP_TOLERANCE", "import_tiled", "read_tiled"]

#: Vertices are snapped to multiples of this many tiles...
DEFAULT_SNAP_STEP = 0.5
#: ...when they are this close (in tiles: 2.56 pixels on 64-pixel tiles).
DEFAULT_SNAP_TOLERANCE = 0.04

_FLOOR_WORDS = ("floor", "ground")
_WALL_WORDS = ("wall", "collision")
_CLOSED_SHAPES = ("rectangle", "polygon", "ellipse", "tile")
_TILESET_READERS = {".tsx": read_tsx_tiles, ".tsj": read_tsj_tiles, ".json": read_tsj_tiles}


def read_tiled(path: str | os.PathLike[str], *, max_file_bytes: int = DEFAULT_MAX_FILE_BYTES) -> TiledMap:
    """Read a TMX (``.tmx``) or Tiled JSON (``.json``, ``.tmj``) map, with its external tilesets."""
    source = str(path)
    folder = Path(path).parent
    data = read_source_bytes(path, max_file_bytes)
    if Path(path).suffix.lower() == ".tmx":
        return TmxReader(source, folder, _TILESET_READERS).map(parse_xml(data, source))
    return JsonMapReader(source, folder, _TILESET_READERS).map(parse_json(data, source))


def import_tiled(
    path: str | os.PathLike[str],
    *,
    cell_size: float = 1.0,
    spawn_tiles: Iterable[int] = (),
    snap_step: float = DEFAULT_SNAP_STEP,
    snap_tolerance: float = DEFAULT_SNAP_TOLERANCE,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Convert a Tiled map to a level (one tile = one world unit; see the module notes for the roles).

    Parameters
    ----------
    spawn_tiles
        Global tile ids that mark a guard spawn, for maps whose tilesets do not say which tile that is.
    snap_step, snap_tolerance
        Wall and boundary vertices within ``snap_tolerance`` tiles of a multiple of ``snap_step`` tiles are
        moved onto it.
    """
    source = str(path)
    tiled = read_tiled(path, max_file_bytes=max_file_bytes)
    scale = np.array([tiled.tile_width, tiled.tile_height])
    changes: list[str] = []

    def tiles_of(outline: Iterable[tuple[float, float]]) -> np.ndarray:
        return np.asarray(list(outline), dtype=float) / scale

    snapped = 0

    def snapped_polygon(item: TiledObject) -> Polygon:
        nonlocal snapped
        points, moved = snap_points(tiles_of(item.outline), snap_step, snap_tolerance)
        snapped += moved
        return Polygon(points)

    boundary = [
        (layer, item) for layer, item in _objects(tiled.object_layers) if _is_boundary(layer, item) and _closed(item)
    ]
    if boundary:
        free = shapely.union_all([shapely.make_valid(snapped_polygon(item)) for _, item in boundary])
        changes.append(f"free area from {len(boundary)} boundary object{'s' if len(boundary) != 1 else ''}")
    else:
        floor_layers, rule = _floor_layers(tiled.tile_layers)
        if not floor_layers:
            raise LevelError(
                f"{source}: no floor: give a tile layer the boolean property 'floor', or draw a boundary object"
            )
        free = shapely.union_all([piece for layer in floor_layers for piece in _tile_boxes(layer, scale)])
        changes.append(f"floor from {_names(floor_layers)} ({rule})")
    if free.is_empty:
        raise LevelError(f"{source}: the floor (or boundary) is empty")

    wall_layers = [layer for layer in tiled.object_layers if _is_wall_layer(layer)]
    wall_objects = [
        item
        for layer, item in _objects(tiled.object_layers)
        if _is_wall(layer, item) and not _is_boundary(layer, item) and not _is_spawn(layer, item)
    ]
    walls: list[shapely.Geometry] = [snapped_polygon(item) for item in wall_objects if _closed(item)]
    open_walls = sum(1 for item in wall_objects if not _closed(item))
    wall_tiles = [piece for layer in tiled.tile_layers for piece in _tile_boxes(layer, scale, _wall_gids(layer, tiled))]
    walls += wall_tiles
    changes.append(
        f"walls from {len(walls) - len(wall_tiles)} objects"
        + (f" in {_names(wall_layers)}" if wall_layers else "")
        + (f" and {len(wall_tiles)} collision tile runs" if wall_tiles else "")
    )

    min_x, min_y, max_x, max_y = free.bounds
    bounds = (float(math.floor(min_x)), float(math.floor(min_y)), float(math.ceil(max_x)), float(math.ceil(max_y)))
    off_floor = box(*bounds).difference(free)
    level, report = level_from_walls(
        [*walls, *([] if off_floor.is_empty else [off_floor])],
        bounds,
        name=Path(source).stem,
        source=source,
        cell_size=cell_size,
        cut_step=snap_step,
        max_cells=max_cells,
        max_vertices=max_vertices,
    )
    changes.append(report.describe("wall pieces"))
    changes.append(f"snapped {snapped} vertices to the {snap_step:g}-tile grid")
    if open_walls:
        changes.append(f"ignored {open_walls} open wall polylines or points (walls must be closed shapes)")

    spawns = _spawns(tiled, scale, set(spawn_tiles))
    starts, dropped = _usable_starts(level, spawns)
    changes.append(f"{len(starts)} guard spawn{'s' if len(starts) != 1 else ''}")
    changes += [f"dropped spawn ({x:g}, {y:g}): {why}" for (x, y), why in dropped]
    changes += list(tiled.notes)
    if starts:
        data = level_to_data(level)
        data["guard"]["start"] = list(starts[0])
        data["starts"] = [list(point) for point in starts]
        level = parse_level(data, source=source, max_cells=max_cells, max_vertices=max_vertices)
    width, height = bounds[2] - bounds[0], bounds[3] - bounds[1]
    return ImportedLevel(level, "Tiled map", (int(width), int(height)), tuple(changes))


def _flag(properties: Properties, key: str) -> bool | None:
    """A boolean property: ``True``, ``False`` or ``None`` when absent."""
    value = properties.get(key)
    if value is None:
        return None
    if isinstance(value, str):
        return value.strip().lower() in ("true", "1", "yes")
    return bool(value)


def _named(path: tuple[str, ...], words: tuple[str, ...]) -> bool:
    return any(word in part.lower() for part in path for word in words)


def _names(layers: Iterable[TileLayer | ObjectLayer]) -> str:
    return ", ".join(repr(layer.name) for layer in layers)


def _objects(layers: Iterable[ObjectLayer]) -> Iterable[tuple[ObjectLayer, TiledObject]]:
    return ((layer, item) for layer in layers for item in layer.objects)


def _closed(item: TiledObject) -> bool:
    return item.shape in _CLOSED_SHAPES and len(item.outline) >= 3


def _floor_layers(layers: tuple[TileLayer, ...]) -> tuple[list[TileLayer], str]:
    """The floor layers and the rule that chose them."""
    marked = [layer for layer in layers if _flag(layer.properties, "floor")]
    if marked:
        return marked, "property floor"
    candidates = [layer for layer in layers if _flag(layer.properties, "floor") is not False]
    named = [layer for layer in candidates if _named(layer.path, _FLOOR_WORDS)]
    if named:
        return named, "named floor or ground"
    return candidates[:1], "the first tile layer"


def _is_boundary(layer: ObjectLayer, item: TiledObject) -> bool:
    own = _flag(item.properties, "boundary")
    if own is not None:
        return own
    return (
        item.kind.lower() == "boundary"
        or bool(_flag(layer.properties, "boundary"))
        or _named(layer.path, ("boundary",))
    )


def _is_wall_layer(layer: ObjectLayer) -> bool:
    marked = _flag(layer.properties, "collision")
    return marked if marked is not None else _named(layer.path, _WALL_WORDS)


def _is_wall(layer: ObjectLayer, item: TiledObject) -> bool:
    own = _flag(item.properties, "collision")
    return own if own is not None else _is_wall_layer(layer)


def _is_spawn(layer: ObjectLayer, item: TiledObject) -> bool:
    own = _flag(item.properties, "guard_spawn")
    if own is not None:
        return own
    return item.kind.lower() == "guard" or bool(_flag(layer.properties, "guard_spawn"))


def _wall_gids(layer: TileLayer, tiled: TiledMap) -> set[int] | None:
    """Tile ids that are walls in this layer; ``None`` means every tile."""
    if _flag(layer.properties, "collision"):
        return None
    return {gid for gid, properties in tiled.tiles.items() if _flag(properties, "collision")}


def _tile_boxes(layer: TileLayer, scale: np.ndarray, gids: set[int] | None = None) -> list[Polygon]:
    """Rectangles (in tiles) covering the layer's tiles whose id is in ``gids`` (all tiles for ``None``)."""
    keep = np.ones(layer.gids.size, dtype=bool) if gids is None else np.isin(layer.gids, list(gids))
    if not keep.any():
        return []
    cols, rows = layer.cols[keep], layer.rows[keep]
    # Runs of consecutive tiles in a row, found from the sorted tiles rather than a dense mask, so that
    # one stray tile far away costs nothing here (the grid size limit reports it later).
    order = np.lexsort((cols, rows))
    cols, rows = cols[order], rows[order]
    starts = np.flatnonzero(np.r_[True, (rows[1:] != rows[:-1]) | (cols[1:] != cols[:-1] + 1)])
    ends = np.r_[starts[1:], cols.size] - 1
    dx, dy = layer.offset[0] / scale[0], layer.offset[1] / scale[1]
    return list(shapely.box(cols[starts] + dx, rows[starts] + dy, cols[ends] + 1 + dx, rows[starts] + 1 + dy))


def _spawns(tiled: TiledMap, scale: np.ndarray, spawn_tiles: set[int]) -> list[tuple[float, float]]:
    """Guard spawn points in tiles: spawn objects first (layer order), then spawn tiles (row by row)."""
    points: list[tuple[float, float]] = []
    for layer, item in _objects(tiled.object_layers):
        if _is_spawn(layer, item):
            outline = np.asarray(item.outline, dtype=float) / scale
            centre = Polygon(outline).centroid if _closed(item) else ShapelyPoint(outline.mean(axis=0))
            points.append((round(centre.x, 6), round(centre.y, 6)))
    tile_ids = spawn_tiles | {
        gid
        for gid, properties in tiled.tiles.items()
        if str(properties.get("class", "")).lower() == "guard" or _flag(properties, "guard_spawn")
    }
    for layer in tiled.tile_layers:
        keep = np.isin(layer.gids, list(tile_ids))
        order = np.lexsort((layer.cols[keep], layer.rows[keep]))
        for col, row in zip(layer.cols[keep][order].tolist(), layer.rows[keep][order].tolist(), strict=False):
            points.append((col + 0.5 + layer.offset[0] / scale[0], row + 0.5 + layer.offset[1] / scale[1]))
    return points


def _usable_starts(
    level: Level, points: list[tuple[float, float]]
) -> tuple[list[tuple[float, float]], list[tuple[tuple[float, float], str]]]:
    """Spawns whose grid cell the guard can stand in, and the others with the reason."""
    world = World(level)
    free = level.free_area()
    min_x, min_y, _, _ = level.bounds
    rows, cols = level.grid_shape()
    size = level.cell_size
    usable, dropped = [], []
    for point in points:
        col, row = math.floor((point[0] - min_x) / size), math.floor((point[1] - min_y) / size)
        centre = (min_x + (col + 0.5) * size, min_y + (row + 0.5) * size)
        if not (0 <= col < cols and 0 <= row < rows) or not free.contains(ShapelyPoint(point)):
            dropped.append((point, "not on the free area"))
        elif not free.contains(ShapelyPoint(centre)) or not world.fits(centre, level.guard.radius):
            dropped.append((point, f"the guard does not fit in its cell at ({centre[0]:g}, {centre[1]:g})"))
        elif point not in usable:
            usable.append(point)
    return usable, dropped
