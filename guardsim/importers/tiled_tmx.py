"""Reading TMX maps and TSX tilesets (Tiled's XML formats)."""

from __future__ import annotations

from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np

from guardsim.errors import LevelError
from guardsim.importers.imported import read_source_bytes
from guardsim.importers.tiled_format import (
    GID_MASK,
    MapReader,
    ObjectLayer,
    Point,
    Properties,
    TiledMap,
    TiledObject,
    decode_tile_data,
    object_outline,
)

__all__ = ["TmxReader", "parse_xml", "read_tsx_tiles"]


def parse_xml(data: bytes, source: str) -> ElementTree.Element:
    try:
        root = ElementTree.fromstring(data)
    except ElementTree.ParseError as error:
        line, column = error.position
        raise LevelError(f"{source}: line {line} column {column + 1}: not well-formed XML") from None
    if root.tag not in ("map", "tileset"):
        raise LevelError(f"{source}: the root element is <{root.tag}>, not <map>: not a Tiled map")
    return root


def read_tsx_tiles(path: Path, firstgid: int) -> dict[int, Properties]:
    """Properties of the tiles of a TSX tileset file, by global id."""
    root = parse_xml(read_source_bytes(path), str(path))
    tiles: dict[int, Properties] = {}
    TmxReader(str(path), path.parent).add_tileset_tiles(root, firstgid, tiles)
    return tiles


class TmxReader(MapReader):
    """Reads a TMX map (or a TSX tileset's tiles)."""

    def map(self, root: ElementTree.Element) -> TiledMap:
        if root.tag != "map":
            raise LevelError(f"{self.source}: a tileset, not a map")
        self.check_orientation(root.get("orientation"))
        for tileset in root.findall("tileset"):
            firstgid = self.integer(tileset.get("firstgid"), "tileset firstgid")
            if tileset.get("source"):
                self.external_tileset(tileset.get("source", ""), firstgid)
            else:
                self.add_tileset_tiles(tileset, firstgid, self.tiles)
        self.layers(root, (), {}, (0.0, 0.0))
        return self.result(root.get("tilewidth"), root.get("tileheight"))

    def properties(self, element: ElementTree.Element) -> Properties:
        values: Properties = {}
        for item in element.findall("properties/property"):
            kind, text = item.get("type", "string"), item.get("value", item.text or "")
            if kind == "bool":
                values[item.get("name", "")] = text == "true"
            elif kind in ("int", "float"):
                values[item.get("name", "")] = self.number(text, f"property {item.get('name')!r}")
            else:
                values[item.get("name", "")] = text
        return values

    def add_tileset_tiles(self, tileset: ElementTree.Element, firstgid: int, tiles: dict[int, Properties]) -> None:
        for tile in tileset.findall("tile"):
            properties = self.tileset_tile(self.properties(tile), tile.get("class", tile.get("type")))
            if properties:
                tiles[firstgid + self.integer(tile.get("id"), "tile id")] = properties

    def layers(self, parent: ElementTree.Element, path: tuple[str, ...], inherited: Properties, offset: Point) -> None:
        for element in parent:
            if element.tag not in ("layer", "objectgroup", "group"):
                continue
            name = element.get("name", "")
            where = f"layer {name!r}"
            layer_path = (*path, name)
            properties = {**inherited, **self.properties(element)}
            shift = (
                offset[0] + self.number(element.get("offsetx"), f"{where} offsetx", 0.0),
                offset[1] + self.number(element.get("offsety"), f"{where} offsety", 0.0),
            )
            if element.tag == "group":
                self.layers(element, layer_path, properties, shift)
            elif element.tag == "layer":
                self.tile_layer(element, name, layer_path, properties, shift, where)
            else:
                objects = tuple(self.object(item, shift, f"{where} object") for item in element.findall("object"))
                self.object_layers.append(ObjectLayer(name, layer_path, properties, objects))

    def tile_layer(
        self,
        element: ElementTree.Element,
        name: str,
        path: tuple[str, ...],
        properties: Properties,
        offset: Point,
        where: str,
    ) -> None:
        data = element.find("data")
        blocks: list[tuple[int, int, int, np.ndarray]] = []
        if data is not None:
            encoding, compression = data.get("encoding"), data.get("compression")
            chunks = data.findall("chunk")
            parts = chunks if chunks else [data]
            for part in parts:
                width = self.integer(part.get("width", element.get("width")), f"{where} width")
                height = self.integer(part.get("height", element.get("height")), f"{where} height")
                x = self.integer(part.get("x"), f"{where} chunk x", 0) if chunks else 0
                y = self.integer(part.get("y"), f"{where} chunk y", 0) if chunks else 0
                raw: Any = (part.text or "") if encoding else [tile.get("gid", "0") for tile in part.findall("tile")]
                chunk_where = f"{self.source}: {where}" + (f" chunk ({x}, {y})" if chunks else "")
                blocks.append((x, y, width, decode_tile_data(raw, encoding, compression, width * height, chunk_where)))
        self.add_cells(name, path, properties, offset, blocks)

    def object(self, element: ElementTree.Element, offset: Point, where: str) -> TiledObject:
        identifier = self.integer(element.get("id"), f"{where} id", 0)
        where = f"{where} {identifier}"
        if element.get("template"):
            raise self.template_error(where)
        x = self.number(element.get("x"), f"{where} x", 0.0)
        y = self.number(element.get("y"), f"{where} y", 0.0)
        width = self.number(element.get("width"), f"{where} width", 0.0)
        height = self.number(element.get("height"), f"{where} height", 0.0)
        rotation = self.number(element.get("rotation"), f"{where} rotation", 0.0)
        gid = self.integer(element.get("gid"), f"{where} gid", 0) & GID_MASK
        points: list[Point] = []
        shape = "tile" if gid else "rectangle"
        for tag in ("polygon", "polyline", "ellipse", "point", "text"):
            child = element.find(tag)
            if child is not None:
                shape = tag
                if tag in ("polygon", "polyline"):
                    points = [self.point(pair, f"{where} {tag}") for pair in child.get("points", "").split()]
        outline = object_outline(shape, x, y, width, height, rotation, points, offset)
        return self.tiled_object(
            identifier,
            element.get("name", ""),
            element.get("class", element.get("type", "")),
            shape,
            outline,
            gid,
            self.properties(element),
        )

    def point(self, pair: str, where: str) -> Point:
        parts = pair.split(",")
        if len(parts) != 2:
            raise LevelError(f"{self.source}: {where}: point {pair!r} is not x,y")
        return self.number(parts[0], f"{where} point"), self.number(parts[1], f"{where} point")
