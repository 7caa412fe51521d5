"""A Tiled map's shapes in tile units: objects, tile runs, tile collision shapes, and the blocked-cell mask."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from guardsim.importers.tiled_data import TiledMap, TiledObject, TileLayer
from guardsim.importers.walls import snap_points

__all__ = ["TileGeometry", "blocked_mask"]


class TileGeometry:
    """Pixel shapes to tile units, with vertex snapping counted."""

    def __init__(self, tiled: TiledMap, snap_step: float, snap_tolerance: float) -> None:
        self.tiled = tiled
        self.scale = np.array([tiled.tile_width, tiled.tile_height])
        self.snap_step = snap_step
        self.snap_tolerance = snap_tolerance
        self.snapped = 0

    def polygon(self, item: TiledObject) -> Polygon:
        points, moved = snap_points(
            np.asarray(item.outline, dtype=float) / self.scale, self.snap_step, self.snap_tolerance
        )
        self.snapped += moved
        return Polygon(points)

    def object_wall(self, item: TiledObject) -> BaseGeometry | None:
        """A wall object's area; a tile object of a tile with collision shapes is those shapes."""
        info = self.tiled.tiles.get(item.gid) if item.gid else None
        if info is None or not info.shapes:
            return self.polygon(item)
        # Tile objects hang from their bottom-left corner and may be scaled from the tile's size.
        (left, top), (right, _), _, (_, bottom) = item.outline[:4]
        sx = (right - left) / info.size[0] if info.size[0] else 1.0
        sy = (bottom - top) / info.size[1] if info.size[1] else 1.0
        pieces = []
        for shape in info.shapes:
            if not shape.closed:
                continue
            points = np.asarray(shape.outline, dtype=float) * (sx, sy) + (left, top)
            pieces.append(shapely.make_valid(Polygon(points / self.scale)))
        return shapely.union_all(pieces) if pieces else None

    def tile_boxes(self, layer: TileLayer, gids: np.ndarray | None = None) -> list[Polygon]:
        """Rectangles (in tiles) covering the layer's tiles whose id is in ``gids`` (all tiles for ``None``)."""
        keep = np.ones(layer.gids.size, dtype=bool) if gids is None else np.isin(layer.gids, gids)
        if not keep.any():
            return []
        cols, rows = layer.cols[keep], layer.rows[keep]
        # Runs of consecutive tiles in a row, found from the sorted tiles rather than a dense mask.
        order = np.lexsort((cols, rows))
        cols, rows = cols[order], rows[order]
        starts = np.flatnonzero(np.r_[True, (rows[1:] != rows[:-1]) | (cols[1:] != cols[:-1] + 1)])
        ends = np.r_[starts[1:], cols.size] - 1
        dx, dy = layer.offset[0] / self.scale[0], layer.offset[1] / self.scale[1]
        return list(shapely.box(cols[starts] + dx, rows[starts] + dy, cols[ends] + 1 + dx, rows[starts] + 1 + dy))

    def tile_shapes(self, layer: TileLayer, gids: set[int]) -> list[BaseGeometry]:
        """The collision shapes of the layer's tiles in ``gids``, placed at their cells (in tiles)."""
        keep = np.isin(layer.gids, list(gids)) if gids else np.zeros(layer.gids.size, dtype=bool)
        pieces: list[BaseGeometry] = []
        for col, row, gid in zip(layer.cols[keep].tolist(), layer.rows[keep].tolist(), layer.gids[keep].tolist()):
            info = self.tiled.tiles[gid]
            # A tile taller than the grid is drawn from the cell's bottom-left corner, as Tiled does.
            left = col * self.scale[0] + layer.offset[0]
            top = (row + 1) * self.scale[1] - (info.size[1] or self.scale[1]) + layer.offset[1]
            for shape in info.shapes:
                if shape.closed:
                    points = (np.asarray(shape.outline, dtype=float) + np.array([left, top])) / self.scale
                    pieces.append(shapely.make_valid(Polygon(points)))
        return pieces


def blocked_mask(
    bounds: tuple[float, float, float, float], floor_boxes: list[Polygon], wall_boxes: list[Polygon]
) -> np.ndarray:
    """Cells of the level's tile grid that no floor covers or a wall tile covers, for the vertex estimate.

    Boxes are one-row runs; each is painted with a difference array, so a million runs cost no Python loop.
    Runs off whole tiles (layer offsets) are rounded, which is all an estimate needs.
    """
    min_x, min_y, max_x, max_y = bounds
    rows, cols = int(max_y - min_y), int(max_x - min_x)

    def painted(boxes: list[Polygon]) -> np.ndarray:
        if not boxes:
            return np.zeros((rows, cols), dtype=bool)
        x0, y0, x1, _ = np.round(shapely.bounds(np.asarray(boxes, dtype=object))).astype(np.int64).T
        row = np.clip(y0 - int(min_y), 0, rows - 1)
        start, stop = np.clip(x0 - int(min_x), 0, cols), np.clip(x1 - int(min_x), 0, cols)
        change = np.zeros((rows, cols + 1), dtype=np.int64)
        np.add.at(change, (row, start), 1)
        np.add.at(change, (row, stop), -1)
        return np.cumsum(change, axis=1)[:, :cols] > 0

    walls = painted(wall_boxes)
    return walls | ~painted(floor_boxes) if floor_boxes else walls
