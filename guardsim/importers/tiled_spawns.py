"""Guard spawns of a Tiled map: where they are, which the guard can start from, and the areas they keep;
and the player's starts, which are never a guard's."""

from __future__ import annotations

import math
from typing import cast

import numpy as np
import shapely
from shapely.geometry import Point as ShapelyPoint
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from guardsim.importers.imported import counted, level_from_walls, listed
from guardsim.importers.tiled_data import TiledMap
from guardsim.importers.tiled_geometry import TileGeometry
from guardsim.importers.tiled_roles import Guesses
from guardsim.level import Level
from guardsim.world import World

__all__ = ["keep_spawn_areas", "player_starts", "spawn_points", "unguarded_players", "usable_starts"]


def _centre(outline: np.ndarray, closed: bool) -> tuple[float, float]:
    """An object's centre in tiles: a closed shape's centroid, else the mean of its points."""
    centre = Polygon(outline).centroid if closed else ShapelyPoint(outline.mean(axis=0))
    return round(centre.x, 6), round(centre.y, 6)


def player_starts(level: Level, roles: Guesses, geometry: TileGeometry) -> tuple[list[tuple[float, float]], str]:
    """The player's start points (world units: tiles) in layer order, and a summary phrase ("" for none)."""
    points: list[tuple[float, float]] = []
    where: list[str] = []
    free = cast(BaseGeometry, level.free_area())
    for object_layer, item in roles.player_objects:
        point = _centre(np.asarray(item.outline, dtype=float) / geometry.scale, item.closed)
        points.append(point)
        label = item.name or item.kind or f"object {item.id}"
        off = "" if free.contains(ShapelyPoint(point)) else ", not on the free area"
        where.append(f"({point[0]:g}, {point[1]:g}) from {label!r} in {'/'.join(object_layer.path)!r}{off}")
    if not points:
        return [], ""
    return points, f"{counted(len(points), 'player start')} {listed(where, 3)} (the intruder's, not a guard spawn)"


def spawn_points(tiled: TiledMap, roles: Guesses, geometry: TileGeometry) -> tuple[list[tuple[float, float]], str]:
    """Guard spawn points in tiles (spawn objects in layer order, then spawn tiles row by row), and their source."""
    points: list[tuple[float, float]] = []
    sources = []
    layers: dict[str, int] = {}
    for object_layer, item in roles.spawn_objects:
        points.append(_centre(np.asarray(item.outline, dtype=float) / geometry.scale, item.closed))
        name = "/".join(object_layer.path)
        layers[name] = layers.get(name, 0) + 1
    sources += [f"{count} objects in {name!r}" for name, count in layers.items()]
    tile_count = 0
    for layer in tiled.tile_layers:
        keep = np.isin(layer.gids, list(roles.spawn_gids))
        order = np.lexsort((layer.cols[keep], layer.rows[keep]))
        for col, row in zip(layer.cols[keep][order].tolist(), layer.rows[keep][order].tolist()):
            points.append(
                (col + 0.5 + layer.offset[0] / geometry.scale[0], row + 0.5 + layer.offset[1] / geometry.scale[1])
            )
            tile_count += 1
    if tile_count:
        sources.append(f"{counted(tile_count, 'spawn tile')} (gids {listed(map(str, sorted(roles.spawn_gids)))})")
    return points, ", ".join(sources)


def usable_starts(
    level: Level, points: list[tuple[float, float]]
) -> tuple[list[tuple[float, float]], list[tuple[tuple[float, float], str]]]:
    """Spawns whose grid cell the guard can stand in, and the others with the reason."""
    if not points:
        return [], []
    world = World(level)
    free = cast(BaseGeometry, level.free_area())
    min_x, min_y, _, _ = level.bounds
    rows, cols = level.grid_shape()
    size = level.cell_size
    usable: list[tuple[float, float]] = []
    dropped = []
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


def keep_spawn_areas(
    level: Level,
    starts: list[tuple[float, float]],
    *,
    source: str,
    max_cells: int,
    max_vertices: int,
    what: str = "spawn",
) -> tuple[Level, str]:
    """The level without the parts of its free area that hold no start (when there are starts), cropped
    to the whole tiles around the parts kept; ``what`` names the starts in the summary phrase."""
    parts = list(shapely.get_parts(cast(BaseGeometry, level.free_area())))
    if not starts or len(parts) < 2:
        return level, ""
    points = [ShapelyPoint(point) for point in starts]
    drop = [part for part in parts if not any(part.intersects(point) for point in points)]
    if not drop or len(drop) == len(parts):
        # No start on the free area at all: nothing tells which parts to keep (the starts are warned of).
        return level, ""
    area = sum(part.area for part in drop)
    kept = shapely.union_all([part for part in parts if not any(part is other for other in drop)])
    # The picture and the grid hold what is kept, not the map's whole rectangle (whole tiles, so that
    # cells stay on the map's tile grid).
    left, top, right, bottom = kept.bounds
    bounds = (
        max(level.bounds[0], float(math.floor(left))),
        max(level.bounds[1], float(math.floor(top))),
        min(level.bounds[2], float(math.ceil(right))),
        min(level.bounds[3], float(math.ceil(bottom))),
    )
    frame = shapely.box(*bounds)
    walls = [
        piece
        for wall in [Polygon(ring) for ring in level.holes] + drop
        if not (piece := shapely.intersection(wall, frame)).is_empty and piece.area > 0
    ]
    new_level, _ = level_from_walls(
        walls,
        bounds,
        name=level.name,
        source=source,
        cell_size=level.cell_size,
        max_cells=max_cells,
        max_vertices=max_vertices,
    )
    phrase = f"left out {counted(len(drop), 'free part')} holding no {what} ({area:g} square tiles)"
    if bounds != tuple(level.bounds):
        phrase += (
            f"; cropped to the parts kept: {bounds[2] - bounds[0]:g} x {bounds[3] - bounds[1]:g} tiles "
            f"from ({bounds[0]:g}, {bounds[1]:g})"
        )
    return new_level, phrase


def unguarded_players(level: Level, starts: list[tuple[float, float]], players: list[tuple[float, float]]) -> str:
    """A warning when a player start stands in a free part no guard spawn is in ("" otherwise): no guard
    ever walks where the player is, so every sneak there is unseen."""
    if not starts or not players:
        return ""
    parts = list(shapely.get_parts(cast(BaseGeometry, level.free_area())))
    lonely = [
        point
        for point in players
        for part in parts
        if part.intersects(ShapelyPoint(point)) and not any(part.intersects(ShapelyPoint(s)) for s in starts)
    ]
    if not lonely:
        return ""
    x, y = lonely[0]
    return (
        f"the player start ({x:g}, {y:g}) is in a free part no guard spawn is in: no guard can reach the player "
        "there (add a spawn in that part, or join the parts)"
    )
