"""A patrol for a game or an editor: waypoints in world coordinates, and a Tiled object layer.

route.json (``guardsim patrol --export``) lists each guard's waypoints: the points where its motion
changes (a turn, a stop, a start), straight runs merged, each with its arrival tick, its time in seconds
at ``speed`` world units per second, and the guard's heading there in degrees (0 along +x, 90 along +y,
y down as in Tiled). A wait is two waypoints at the same place. A repeating guard's last waypoint is
its first again, one period later.

The Tiled copy (``--tiled-out``) is the source map with one more object layer, ``guardsim``, holding
each guard's route as a polyline object (class ``guardsim_route``, custom properties ``period`` in
seconds, ``period_ticks`` and ``speed``). Names are chosen so that guardsim's own importer reads none of
it as a wall or a spawn: the layer and object names hold no wall, spawn, guard or patrol word. Each
route keeps its headings and times (string properties ``headings``, degrees per polyline point, and
``times``, seconds), and each place the guard stands still is a point object of class
``guardsim_wait`` with ``wait`` (seconds) and ``facing`` (degrees) properties.

A level drawn by hand has no source map: :func:`tiled_from_level` writes a fresh one, the level's outer
ring as a ``boundary`` polygon, its holes as polygons on a ``walls`` layer and its starts as
``guard spawn`` points, one tile per world unit (``tile_pixels`` pixels), with the route layer.
"""

from __future__ import annotations

import copy
import itertools
import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

from guardsim.grid import CoverageGrid
from guardsim.level import Level
from guardsim.patrol.format import PatrolError
from guardsim.patrol.model import Patrol

__all__ = [
    "DEFAULT_SPEED",
    "LAYER_NAME",
    "OBJECT_CLASS",
    "check_tiled_formats",
    "route_data",
    "tiled_from_level",
    "tiled_with_routes",
    "waypoints",
]

#: World units per second a guard walks at unless told otherwise (a walking pace when a unit is a metre).
DEFAULT_SPEED = 2.0
#: The object layer written into Tiled maps, and the class of its objects.
LAYER_NAME = "guardsim"
OBJECT_CLASS = "guardsim_route"
WAIT_CLASS = "guardsim_wait"
#: Pixels per tile (one world unit) in a map written for a level that has no source map.
DEFAULT_TILE_PIXELS = 32


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


def _route_objects(
    routes: list[list[dict[str, Any]]],
    properties: list[tuple[str, str, float | int]],
    scale: tuple[float, float],
    first_id: int,
) -> list[dict[str, Any]]:
    """The route layer's objects in Tiled JSON's shape: per guard a polyline (its headings and times as
    properties), then a ``guardsim_wait`` point wherever it stands still."""
    objects: list[dict[str, Any]] = []
    for number, points in enumerate(routes):
        shared = [{"name": name, "type": kind, "value": value} for name, kind, value in properties]
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
                    {"name": "headings", "type": "string", "value": " ".join(f"{h:g}" for h in headings)},
                    {"name": "times", "type": "string", "value": " ".join(f"{t:g}" for t in times)},
                ],
            }
        )
        for here, after in itertools.pairwise(points):
            if (here["x"], here["y"]) == (after["x"], after["y"]) and after["time"] > here["time"]:
                objects.append(
                    {
                        "name": f"route {number + 1} wait",
                        "type": WAIT_CLASS,
                        "x": here["x"] * scale[0],
                        "y": here["y"] * scale[1],
                        "properties": [
                            {"name": "guard", "type": "int", "value": number + 1},
                            {"name": "wait", "type": "float", "value": round(after["time"] - here["time"], 6)},
                            {"name": "facing", "type": "float", "value": here["heading"]},
                            {"name": "time", "type": "float", "value": here["time"]},
                        ],
                    }
                )
    for offset, item in enumerate(objects):
        item["id"] = first_id + offset
    return objects


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


