"""Checking a level's cameras, lamps and ambient light: every problem named by its key path.

A camera or a lamp stands on the free area or on the boundary of a wall (a camera on a wall looks out
of it); inside a wall or off the level it is refused, as is a swing over 360 degrees or a lamp's
intensity outside (0, 1]. Each problem's location is the key path, e.g. ``cameras[2].position``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import shapely
from shapely.geometry import Polygon

from guardsim.files.reading import NumberError, excerpt, finite_number, json_type, quoted
from guardsim.level.model import Camera, Light, Point, Problem, Ring

__all__ = ["CAMERA_KEYS", "LIGHT_KEYS", "check_placements", "parse_ambient", "parse_cameras", "parse_lights"]

CAMERA_KEYS = (
    "position", "heading", "fov_degrees", "view_range", "sweep", "turn_speed", "pause", "detect_near", "detect_far",
)  # fmt: skip
LIGHT_KEYS = ("position", "radius", "intensity")


def _number(
    value: dict[str, Any],
    key: str,
    where: str,
    problems: list[Problem],
    default: float | None,
    *,
    positive: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
) -> float | None:
    if key not in value:
        return default
    try:
        return finite_number(value[key], positive=positive, minimum=minimum, maximum=maximum, magnitude=math.inf)
    except NumberError as error:
        problems.append(Problem(f"{where}.{key}", str(error)))
        return None


def _position(value: dict[str, Any], where: str, problems: list[Problem]) -> Point | None:
    point = value.get("position")
    if point is None:
        problems.append(Problem(f"{where}.position", "missing", "give [x, y] in world units"))
        return None
    if (
        not isinstance(point, list)
        or len(point) != 2
        or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in point)
    ):
        problems.append(Problem(f"{where}.position", f"must be [x, y], two numbers, not {excerpt(point, 40)}"))
        return None
    try:
        return (finite_number(point[0]), finite_number(point[1]))
    except NumberError as error:
        problems.append(Problem(f"{where}.position", f"coordinate {error}"))
        return None


def _objects(data: Any, key: str, known: tuple[str, ...], problems: list[Problem]) -> list[tuple[str, dict[str, Any]]]:
    # null is refused as the schema refuses it (an absent key is the default; null says neither 0 nor 1).
    if not isinstance(data, list):
        problems.append(Problem(key, f"must be a list of objects, not {json_type(data)}"))
        return []
    found = []
    for index, item in enumerate(data):
        where = f"{key}[{index}]"
        if not isinstance(item, dict):
            problems.append(Problem(where, f"must be an object, not {json_type(item)}"))
            continue
        for name in sorted(set(item) - set(known), key=str):
            shown = name if str(name).isprintable() and len(str(name)) <= 40 else quoted(name)
            problems.append(Problem(f"{where}.{shown}", "unknown key", f"known keys: {', '.join(known)}"))
        found.append((where, item))
    return found


def parse_cameras(data: Any, problems: list[Problem]) -> list[Camera] | None:
    """The ``cameras`` key: a list of :class:`Camera`, or ``None`` after adding problems."""
    count = len(problems)
    cameras = []
    for where, item in _objects(data, "cameras", CAMERA_KEYS, problems):
        position = _position(item, where, problems)
        numbers = {
            "heading": _number(item, "heading", where, problems, 0.0),
            "fov_degrees": _number(item, "fov_degrees", where, problems, 60.0, positive=True, maximum=360),
            "view_range": _number(item, "view_range", where, problems, None, positive=True),
            "sweep": _number(item, "sweep", where, problems, 0.0, minimum=0, maximum=360),
            "turn_speed": _number(item, "turn_speed", where, problems, 30.0, positive=True),
            "pause": _number(item, "pause", where, problems, 1.0, minimum=0),
            "detect_near": _number(item, "detect_near", where, problems, None, minimum=0),
            "detect_far": _number(item, "detect_far", where, problems, None, minimum=0),
        }
        if len(problems) == count and position is not None:
            cameras.append(Camera(position, **numbers))  # type: ignore[arg-type]
    return cameras if len(problems) == count else None


def parse_lights(data: Any, problems: list[Problem]) -> list[Light] | None:
    """The ``lights`` key: a list of :class:`Light`, or ``None`` after adding problems."""
    count = len(problems)
    lights = []
    for where, item in _objects(data, "lights", LIGHT_KEYS, problems):
        position = _position(item, where, problems)
        radius = _number(item, "radius", where, problems, None, positive=True)
        if radius is None and "radius" not in item:
            problems.append(Problem(f"{where}.radius", "missing", "give the distance at which its light fades to 0"))
        intensity = _number(item, "intensity", where, problems, 1.0, positive=True, maximum=1)
        if len(problems) == count and position is not None and radius is not None and intensity is not None:
            lights.append(Light(position, radius, intensity))
    return lights if len(problems) == count else None


def parse_ambient(data: dict[str, Any], problems: list[Problem]) -> float | None:
    """The ``ambient_light`` key, in [0, 1] (default 1 when absent)."""
    if "ambient_light" not in data:
        return 1.0
    value = data["ambient_light"]
    try:
        return finite_number(value, minimum=0, maximum=1)
    except NumberError as error:
        problems.append(Problem("ambient_light", str(error)))
        return None


def check_placements(
    outer: Ring, holes: list[Ring], cameras: list[Camera], lights: list[Light], problems: list[Problem]
) -> None:
    """Each camera and lamp on the free area or on a wall's boundary: off the level or inside a wall is a
    problem at ``cameras[i].position`` / ``lights[i].position``."""
    placed = [(f"cameras[{i}].position", c.position) for i, c in enumerate(cameras)]
    placed += [(f"lights[{i}].position", light.position) for i, light in enumerate(lights)]
    if not placed:
        return
    outer_polygon = Polygon(outer)
    hole_polygons = np.asarray([Polygon(hole) for hole in holes], dtype=object)
    for where, point in placed:
        spot = shapely.Point(point)
        shown = f"({point[0]:g}, {point[1]:g})"
        if not outer_polygon.covers(spot):
            problems.append(Problem(where, f"{shown} lies off the level", "place it on the floor or on a wall's edge"))
            continue
        if hole_polygons.size:
            inside = np.flatnonzero(shapely.contains_xy(hole_polygons, *point))
            if inside.size:
                problems.append(
                    Problem(
                        where, f"{shown} lies inside a wall (holes[{int(inside[0])}])", "move it onto the wall's edge"
                    )
                )
