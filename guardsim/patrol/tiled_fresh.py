"""A fresh Tiled map for a level drawn by hand (``guardsim patrol --tiled-out`` without a source map).

One tile is one world unit (``tile_pixels`` pixels: the level's own :attr:`~guardsim.level.Level.tile_pixels`
when it records them, else 32). The level's outer ring is a ``boundary`` polygon,
its holes are polygons on a ``walls`` layer inside a wall border one tile wide, its starts are
``guard spawn`` points, and the ``guardsim`` layer holds the routes
(:mod:`guardsim.patrol.tiled_export`).
"""

from __future__ import annotations

import json
import math
import os
from typing import Any
from xml.etree import ElementTree

from guardsim.errors import PatrolError
from guardsim.grid import CoverageGrid
from guardsim.level import MAX_TILE_PIXELS, Level
from guardsim.patrol.export import DEFAULT_SPEED, guard_routes
from guardsim.patrol.model import Patrol
from guardsim.patrol.tiled_export import route_properties, tiled_kind, tmx_with_routes

__all__ = ["DEFAULT_TILE_PIXELS", "tiled_from_level"]

#: Pixels per tile (one world unit) in a map written for a level that has no source map.
DEFAULT_TILE_PIXELS = 32


def tiled_from_level(
    level: Level,
    target: str | os.PathLike[str],
    patrol: Patrol,
    grid: CoverageGrid,
    *,
    speed: float = DEFAULT_SPEED,
    tile_pixels: int | tuple[int, int] = DEFAULT_TILE_PIXELS,
    routes: list[dict[str, Any]] | None = None,
) -> bytes:
    """A fresh Tiled map (``.tmx``, or JSON for ``.tmj``/``.json``) of a level drawn without one, with
    tiles of ``tile_pixels`` pixels (one side, or ``(width, height)``).

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
    tile_width, tile_height = (tile_pixels, tile_pixels) if isinstance(tile_pixels, int) else tile_pixels
    for side in (tile_width, tile_height):
        if not (isinstance(side, int) and 1 <= side <= MAX_TILE_PIXELS):
            raise PatrolError(
                f"{target}: tile size must be a whole number of pixels from 1 to {MAX_TILE_PIXELS}, not {side}"
            )
    kind = tiled_kind(target)
    xs = [x for x, _ in level.outer]
    ys = [y for _, y in level.outer]
    # A wall border one tile wide keeps the level off the map's edges, where the importer would warn
    # that walls may be missing.
    left, top = min(xs) - 1, min(ys) - 1
    width = math.ceil(max(xs) - left - 1e-9) + 1
    height = math.ceil(max(ys) - top - 1e-9) + 1

    def ring(points: tuple[tuple[float, float], ...]) -> str:
        return " ".join(f"{(x - left) * tile_width:g},{(y - top) * tile_height:g}" for x, y in points)

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
        f'x="{(x - left) * tile_width:g}" y="{(y - top) * tile_height:g}"><point/></object>'
        for index, (x, y) in enumerate(level.starts or ((level.guard.start,) if level.guard.start else ()))
    ]
    from xml.sax.saxutils import quoteattr

    skeleton = "\n".join(
        [
            '<?xml version="1.0" encoding="UTF-8"?>',
            f'<map version="1.8" tiledversion="1.8.2" orientation="orthogonal" renderorder="right-down" '
            f'width="{width}" height="{height}" tilewidth="{tile_width}" tileheight="{tile_height}" infinite="0" '
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
        {
            **route,
            "waypoints": [{**point, "x": point["x"] - left, "y": point["y"] - top} for point in route["waypoints"]],
        }
        for route in (guard_routes(patrol, grid, speed=speed) if routes is None else routes)
    ]
    properties = route_properties(patrol, grid, speed)
    data = tmx_with_routes(target, skeleton, routes, properties, lambda path: path)
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
