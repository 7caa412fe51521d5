"""A patrol for a game or an engine: waypoints per guard (route.json), and where a guard is at any time.

route.json (``guardsim patrol --export``) lists each guard's waypoints: the points where its motion
changes (a turn, a stop, a start), straight runs merged. Each waypoint has its arrival ``tick`` and
``time`` (seconds at ``speed``), the ``heading`` on arrival in degrees, and ``wait``, the seconds the
guard stands there before walking on (with ``scan``, the headings it faces in turn, when it turns on the
spot). Per guard: ``loop_mode`` (``loop``: the last waypoint is the first again, one period later;
``ping-pong``: walk to the last waypoint, then back through the same waypoints and waits, the period
being there and back; ``once``: a patrol that does not repeat) and ``phase``, the seconds along the
route the guard is at time 0 (a team sharing one cycle gets the same waypoints and evenly spaced
phases). :func:`position_at` is the rule every exporter and test replays.

Points are in world units with y down unless a :class:`RouteFrame` says otherwise (pixels or tiles,
y up). The Tiled layer is :mod:`guardsim.patrol.tiled_export`, the Godot scene :mod:`guardsim.patrol.godot`.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from guardsim.errors import PatrolError
from guardsim.grid import CoverageGrid
from guardsim.patrol.model import Patrol

__all__ = [
    "AXES",
    "DEFAULT_SPEED",
    "UNITS",
    "RouteFrame",
    "guard_routes",
    "position_at",
    "route_data",
    "waypoints",
]

#: World units per second a guard walks at unless told otherwise (a walking pace when a unit is a metre).
DEFAULT_SPEED = 2.0
#: The units route points can be written in, and the two axis conventions.
UNITS = ("world", "pixels", "tiles")
AXES = ("y-down", "y-up")


def _dedupe(values: list[float]) -> list[float]:
    kept: list[float] = []
    for value in values:
        if not kept or kept[-1] != value:
            kept.append(value)
    return kept


def waypoints(patrol: Patrol, grid: CoverageGrid, guard: int, *, speed: float = DEFAULT_SPEED) -> list[dict[str, Any]]:
    """Guard ``guard``'s own waypoints in world units, y down (see the module docstring).

    Examples
    --------
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 3), dtype=bool), np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]]))
    >>> lap = Patrol(np.array([[0 * 4 + 2, 1 * 4 + 0, 2 * 4 + 0, 2 * 4 + 0, 1 * 4 + 2]]), 5, "loop")
    >>> [(w["x"], w["tick"], w["heading"], w["wait"]) for w in waypoints(lap, grid, 0)]
    [(0.5, 0, 180.0, 0.0), (2.5, 2, 0.0, 0.5), (0.5, 5, 180.0, 0.0)]
    """
    cells = patrol.cells(grid, guard)
    headings = patrol.headings(guard)
    if patrol.period is not None:
        cells.append(cells[0])
        headings.append(headings[0])
    seconds_per_tick = grid.cell_size / speed
    # What each tick's move is: a heading, or -1 for standing.
    kinds = [headings[index + 1] if cells[index + 1] != cells[index] else -1 for index in range(len(cells) - 1)]
    kept = [0] + [index for index in range(1, len(cells) - 1) if kinds[index - 1] != kinds[index]]
    if len(cells) > 1:
        kept.append(len(cells) - 1)
    points: list[dict[str, Any]] = []
    for number, index in enumerate(kept):
        if number > 0 and kinds[kept[number - 1]] == -1 and index != kept[-1]:
            continue  # the end of a stand is its start's wait, not a waypoint of its own
        x, y = grid.centre(*cells[index])
        point: dict[str, Any] = {
            "x": round(x, 6),
            "y": round(y, 6),
            "tick": index,
            "time": round(index * seconds_per_tick, 6),
            "heading": float(90 * headings[index]),
            "wait": 0.0,
        }
        if index < len(kinds) and kinds[index] == -1:
            until = kept[number + 1]
            point["wait"] = round((until - index) * seconds_per_tick, 6)
            scan = _dedupe([float(90 * heading) for heading in headings[index : until + 1]])
            if len(scan) > 1:
                point["scan"] = scan
        points.append(point)
    return points


def _shift(states: np.ndarray, first: np.ndarray) -> int | None:
    """Ticks ``s`` with ``states[t] == first[(t + s) % period]`` for every ``t``, if any."""
    for shift in np.flatnonzero(first == states[0]).tolist():
        if np.array_equal(np.roll(first, -shift), states):
            return int(shift)
    return None


def _ping_pong(points: list[dict[str, Any]]) -> list[dict[str, Any]] | None:
    """The outward half of a closed route that walks back the way it came, with the same waits."""
    last = len(points) - 1
    if last < 2 or last % 2 or points[last]["wait"] != 0.0:
        return None
    middle = last // 2
    for index in range(middle + 1):
        there, back = points[index], points[last - index]
        if (there["x"], there["y"]) != (back["x"], back["y"]):
            return None
        if 0 < index < middle and (there["wait"] != back["wait"] or there.get("scan") != back.get("scan")):
            return None

    def leg(index: int) -> float:
        return float(points[index + 1]["time"] - points[index]["time"] - points[index]["wait"])

    if not np.allclose(
        [leg(index) for index in range(middle)], [leg(last - 1 - index) for index in range(middle)], atol=1e-6
    ):
        return None
    return points[: middle + 1]


def _as_ping_pong(
    patrol: Patrol, grid: CoverageGrid, guard: int, speed: float
) -> tuple[list[dict[str, Any]], int] | None:
    """The outward half of a lap that walks back the way it came, and the tick the half starts at."""
    assert patrol.period is not None
    cells = np.asarray(patrol.states[guard]) // 4
    if _shift(cells[::-1], cells) is None:
        return None  # the cells, read backwards, are not the same cycle
    arrivals = [0, *np.flatnonzero(cells != np.roll(cells, 1)).tolist()]
    for start in dict.fromkeys(arrivals):
        lap = Patrol(np.roll(patrol.states[guard], -start)[None, :], patrol.period, patrol.strategy)
        outward = _ping_pong(waypoints(lap, grid, 0, speed=speed))
        if outward is not None:
            return outward, start
    return None


def guard_routes(patrol: Patrol, grid: CoverageGrid, *, speed: float = DEFAULT_SPEED) -> list[dict[str, Any]]:
    """Each guard's route: ``loop_mode``, ``period`` and ``phase`` (seconds), and ``waypoints`` (world
    units, y down).

    A guard whose lap is the first guard's lap started later shares its waypoints, with a phase; a
    closed route that walks back the way it came is written once, as ``ping-pong``.
    """
    seconds_per_tick = grid.cell_size / speed
    routes: list[dict[str, Any]] = []
    for guard in range(patrol.guards):
        if patrol.period is None:
            points = waypoints(patrol, grid, guard, speed=speed)
            routes.append({"loop_mode": "once", "phase": 0.0, "waypoints": points})
            continue
        shift = None if guard == 0 else _shift(patrol.states[guard], patrol.states[0])
        start = 0
        if shift is not None:
            # The first guard's route, ``shift`` ticks further on.
            start = routes[0]["start"] - shift
            route = {**routes[0]}
        else:
            half = _as_ping_pong(patrol, grid, guard, speed)
            if half is not None:
                route = {"loop_mode": "ping-pong", "waypoints": half[0]}
                start = half[1]
            else:
                route = {"loop_mode": "loop", "waypoints": waypoints(patrol, grid, guard, speed=speed)}
        # The route starts at the guard's tick ``start``: at time 0 the guard is ``-start`` ticks along it.
        route["start"] = start
        route["phase"] = round((-start % patrol.period) * seconds_per_tick, 6)
        routes.append(route)
    period = None if patrol.period is None else round(patrol.period * seconds_per_tick, 6)
    return [
        {"loop_mode": route["loop_mode"], "period": period, "phase": route["phase"], "waypoints": route["waypoints"]}
        for route in routes
    ]


def position_at(route: dict[str, Any], seconds: float) -> tuple[float, float]:
    """Where a guard following ``route`` (one of :func:`guard_routes`) is ``seconds`` after time 0.

    Between waypoints the guard walks straight at a constant pace; it stands ``wait`` seconds at each;
    a ``loop`` or ``ping-pong`` route repeats every ``period`` seconds.
    """
    points = route["waypoints"]
    period = route["period"]
    time = seconds + route["phase"]
    mode = route["loop_mode"]
    if mode != "once":
        if period is None or not period > 0:
            raise PatrolError(f"a {mode} route needs a positive period")
        time %= period
    if mode == "ping-pong":
        turn = points[-1]["time"] + points[-1]["wait"]
        if time > turn:
            time = points[-1]["time"] - (time - turn)
    times = [point["time"] for point in points]
    index = max(0, bisect.bisect_right(times, time) - 1)
    here = points[index]
    if index == len(points) - 1 or time <= here["time"] + here["wait"]:
        return here["x"], here["y"]
    after = points[index + 1]
    leave = here["time"] + here["wait"]
    share = (time - leave) / (after["time"] - leave)
    return here["x"] + share * (after["x"] - here["x"]), here["y"] + share * (after["y"] - here["y"])


@dataclass(frozen=True)
class RouteFrame:
    """The units and axis route points are written in.

    ``pixels`` multiplies world units by ``pixels_per_unit`` (x, y: a Tiled map's tile size, as one tile
    is one world unit); ``tiles`` divides by the level's ``cell_size`` (grid cells); ``y-up`` negates y
    (and headings turn the other way: 90 is then along +y, up).

    Examples
    --------
    >>> RouteFrame("pixels", "y-up", (16.0, 16.0)).point(2.5, 1.0)
    (40.0, -16.0)
    >>> RouteFrame("world", "y-up").heading(90.0)
    270.0
    """

    units: str = "world"
    axis: str = "y-down"
    pixels_per_unit: tuple[float, float] = (32.0, 32.0)
    cell_size: float = 1.0

    def __post_init__(self) -> None:
        if self.units not in UNITS:
            raise PatrolError(f"units must be one of {', '.join(UNITS)}, not {self.units!r}")
        if self.axis not in AXES:
            raise PatrolError(f"axis must be one of {', '.join(AXES)}, not {self.axis!r}")
        if not all(math.isfinite(v) and v > 0 for v in (*self.pixels_per_unit, self.cell_size)):
            raise PatrolError("pixels per unit and cell size must be positive numbers")

    @property
    def scale(self) -> tuple[float, float]:
        """Output units per world unit along x and y."""
        if self.units == "pixels":
            return self.pixels_per_unit
        if self.units == "tiles":
            return 1.0 / self.cell_size, 1.0 / self.cell_size
        return 1.0, 1.0

    def point(self, x: float, y: float) -> tuple[float, float]:
        sx, sy = self.scale
        y = y * sy
        return round(x * sx, 6), round(-y if self.axis == "y-up" else y, 6) + 0.0

    def heading(self, degrees: float) -> float:
        return (-degrees) % 360.0 if self.axis == "y-up" else degrees

    def speed(self, speed: float) -> float | None:
        """A speed in output units per second, or ``None`` when x and y scale differently."""
        sx, sy = self.scale
        return round(speed * sx, 6) if sx == sy else None


def _framed(route: dict[str, Any], frame: RouteFrame) -> dict[str, Any]:
    points = []
    for point in route["waypoints"]:
        x, y = frame.point(point["x"], point["y"])
        moved = {**point, "x": x, "y": y, "heading": frame.heading(point["heading"])}
        if "scan" in point:
            moved["scan"] = [frame.heading(value) for value in point["scan"]]
        points.append(moved)
    return {**route, "waypoints": points}


def route_data(
    patrol: Patrol,
    grid: CoverageGrid,
    *,
    level: str,
    speed: float = DEFAULT_SPEED,
    frame: RouteFrame | None = None,
    routes: list[dict[str, Any]] | None = None,
) -> dict[str, Any]:
    """The JSON-ready route.json of a patrol, its points in ``frame`` (world units, y down by default);
    ``routes`` are :func:`guard_routes` (or cleaned ones, :mod:`guardsim.patrol.cleaning`) when given."""
    if routes is None:
        routes = guard_routes(patrol, grid, speed=speed)
    frame = frame or RouteFrame(cell_size=grid.cell_size)
    seconds_per_tick = grid.cell_size / speed
    data: dict[str, Any] = {
        "level": level,
        "units": frame.units,
        "axis": frame.axis,
    }
    if frame.units == "pixels":
        data["pixels_per_unit"] = list(frame.pixels_per_unit)
    data.update(
        {
            "speed": frame.speed(speed),
            "world_speed": speed,
            "seconds_per_tick": seconds_per_tick,
            "period_ticks": patrol.period,
            "period_seconds": None if patrol.period is None else round(patrol.period * seconds_per_tick, 6),
            "repeats": patrol.period is not None,
            "guards": [_framed(route, frame) for route in routes],
        }
    )
    return data
