"""The parts of a Tiled map a level is built from, in pixels, checked and flattened.

:mod:`guardsim.importers.tiled_read` fills these from pytiled-parser's objects; deciding which layers
are floor, walls and spawns is :mod:`guardsim.importers.tiled_roles`' job. Group layers are flattened:
each layer keeps the names of its groups (``path``), their properties merged under its own, the sum of
their offsets, and whether it and every group around it are visible.
"""

from __future__ import annotations

import base64
import math
import zlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from guardsim.errors import ArgumentError, LevelError
from guardsim.files.reading import NumberError, finite_number
from guardsim.importers.source import excerpt

__all__ = [
    "FLIP_DIAGONAL",
    "FLIP_HORIZONTAL",
    "FLIP_VERTICAL",
    "GID_MASK",
    "MAX_COORDINATE",
    "ObjectLayer",
    "TileInfo",
    "TileLayer",
    "TiledMap",
    "TiledObject",
    "decode_tile_data",
    "flipped",
    "object_outline",
    "split_gid",
    "tile_outline",
]

Point = tuple[float, float]
Properties = dict[str, Any]

#: The flip and rotation flags in the top bits of a global tile id.
GID_MASK = 0x0FFFFFFF
#: Flip flags as :func:`split_gid` returns them (bits 31, 30 and 29 of a global tile id, shifted down).
FLIP_HORIZONTAL, FLIP_VERTICAL, FLIP_DIAGONAL = 4, 2, 1
#: Largest pixel coordinate or size read (far past any real map; keeps geometry libraries finite).
MAX_COORDINATE = 1e9


@dataclass(frozen=True)
class TiledObject:
    """One object of an object layer (or of a tile's collision shapes), in pixels."""

    id: int
    name: str
    kind: str
    """The object's class (``type`` before Tiled 1.9), or its tile's class."""
    shape: str
    """``rectangle``, ``polygon``, ``polyline``, ``ellipse``, ``point``, ``tile`` or ``text``."""
    outline: tuple[Point, ...]
    """Absolute pixel vertices after rotation and layer offset (the position alone for a point)."""
    gid: int = 0
    """The tile of a tile object, flip flags cleared (0 for other shapes)."""
    properties: Properties = field(default_factory=dict)
    flips: int = 0
    """A tile object's flip flags (:data:`FLIP_HORIZONTAL` | :data:`FLIP_VERTICAL` | :data:`FLIP_DIAGONAL`)."""
    anchor: Point = (0.0, 0.0)
    """Absolute pixel position (``x``, ``y`` plus the layer offset): the point it is rotated about."""
    size: tuple[float, float] = (0.0, 0.0)
    """Width and height in pixels as placed (for a tile object: its drawn size)."""
    rotation: float = 0.0
    """Degrees clockwise on screen about :attr:`anchor`."""
    align: Point = (0.0, 1.0)
    """Where in a tile object's box its anchor lies, as fractions of width and height (bottom-left)."""

    @property
    def closed(self) -> bool:
        """Whether the object encloses an area (rectangle, polygon, ellipse, tile)."""
        return self.shape in ("rectangle", "polygon", "ellipse", "tile") and len(self.outline) >= 3


@dataclass(frozen=True)
class TileInfo:
    """What a tileset says about one tile."""

    kind: str
    """The tile's class (``type`` before Tiled 1.9)."""
    properties: Properties
    shapes: tuple[TiledObject, ...]
    """Collision shapes drawn in the tile (Tiled's tile collision editor), relative to its top-left corner."""
    tileset: str
    size: tuple[float, float] = (0.0, 0.0)
    """The tile's width and height in pixels: its own image's in a collection of images, else the
    tileset's tile size; ``(0, 0)`` when an old file gives neither."""


@dataclass(frozen=True)
class TileLayer:
    """A tile layer: which global tile id sits in which cell."""

    name: str
    path: tuple[str, ...]
    """Names of the enclosing group layers and this layer, outermost first."""
    properties: Properties
    kind: str
    offset: Point
    visible: bool
    cols: np.ndarray
    rows: np.ndarray
    gids: np.ndarray
    """Column, row and global tile id (flip flags cleared) of every non-empty cell."""
    flips: np.ndarray | None = None
    """Each cell's flip flags (as :func:`split_gid` gives them), or ``None`` when no tile is flipped."""


