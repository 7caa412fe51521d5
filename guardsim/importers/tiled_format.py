"""The parts of a Tiled map a level is built from, and what the TMX and JSON readers share.

Only what a level needs is kept: tile layers as arrays of global tile ids (finite or chunked infinite
maps; CSV, base64, zlib and gzip data), object layers with their objects' shapes, custom properties of
layers, objects and tiles (from embedded or external ``.tsx`` / ``.tsj`` / ``.json`` tilesets), and
layer offsets, accumulated through group layers. The readers are
:mod:`~guardsim.importers.tiled_tmx` and :mod:`~guardsim.importers.tiled_json`; turning layers into walls
and floor is :mod:`guardsim.importers.tiled`'s job.
"""

from __future__ import annotations

import base64
import math
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from guardsim.errors import LevelError

__all__ = [
    "MapReader",
    "ObjectLayer",
    "TileLayer",
    "TiledMap",
    "TiledObject",
    "TilesetReader",
    "decode_tile_data",
    "object_outline",
]

Point = tuple[float, float]
Properties = dict[str, Any]

#: The flip and rotation flags in the top bits of a global tile id.
GID_MASK = 0x0FFFFFFF
#: Most tiles in one layer or chunk (64 MiB of tile ids).
MAX_LAYER_TILES = 2**24


@dataclass(frozen=True)
class TiledObject:
    """One object of an object layer, in pixels."""

    id: int
    name: str
    kind: str
    """The object's class (``type`` before Tiled 1.9), or its tile's class."""
    shape: str
    """``rectangle``, ``polygon``, ``polyline``, ``ellipse``, ``point``, ``tile`` or ``text``."""
    outline: tuple[Point, ...]
    """Absolute pixel vertices after rotation and layer offset (the position alone for a point)."""
    gid: int = 0
    properties: Properties = field(default_factory=dict)


@dataclass(frozen=True)
class TileLayer:
    """A tile layer: which global tile id sits in which cell."""

    name: str
    path: tuple[str, ...]
    """Names of the enclosing group layers and this layer, outermost first."""
    properties: Properties
    offset: Point
    """Pixel offset, including the enclosing groups'."""
    cols: np.ndarray
    rows: np.ndarray
    gids: np.ndarray
    """Column, row and global tile id (flip flags cleared) of every non-empty cell."""


@dataclass(frozen=True)
class ObjectLayer:
    """An object layer."""

    name: str
    path: tuple[str, ...]
    properties: Properties
    objects: tuple[TiledObject, ...]


@dataclass(frozen=True)
class TiledMap:
    """The parts of a Tiled map a level is built from."""

    tile_width: float
    tile_height: float
    tile_layers: tuple[TileLayer, ...]
    object_layers: tuple[ObjectLayer, ...]
    tiles: dict[int, Properties]
    """Properties of tiles by global id; a tile's class is under the key ``class``."""
    notes: tuple[str, ...] = ()
    """Things the reader could not use (a missing tileset file), for the summary."""


def _rotated(points: list[Point], x: float, y: float, degrees: float, offset: Point) -> tuple[Point, ...]:
    """Object-relative points rotated clockwise on screen (y down) about the object's origin, made absolute."""
    # Quarter turns are exact, so rectangles on the tile grid stay on it.
    quarter = {0: (1.0, 0.0), 90: (0.0, 1.0), 180: (-1.0, 0.0), 270: (0.0, -1.0)}.get(int(degrees) % 360)
    if quarter is not None and float(degrees).is_integer():
        cos, sin = quarter
    else:
        cos, sin = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return tuple((x + dx * cos - dy * sin + offset[0], y + dx * sin + dy * cos + offset[1]) for dx, dy in points)


def _relative_outline(shape: str, width: float, height: float, points: list[Point]) -> list[Point]:
    """Object-relative outline of a shape before rotation."""
    if shape in ("polygon", "polyline"):
        return points
    if shape == "point":
        return [(0.0, 0.0)]
    if shape == "tile":
        # Tile objects hang from their bottom-left corner.
        return [(0.0, -height), (width, -height), (width, 0.0), (0.0, 0.0)]
    if shape == "ellipse":
        steps = 32
        return [
            (width / 2 * (1 + math.cos(2 * math.pi * k / steps)), height / 2 * (1 + math.sin(2 * math.pi * k / steps)))
            for k in range(steps)
        ]
    return [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)]


def decode_tile_data(raw: Any, encoding: str | None, compression: str | None, count: int, where: str) -> np.ndarray:
    """Global tile ids (flags cleared) of one layer's or chunk's data, as ``uint32 (count,)``."""
    if not 0 <= count <= MAX_LAYER_TILES:
        raise LevelError(f"{where}: {count} tiles in one layer or chunk; guardsim reads at most {MAX_LAYER_TILES}")
    try:
        if encoding == "csv":
            text = raw.strip().rstrip(",")
            values = np.array([int(value) for value in text.split(",")], dtype=np.uint64) if text else np.zeros(0)
        elif encoding == "base64":
            packed = base64.b64decode(raw.strip(), validate=False)
            if compression in ("zlib", "gzip"):
                # Inflate no further than the tiles expected, so a tiny file cannot unpack to gigabytes.
                inflater = zlib.decompressobj(wbits=15 if compression == "zlib" else 31)
                packed = inflater.decompress(packed, count * 4 + 4)
            elif compression:
                raise LevelError(f"{where}: {compression} compression is not supported (save as CSV, zlib or gzip)")
            values = np.frombuffer(packed, dtype="<u4").astype(np.uint64)
        else:
            values = np.array([int(value) for value in raw], dtype=np.uint64)
    except (ValueError, TypeError, OverflowError, zlib.error, EOFError):
        raise LevelError(f"{where}: tile data is not valid {encoding or 'tile list'} data") from None
    if values.size != count:
        raise LevelError(f"{where}: tile data has {values.size} tiles, expected {count}")
    return (values & GID_MASK).astype(np.int64)


