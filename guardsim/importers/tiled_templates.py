"""Object templates (``.tx``, ``.tj``): each instance merged over its template before it is parsed.

Tiled stores a templated object as the template's file name plus whatever the instance changed (its
position, often its size, some properties). pytiled-parser can merge templates itself, but its JSON
merge lets the template's keys override the instance's (a resized instance gets the template's size)
and its TMX merge runs after guardsim has filled in defaults; so the merge is done here, the way Tiled
does it: the instance's attributes win, properties are merged by name, the template's shape stays
unless the instance has its own, and a tile template's tile id is counted in the map's own tilesets.
Every template (and its tileset) is read once, through the same capped reader as the map.
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

from guardsim.errors import LevelError
from guardsim.importers.source import display_name, parse_json_bytes, parse_xml_bytes, read_capped_bytes
from guardsim.importers.tiled_data import GID_MASK

__all__ = ["Templates"]

_SHAPES = ("polygon", "polyline", "ellipse", "point", "text")


class Templates:
    """The templates one map uses, read once each.

    Parameters
    ----------
    folder
        The map's folder; template paths are relative to it.
    tileset_files
        The map's external tilesets: resolved file path -> firstgid, for tile templates.
    """

    def __init__(self, source: str, folder: Path, max_file_bytes: int, tileset_files: dict[Path, int]) -> None:
        self.source = source
        self.folder = folder
        self.max_file_bytes = max_file_bytes
        self.tileset_files = tileset_files
        self.read: dict[Path, tuple[Any, int | None]] = {}
        self.notes: list[str] = []

    def _template(self, name: str, where: str, xml: bool) -> tuple[Any, int | None]:
        """The template's object (an element or a dict) and the map firstgid its tile ids count from."""
        path = (self.folder / name).resolve()
        if path in self.read:
            return self.read[path]
        if not path.is_file():
            raise LevelError(f"{self.source}: {where}: template {display_name(name)} not found")
        data = read_capped_bytes(path, max_file_bytes=self.max_file_bytes, kind="template")
        shown = display_name(path)
        tileset: Any
        if data.lstrip()[:1] == b"<":
            root = parse_xml_bytes(data, shown)
            item, tileset = root.find("object"), root.find("tileset")
            tileset = None if tileset is None else dict(tileset.attrib)
        else:
            value = parse_json_bytes(data, shown)
            item = value.get("object") if isinstance(value, dict) else None
            tileset = value.get("tileset") if isinstance(value, dict) else None
        if (
            item is None
            or (xml and not isinstance(item, ElementTree.Element))
            or (not xml and not isinstance(item, dict))
        ):
            kind = "an XML (.tx)" if xml else "a JSON (.tj)"
            raise LevelError(f"{self.source}: {where}: template {display_name(name)} is not {kind} object template")
        offset = None
        if isinstance(tileset, dict) and tileset.get("source"):
            tileset_path = (path.parent / str(tileset["source"])).resolve()
            firstgid = self.tileset_files.get(tileset_path)
            if firstgid is None:
                self.notes.append(f"template {display_name(name)}: its tileset is not one the map uses; tile left out")
            else:
                offset = firstgid - _int(tileset.get("firstgid", 1))
        self.read[path] = (item, offset)
        return item, offset

    def tmx(self, layer: ElementTree.Element, where: str) -> ElementTree.Element:
        """The object layer with every templated object merged over its template."""
        if not any(item.get("template") for item in layer.findall("object")):
            return layer
        merged_layer = copy.copy(layer)
        merged_layer[:] = []
        for child in layer:
            if child.tag == "object" and child.get("template"):
                child = self._tmx_object(child, f"{where} object {child.get('id')}")
            merged_layer.append(child)
        return merged_layer

    def _tmx_object(self, instance: ElementTree.Element, where: str) -> ElementTree.Element:
        template, offset = self._template(instance.get("template", ""), where, xml=True)
        merged = copy.deepcopy(template)
        if "gid" in merged.attrib and "gid" not in instance.attrib:
            gid = _remapped(_int(merged.get("gid")), offset)
            merged.attrib.pop("gid") if gid is None else merged.set("gid", str(gid))
        merged.attrib.update({key: value for key, value in instance.attrib.items() if key != "template"})
        for tag in _SHAPES:
            own = instance.find(tag)
            if own is not None:
                for old in merged.findall(tag):
                    merged.remove(old)
                merged.append(copy.deepcopy(own))
        own_properties = instance.find("properties")
        if own_properties is not None:
            properties = merged.find("properties")
            if properties is None:
                properties = ElementTree.SubElement(merged, "properties")
            names = {item.get("name") for item in own_properties}
            for item in [item for item in properties if item.get("name") in names]:
                properties.remove(item)
            properties.extend(copy.deepcopy(list(own_properties)))
        return merged

    def json(self, instance: dict[str, Any], where: str) -> dict[str, Any]:
        """A JSON object merged over its template (unchanged if it has none)."""
        if not instance.get("template"):
            return instance
        template, offset = self._template(str(instance["template"]), where, xml=False)
        merged = {key: value for key, value in template.items() if key != "id"}
        if "gid" in merged and "gid" not in instance:
            gid = _remapped(_int(merged["gid"]), offset)
            merged.pop("gid") if gid is None else merged.update(gid=gid)
        merged.update({key: value for key, value in instance.items() if key not in ("template", "properties")})
        own = instance.get("properties")
        if isinstance(own, list) and isinstance(merged.get("properties"), list):
            names = {item.get("name") for item in own if isinstance(item, dict)}
            kept = [item for item in merged["properties"] if not (isinstance(item, dict) and item.get("name") in names)]
            merged["properties"] = kept + own
        elif own is not None:
            merged["properties"] = own
        return merged


def _int(value: Any) -> int:
    try:
        return int(value)
    except (TypeError, ValueError, OverflowError):
        return 0


def _remapped(gid: int, offset: int | None) -> int | None:
    """A template's tile id counted in the map's tilesets, flip flags kept; ``None`` if it cannot be."""
    if offset is None or not gid & GID_MASK:
        return None
    return ((gid & GID_MASK) + offset) | (gid & ~GID_MASK & 0xFFFFFFFF)
