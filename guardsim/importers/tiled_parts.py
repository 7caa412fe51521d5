"""What the TMX and the JSON readers share: one map being read, within guardsim's limits.

:class:`MapReader` holds the file, the limits, the tilesets read so far and the layers found, and turns
pytiled-parser's objects into :mod:`guardsim.importers.tiled_data` records with every number checked.
Each pytiled-parser step runs through :meth:`MapReader.call`, so whatever it raises becomes one
:class:`LevelError` naming the file and the place.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar, cast
from xml.etree import ElementTree

import numpy as np
import pytiled_parser.tiled_object as pto
from pytiled_parser.layer import Layer as PtLayer
from pytiled_parser.layer import ObjectLayer as PtObjectLayer
from pytiled_parser.parsers.json import tileset as json_tileset
from pytiled_parser.parsers.tmx import tileset as tmx_tileset
from pytiled_parser.tileset import Tileset

from guardsim.errors import LevelError
from guardsim.importers.source import display_name, excerpt, parse_json_bytes, parse_xml_bytes, read_capped_bytes
from guardsim.importers.tiled_data import (
    GID_MASK,
    ObjectLayer,
    Point,
    Properties,
    TiledMap,
    TiledObject,
    TileInfo,
    TileLayer,
    check_number,
    object_outline,
    split_gid,
)
from guardsim.importers.tiled_defaults import json_tileset_defaults, tmx_tileset_defaults
from guardsim.importers.tiled_templates import Templates

__all__ = [
    "COMPRESSIONS",
    "MAX_GROUP_DEPTH",
    "TILE_ENCODINGS",
    "Blocks",
    "MapReader",
    "dicts",
    "properties_of",
    "text",
    "word",
]

#: Deepest nesting of group layers read.
MAX_GROUP_DEPTH = 50
#: Tile data encodings Tiled writes (``None``: XML ``<tile>`` elements or a JSON list), and compressions read.
TILE_ENCODINGS = (None, "csv", "base64")
COMPRESSIONS = (None, "", "zlib", "gzip")
#: ``(x, y, width, gids)`` of a whole tile layer or of each of its chunks.
Blocks = list[tuple[int, int, int, np.ndarray]]
T = TypeVar("T")
#: Where a tile object's anchor lies in its box for each ``objectalignment`` of its tileset (fractions of
#: width and height); orthogonal maps' default ("unspecified") is the bottom-left corner.
ALIGNMENTS = {
    "topleft": (0.0, 0.0),
    "top": (0.5, 0.0),
    "topright": (1.0, 0.0),
    "left": (0.0, 0.5),
    "center": (0.5, 0.5),
    "right": (1.0, 0.5),
    "bottomleft": (0.0, 1.0),
    "bottom": (0.5, 1.0),
    "bottomright": (1.0, 1.0),
}


def why(error: BaseException) -> str:
    """A short phrase for an exception raised inside pytiled-parser."""
    if isinstance(error, KeyError):
        return f"missing {excerpt(error.args[0] if error.args else '?')}"
    if isinstance(error, RecursionError):
        return "nested too deeply"
    if isinstance(error, (ValueError, OverflowError)):
        # float('x'), int('1.5'), round(float('inf')): a number attribute that is not one.
        match = re.search(r"(?:float|int\(\) with base 10|integer): ('.*')$", str(error))
        if match:
            return f"not a number ({excerpt(match.group(1)[1:-1])})"
        if isinstance(error, OverflowError) or "NaN" in str(error):
            return "a number is not finite"
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    return f"{type(error).__name__}: {text[:80]}"


class MapReader:
    """One map being read: its file, limits, tilesets so far, layers and notes; subclassed per format."""

    def __init__(self, path: Path, max_file_bytes: int, max_cells: int, cells_per_tile: float) -> None:
        self.path = path
        self.source = display_name(path)
        self.folder = path.parent
        self.max_file_bytes = max_file_bytes
        self.max_tiles = max(1, int(max_cells / max(cells_per_tile, 1e-12)))
        self.max_cells = max_cells
        self.tilesets: dict[int, Tileset] = {}
        self.tile_layers: list[TileLayer] = []
        self.object_layers: list[ObjectLayer] = []
        self.notes: list[str] = []
        self.warnings: list[str] = []
        self.missing_tilesets: list[str] = []
        self.tileset_files: dict[Path, int] = {}
        """External tileset files (resolved) -> firstgid, for tile templates."""
        self.templates = Templates(self.source, self.folder, max_file_bytes, self.tileset_files)
        self.infinite = False
        self.properties: Properties = {}
        """The map's own custom properties."""

    # -- shared -------------------------------------------------------------------------------------
    def error(self, where: str, message: str) -> LevelError:
        return LevelError(f"{self.source}: {where}: {message}" if where else f"{self.source}: {message}")

    def call(self, where: str, parse: Callable[[], T]) -> T:
        """Run one pytiled-parser step; any exception becomes a located :class:`LevelError`."""
        try:
            return parse()
        except LevelError:
            raise
        except Exception as error:  # pytiled-parser signals bad input with whatever its code hits
            raise self.error(where, why(error)) from None

    def read_properties(self, parse: Callable[[], Any]) -> None:
        """The map's own custom properties, read by ``parse``; only a hint (a side view's gravity), so
        properties that cannot be read are left out with a note rather than refusing the map."""
        try:
            self.properties = _properties(parse())
        except Exception:  # pytiled-parser signals bad input with whatever its code hits
            self.notes.append("the map's own custom properties could not be read: left out")

    def number(self, value: Any, where: str, default: float | None = None) -> float:
        if value is None and default is not None:
            return default
        return check_number(value, f"{self.source}: {where}")

    def integer(self, value: Any, where: str, default: int | None = None) -> int:
        number = self.number(value, where, None if default is None else float(default))
        if not number.is_integer() or not -(2**31) <= number < 2**32:
            raise self.error(where, f"must be a whole number within 32 bits, not {excerpt(value)}")
        return int(number)

    def stored_gid(self, value: Any, where: str) -> int:
        """A global tile id as stored, flip flags (bits 31-29) included: a whole number below 2**32."""
        number = check_number(value, f"{self.source}: {where}", limit=2.0**32)
        if not number.is_integer() or not 0 <= number < 2**32:
            raise self.error(where, f"must be a whole number from 0 to 2**32 - 1, not {excerpt(value)}")
        return int(number)

    def gid(self, value: Any, where: str) -> tuple[int, int]:
        """A stored global tile id as ``(gid, flips)``: flip flags are stripped, as Tiled does."""
        return split_gid(self.stored_gid(value, where))

    def read_file(self, name: str, what: str) -> tuple[Path, bytes] | None:
        """An external file's bytes (tileset, template), or ``None`` with a note if it is missing."""
        path = self.folder / name
        if not path.exists():
            self.notes.append(f"{what} {display_name(name)} not found: left out")
            if what == "tileset":
                self.missing_tilesets.append(display_name(name))
            return None
        return path, read_capped_bytes(path, max_file_bytes=self.max_file_bytes, kind=what)

    def check_tile_count(self, width: int, height: int, where: str) -> None:
        if width < 0 or height < 0:
            raise self.error(where, f"size {width} x {height} is negative")
        if width * height > self.max_tiles:
            raise self.error(
                where,
                f"{width} x {height} = {width * height} tiles is over the limit of {self.max_cells} cells "
                "(raise it with --max-cells)",
            )

    def check_orientation(self, orientation: Any) -> None:
        if orientation != "orthogonal":
            raise self.error("", f"orientation {excerpt(orientation)} is not supported (only orthogonal maps)")

    def result(self, tilewidth: Any, tileheight: Any, width: Any, height: Any) -> TiledMap:
        tile_width, tile_height = self.number(tilewidth, "tilewidth"), self.number(tileheight, "tileheight")
        if tile_width <= 0 or tile_height <= 0:
            raise self.error("", f"tilewidth and tileheight must be positive, not {tile_width:g} x {tile_height:g}")
        size = (self.integer(width, "width", 0), self.integer(height, "height", 0))
        return TiledMap(
            tile_width,
            tile_height,
            size,
            tuple(self.tile_layers),
            tuple(self.object_layers),
            self.tile_infos(),
            tuple(self.notes + self.templates.notes),
            self.image_sizes(),
            tuple(self.missing_tilesets),
            tuple(self.warnings),
            self.properties,
        )

    def tileset_of(self, gid: int) -> tuple[int, Tileset] | None:
        """The tileset holding global tile id ``gid`` (the one with the largest firstgid not above it)."""
        firsts = [first for first in self.tilesets if first <= gid]
        if not firsts:
            return None
        first = max(firsts)
        return first, self.tilesets[first]

    def tile_size(self, gid: int) -> tuple[float, float]:
        """A tile's size in pixels: its own image's in a collection of images, else its tileset's tile size;
        ``(0, 0)`` if neither is known (an old file's image without width and height)."""
        found = self.tileset_of(gid)
        if found is None:
            return (0.0, 0.0)
        first, tileset = found
        tile = (tileset.tiles or {}).get(gid - first)
        if tile is not None and tile.image is not None:
            width, height = (self.number(v, f"tile {gid} size", 0.0) for v in (tile.width, tile.height))
            return (width, height) if width > 0 and height > 0 else (0.0, 0.0)
        width = self.number(tileset.tile_width, f"tileset {text(tileset.name)!r} tilewidth", 0.0)
        height = self.number(tileset.tile_height, f"tileset {text(tileset.name)!r} tileheight", 0.0)
        return (width, height) if width > 0 and height > 0 else (0.0, 0.0)

    def image_sizes(self) -> dict[int, tuple[float, float]]:
        """Every tile of a collection of images (a tile with its own image) by global id, with its size."""
        return {
            first + int(tile_id): self.tile_size(first + int(tile_id))
            for first, tileset in self.tilesets.items()
            for tile_id, tile in (tileset.tiles or {}).items()
            if tile.image is not None and isinstance(tile_id, int)
        }

    def tile_infos(self) -> dict[int, TileInfo]:
        infos: dict[int, TileInfo] = {}
        for firstgid, tileset in self.tilesets.items():
            for tile_id, tile in (tileset.tiles or {}).items():
                where = f"tileset {tileset.name!r} tile {tile_id}"
                shapes: tuple[TiledObject, ...] = ()
                if tile.objects is not None and isinstance(tile.objects, PtObjectLayer):
                    shapes = tuple(
                        self.convert_object(item, (0.0, 0.0), f"{where} collision shape")
                        for item in tile.objects.tiled_objects
                    )
                properties = _properties(tile.properties)
                if tile.class_ or properties or shapes:
                    gid = firstgid + self.integer(tile_id, f"{where} id")
                    infos[gid] = TileInfo(
                        text(tile.class_), properties, shapes, text(tileset.name), self.tile_size(gid)
                    )
        return infos

    def convert_object(self, item: pto.TiledObject, offset: Point, where: str) -> TiledObject:
        where = f"{where} {item.id}"
        x = self.number(item.coordinates.x, f"{where} x")
        y = self.number(item.coordinates.y, f"{where} y")
        width = self.number(item.size.width, f"{where} width", 0.0)
        height = self.number(item.size.height, f"{where} height", 0.0)
        rotation = self.number(item.rotation, f"{where} rotation", 0.0)
        points: list[Point] = []
        gid = flips = 0
        align = (0.0, 1.0)
        shape = {
            pto.Ellipse: "ellipse",
            pto.Point: "point",
            pto.Polygon: "polygon",
            pto.Polyline: "polyline",
            pto.Text: "text",
            pto.Tile: "tile",
        }.get(type(item), "rectangle")
        if isinstance(item, (pto.Polygon, pto.Polyline)):
            points = [
                (self.number(p.x, f"{where} {shape} point"), self.number(p.y, f"{where} {shape} point"))
                for p in item.points
            ]
        if isinstance(item, pto.Tile):
            gid, flips = self.gid(item.gid, f"{where} gid")
            found = self.tileset_of(gid)
            if found is not None:
                align = ALIGNMENTS.get(text(found[1].alignment).lower(), align)
            if width <= 0 or height <= 0:
                # Old files leave out a tile object's size: it is drawn at its tile's size.
                width, height = self.tile_size(gid)
                if width <= 0 or height <= 0:
                    width, height = self._unknown_tile_size(gid, where)
        return TiledObject(
            self.integer(item.id, f"{where} id", 0),
            text(item.name),
            text(item.class_),
            shape,
            object_outline(shape, x, y, width, height, rotation, points, offset, align),
            gid,
            _properties(item.properties),
            flips,
            (x + offset[0], y + offset[1]),
            (width, height),
            rotation,
            align,
        )

    def _unknown_tile_size(self, gid: int, where: str) -> tuple[float, float]:
        """The size a tile object with no size of its own is drawn at when its tile's image gives none either:
        its tileset's tile size (the largest image, in a collection), with a warning."""
        found = self.tileset_of(gid)
        if found is None:
            self.warnings.append(f"{where} has no width or height and tile {gid} is in no tileset: left out")
            return (0.0, 0.0)
        tileset = found[1]
        width, height = float(tileset.tile_width or 0), float(tileset.tile_height or 0)
        self.warnings.append(
            f"{where} has no width or height, and tile {gid}'s image in tileset {text(tileset.name)!r} gives no "
            f"size either: drawn at the tileset's tile size, {width:g} x {height:g} pixels"
        )
        return (width, height)

    def load_tileset(self, firstgid: int, external: str | None, embedded: Any, where: str) -> None:
        """A tileset embedded in the map (an element or a dict) or in the ``external`` file beside it."""
        folder = self.folder
        if external:
            found = self.read_file(external, "tileset")
            if found is None:
                return
            path, data = found
            folder = path.parent
            self.tileset_files[path.resolve()] = firstgid
            embedded = (
                parse_xml_bytes(data, display_name(path))
                if data.lstrip()[:1] == b"<"
                else parse_json_bytes(data, display_name(path))
            )
        if isinstance(embedded, ElementTree.Element):
            element = tmx_tileset_defaults(embedded)
            self.tilesets[firstgid] = self.call(where, lambda: tmx_tileset.parse(element, firstgid, "utf-8", folder))
        else:
            try:
                raw = json_tileset_defaults(embedded)
            except LevelError as error:
                raise self.error(where, str(error)) from None
            self.tilesets[firstgid] = self.call(
                where, lambda: json_tileset.parse(cast(Any, raw), firstgid, "utf-8", folder)
            )

    def add_tile_layer(
        self,
        layer: PtLayer,
        path: tuple[str, ...],
        inherited: Properties,
        offset: Point,
        visible: bool,
        blocks: Blocks,
    ) -> None:
        """``blocks`` are ``(x, y, width, gids)`` of the whole layer or of each chunk."""
        cols, rows, gids = [], [], []
        for x, y, width, values in blocks:
            # Flip flags are never part of the tile's id; a cell with flags and no tile is empty.
            index = np.flatnonzero(values & GID_MASK)
            cols.append(x + index % max(width, 1))
            rows.append(y + index // max(width, 1))
            gids.append(values[index])
        joined = [np.concatenate(part) if part else np.zeros(0, dtype=np.int64) for part in (cols, rows, gids)]
        raw = joined[2]
        flips = (raw >> 29) & 7
        properties = {**inherited, **_properties(layer.properties)}
        self.tile_layers.append(
            TileLayer(
                text(layer.name),
                path,
                properties,
                text(layer.class_),
                offset,
                visible,
                joined[0],
                joined[1],
                raw & GID_MASK,
                flips if flips.any() else None,
            )
        )

    def add_object_layer(
        self,
        layer: PtObjectLayer,
        path: tuple[str, ...],
        inherited: Properties,
        offset: Point,
        visible: bool,
        where: str,
    ) -> None:
        objects = layer.tiled_objects
        self.object_layers.append(
            ObjectLayer(
                text(layer.name),
                path,
                {**inherited, **_properties(layer.properties)},
                text(layer.class_),
                visible,
                tuple(self.convert_object(item, offset, f"{where} object") for item in objects),
            )
        )


def text(value: Any) -> str:
    """A name or class as text; JSON lets a map hold anything there, and pytiled-parser passes it on."""
    return value if isinstance(value, str) else "" if value is None else excerpt(value)


def _properties(value: Any) -> Properties:
    """Custom properties with text names (JSON ones can be anything)."""
    return {str(key): item for key, item in value.items()} if isinstance(value, dict) else {}


def properties_of(layer: PtLayer) -> Properties:
    """A pytiled-parser layer's custom properties, names as text."""
    return _properties(layer.properties)


def word(value: Any) -> str:
    """A short identifier as it is (``zstd``), anything else as a quoted excerpt."""
    return value if isinstance(value, str) and re.fullmatch(r"[A-Za-z0-9_.-]{1,20}", value) else excerpt(value)


def dicts(value: Any, where: str) -> list[dict[str, Any]]:
    if not isinstance(value, list) or not all(isinstance(item, dict) for item in value):
        raise LevelError(f"{where} must be a list of objects")
    return value