@dataclass(frozen=True)
class ObjectLayer:
    """An object layer."""

    name: str
    path: tuple[str, ...]
    properties: Properties
    kind: str
    visible: bool
    objects: tuple[TiledObject, ...]


@dataclass(frozen=True)
class TiledMap:
    """The parts of a Tiled map a level is built from."""

    tile_width: float
    tile_height: float
    size: tuple[int, int]
    """``(width, height)`` in tiles as the map declares it (nominal for an infinite map)."""
    tile_layers: tuple[TileLayer, ...]
    object_layers: tuple[ObjectLayer, ...]
    tiles: dict[int, TileInfo]
    """Tiles the tilesets say something about, by global id."""
    notes: tuple[str, ...] = ()
    """Things the reader could not use (a missing tileset file), for the summary."""
    image_sizes: dict[int, tuple[float, float]] = field(default_factory=dict)
    """Tiles of collections of images, by global id: each image's size in pixels (``(0, 0)``: not given)."""
    missing_tilesets: tuple[str, ...] = ()
    """External tileset files that were not found (their tiles' marks are unknown)."""
    warnings: tuple[str, ...] = ()
    """Things the reader had to guess that may change the walls, one line each."""
    properties: Properties = field(default_factory=dict)
    """The map's own custom properties (``gravity``: a side view)."""


def check_number(value: Any, where: str, *, limit: float = MAX_COORDINATE) -> float:
    """``value`` as a float, or a :class:`LevelError` if it is not a finite number within ``limit``."""
    if isinstance(value, str):
        # TMX attributes reach here as text when pytiled-parser leaves them alone.
        try:
            value = float(value)
        except ValueError:
            raise LevelError(f"{where} must be a number, not {excerpt(value)}") from None
    try:
        return finite_number(value, magnitude=limit)
    except NumberError as error:
        raise LevelError(f"{where} {error}") from None


def _rotated(points: list[Point], x: float, y: float, degrees: float, offset: Point) -> tuple[Point, ...]:
    """Object-relative points rotated clockwise on screen (y down) about the object's origin, made absolute."""
    # Quarter turns are exact, so rectangles on the tile grid stay on it.
    quarter = {0: (1.0, 0.0), 90: (0.0, 1.0), 180: (-1.0, 0.0), 270: (0.0, -1.0)}.get(int(degrees) % 360)
    if quarter is not None and float(degrees).is_integer():
        cos, sin = quarter
    else:
        cos, sin = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return tuple((x + dx * cos - dy * sin + offset[0], y + dx * sin + dy * cos + offset[1]) for dx, dy in points)


def _relative_outline(
    shape: str, width: float, height: float, points: list[Point], align: Point = (0.0, 1.0)
) -> list[Point]:
    """Object-relative outline of a shape before rotation."""
    if shape in ("polygon", "polyline"):
        return points
    if shape == "point":
        return [(0.0, 0.0)]
    if shape == "tile":
        # Tile objects hang from their anchor: the bottom-left corner unless the tileset aligns them otherwise.
        left, top = -align[0] * width, -align[1] * height
        return [(left, top), (left + width, top), (left + width, top + height), (left, top + height)]
    if shape == "ellipse":
        steps = 32
        return [
            (width / 2 * (1 + math.cos(2 * math.pi * k / steps)), height / 2 * (1 + math.sin(2 * math.pi * k / steps)))
            for k in range(steps)
        ]
    return [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)]


def object_outline(
    shape: str,
    x: float,
    y: float,
    width: float,
    height: float,
    rotation: float,
    points: list[Point],
    offset: Point,
    align: Point = (0.0, 1.0),
) -> tuple[Point, ...]:
    """Absolute pixel outline of an object: its shape, rotated about its origin, moved by the layer offset."""
    return _rotated(_relative_outline(shape, width, height, points, align), x, y, rotation, offset)


