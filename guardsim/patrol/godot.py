"""A patrol as a Godot scene (``guardsim patrol --godot OUT.tscn``): one ``Path2D`` per guard.

The scene's root is a ``Node2D`` named after the level; under it, per guard, a ``Path2D`` (``Guard1``,
``Guard2``, ...) whose ``Curve2D`` holds the route's waypoints (:func:`guardsim.patrol.export.guard_routes`)
in pixels, y down as in Godot, and under each a ``PathFollow2D`` named ``Follow`` (``loop`` on for a
looping route, ``rotate`` off, linear interpolation so that it stays on the route's straight legs).

Each ``Path2D`` carries the route's timing as metadata: ``guard``, ``loop_mode`` (``loop``,
``ping-pong`` or ``once``), ``phase`` and ``period`` (seconds), ``speed`` (pixels per second), and per
curve point ``times`` (arrival, seconds), ``waits`` (seconds standing there) and ``headings`` (degrees
on arrival, Godot's rotation: 0 along +x, 90 along +y). ``examples/godot/`` has a follower script for
Godot 4 and 3 that plays it (it measures each point's ``offset``/``progress`` on the curve Godot bakes,
which cuts sharp turns by up to a pixel); ``tests/test_godot_export.py`` loads the Godot 3 scene in
real Godot and checks the follower's positions against route.json.

Points are the map's pixels for a level imported from a Tiled map (one tile is one world unit), else
world units times ``pixels_per_unit`` (:data:`DEFAULT_PIXELS_PER_UNIT` unless told).
"""

from __future__ import annotations

import json
import re
from typing import Any

from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.patrol.export import DEFAULT_SPEED, RouteFrame, guard_routes
from guardsim.patrol.model import Patrol

__all__ = ["DEFAULT_PIXELS_PER_UNIT", "GODOT_VERSIONS", "godot_scene"]

#: Pixels per world unit for a level with no map behind it (Tiled's usual tile size).
DEFAULT_PIXELS_PER_UNIT = 32.0
GODOT_VERSIONS = (3, 4)


def _number(value: float) -> str:
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _floats(values: list[float], version: int) -> str:
    kind = "PackedFloat32Array" if version == 4 else "PoolRealArray"
    inner = ", ".join(_number(value) for value in values)
    return f"{kind}({inner})" if version == 4 else f"{kind}( {inner} )"


def _value(value: Any, version: int) -> str:
    if isinstance(value, list):
        return _floats(value, version)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    text = _number(float(value))
    return text if "." in text else f"{text}.0"  # a float in Godot's eyes


def _metadata(values: dict[str, Any], version: int) -> list[str]:
    if version == 4:
        return [f"metadata/{name} = {_value(value, version)}" for name, value in values.items()]
    lines = ",\n".join(f"{json.dumps(name)}: {_value(value, version)}" for name, value in values.items())
    return ["__meta__ = {", lines, "}"]


def _node_name(text: str) -> str:
    """A Godot node name: the characters Godot refuses (. : @ / " %) replaced."""
    name = re.sub(r'[.:@/"%\s]+', "_", text).strip("_")
    return name or "Patrol"


def godot_scene(
    patrol: Patrol,
    grid: CoverageGrid,
    *,
    level: str,
    speed: float = DEFAULT_SPEED,
    pixels_per_unit: tuple[float, float] = (DEFAULT_PIXELS_PER_UNIT, DEFAULT_PIXELS_PER_UNIT),
    version: int = 4,
    routes: list[dict[str, Any]] | None = None,
) -> str:
    """The text of a ``.tscn`` scene holding the patrol (see the module docstring); ``routes`` are
    :func:`~guardsim.patrol.export.guard_routes` (or cleaned ones) when given.

    Examples
    --------
    >>> import numpy as np
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 3), dtype=bool), np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]]))
    >>> lap = Patrol(np.array([[0 * 4 + 2, 1 * 4 + 0, 2 * 4 + 0, 1 * 4 + 2]]), 4, "loop")
    >>> scene = godot_scene(lap, grid, level="Strip", version=3)
    >>> print(scene.splitlines()[5])
    "points": PoolVector2Array( 0, 0, 0, 0, 16, 16, 0, 0, 0, 0, 80, 16 )
    """
    if version not in GODOT_VERSIONS:
        raise ArgumentError(f"Godot version must be 3 or 4, not {version}")
    frame = RouteFrame("pixels", "y-down", pixels_per_unit, grid.cell_size)
    seconds_per_tick = grid.cell_size / speed
    if routes is None:
        routes = guard_routes(patrol, grid, speed=speed)
    resources: list[str] = []
    nodes: list[str] = []
    root = _node_name(level)
    root_meta: dict[str, Any] = {
        "guardsim_level": level,
        "pixels_per_unit": list(pixels_per_unit),
        "seconds_per_tick": seconds_per_tick,
    }
    nodes += ["", f'[node name="{root}" type="Node2D"]', *_metadata(root_meta, version)]
    for number, route in enumerate(routes, start=1):
        points = [frame.point(point["x"], point["y"]) for point in route["waypoints"]]
        flat = ", ".join(_number(v) for x, y in points for v in (0.0, 0.0, 0.0, 0.0, x, y))
        ident = str(number) if version == 3 else f'"Curve2D_{number}"'
        resource = [
            "",
            f'[sub_resource type="Curve2D" id={ident}]',
            "bake_interval = 1.0",
            "_data = {",
            f'"points": PackedVector2Array({flat})' if version == 4 else f'"points": PoolVector2Array( {flat} )',
            "}",
        ]
        if version == 4:
            resource.append(f"point_count = {len(points)}")
        resources += resource
        meta = {
            "guard": number,
            "loop_mode": route["loop_mode"],
            "phase": route["phase"],
            "period": -1.0 if route["period"] is None else route["period"],
            "speed": frame.speed(speed) or speed * pixels_per_unit[0],
            "times": [point["time"] for point in route["waypoints"]],
            "waits": [point["wait"] for point in route["waypoints"]],
            "headings": [point["heading"] for point in route["waypoints"]],
        }
        curve = f"SubResource( {number} )" if version == 3 else f'SubResource("Curve2D_{number}")'
        nodes += [
            "",
            f'[node name="Guard{number}" type="Path2D" parent="."]',
            f"curve = {curve}",
            *_metadata(meta, version),
        ]
        follow = [
            "",
            f'[node name="Follow" type="PathFollow2D" parent="Guard{number}"]',
            f"loop = {'true' if route['loop_mode'] == 'loop' else 'false'}",
            "rotates = false" if version == 4 else "rotate = false",
            "cubic_interp = false",
        ]
        nodes += follow
    header = f"[gd_scene load_steps={len(routes) + 1} format={3 if version == 4 else 2}]"
    return "\n".join([header, *resources, *nodes]) + "\n"
