"""A Tiled map's shapes in tile units: objects, tile runs, tile collision shapes, and the blocked-cell mask."""

from __future__ import annotations

from collections.abc import Collection

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from guardsim.importers.tiled_data import FLIP_DIAGONAL, TiledMap, TiledObject, TileLayer, flipped, tile_outline
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
        grid = (tiled.tile_width, tiled.tile_height)
        #: Tiles of collections of images drawn at a size other than the map's tile: their footprint.
        self.images = {gid: size for gid, size in tiled.image_sizes.items() if size != grid and size != (0.0, 0.0)}
        #: Tiles of collections of images whose size the file does not give (drawn as one tile).
        self.unsized = {gid for gid, size in tiled.image_sizes.items() if size == (0.0, 0.0)}

    def polygon(self, item: TiledObject) -> Polygon:
        points, moved = snap_points(
            np.asarray(item.outline, dtype=float) / self.scale, self.snap_step, self.snap_tolerance
        )
        self.snapped += moved
        return Polygon(points)

    def object_wall(self, item: TiledObject) -> BaseGeometry | None:
        """A wall object's area; a tile object of a tile with collision shapes is those shapes.

        A tile object's shapes are placed as Tiled draws its tile: flipped, scaled from the tile's size to
        the object's, hung from the object's anchor (bottom-left) and rotated about it.
        """
        info = self.tiled.tiles.get(item.gid) if item.gid else None
        if info is None or not info.shapes:
            return self.polygon(item)
        pieces = []
        for shape in info.shapes:
            if not shape.closed:
                continue
            points = tile_outline(item, np.asarray(shape.outline, dtype=float), info.size)
            pieces.append(shapely.make_valid(Polygon(points / self.scale)))
        return shapely.union_all(pieces) if pieces else None

    def tile_boxes(self, layer: TileLayer, gids: np.ndarray | None = None, skip: Collection[int] = ()) -> list[Polygon]:
        """Rectangles (in tiles) covering the layer's tiles whose id is in ``gids`` (all tiles for ``None``),
        one cell each, leaving out the tiles in ``skip``."""
        keep = np.ones(layer.gids.size, dtype=bool) if gids is None else np.isin(layer.gids, gids)
        if skip:
            keep &= ~np.isin(layer.gids, list(skip))
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

    def _drawn(self, layer: TileLayer, keep: np.ndarray) -> list[tuple[int, float, float, tuple[float, float], int]]:
        """``(gid, left, top, size, flips)`` in pixels of each kept tile as Tiled draws it: at its own
        ``size`` (width and height), standing on its cell's bottom-left corner, and with width and height
        swapped when flipped diagonally (``left, top`` is the drawn image's top-left corner)."""
        flips = layer.flips[keep].tolist() if layer.flips is not None else [0] * int(keep.sum())
        cells = zip(layer.cols[keep].tolist(), layer.rows[keep].tolist(), layer.gids[keep].tolist(), flips)
        drawn = []
        for col, row, gid, flip in cells:
            info = self.tiled.tiles.get(gid)
            width, height = self.images.get(gid) or (info.size if info is not None else (0.0, 0.0))
            if not (width and height):
                width, height = float(self.scale[0]), float(self.scale[1])
            tall = width if flip & FLIP_DIAGONAL else height
            left = col * self.scale[0] + layer.offset[0]
            top = (row + 1) * self.scale[1] - tall + layer.offset[1]
            drawn.append((gid, float(left), float(top), (float(width), float(height)), flip))
        return drawn

    def tile_shapes(self, layer: TileLayer, gids: set[int]) -> list[BaseGeometry]:
        """The collision shapes of the layer's tiles in ``gids``, placed at their cells (in tiles) and
        flipped as each cell says."""
        keep = np.isin(layer.gids, list(gids)) if gids else np.zeros(layer.gids.size, dtype=bool)
        pieces: list[BaseGeometry] = []
        for gid, left, top, size, flips in self._drawn(layer, keep):
            drawn = np.array(size[::-1] if flips & FLIP_DIAGONAL else size)
            for shape in self.tiled.tiles[gid].shapes:
                if shape.closed:
                    unit = np.asarray(shape.outline, dtype=float) / np.array(size)
                    points = (flipped(unit, flips) * drawn + np.array([left, top])) / self.scale
                    pieces.append(shapely.make_valid(Polygon(points)))
        return pieces

    def image_tiles(self, layer: TileLayer, gids: np.ndarray | None) -> list[Polygon]:
        """The footprints (in tiles) of the layer's image-collection tiles in ``gids`` (all for ``None``)
        that are not one map tile in size: each image's rectangle, standing on its cell's bottom-left corner."""
        keep = np.isin(layer.gids, list(self.images))
        if gids is not None:
            keep &= np.isin(layer.gids, gids)
        boxes = []
        for _, left, top, (width, height), flips in self._drawn(layer, keep):
            if flips & FLIP_DIAGONAL:
                width, height = height, width
            (x0, y0), (x1, y1) = np.array([[left, top], [left + width, top + height]]) / self.scale
            boxes.append(shapely.box(x0, y0, x1, y1))
        return boxes


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
