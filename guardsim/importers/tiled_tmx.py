"""Reading TMX maps (Tiled's XML) with pytiled-parser's TMX parsers, part by part."""

from __future__ import annotations

import functools
import math
from typing import Any
from xml.etree import ElementTree

from pytiled_parser.layer import ObjectLayer as PtObjectLayer
from pytiled_parser.parsers.tmx import layer as tmx_layer
from pytiled_parser.parsers.tmx import properties as tmx_properties
from pytiled_parser.parsers.tmx import tiled_object as tmx_object

from guardsim.errors import LevelError
from guardsim.importers.source import display_name, excerpt
from guardsim.importers.tiled_data import Point, Properties, TiledMap, decode_tile_data
from guardsim.importers.tiled_defaults import layer_shell, tmx_objects_defaults
from guardsim.importers.tiled_parts import (
    COMPRESSIONS,
    MAX_GROUP_DEPTH,
    TILE_ENCODINGS,
    Blocks,
    MapReader,
    properties_of,
    why,
    word,
)

__all__ = ["TmxReader"]


class TmxReader(MapReader):
    """Reads a TMX map."""

    def read(self, root: ElementTree.Element) -> TiledMap:
        if root.tag == "tileset":
            raise self.error("", "a tileset, not a map: not a Tiled map")
        if root.tag != "map":
            raise self.error("", f"the root element is <{excerpt(root.tag, 30)}>, not <map>: not a Tiled map")
        self.check_orientation(root.get("orientation"))
        self.infinite = root.get("infinite") == "1"
        own = root.find("properties")
        if own is not None:
            self.read_properties(lambda: tmx_properties.parse(own))
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
                shell = layer_shell(element)
                common = self.call(where, functools.partial(tmx_layer.parse, shell, "utf-8", self.folder))
                shift = (
                    offset[0] + self.number(element.get("offsetx"), f"{where} offsetx", 0.0),
                    offset[1] + self.number(element.get("offsety"), f"{where} offsety", 0.0),
                )
                shown = visible and bool(common.visible)
                properties = {**inherited, **properties_of(common)}
                if element.tag == "group":
                    if depth + 1 > MAX_GROUP_DEPTH:
                        raise self.error(where, f"group layers nested more than {MAX_GROUP_DEPTH} deep")
                    pending.append((element, (*path, name), properties, shift, shown, depth + 1))
                elif element.tag == "layer":
                    blocks = self.tmx_tile_data(element, where)
                    self.add_tile_layer(common, (*path, name), inherited, shift, shown, blocks)
                elif element.tag == "objectgroup":
                    layer = self.tmx_object_layer(self.templates.tmx(element, where), where)
                    self.add_object_layer(layer, (*path, name), inherited, shift, shown, where)
            stack.extend(reversed(pending))
        return self.result(root.get("tilewidth"), root.get("tileheight"), root.get("width"), root.get("height"))

    def tmx_object_layer(self, element: ElementTree.Element, where: str) -> PtObjectLayer:
        """The object layer parsed by pytiled-parser; on failure, the first object it fails on is named."""
        filled = tmx_objects_defaults(element)
        for item in filled.findall("object"):
            for tag in ("polygon", "polyline"):
                child = item.find(tag)
                if child is not None:
                    self.check_points(child.get("points", ""), f"{where} object {word(item.get('id'))} {tag}")
        try:
            layer = tmx_layer.parse(filled, "utf-8", self.folder)
        except LevelError:
            raise
        except Exception as error:  # see call()
            for item in filled.findall("object"):
                self.call(
                    f"{where} object {word(item.get('id'))}",
                    functools.partial(tmx_object.parse, item, "utf-8", self.folder),
                )
            raise self.error(where, why(error)) from None
        if not isinstance(layer, PtObjectLayer):
            raise self.error(where, "not an object layer")
        return layer

    def check_points(self, text: str, where: str) -> None:
        """A ``points`` list is pairs ``x,y`` of finite numbers separated by spaces (Tiled's own format);
        anything else is refused here rather than guessed into a shape."""
        pairs = text.split()
        if not pairs:
            raise self.error(where, "points is empty")
        for index, pair in enumerate(pairs):
            parts = pair.split(",")
            if len(parts) != 2:
                raise self.error(where, f"point {index + 1} is {word(pair)}, not x,y")
            for part in parts:
                try:
                    value = float(part)
                except ValueError:
                    raise self.error(where, f"point {index + 1} is {word(pair)}, not two numbers") from None
                if not math.isfinite(value):
                    raise self.error(where, f"point {index + 1} is {word(pair)}, not two finite numbers")

    def tmx_tile_data(self, element: ElementTree.Element, where: str) -> Blocks:
        data = element.find("data")
        if data is None:
            return []
        encoding, compression = data.get("encoding"), data.get("compression")
        if encoding not in TILE_ENCODINGS:
            raise self.error(where, f"tile data encoding {word(encoding)} is not one Tiled writes (csv or base64)")
        if compression not in COMPRESSIONS:
            raise self.error(where, f"{word(compression)} compression is not supported (save as CSV, zlib or gzip)")
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
                raw = [
                    self.stored_gid(tile.get("gid"), f"{where} tile gid") if tile.get("gid") is not None else 0
                    for tile in part.findall("tile")
                ]
            blocks.append((x, y, width, decode_tile_data(raw, encoding, compression, width * height, here)))
        return blocks

    # -- JSON ---------------------------------------------------------------------------------------
