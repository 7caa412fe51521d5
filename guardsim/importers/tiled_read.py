"""Reading Tiled maps (TMX and Tiled JSON) with pytiled-parser, inside guardsim's input limits.

pytiled-parser (the Arcade project's Tiled reader) turns layers, objects (with their templates),
properties and tilesets (with tile classes and collision shapes) into typed objects. guardsim calls it
part by part rather than through ``pytiled_parser.parse_map``, because of what that entry point does not
do for untrusted files:

* it opens files itself, with no byte cap and no guard against a FIFO or ``/dev/zero``; here every map,
  tileset and template is read through :func:`guardsim.importers.source.read_capped_bytes` first;
* it inflates zlib/gzip tile data with no cap, and stores tiles as nested Python lists, so a 20 KB file
  can become gigabytes: tile data is decoded here (:func:`~guardsim.importers.tiled_data.decode_tile_data`),
  after the declared size has been checked against ``max_cells``;
* it reads ``<data encoding="hex">`` as base64, and recurses once per group layer: encodings are
  checked, and groups are walked here without recursion under a depth cap;
* it raises ``KeyError``/``ValueError``/``AttributeError`` with no file or place, and requires every
  attribute recent Tiled versions write (old maps without ``infinite`` or ``tilecount`` fail): each part
  is given Tiled's documented defaults, and any exception becomes one :class:`LevelError` naming the
  file, the layer and the object.
"""

from __future__ import annotations

import copy
import functools
import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar, cast
from xml.etree import ElementTree

import numpy as np
import pytiled_parser.tiled_object as pto
from pytiled_parser.layer import Layer as PtLayer
from pytiled_parser.layer import ObjectLayer as PtObjectLayer
from pytiled_parser.parsers.json import layer as json_layer
from pytiled_parser.parsers.json import tiled_object as json_object
from pytiled_parser.parsers.json import tileset as json_tileset
from pytiled_parser.parsers.tmx import layer as tmx_layer
from pytiled_parser.parsers.tmx import tiled_object as tmx_object
from pytiled_parser.parsers.tmx import tileset as tmx_tileset
from pytiled_parser.tileset import Tileset

from guardsim.errors import LevelError
from guardsim.importers.source import (
    display_name,
    excerpt,
    parse_json_bytes,
    parse_xml_bytes,
    read_capped_bytes,
)
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
    decode_tile_data,
    object_outline,
)
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES

__all__ = ["MAX_GROUP_DEPTH", "read_tiled"]

#: Deepest nesting of group layers read.
MAX_GROUP_DEPTH = 50
_TILE_ENCODINGS = (None, "csv", "base64")
_COMPRESSIONS = (None, "", "zlib", "gzip")
T = TypeVar("T")


def read_tiled(
    path: str | os.PathLike[str],
    *,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    max_cells: int = DEFAULT_MAX_CELLS,
    cells_per_tile: float = 1.0,
) -> TiledMap:
    """Read a TMX or Tiled JSON map (told apart by content) with its external tilesets and templates.

    ``max_cells`` (with ``cells_per_tile``, the level cells one tile becomes) caps the tiles a layer may
    declare, checked before any tile data is decoded.
    """
    data = read_capped_bytes(path, max_file_bytes=max_file_bytes)
    reader = _Reader(Path(path), max_file_bytes, max_cells, cells_per_tile)
    if data.lstrip()[:1] == b"<":
        return reader.tmx(parse_xml_bytes(data, reader.source))
    return reader.json(parse_json_bytes(data, reader.source))


def _why(error: BaseException) -> str:
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


