"""Reading Tiled JSON maps (``.json``, ``.tmj``) and JSON tilesets (``.tsj``, ``.json``)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

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

__all__ = ["JsonMapReader", "parse_json", "read_tsj_tiles"]


def parse_json(data: bytes, source: str) -> dict[str, Any]:
    try:
        value = json.loads(data.decode("utf-8"))
    except UnicodeDecodeError as error:
        raise LevelError(f"{source}: not UTF-8 text (byte {error.start})") from None
    except json.JSONDecodeError as error:
        raise LevelError(f"{source}: line {error.lineno} column {error.colno}: not valid JSON: {error.msg}") from None
    except RecursionError:
        raise LevelError(f"{source}: not valid JSON: nested too deeply") from None
    if not isinstance(value, dict) or ("orientation" not in value and value.get("type") != "map"):
        raise LevelError(f'{source}: not a Tiled JSON map (no \'orientation\' or "type": "map")')
    return value


def read_tsj_tiles(path: Path, firstgid: int) -> dict[int, Properties]:
    """Properties of the tiles of a JSON tileset file, by global id."""
    try:
        tileset = json.loads(read_source_bytes(path).decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        raise LevelError(f"{path}: not a valid JSON tileset") from None
    if not isinstance(tileset, dict):
        raise LevelError(f"{path}: not a valid JSON tileset")
    tiles: dict[int, Properties] = {}
    JsonMapReader(str(path), path.parent).add_tileset_tiles(tileset, firstgid, tiles)
    return tiles


class JsonMapReader(MapReader):
    """Reads a Tiled JSON map (or a JSON tileset's tiles)."""

    def map(self, root: dict[str, Any]) -> TiledMap:
        self.check_orientation(root.get("orientation"))
        for index, tileset in enumerate(self.list(root, "tilesets", "map")):
            where = f"tilesets[{index}]"
            firstgid = self.integer(tileset.get("firstgid"), f"{where}.firstgid")
            if "source" in tileset:
                self.external_tileset(str(tileset["source"]), firstgid)
            else:
                self.add_tileset_tiles(tileset, firstgid, self.tiles)
        self.layers(self.list(root, "layers", "map"), (), {}, (0.0, 0.0), "layers")
        return self.result(root.get("tilewidth"), root.get("tileheight"))

    def list(self, value: Any, key: str, where: str) -> list[dict[str, Any]]:
        items = value.get(key, []) if isinstance(value, dict) else None
        if not isinstance(items, list) or not all(isinstance(item, dict) for item in items):
            raise LevelError(f"{self.source}: {where}.{key} must be a list of objects")
        return items

    def properties(self, value: dict[str, Any], where: str) -> Properties:
        items = value.get("properties", [])
        if isinstance(items, dict):  # the pre-1.2 JSON format stored a plain object
            return dict(items)
        if not isinstance(items, list) or not all(isinstance(item, dict) and "name" in item for item in items):
            raise LevelError(f"{self.source}: {where}.properties must be a list of {{name, value}} objects")
        return {str(item["name"]): item.get("value") for item in items}

    def add_tileset_tiles(self, tileset: dict[str, Any], firstgid: int, tiles: dict[int, Properties]) -> None:
        for index, tile in enumerate(self.list(tileset, "tiles", "tileset")):
            properties = self.tileset_tile(
                self.properties(tile, f"tiles[{index}]"), tile.get("class", tile.get("type"))
            )
            if properties:
                tiles[firstgid + self.integer(tile.get("id"), f"tiles[{index}].id")] = properties

    def layers(
        self, layers: list[dict[str, Any]], path: tuple[str, ...], inherited: Properties, offset: Point, where: str
    ) -> None:
        for index, layer in enumerate(layers):
            name = str(layer.get("name", ""))
            here = f"{where}[{index}] ({name!r})"
            layer_path = (*path, name)
            properties = {**inherited, **self.properties(layer, here)}
            shift = (
                offset[0] + self.number(layer.get("offsetx"), f"{here}.offsetx", 0.0),
                offset[1] + self.number(layer.get("offsety"), f"{here}.offsety", 0.0),
            )
            kind = layer.get("type")
            if kind == "group":
                self.layers(self.list(layer, "layers", here), layer_path, properties, shift, f"{here}.layers")
            elif kind == "tilelayer":
                self.tile_layer(layer, name, layer_path, properties, shift, here)
            elif kind == "objectgroup":
                objects = tuple(
                    self.object(item, shift, f"{here}.objects[{number}]")
                    for number, item in enumerate(self.list(layer, "objects", here))
                )
                self.object_layers.append(ObjectLayer(name, layer_path, properties, objects))

    def tile_layer(
        self, layer: dict[str, Any], name: str, path: tuple[str, ...], properties: Properties, offset: Point, where: str
    ) -> None:
        encoding = layer.get("encoding", "csv")
        compression = layer.get("compression") or None
        blocks = []
        chunks = layer.get("chunks")
        parts = self.list(layer, "chunks", where) if chunks is not None else [layer]
        for index, part in enumerate(parts):
            here = f"{where}.chunks[{index}]" if chunks is not None else where
            width = self.integer(part.get("width"), f"{here}.width")
            height = self.integer(part.get("height"), f"{here}.height")
            x = self.integer(part.get("x"), f"{here}.x", 0) if chunks is not None else 0
            y = self.integer(part.get("y"), f"{here}.y", 0) if chunks is not None else 0
            raw = part.get("data", [])
            kind = "base64" if encoding == "base64" else None
            blocks.append(
                (x, y, width, decode_tile_data(raw, kind, compression, width * height, f"{self.source}: {here}.data"))
            )
        self.add_cells(name, path, properties, offset, blocks)

    def object(self, value: dict[str, Any], offset: Point, where: str) -> TiledObject:
        if "template" in value:
            raise self.template_error(where)
        x = self.number(value.get("x"), f"{where}.x", 0.0)
        y = self.number(value.get("y"), f"{where}.y", 0.0)
        width = self.number(value.get("width"), f"{where}.width", 0.0)
        height = self.number(value.get("height"), f"{where}.height", 0.0)
        rotation = self.number(value.get("rotation"), f"{where}.rotation", 0.0)
        gid = self.integer(value.get("gid"), f"{where}.gid", 0) & GID_MASK
        shape = "tile" if gid else "rectangle"
        points: list[Point] = []
        for key in ("polygon", "polyline"):
            if key in value:
                shape = key
                items = value[key]
                if not isinstance(items, list) or not all(isinstance(item, dict) for item in items):
                    raise LevelError(f"{self.source}: {where}.{key} must be a list of {{x, y}} points")
                points = [
                    (
                        self.number(item.get("x"), f"{where}.{key}[{i}].x"),
                        self.number(item.get("y"), f"{where}.{key}[{i}].y"),
                    )
                    for i, item in enumerate(items)
                ]
        for key in ("ellipse", "point", "text"):
            if value.get(key):
                shape = key
        return self.tiled_object(
            self.integer(value.get("id"), f"{where}.id", 0),
            str(value.get("name", "")),
            value.get("class", value.get("type", "")),
            shape,
            object_outline(shape, x, y, width, height, rotation, points, offset),
            gid,
            self.properties(value, where),
        )
