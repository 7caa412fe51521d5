"""Reading Tiled JSON maps (``.json``, ``.tmj``) with pytiled-parser's JSON parsers, part by part."""

from __future__ import annotations

import functools
from typing import Any, cast

from pytiled_parser.layer import ObjectLayer as PtObjectLayer
from pytiled_parser.parsers.json import layer as json_layer
from pytiled_parser.parsers.json import properties as json_properties
from pytiled_parser.parsers.json import tiled_object as json_object

from guardsim.importers.source import excerpt
from guardsim.importers.tiled_data import Point, Properties, TiledMap, decode_tile_data
from guardsim.importers.tiled_defaults import json_layer_defaults, json_object_defaults
from guardsim.importers.tiled_parts import (
    COMPRESSIONS,
    MAX_GROUP_DEPTH,
    Blocks,
    MapReader,
    dicts,
    properties_of,
    text,
    word,
)

__all__ = ["JsonReader"]


class JsonReader(MapReader):
    """Reads a Tiled JSON map."""

    def read(self, root: Any) -> TiledMap:
        if not isinstance(root, dict) or ("orientation" not in root and root.get("type") != "map"):
            raise self.error("", 'not a Tiled JSON map (no "orientation" or "type": "map")')
        self.check_orientation(root.get("orientation"))
        if root.get("properties"):
            raw = root["properties"]
            self.read_properties(lambda: json_properties.parse(raw))
        for index, raw in enumerate(dicts(root.get("tilesets", []), f"{self.source}: tilesets")):
            where = f"tilesets[{index}]"
            firstgid = self.integer(raw.get("firstgid"), f"{where}.firstgid")
            self.load_tileset(firstgid, str(raw["source"]) if "source" in raw else None, raw, where)
        self.check_tile_count(
            self.integer(root.get("width"), "width", 0), self.integer(root.get("height"), "height", 0), "map"
        )
        stack: list[tuple[list[dict[str, Any]], str, tuple[str, ...], Properties, Point, bool, int]] = [
            (dicts(root.get("layers", []), f"{self.source}: layers"), "layers", (), {}, (0.0, 0.0), True, 0)
        ]
        while stack:
            layers, prefix, path, inherited, offset, visible, depth = stack.pop()
            pending = []
            for index, raw in enumerate(layers):
                name = text(raw.get("name", ""))
                where = f"{prefix}[{index}] ({excerpt(name)})"
                kind = raw.get("type")
                shell = {
                    key: value
                    for key, value in json_layer_defaults(raw).items()
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
                properties = {**inherited, **properties_of(common)}
                if kind == "group":
                    if depth + 1 > MAX_GROUP_DEPTH:
                        raise self.error(where, f"group layers nested more than {MAX_GROUP_DEPTH} deep")
                    pending.append(
                        (
                            dicts(raw.get("layers", []), f"{self.source}: {where}.layers"),
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
                    raw_objects = [
                        self.templates.json(item, f"{where}.objects[{number}]")
                        for number, item in enumerate(dicts(raw.get("objects", []), f"{self.source}: {where}.objects"))
                    ]
                    objects = [
                        self.call(
                            f"{where}.objects[{number}]",
                            functools.partial(
                                json_object.parse, cast(Any, json_object_defaults(item)), "utf-8", self.folder
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

    def json_tile_data(self, raw: dict[str, Any], where: str) -> Blocks:
        encoding = raw.get("encoding", "csv")
        compression = raw.get("compression") or None
        if encoding not in ("csv", "base64"):
            raise self.error(where, f"tile data encoding {word(encoding)} is not one Tiled writes (csv or base64)")
        if compression not in COMPRESSIONS:
            raise self.error(where, f"{word(compression)} compression is not supported (save as CSV, zlib or gzip)")
        chunks = raw.get("chunks")
        parts = dicts(chunks, f"{self.source}: {where}.chunks") if chunks is not None else [raw]
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
