"""A patrol for a game or an editor: waypoints in world coordinates, and a Tiled object layer.

route.json (``guardsim patrol --export``) lists each guard's waypoints: the points where its motion
changes (a turn, a stop, a start), straight runs merged, each with its arrival tick, its time in seconds
at ``speed`` world units per second, and the guard's heading there in degrees (0 along +x, 90 along +y,
y down as in Tiled). A wait is two waypoints at the same place. A repeating guard's last waypoint is
its first again, one period later.

The Tiled copy (``--tiled-out``) is the source map with one more object layer, ``guardsim``, holding
each guard's route as a polyline object (class ``guardsim_route``, custom properties ``period`` in
seconds, ``period_ticks`` and ``speed``). Names are chosen so that guardsim's own importer reads none of
it as a wall or a spawn: the layer and object names hold no wall, spawn, guard or patrol word.
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

from guardsim.grid import CoverageGrid
from guardsim.patrol.format import PatrolError
from guardsim.patrol.model import Patrol

__all__ = [
    "DEFAULT_SPEED",
    "LAYER_NAME",
    "OBJECT_CLASS",
    "check_tiled_formats",
    "route_data",
    "tiled_with_routes",
    "waypoints",
]

#: World units per second a guard walks at unless told otherwise (a walking pace when a unit is a metre).
DEFAULT_SPEED = 2.0
#: The object layer written into Tiled maps, and the class of its objects.
LAYER_NAME = "guardsim"
OBJECT_CLASS = "guardsim_route"


def waypoints(patrol: Patrol, grid: CoverageGrid, guard: int, *, speed: float = DEFAULT_SPEED) -> list[dict[str, Any]]:
    """Guard ``guard``'s waypoints, straight runs merged (see the module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 3), dtype=bool), np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]]))
    >>> lap = Patrol(np.array([[0 * 4 + 2, 1 * 4 + 0, 2 * 4 + 0, 1 * 4 + 2]]), 4, "loop")
    >>> [(w["x"], w["tick"], w["heading"]) for w in waypoints(lap, grid, 0)]
    [(0.5, 0, 180.0), (2.5, 2, 0.0), (0.5, 4, 180.0)]
    """
    cells = patrol.cells(grid, guard)
    headings = patrol.headings(guard)
    if patrol.period is not None:
        cells.append(cells[0])
        headings.append(headings[0])
    seconds_per_tick = grid.cell_size / speed
    moves = [cells[index + 1] != cells[index] for index in range(len(cells) - 1)]
    kinds = [
        headings[index + 1] if moves[index] else -1 for index in range(len(moves))
    ]  # what each tick's move is: a heading, or -1 for standing
    kept = [0]
    for index in range(1, len(cells) - 1):
        if kinds[index - 1] != kinds[index]:
            kept.append(index)
    if len(cells) > 1:
        kept.append(len(cells) - 1)
    points = []
    for index in kept:
        x, y = grid.centre(*cells[index])
        points.append(
            {
                "x": round(x, 6),
                "y": round(y, 6),
                "tick": index,
                "time": round(index * seconds_per_tick, 6),
                "heading": float(90 * headings[index]),
            }
        )
    return points


def route_data(patrol: Patrol, grid: CoverageGrid, *, level: str, speed: float = DEFAULT_SPEED) -> dict[str, Any]:
    """The JSON-ready route.json of a patrol."""
    seconds_per_tick = grid.cell_size / speed
    return {
        "level": level,
        "units": "world",
        "speed": speed,
        "seconds_per_tick": seconds_per_tick,
        "period_ticks": patrol.period,
        "period_seconds": None if patrol.period is None else round(patrol.period * seconds_per_tick, 6),
        "repeats": patrol.period is not None,
        "guards": [{"waypoints": waypoints(patrol, grid, guard, speed=speed)} for guard in range(patrol.guards)],
    }


def _polyline(points: list[dict[str, Any]], scale: tuple[float, float]) -> list[tuple[float, float]]:
    line = [(point["x"] * scale[0], point["y"] * scale[1]) for point in points]
    if len(line) == 1:
        # A post: Tiled draws a polyline of one point as nothing, so give it a zero-length second point.
        line.append(line[0])
    return line


def _properties(patrol: Patrol, grid: CoverageGrid, speed: float) -> list[tuple[str, str, float | int]]:
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
) -> bytes:
    """The Tiled map ``source`` (its bytes given) with the ``guardsim`` route layer, in ``target``'s format.

    One tile is one world unit (as the importer reads it), so route points are scaled by the map's tile
    size. ``target`` must have the same format as ``source`` (``.tmx`` or ``.tmj``/``.json``). An
    existing ``guardsim`` layer is replaced.
    """
    source_kind = check_tiled_formats(source, target)
    routes = [waypoints(patrol, grid, guard, speed=speed) for guard in range(patrol.guards)]
    properties = _properties(patrol, grid, speed)
    moved = _rebaser(source, target)
    if source_kind == "tmx":
        return _tmx(source, source_bytes, routes, properties, moved)
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
    source_kind = _kind(source)
    if _kind(target) != source_kind:
        raise PatrolError(
            f"{target}: a copy of {Path(source).name} must keep its format ({'.tmx' if source_kind == 'tmx' else '.tmj or .json'})"
        )
    return source_kind


def _kind(path: str | os.PathLike[str]) -> str:
    suffix = Path(path).suffix.lower()
    if suffix == ".tmx":
        return "tmx"
    if suffix in (".tmj", ".json"):
        return "json"
    raise PatrolError(f"{path}: a Tiled map must end in .tmx, .tmj or .json")


def _tmx(
    source: str | os.PathLike[str],
    data: bytes,
    routes: list[list[dict[str, Any]]],
    properties: list[tuple[str, str, float | int]],
    moved: Callable[[str], str],
) -> bytes:
    from guardsim.reading import read_xml_root

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
    for number, points in enumerate(routes):
        item = ElementTree.SubElement(
            group,
            "object",
            {"id": str(next_object + number), "name": f"route {number + 1}", "type": OBJECT_CLASS, "x": "0", "y": "0"},
        )
        props = ElementTree.SubElement(item, "properties")
        for name, kind, value in properties:
            ElementTree.SubElement(props, "property", {"name": name, "type": kind, "value": str(value)})
        line = " ".join(f"{x:g},{y:g}" for x, y in _polyline(points, scale))
        ElementTree.SubElement(item, "polyline", {"points": line})
    root.set("nextlayerid", str(next_layer + 1))
    root.set("nextobjectid", str(next_object + len(routes)))
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


def _tmj(
    source: str | os.PathLike[str],
    data: bytes,
    routes: list[list[dict[str, Any]]],
    properties: list[tuple[str, str, float | int]],
    moved: Callable[[str], str],
) -> bytes:
    from guardsim.reading import parse_json

    tiled = parse_json(data.decode("utf-8-sig", errors="replace"), source=str(source), error=PatrolError)
    if not isinstance(tiled, dict) or not isinstance(tiled.get("layers"), list):
        raise PatrolError(f"{source}: not a Tiled JSON map (no layers list)")
    tiled = copy.deepcopy(tiled)
    _rebase_json(tiled, moved)
    scale = (float(tiled.get("tilewidth") or 0), float(tiled.get("tileheight") or 0))
    if not all(math.isfinite(v) and v > 0 for v in scale):
        raise PatrolError(f"{source}: the map's tilewidth and tileheight must be positive numbers")
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
    objects = []
    for number, points in enumerate(routes):
        objects.append(
            {
                "id": next_object + number,
                "name": f"route {number + 1}",
                "type": OBJECT_CLASS,
                "x": 0,
                "y": 0,
                "width": 0,
                "height": 0,
                "rotation": 0,
                "visible": True,
                "polyline": [{"x": x, "y": y} for x, y in _polyline(points, scale)],
                "properties": [{"name": name, "type": kind, "value": value} for name, kind, value in properties],
            }
        )
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
    tiled["nextobjectid"] = next_object + len(routes)
    return (json.dumps(tiled, indent=1) + "\n").encode("utf-8")
