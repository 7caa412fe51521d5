"""A patrol in a Tiled map: the ``guardsim`` object layer (``guardsim patrol --tiled-out``).

The Tiled copy is the source map with one more object layer, ``guardsim``, holding each guard's route as
a polyline object (class ``guardsim_route``, custom properties ``period`` in seconds, ``period_ticks``
and ``speed``). Names are chosen so that guardsim's own importer reads none of it as a wall or a spawn:
the layer and object names hold no wall, spawn, guard or patrol word. Each route is route.json's
(:func:`guardsim.patrol.export.guard_routes`: ``loop_mode`` and ``phase`` properties) and keeps its
headings and times (string properties ``headings``, degrees per polyline point, and ``times``,
seconds); each place the guard stands still is a point object of class ``guardsim_wait`` with ``wait``
(seconds), ``facing`` (degrees) and, when it turns on the spot, ``scan`` properties.

A level drawn by hand has no source map: :mod:`guardsim.patrol.tiled_fresh` writes a fresh one.
"""

from __future__ import annotations

import copy
import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

from guardsim.errors import PatrolError
from guardsim.grid import CoverageGrid
from guardsim.patrol.export import DEFAULT_SPEED, guard_routes
from guardsim.patrol.model import Patrol

__all__ = [
    "LAYER_NAME",
    "OBJECT_CLASS",
    "WAIT_CLASS",
    "check_tiled_formats",
    "map_tile_size",
    "route_properties",
    "tiled_kind",
    "tiled_with_routes",
    "tmx_with_routes",
]

#: The object layer written into Tiled maps, and the class of its objects.
LAYER_NAME = "guardsim"
OBJECT_CLASS = "guardsim_route"
WAIT_CLASS = "guardsim_wait"


def _polyline(points: list[dict[str, Any]], scale: tuple[float, float]) -> list[tuple[float, float]]:
    line = [(point["x"] * scale[0], point["y"] * scale[1]) for point in points]
    if len(line) == 1:
        # A post: Tiled draws a polyline of one point as nothing, so give it a zero-length second point.
        line.append(line[0])
    return line


def _route_objects(
    routes: list[dict[str, Any]],
    properties: list[tuple[str, str, float | int]],
    scale: tuple[float, float],
    first_id: int,
) -> list[dict[str, Any]]:
    """The route layer's objects in Tiled JSON's shape: per guard a polyline (its loop mode, phase,
    headings and times as properties), then a ``guardsim_wait`` point wherever it stands still."""
    objects: list[dict[str, Any]] = []
    for number, route in enumerate(routes):
        points = route["waypoints"]
        shared = [
            {"name": name, "type": kind, "value": route["period"] if name == "period" and route["period"] else value}
            for name, kind, value in properties
        ]
        line = _polyline(points, scale)
        headings = [point["heading"] for point in points] + [points[-1]["heading"]] * (len(line) - len(points))
        times = [point["time"] for point in points] + [points[-1]["time"]] * (len(line) - len(points))
        objects.append(
            {
                "name": f"route {number + 1}",
                "type": OBJECT_CLASS,
                "x": 0,
                "y": 0,
                "polyline": [{"x": x, "y": y} for x, y in line],
                "properties": [
                    *shared,
                    {"name": "guard", "type": "int", "value": number + 1},
                    {"name": "loop_mode", "type": "string", "value": route["loop_mode"]},
                    {"name": "phase", "type": "float", "value": route["phase"]},
                    {"name": "headings", "type": "string", "value": " ".join(f"{h:g}" for h in headings)},
                    {"name": "times", "type": "string", "value": " ".join(f"{t:g}" for t in times)},
                ],
            }
        )
        for here in points:
            if here["wait"] > 0:
                objects.append(
                    {
                        "name": f"route {number + 1} wait",
                        "type": WAIT_CLASS,
                        "x": here["x"] * scale[0],
                        "y": here["y"] * scale[1],
                        "properties": [
                            {"name": "guard", "type": "int", "value": number + 1},
                            {"name": "wait", "type": "float", "value": here["wait"]},
                            {"name": "facing", "type": "float", "value": here["heading"]},
                            {"name": "time", "type": "float", "value": here["time"]},
                            *(
                                [{"name": "scan", "type": "string", "value": " ".join(f"{h:g}" for h in here["scan"])}]
                                if "scan" in here
                                else []
                            ),
                        ],
                    }
                )
    for offset, item in enumerate(objects):
        item["id"] = first_id + offset
    return objects