class _Reader:
    """One map being read: its file, limits, tilesets so far and notes."""

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
        self.checked_files: set[Path] = set()
        self.infinite = False

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
            raise self.error(where, _why(error)) from None

    def number(self, value: Any, where: str, default: float | None = None) -> float:
        if value is None and default is not None:
            return default
        return check_number(value, f"{self.source}: {where}")

    def integer(self, value: Any, where: str, default: int | None = None) -> int:
        number = self.number(value, where, None if default is None else float(default))
        if not number.is_integer() or not -(2**31) <= number < 2**32:
            raise self.error(where, f"must be a whole number within 32 bits, not {excerpt(value)}")
        return int(number)

    def read_file(self, name: str, what: str) -> tuple[Path, bytes] | None:
        """An external file's bytes (tileset, template), or ``None`` with a note if it is missing."""
        path = self.folder / name
        if not path.exists():
            self.notes.append(f"{what} {display_name(name)} not found: left out")
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
            tuple(self.notes),
        )

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
                properties = dict(tile.properties or {})
                if tile.class_ or properties or shapes:
                    size = (float(tileset.tile_width or 0), float(tileset.tile_height or 0))
                    infos[firstgid + int(tile_id)] = TileInfo(
                        str(tile.class_ or ""), properties, shapes, tileset.name, size
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
        gid = 0
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
            gid = self.integer(item.gid, f"{where} gid") & GID_MASK
        return TiledObject(
            self.integer(item.id, f"{where} id", 0),
            str(item.name or ""),
            str(item.class_ or ""),
            shape,
            object_outline(shape, x, y, width, height, rotation, points, offset),
            gid,
            dict(item.properties or {}),
        )

    def load_tileset(self, firstgid: int, external: str | None, embedded: Any, where: str) -> None:
        """A tileset embedded in the map (an element or a dict) or in the ``external`` file beside it."""
        folder = self.folder
        if external:
            found = self.read_file(external, "tileset")
            if found is None:
                return
            path, data = found
            folder = path.parent
            embedded = (
                parse_xml_bytes(data, display_name(path))
                if data.lstrip()[:1] == b"<"
                else parse_json_bytes(data, display_name(path))
            )
        if isinstance(embedded, ElementTree.Element):
            element = _tmx_tileset_defaults(embedded)
            self.tilesets[firstgid] = self.call(where, lambda: tmx_tileset.parse(element, firstgid, "utf-8", folder))
        else:
            raw = _json_tileset_defaults(embedded)
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
        blocks: list[tuple[int, int, int, np.ndarray]],
    ) -> None:
        """``blocks`` are ``(x, y, width, gids)`` of the whole layer or of each chunk."""
        cols, rows, gids = [], [], []
        for x, y, width, values in blocks:
            index = np.flatnonzero(values)
            cols.append(x + index % max(width, 1))
            rows.append(y + index // max(width, 1))
            gids.append(values[index])
        joined = [np.concatenate(part) if part else np.zeros(0, dtype=np.int64) for part in (cols, rows, gids)]
        properties = {**inherited, **dict(layer.properties or {})}
        self.tile_layers.append(
            TileLayer(layer.name, path, properties, str(layer.class_ or ""), offset, visible, *joined)
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
        objects = tuple(self.template_gid(item) for item in layer.tiled_objects)
        self.object_layers.append(
            ObjectLayer(
                layer.name,
                path,
                {**inherited, **dict(layer.properties or {})},
                str(layer.class_ or ""),
                visible,
                tuple(self.convert_object(item, offset, f"{where} object") for item in objects),
            )
        )

    def template_gid(self, item: pto.TiledObject) -> pto.TiledObject:
        """A tile object from a template: its gid counted in the map's tilesets (as parse_map does)."""
        new = getattr(item, "new_tileset", None)
        if isinstance(item, pto.Tile) and new is not None:
            name = new.get("name") if isinstance(new, (dict, ElementTree.Element)) else None
            match = next((ts for ts in self.tilesets.values() if ts.name == name), None)
            if match is not None:
                item.gid = item.gid + match.firstgid - 1
            item.new_tileset = None
        return item

    def check_templates(self, uses: list[tuple[Any, str]], where: str) -> None:
        """Templates (and their tilesets) pass the file rules before pytiled-parser opens them.

        ``uses`` are ``(object id, template file)`` pairs of one layer.
        """
        for identifier, name in uses:
            path = self.folder / name
            if path in self.checked_files:
                continue
            if not path.is_file():
                raise self.error(f"{where} object {identifier}", f"template {display_name(name)} not found")
            self.checked_files.add(path)
            data = read_capped_bytes(path, max_file_bytes=self.max_file_bytes, kind="template")
            source = display_name(path)
            if data.lstrip()[:1] == b"<":
                root = parse_xml_bytes(data, source)
                tileset = root.find("tileset")
                inner = tileset.get("source") if tileset is not None else None
            else:
                value = parse_json_bytes(data, source)
                tileset = value.get("tileset") if isinstance(value, dict) else None
                inner = tileset.get("source") if isinstance(tileset, dict) else None
            if inner:
                read_capped_bytes(path.parent / str(inner), max_file_bytes=self.max_file_bytes, kind="tileset")

    # -- TMX ----------------------------------------------------------------------------------------
    def tmx(self, root: ElementTree.Element) -> TiledMap:
        if root.tag == "tileset":
            raise self.error("", "a tileset, not a map: not a Tiled map")
        if root.tag != "map":
            raise self.error("", f"the root element is <{excerpt(root.tag, 30)}>, not <map>: not a Tiled map")
        self.check_orientation(root.get("orientation"))
        self.infinite = root.get("infinite") == "1"
        for index, element in enumerate(root.findall("tileset")):
            firstgid = self.integer(element.get("firstgid"), f"tileset {index} firstgid")
            where = f"tileset {display_name(element.get('source') or element.get('name') or str(index))}"
            self.load_tileset(firstgid, element.get("source"), element, where)
        self.check_tile_count(
            self.integer(root.get("width"), "map width", 0), self.integer(root.get("height"), "map height", 0), "map"
        )
        stack: list[tuple[ElementTree.Element, tuple[str, ...], Properties, Point, bool, int]] = [
            (root, (), {}, (0.0, 0.0), True, 0)
        ]
        while stack:
            parent, path, inherited, offset, visible, depth = stack.pop()
            children = [child for child in parent if child.tag in ("layer", "objectgroup", "imagelayer", "group")]
            # Reversed onto the stack so that layers are read in file order.
            pending = []
            for element in children:
                name = element.get("name", "")
                where = f"layer {excerpt(name)}"
                shell = _shell(element)
                common = self.call(where, functools.partial(tmx_layer.parse, shell, "utf-8", self.folder))
                shift = (
                    offset[0] + self.number(element.get("offsetx"), f"{where} offsetx", 0.0),
                    offset[1] + self.number(element.get("offsety"), f"{where} offsety", 0.0),
                )
                shown = visible and bool(common.visible)
                properties = {**inherited, **dict(common.properties or {})}
                if element.tag == "group":
                    if depth + 1 > MAX_GROUP_DEPTH:
                        raise self.error(where, f"group layers nested more than {MAX_GROUP_DEPTH} deep")
                    pending.append((element, (*path, name), properties, shift, shown, depth + 1))
                elif element.tag == "layer":
                    blocks = self.tmx_tile_data(element, where)
                    self.add_tile_layer(common, (*path, name), inherited, shift, shown, blocks)
                elif element.tag == "objectgroup":
                    self.check_templates(
                        [(o.get("id"), o.get("template", "")) for o in element.findall("object") if o.get("template")],
                        where,
                    )
                    layer = self.tmx_object_layer(element, where)
                    self.add_object_layer(layer, (*path, name), inherited, shift, shown, where)
            stack.extend(reversed(pending))
        return self.result(root.get("tilewidth"), root.get("tileheight"), root.get("width"), root.get("height"))

    def tmx_object_layer(self, element: ElementTree.Element, where: str) -> PtObjectLayer:
        """The object layer parsed by pytiled-parser; on failure, the first object it fails on is named."""
        filled = _tmx_objects_defaults(element)
        try:
            layer = tmx_layer.parse(filled, "utf-8", self.folder)
        except LevelError:
            raise
        except Exception as error:  # see call()
            for item in filled.findall("object"):
                self.call(
                    f"{where} object {_word(item.get('id'))}",
                    functools.partial(tmx_object.parse, item, "utf-8", self.folder),
                )
            raise self.error(where, _why(error)) from None
        if not isinstance(layer, PtObjectLayer):
            raise self.error(where, "not an object layer")
        return layer

    def tmx_tile_data(self, element: ElementTree.Element, where: str) -> list[tuple[int, int, int, np.ndarray]]:
        data = element.find("data")
        if data is None:
            return []
        encoding, compression = data.get("encoding"), data.get("compression")
        if encoding not in _TILE_ENCODINGS:
            raise self.error(where, f"tile data encoding {_word(encoding)} is not one Tiled writes (csv or base64)")
        if compression not in _COMPRESSIONS:
            raise self.error(where, f"{_word(compression)} compression is not supported (save as CSV, zlib or gzip)")
        chunks = data.findall("chunk")
        parts = chunks if chunks else [data]
        blocks = []
        total = 0
        for part in parts:
            width = self.integer(part.get("width", element.get("width")), f"{where} width")
            height = self.integer(part.get("height", element.get("height")), f"{where} height")
            total += width * height
            self.check_tile_count(width, height, where)
            self.check_tile_count(total, 1, where)
            x = self.integer(part.get("x"), f"{where} chunk x", 0) if chunks else 0
            y = self.integer(part.get("y"), f"{where} chunk y", 0) if chunks else 0
            here = f"{self.source}: {where}" + (f" chunk ({x}, {y})" if chunks else "")
            if not chunks and self.infinite and not (part.text or "").strip() and not part.findall("tile"):
                continue  # Tiled writes an empty layer of an infinite map as an empty <data/>
            if encoding:
                raw: Any = part.text or ""
            else:
                raw = [self.integer(tile.get("gid"), f"{where} tile gid", 0) for tile in part.findall("tile")]
            blocks.append((x, y, width, decode_tile_data(raw, encoding, compression, width * height, here)))
        return blocks

    # -- JSON ---------------------------------------------------------------------------------------
    def json(self, root: Any) -> TiledMap:
        if not isinstance(root, dict) or ("orientation" not in root and root.get("type") != "map"):
            raise self.error("", 'not a Tiled JSON map (no "orientation" or "type": "map")')
        self.check_orientation(root.get("orientation"))
        for index, raw in enumerate(_dicts(root.get("tilesets", []), f"{self.source}: tilesets")):
            where = f"tilesets[{index}]"
            firstgid = self.integer(raw.get("firstgid"), f"{where}.firstgid")
            self.load_tileset(firstgid, str(raw["source"]) if "source" in raw else None, raw, where)
        self.check_tile_count(
            self.integer(root.get("width"), "width", 0), self.integer(root.get("height"), "height", 0), "map"
        )
        stack: list[tuple[list[dict[str, Any]], str, tuple[str, ...], Properties, Point, bool, int]] = [
            (_dicts(root.get("layers", []), f"{self.source}: layers"), "layers", (), {}, (0.0, 0.0), True, 0)
        ]
        while stack:
            layers, prefix, path, inherited, offset, visible, depth = stack.pop()
            pending = []
            for index, raw in enumerate(layers):
                name = str(raw.get("name", ""))
                where = f"{prefix}[{index}] ({excerpt(name)})"
                kind = raw.get("type")
                shell = {
                    key: value
                    for key, value in _json_layer_defaults(raw).items()
                    if key not in ("data", "chunks", "layers", "objects")
                }
                if kind == "objectgroup":
                    shell["objects"] = []
                elif kind == "group":
                    shell["layers"] = []
                elif kind == "tilelayer":
                    shell.pop("encoding", None)
                elif kind != "imagelayer":
                    continue
                common = self.call(where, functools.partial(json_layer.parse, cast(Any, shell), "utf-8", self.folder))
                shift = (
                    offset[0] + self.number(raw.get("offsetx"), f"{where}.offsetx", 0.0),
                    offset[1] + self.number(raw.get("offsety"), f"{where}.offsety", 0.0),
                )
                shown = visible and bool(common.visible)
                properties = {**inherited, **dict(common.properties or {})}
                if kind == "group":
                    if depth + 1 > MAX_GROUP_DEPTH:
                        raise self.error(where, f"group layers nested more than {MAX_GROUP_DEPTH} deep")
                    pending.append(
                        (
                            _dicts(raw.get("layers", []), f"{self.source}: {where}.layers"),
                            f"{where}.layers",
                            (*path, name),
                            properties,
                            shift,
                            shown,
                            depth + 1,
                        )
                    )
                elif kind == "tilelayer":
                    blocks = self.json_tile_data(raw, where)
                    self.add_tile_layer(common, (*path, name), inherited, shift, shown, blocks)
                elif kind == "objectgroup":
                    raw_objects = _dicts(raw.get("objects", []), f"{self.source}: {where}.objects")
                    self.check_templates(
                        [(o.get("id"), str(o["template"])) for o in raw_objects if o.get("template")],
                        f"{where}.objects",
                    )
                    objects = [
                        self.call(
                            f"{where}.objects[{number}]",
                            functools.partial(
                                json_object.parse, cast(Any, _json_object_defaults(item)), "utf-8", self.folder
                            ),
                        )
                        for number, item in enumerate(raw_objects)
                    ]
                    layer = PtObjectLayer(
                        tiled_objects=objects,
                        **{k: v for k, v in common.__dict__.items() if k != "tiled_objects" and k != "draw_order"},
                    )
                    self.add_object_layer(layer, (*path, name), inherited, shift, shown, where + ".objects")
            stack.extend(reversed(pending))
        return self.result(root.get("tilewidth"), root.get("tileheight"), root.get("width"), root.get("height"))

    def json_tile_data(self, raw: dict[str, Any], where: str) -> list[tuple[int, int, int, np.ndarray]]:
        encoding = raw.get("encoding", "csv")
        compression = raw.get("compression") or None
        if encoding not in ("csv", "base64"):
            raise self.error(where, f"tile data encoding {_word(encoding)} is not one Tiled writes (csv or base64)")
        if compression not in _COMPRESSIONS:
            raise self.error(where, f"{_word(compression)} compression is not supported (save as CSV, zlib or gzip)")
        chunks = raw.get("chunks")
        parts = _dicts(chunks, f"{self.source}: {where}.chunks") if chunks is not None else [raw]
        blocks = []
        total = 0
        for index, part in enumerate(parts):
            here = f"{where}.chunks[{index}]" if chunks is not None else where
            width = self.integer(part.get("width"), f"{here}.width")
            height = self.integer(part.get("height"), f"{here}.height")
            total += width * height
            self.check_tile_count(width, height, here)
            self.check_tile_count(total, 1, where)
            x = self.integer(part.get("x"), f"{here}.x", 0) if chunks is not None else 0
            y = self.integer(part.get("y"), f"{here}.y", 0) if chunks is not None else 0
            data = part.get("data", [])
            kind = "base64" if encoding == "base64" else None
            blocks.append(
                (x, y, width, decode_tile_data(data, kind, compression, width * height, f"{self.source}: {here}.data"))
            )
        return blocks


def _word(value: Any) -> str:
    """A short identifier as it is (``zstd``), anything else as a quoted excerpt."""
    return value if isinstance(value, str) and re.fullmatch(r"[A-Za-z0-9_.-]{1,20}", value) else excerpt(value)


def _dicts(value: Any, where: str) -> list[dict[str, Any]]:
    if not isinstance(value, list) or not all(isinstance(item, dict) for item in value):
        raise LevelError(f"{where} must be a list of objects")
    return value


def _shell(element: ElementTree.Element) -> ElementTree.Element:
    """A layer element with its attributes and properties only (no tile data, objects or child layers)."""
    shell = ElementTree.Element(element.tag, dict(element.attrib))
    properties = element.find("properties")
    if properties is not None:
        shell.append(properties)
    if element.tag == "layer":
        shell.attrib.setdefault("width", "0")
        shell.attrib.setdefault("height", "0")
    if element.tag == "imagelayer":
        shell.append(ElementTree.Element("image", {"source": ""}))
    if "offsetx" in shell.attrib or "offsety" in shell.attrib:
        shell.attrib.setdefault("offsetx", "0")
        shell.attrib.setdefault("offsety", "0")
    return shell


def _tmx_objects_defaults(element: ElementTree.Element) -> ElementTree.Element:
    """An object layer with Tiled's defaults filled in where an object leaves them out."""
    layer = copy.deepcopy(element)
    if "offsetx" in layer.attrib or "offsety" in layer.attrib:
        layer.attrib.setdefault("offsetx", "0")
        layer.attrib.setdefault("offsety", "0")
    for item in layer.findall("object"):
        for key in ("id", "x", "y"):
            item.attrib.setdefault(key, "0")
        if "width" in item.attrib or "height" in item.attrib:
            item.attrib.setdefault("width", "0")
            item.attrib.setdefault("height", "0")
        for tag in ("polygon", "polyline"):
            child = item.find(tag)
            if child is not None:
                # pytiled-parser splits on single spaces; Tiled writes single spaces, hand edits may not.
                child.attrib["points"] = " ".join(child.get("points", "").split())
    return layer


def _tmx_tileset_defaults(element: ElementTree.Element) -> ElementTree.Element:
    """A tileset element with the attributes old Tiled files leave out."""
    tileset = copy.deepcopy(element)
    for key, default in (("name", ""), ("tilewidth", "1"), ("tileheight", "1"), ("tilecount", "0"), ("columns", "0")):
        tileset.attrib.setdefault(key, default)
    for tile in tileset.findall("tile"):
        group = tile.find("objectgroup")
        if group is not None:
            tile.remove(group)
            tile.append(_tmx_objects_defaults(group))
    return tileset


def _json_tileset_defaults(raw: Any) -> dict[str, Any]:
    if not isinstance(raw, dict):
        raise LevelError("a JSON tileset must be an object")
    tileset = {"name": "", "tilecount": 0, "tilewidth": 1, "tileheight": 1, "spacing": 0, "margin": 0, **raw}
    tiles = tileset.get("tiles")
    if isinstance(tiles, list):
        fixed = []
        for tile in tiles:
            if isinstance(tile, dict) and isinstance(tile.get("objectgroup"), dict):
                group = dict(tile["objectgroup"])
                group = _json_layer_defaults({"type": "objectgroup", **group})
                group["objects"] = [
                    _json_object_defaults(item) for item in group.get("objects", []) if isinstance(item, dict)
                ]
                tile = {**tile, "objectgroup": group}
            fixed.append(tile)
        tileset["tiles"] = fixed
    return tileset


def _json_layer_defaults(raw: dict[str, Any]) -> dict[str, Any]:
    layer = {"name": "", "opacity": 1, "visible": True, "draworder": "topdown", **raw}
    if "offsetx" in layer or "offsety" in layer:
        layer.setdefault("offsetx", 0)
        layer.setdefault("offsety", 0)
    if "width" in layer or "height" in layer:
        layer.setdefault("width", 0)
        layer.setdefault("height", 0)
    return layer


def _json_object_defaults(raw: dict[str, Any]) -> dict[str, Any]:
    defaults = {"id": 0, "x": 0, "y": 0, "width": 0, "height": 0, "rotation": 0, "visible": True, "name": ""}
    return {**defaults, **raw}