def split_gid(raw: int) -> tuple[int, int]:
    """A stored global tile id as ``(gid, flips)``: the tile, and its flip flags shifted down to bits 2-0.

    Tiled keeps the horizontal, vertical and diagonal flips in bits 31, 30 and 29 (and bit 28 for
    hexagonal maps); they are never part of the tile's id.

    >>> split_gid(2147483650), split_gid(3)
    ((2, 4), (3, 0))
    """
    return raw & GID_MASK, (raw >> 29) & 7


def flipped(points: np.ndarray, flips: int) -> np.ndarray:
    """Points in a tile's unit square (``u, v`` in 0-1, y down) flipped as Tiled draws the tile: the
    diagonal flip (swap x and y) first, then the horizontal and the vertical."""
    out = np.array(points, dtype=float).reshape(-1, 2)
    if flips & FLIP_DIAGONAL:
        out = out[:, ::-1].copy()
    if flips & FLIP_HORIZONTAL:
        out[:, 0] = 1.0 - out[:, 0]
    if flips & FLIP_VERTICAL:
        out[:, 1] = 1.0 - out[:, 1]
    return out


def tile_outline(item: TiledObject, points: np.ndarray, tile_size: tuple[float, float]) -> np.ndarray:
    """Pixel points drawn inside a tile (relative to its image's top-left corner, in a ``tile_size`` tile)
    placed where tile object ``item`` draws that tile: flipped, scaled to the object's size, moved to its
    anchor and rotated about it, as Tiled does."""
    width, height = item.size
    unit = np.asarray(points, dtype=float).reshape(-1, 2) / np.array(
        [tile_size[0] or width or 1.0, tile_size[1] or height or 1.0]
    )
    local = (flipped(unit, item.flips) - np.asarray(item.align)) * np.array([width, height])
    placed = _rotated([(float(x), float(y)) for x, y in local], *item.anchor, item.rotation, (0.0, 0.0))
    return np.asarray(placed, dtype=float).reshape(-1, 2)


def decode_tile_data(raw: Any, encoding: str | None, compression: str | None, count: int, where: str) -> np.ndarray:
    """Global tile ids as stored (flip flags kept: see :func:`split_gid`) of one layer's or chunk's data,
    as ``int64 (count,)``.

    ``encoding`` is ``csv`` (text or, in JSON, a list of numbers), ``base64`` or ``None`` (a list of ids:
    TMX ``<tile gid>`` elements or a JSON array). Compressed data is inflated no further than ``count``
    tiles, so a tiny file cannot unpack to gigabytes.
    """
    values: np.ndarray
    try:
        if encoding == "csv" and isinstance(raw, str):
            text = raw.strip().rstrip(",")
            values = np.array([int(value) for value in text.split(",")], dtype=np.int64) if text else np.zeros(0)
        elif encoding == "base64":
            if not isinstance(raw, str):
                raise LevelError(f"{where}: base64 tile data must be a string, not a {type(raw).__name__}")
            packed = base64.b64decode(raw.strip(), validate=True)
            if compression in ("zlib", "gzip"):
                inflater = zlib.decompressobj(wbits=15 if compression == "zlib" else 31)
                packed = inflater.decompress(packed, count * 4 + 4)
            if len(packed) % 4:
                raise ArgumentError("not whole 32-bit tile ids")
            values = np.frombuffer(packed, dtype="<u4").astype(np.int64)
        elif isinstance(raw, list) and all(isinstance(value, int) and not isinstance(value, bool) for value in raw):
            values = np.array(raw, dtype=np.int64) if raw else np.zeros(0, dtype=np.int64)
        else:
            raise ArgumentError("not a list of tile ids")
    except (ValueError, TypeError, OverflowError, zlib.error, EOFError):
        raise LevelError(f"{where}: tile data is not valid {encoding or 'tile id list'} data") from None
    if values.size and (values.min() < 0 or values.max() >= 2**32):
        raise LevelError(f"{where}: tile ids must be between 0 and 2**32 - 1")
    if values.size != count:
        raise LevelError(f"{where}: tile data has {values.size} tiles, expected {count}")
    return values.astype(np.int64)