def route_properties(patrol: Patrol, grid: CoverageGrid, speed: float) -> list[tuple[str, str, float | int]]:
    period = patrol.period if patrol.period is not None else patrol.ticks
    return [
        ("period", "float", round(period * grid.cell_size / speed, 6)),
        ("period_ticks", "int", period),
        ("speed", "float", speed),
    ]


def tiled_with_routes(
    source: str | os.PathLike[str],
    target: str | os.PathLike[str],
    patrol: Patrol,
    grid: CoverageGrid,
    *,
    speed: float = DEFAULT_SPEED,
    source_bytes: bytes,
    routes: list[dict[str, Any]] | None = None,
) -> bytes:
    """The Tiled map ``source`` (its bytes given) with the ``guardsim`` route layer, in ``target``'s format.

    One tile is one world unit (as the importer reads it), so route points are scaled by the map's tile
    size. ``target`` must have the same format as ``source`` (``.tmx`` or ``.tmj``/``.json``). An
    existing ``guardsim`` layer is replaced.
    """
    source_kind = check_tiled_formats(source, target)
    if routes is None:
        routes = guard_routes(patrol, grid, speed=speed)
    properties = route_properties(patrol, grid, speed)
    moved = _rebaser(source, target)
    if source_kind == "tmx":
        return tmx_with_routes(source, source_bytes, routes, properties, moved)
    return _tmj(source, source_bytes, routes, properties, moved)


def _rebaser(source: str | os.PathLike[str], target: str | os.PathLike[str]) -> Callable[[str], str]:
    """A function taking a path the source map names (a tileset, an image, a template) to the same file
    named from the copy's folder, so the copy opens in Tiled and re-imports wherever it is written."""
    source_dir = Path(source).resolve().parent
    target_dir = Path(target).resolve().parent

    def moved(path: str) -> str:
        if not path or "://" in path or os.path.isabs(path) or source_dir == target_dir:
            return path
        return Path(os.path.relpath(source_dir / path, target_dir)).as_posix()

    return moved


def check_tiled_formats(source: str | os.PathLike[str], target: str | os.PathLike[str]) -> str:
    """``"tmx"`` or ``"json"``: the format of the Tiled map ``source``, which its copy ``target`` must keep."""
    source_kind = tiled_kind(source)
    if tiled_kind(target) != source_kind:
        raise PatrolError(
            f"{target}: a copy of {Path(source).name} must keep its format ({'.tmx' if source_kind == 'tmx' else '.tmj or .json'})"
        )
    return source_kind


def tiled_kind(path: str | os.PathLike[str]) -> str:
    suffix = Path(path).suffix.lower()
    if suffix == ".tmx":
        return "tmx"
    if suffix in (".tmj", ".json"):
        return "json"
    raise PatrolError(f"{path}: a Tiled map must end in .tmx, .tmj or .json")


def tmx_with_routes(
    source: str | os.PathLike[str],
    data: bytes,
    routes: list[dict[str, Any]],
    properties: list[tuple[str, str, float | int]],
    moved: Callable[[str], str],
) -> bytes:
    from guardsim.files.reading import read_xml_root

    root = read_xml_root(data, source=str(source), error=PatrolError)
    if root.tag != "map":
        raise PatrolError(f"{source}: not a Tiled map (root element {root.tag!r})")
    for element in root.iter():
        for name in ("source", "template"):
            value = element.get(name)
            if value is not None and element.tag in ("tileset", "image", "object"):
                element.set(name, moved(value))
    scale = (_number(root, "tilewidth", source), _number(root, "tileheight", source))
    for layer in list(root):
        if layer.tag == "objectgroup" and layer.get("name") == LAYER_NAME:
            root.remove(layer)
    next_layer = int(
        root.get("nextlayerid")
        or 1
        + max(
            (int(e.get("id") or 0) for e in root.iter() if e.tag in ("layer", "objectgroup", "imagelayer", "group")),
            default=0,
        )
    )
    next_object = int(
        root.get("nextobjectid") or 1 + max((int(e.get("id") or 0) for e in root.iter("object")), default=0)
    )
    group = ElementTree.SubElement(root, "objectgroup", {"id": str(next_layer), "name": LAYER_NAME})
    objects = _route_objects(routes, properties, scale, next_object)
    for item in objects:
        attributes = {"id": str(item["id"]), "name": item["name"], "type": item["type"]}
        attributes.update({key: f"{item[key]:g}" for key in ("x", "y")})
        element = ElementTree.SubElement(group, "object", attributes)
        props = ElementTree.SubElement(element, "properties")
        for prop in item["properties"]:
            ElementTree.SubElement(
                props, "property", {"name": prop["name"], "type": prop["type"], "value": str(prop["value"])}
            )
        if "polyline" in item:
            line = " ".join(f"{point['x']:g},{point['y']:g}" for point in item["polyline"])
            ElementTree.SubElement(element, "polyline", {"points": line})
        else:
            ElementTree.SubElement(element, "point")
    root.set("nextlayerid", str(next_layer + 1))
    root.set("nextobjectid", str(next_object + len(objects)))
    ElementTree.indent(root, space=" ")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ElementTree.tostring(root, encoding="utf-8") + b"\n"