def object_outline(
    shape: str, x: float, y: float, width: float, height: float, rotation: float, points: list[Point], offset: Point
) -> tuple[Point, ...]:
    """Absolute pixel outline of an object: its shape, rotated about its origin, moved by the layer offset."""
    return _rotated(_relative_outline(shape, width, height, points), x, y, rotation, offset)


#: ``(path, firstgid) -> properties by global tile id`` for one external tileset file type.
TilesetReader = Callable[[Path, int], dict[int, Properties]]


class MapReader:
    """What the TMX and JSON readers share: numbers, tile cells, external tilesets, the result."""

    def __init__(self, source: str, folder: Path, tileset_readers: dict[str, TilesetReader] | None = None) -> None:
        self.source = source
        self.folder = folder
        self.tileset_readers = tileset_readers or {}
        self.tile_layers: list[TileLayer] = []
        self.object_layers: list[ObjectLayer] = []
        self.tiles: dict[int, Properties] = {}
        self.notes: list[str] = []

    def number(self, value: Any, where: str, default: float | None = None) -> float:
        if value is None and default is not None:
            return default
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise LevelError(f"{self.source}: {where} must be a number, not {value!r}") from None
        if not math.isfinite(number):
            raise LevelError(f"{self.source}: {where} must be a finite number, not {value!r}")
        return number

    def integer(self, value: Any, where: str, default: int | None = None) -> int:
        """A whole number in Tiled's 32-bit range (tile ids go up to 2**32 with their flag bits)."""
        number = self.number(value, where, None if default is None else float(default))
        if not number.is_integer() or not -(2**31) <= number < 2**32:
            raise LevelError(f"{self.source}: {where} must be a whole number within 32 bits, not {value!r}")
        return int(number)

    def check_orientation(self, orientation: Any) -> None:
        if orientation != "orthogonal":
            raise LevelError(f"{self.source}: orientation {orientation!r} is not supported (only orthogonal maps)")

    def template_error(self, where: str) -> LevelError:
        """The error for an object that uses a template (its fields live in another file, not read)."""
        return LevelError(f"{self.source}: {where}: uses a template; detach it in Tiled (templates are not read)")

    def tileset_tile(self, properties: Properties, kind: Any) -> Properties:
        """A tileset tile's properties with its class (``type`` before Tiled 1.9), if any, under ``class``."""
        if kind:
            properties["class"] = kind
        return properties

    def tiled_object(
        self,
        identifier: int,
        name: str,
        kind: Any,
        shape: str,
        outline: tuple[Point, ...],
        gid: int,
        properties: Properties,
    ) -> TiledObject:
        """An object whose class and properties default to its tile's: its own override them."""
        tile = self.tiles.get(gid, {})
        return TiledObject(
            identifier, name, str(kind or tile.get("class", "")), shape, outline, gid, {**tile, **properties}
        )

    def add_cells(
        self,
        name: str,
        path: tuple[str, ...],
        properties: Properties,
        offset: Point,
        blocks: list[tuple[int, int, int, np.ndarray]],
    ) -> None:
        """``blocks`` are ``(x, y, width, gids)`` of the whole layer or of each chunk."""
        cols, rows, gids = [], [], []
        for x, y, width, values in blocks:
            index = np.flatnonzero(values)
            cols.append(x + index % width)
            rows.append(y + index // width)
            gids.append(values[index])
        joined = [np.concatenate(part) if part else np.zeros(0, dtype=np.int64) for part in (cols, rows, gids)]
        self.tile_layers.append(TileLayer(name, path, properties, offset, *joined))

    def result(self, tilewidth: Any, tileheight: Any) -> TiledMap:
        """The map read, with the tile size given by the map's ``tilewidth`` and ``tileheight`` values."""
        tile_width, tile_height = self.number(tilewidth, "tilewidth"), self.number(tileheight, "tileheight")
        if tile_width <= 0 or tile_height <= 0:
            raise LevelError(
                f"{self.source}: tilewidth and tileheight must be positive, not {tile_width:g} x {tile_height:g}"
            )
        return TiledMap(
            tile_width,
            tile_height,
            tuple(self.tile_layers),
            tuple(self.object_layers),
            self.tiles,
            tuple(self.notes),
        )

    def external_tileset(self, name: str, firstgid: int) -> None:
        path = self.folder / name
        reader = self.tileset_readers.get(path.suffix.lower())
        if reader is None:
            raise LevelError(f"{self.source}: tileset {name}: not a .tsx, .tsj or .json tileset")
        if not path.is_file():
            self.notes.append(f"tileset {name} not found: its tile properties are unknown")
            return
        self.tiles.update(reader(path, firstgid))