def tiled_from_level(
    level: Level,
    target: str | os.PathLike[str],
    patrol: Patrol,
    grid: CoverageGrid,
    *,
    speed: float = DEFAULT_SPEED,
    tile_pixels: int = DEFAULT_TILE_PIXELS,
) -> bytes:
    """A fresh Tiled map (``.tmx``, or JSON for ``.tmj``/``.json``) of a level drawn without one.

    The level sits inside a wall border one tile wide; the map's origin is one tile above and left of
    the level's lowest corner (the map property ``guardsim_origin`` says where, in world units), so the
    map imports again as the same level moved by minus that origin.

    Examples
    --------
    >>> import numpy as np
    >>> level = Level("hall", 1.0, ((0.0, 0.0), (3.0, 0.0), (3.0, 1.0), (0.0, 1.0)))
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 3), dtype=bool), np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]]))
    >>> lap = Patrol(np.array([[0 * 4 + 2, 1 * 4 + 0, 2 * 4 + 0, 1 * 4 + 2]]), 4, "loop")
    >>> text = tiled_from_level(level, "hall.tmx", lap, grid, tile_pixels=16).decode()
    >>> 'width="5" height="3" tilewidth="16" tileheight="16"' in text, text.count("guardsim_route")
    (True, 1)
    """
    if not (isinstance(tile_pixels, int) and 1 <= tile_pixels <= 4096):
        raise PatrolError(f"{target}: tile size must be a whole number of pixels from 1 to 4096, not {tile_pixels}")
    kind = _kind(target)
    xs = [x for x, _ in level.outer]
    ys = [y for _, y in level.outer]
    # A wall border one tile wide keeps the level off the map's edges, where the importer would warn
    # that walls may be missing.
    left, top = min(xs) - 1, min(ys) - 1
    width = math.ceil(max(xs) - left - 1e-9) + 1
    height = math.ceil(max(ys) - top - 1e-9) + 1

    def ring(points: tuple[tuple[float, float], ...]) -> str:
        return " ".join(f"{(x - left) * tile_pixels:g},{(y - top) * tile_pixels:g}" for x, y in points)

    objects = [
        f'  <object id="1" name="level boundary" type="boundary" x="0" y="0"><polygon points="{ring(level.outer)}"/></object>'
    ]
    w, h = width + left, height + top
    border = (
        ((left, top), (w, top), (w, top + 1), (left, top + 1)),
        ((left, h - 1), (w, h - 1), (w, h), (left, h)),
        ((left, top), (left + 1, top), (left + 1, h), (left, h)),
        ((w - 1, top), (w, top), (w, h), (w - 1, h)),
    )
    walls = [
        f'  <object id="{2 + index}" name="{"border" if index < 4 else "wall"} {index + 1}" x="0" y="0">'
        f'<polygon points="{ring(hole)}"/></object>'
        for index, hole in enumerate(border + tuple(level.holes))
    ]
    starts = [
        f'  <object id="{2 + len(walls) + index}" name="guard spawn {index + 1}" type="spawn" '
        f'x="{(x - left) * tile_pixels:g}" y="{(y - top) * tile_pixels:g}"><point/></object>'
        for index, (x, y) in enumerate(level.starts or ((level.guard.start,) if level.guard.start else ()))
    ]
    from xml.sax.saxutils import quoteattr

    skeleton = "\n".join(
        [
            '<?xml version="1.0" encoding="UTF-8"?>',
            f'<map version="1.8" tiledversion="1.8.2" orientation="orthogonal" renderorder="right-down" '
            f'width="{width}" height="{height}" tilewidth="{tile_pixels}" tileheight="{tile_pixels}" infinite="0" '
            f'nextlayerid="4" nextobjectid="{2 + len(walls) + len(starts)}">',
            " <properties>",
            f'  <property name="guardsim_level" value={quoteattr(level.name)}/>',
            f'  <property name="guardsim_origin" value="{left:g},{top:g}"/>',
            " </properties>",
            ' <objectgroup id="1" name="boundary">',
            *objects,
            " </objectgroup>",
            ' <objectgroup id="2" name="walls">',
            *walls,
            " </objectgroup>",
            ' <objectgroup id="3" name="spawns">',
            *starts,
            " </objectgroup>",
            "</map>",
        ]
    ).encode("utf-8")
    routes = [
        [
            {**point, "x": point["x"] - left, "y": point["y"] - top}
            for point in waypoints(patrol, grid, guard, speed=speed)
        ]
        for guard in range(patrol.guards)
    ]
    properties = _properties(patrol, grid, speed)
    data = _tmx(target, skeleton, routes, properties, lambda path: path)
    if kind == "tmx":
        return data
    return _json_of_tmx(target, data)


def _json_of_tmx(target: str | os.PathLike[str], data: bytes) -> bytes:
    """Tiled's JSON form of a map written here as TMX (object layers only, as :func:`tiled_from_level`
    writes them)."""
    root = ElementTree.fromstring(data)

    def props(element: ElementTree.Element) -> list[dict[str, Any]]:
        out = []
        for prop in element.findall("properties/property"):
            kind = prop.get("type", "string")
            raw = prop.get("value", "")
            value: Any = int(raw) if kind == "int" else float(raw) if kind == "float" else raw
            out.append({"name": prop.get("name"), "type": kind, "value": value})
        return out

    def points(text: str) -> list[dict[str, float]]:
        pairs = (pair.split(",") for pair in text.split())
        return [{"x": float(x), "y": float(y)} for x, y in pairs]

    layers = []
    for group in root.findall("objectgroup"):
        objects = []
        for element in group.findall("object"):
            item: dict[str, Any] = {
                "id": int(element.get("id", "0")),
                "name": element.get("name", ""),
                "type": element.get("type", ""),
                "x": float(element.get("x", "0")),
                "y": float(element.get("y", "0")),
                "width": 0,
                "height": 0,
                "rotation": 0,
                "visible": True,
            }
            for shape in ("polygon", "polyline"):
                found = element.find(shape)
                if found is not None:
                    item[shape] = points(found.get("points", ""))
            if element.find("point") is not None:
                item["point"] = True
            if element.find("properties") is not None:
                item["properties"] = props(element)
            objects.append(item)
        layers.append(
            {
                "id": int(group.get("id", "0")),
                "name": group.get("name", ""),
                "type": "objectgroup",
                "draworder": "topdown",
                "opacity": 1,
                "visible": True,
                "x": 0,
                "y": 0,
                "objects": objects,
            }
        )
    tiled = {
        "type": "map",
        "version": "1.8",
        "tiledversion": "1.8.2",
        "orientation": "orthogonal",
        "renderorder": "right-down",
        "infinite": False,
        "compressionlevel": -1,
        **{
            key: int(root.get(key, "0"))
            for key in ("width", "height", "tilewidth", "tileheight", "nextlayerid", "nextobjectid")
        },
        "properties": props(root),
        "layers": layers,
        "tilesets": [],
    }
    return (json.dumps(tiled, indent=1) + "\n").encode("utf-8")


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