def _rebase_json(value: Any, moved: Callable[[str], str]) -> None:
    """Rename, in place, the files a Tiled JSON map names: tilesets' ``source``, ``image`` and objects'
    ``template`` (bounded: the map was read with the depth limit)."""
    if isinstance(value, dict):
        for key in ("source", "image", "template"):
            if isinstance(value.get(key), str):
                value[key] = moved(value[key])
        for item in value.values():
            if isinstance(item, (dict, list)):
                _rebase_json(item, moved)
    elif isinstance(value, list):
        for item in value:
            if isinstance(item, (dict, list)):
                _rebase_json(item, moved)


def _number(element: ElementTree.Element, name: str, source: str | os.PathLike[str]) -> float:
    try:
        value = float(element.get(name, ""))
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value <= 0:
        raise PatrolError(f"{source}: the map's {name} is not a positive number")
    return value


def _json_scale(tiled: dict[str, Any], source: str | os.PathLike[str]) -> tuple[float, float]:
    try:
        scale = (float(tiled.get("tilewidth") or 0), float(tiled.get("tileheight") or 0))
    except (TypeError, ValueError):
        scale = (math.nan, math.nan)
    if not all(math.isfinite(v) and v > 0 for v in scale):
        raise PatrolError(f"{source}: the map's tilewidth and tileheight must be positive numbers")
    return scale


def map_tile_size(source: str | os.PathLike[str], data: bytes) -> tuple[float, float]:
    """The tile width and height in pixels of the Tiled map ``source`` (its bytes given): the pixels of
    one world unit, as the importer reads one tile as one unit."""
    from guardsim.files.reading import parse_json, read_xml_root

    if tiled_kind(source) == "tmx":
        root = read_xml_root(data, source=str(source), error=PatrolError)
        return _number(root, "tilewidth", source), _number(root, "tileheight", source)
    tiled = parse_json(data.decode("utf-8-sig", errors="replace"), source=str(source), error=PatrolError)
    if not isinstance(tiled, dict):
        raise PatrolError(f"{source}: not a Tiled JSON map")
    return _json_scale(tiled, source)


def _tmj(
    source: str | os.PathLike[str],
    data: bytes,
    routes: list[dict[str, Any]],
    properties: list[tuple[str, str, float | int]],
    moved: Callable[[str], str],
) -> bytes:
    from guardsim.files.reading import parse_json

    tiled = parse_json(data.decode("utf-8-sig", errors="replace"), source=str(source), error=PatrolError)
    if not isinstance(tiled, dict) or not isinstance(tiled.get("layers"), list):
        raise PatrolError(f"{source}: not a Tiled JSON map (no layers list)")
    tiled = copy.deepcopy(tiled)
    _rebase_json(tiled, moved)
    scale = _json_scale(tiled, source)
    layers = [
        layer
        for layer in tiled["layers"]
        if not (isinstance(layer, dict) and layer.get("name") == LAYER_NAME and layer.get("type") == "objectgroup")
    ]
    next_layer = int(
        tiled.get("nextlayerid")
        or 1 + max((int(layer.get("id", 0)) for layer in layers if isinstance(layer, dict)), default=0)
    )
    next_object = int(tiled.get("nextobjectid") or 1)
    objects = _route_objects(routes, properties, scale, next_object)
    for item in objects:
        item.update({"width": 0, "height": 0, "rotation": 0, "visible": True})
        if "polyline" not in item:
            item["point"] = True
    layers.append(
        {
            "id": next_layer,
            "name": LAYER_NAME,
            "type": "objectgroup",
            "draworder": "topdown",
            "opacity": 1,
            "visible": True,
            "x": 0,
            "y": 0,
            "objects": objects,
        }
    )
    tiled["layers"] = layers
    tiled["nextlayerid"] = next_layer + 1
    tiled["nextobjectid"] = next_object + len(objects)
    return (json.dumps(tiled, indent=1) + "\n").encode("utf-8")
