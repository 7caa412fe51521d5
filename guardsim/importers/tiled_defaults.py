"""Tiled's documented defaults for what a map part leaves out, filled in before pytiled-parser sees it.

pytiled-parser indexes every attribute recent Tiled versions write (``raw["opacity"]``,
``attrib["tilecount"]``), so older maps (no ``infinite``, no ``tilecount``) and hand-written ones fail
with a ``KeyError``. These functions return copies with the defaults of the TMX and JSON format
references in place; nothing already given is changed.
"""

from __future__ import annotations

import copy
from typing import Any
from xml.etree import ElementTree

from guardsim.errors import LevelError

__all__ = [
    "json_layer_defaults",
    "json_object_defaults",
    "json_tileset_defaults",
    "layer_shell",
    "tmx_objects_defaults",
    "tmx_tileset_defaults",
]


def layer_shell(element: ElementTree.Element) -> ElementTree.Element:
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


def tmx_objects_defaults(element: ElementTree.Element) -> ElementTree.Element:
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


def tmx_tileset_defaults(element: ElementTree.Element) -> ElementTree.Element:
    """A tileset element with the attributes old Tiled files leave out."""
    tileset = copy.deepcopy(element)
    for key, default in (("name", ""), ("tilewidth", "1"), ("tileheight", "1"), ("tilecount", "0"), ("columns", "0")):
        tileset.attrib.setdefault(key, default)
    # Old files write <image source> without its size; 0 stands for "not given" (a tile drawn from such an
    # image has no known size, which only the code that needs it reports).
    for image in [tileset.find("image"), *(tile.find("image") for tile in tileset.findall("tile"))]:
        if image is not None:
            image.attrib.setdefault("width", "0")
            image.attrib.setdefault("height", "0")
    for tile in tileset.findall("tile"):
        group = tile.find("objectgroup")
        if group is not None:
            tile.remove(group)
            tile.append(tmx_objects_defaults(group))
    return tileset


def json_tileset_defaults(raw: Any) -> dict[str, Any]:
    if not isinstance(raw, dict):
        raise LevelError("a JSON tileset must be an object")
    tileset = {"name": "", "tilecount": 0, "tilewidth": 1, "tileheight": 1, "spacing": 0, "margin": 0, **raw}
    for key in ("tilewidth", "tileheight", "tilecount", "columns", "spacing", "margin", "firstgid"):
        value = tileset.get(key, 0)
        # pytiled-parser does arithmetic on these; anything but a number would surface as its TypeError.
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise LevelError(f"a JSON tileset's {key} must be a number, not {type(value).__name__}")
    tiles = tileset.get("tiles")
    if isinstance(tiles, list):
        fixed = []
        for tile in tiles:
            if isinstance(tile, dict) and isinstance(tile.get("objectgroup"), dict):
                group = dict(tile["objectgroup"])
                group = json_layer_defaults({"type": "objectgroup", **group})
                group["objects"] = [
                    json_object_defaults(item) for item in group.get("objects", []) if isinstance(item, dict)
                ]
                tile = {**tile, "objectgroup": group}
            fixed.append(tile)
        tileset["tiles"] = fixed
    return tileset


def json_layer_defaults(raw: dict[str, Any]) -> dict[str, Any]:
    layer = {"name": "", "opacity": 1, "visible": True, "draworder": "topdown", **raw}
    if "offsetx" in layer or "offsety" in layer:
        layer.setdefault("offsetx", 0)
        layer.setdefault("offsety", 0)
    if "width" in layer or "height" in layer:
        layer.setdefault("width", 0)
        layer.setdefault("height", 0)
    return layer


def json_object_defaults(raw: dict[str, Any]) -> dict[str, Any]:
    defaults = {"id": 0, "x": 0, "y": 0, "width": 0, "height": 0, "rotation": 0, "visible": True, "name": ""}
    return {**defaults, **raw}
