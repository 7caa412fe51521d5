"""Checking decoded level JSON: every problem with its location, before any geometry is built.

:func:`check_level_data` collects every problem in a level; :func:`parse_level` raises the first as a
:class:`~guardsim.errors.LevelError`. Sizes are checked before the work they would cost: vertices are
counted on the raw lists, the grid is sized before any ring is tested, and the overlap check of holes
stops after :data:`~guardsim.level.geometry.MAX_OVERLAPS_LISTED` overlaps or a budget of pairs
(:mod:`guardsim.level.geometry` holds the geometry checks).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from guardsim.errors import LevelError
from guardsim.files.reading import (
    NumberError,
    captured_warnings,
    excerpt,
    finite_number,
    json_type,
    quoted,
    warning_note,
)
from guardsim.level.geometry import MAX_OVERLAPS_LISTED, check_geometry
from guardsim.level.limits import DEFAULT_MAX_CELLS, DEFAULT_MAX_VERTICES, MAX_SNEAK_TICKS, MAX_TICK_HZ
from guardsim.level.model import (
    HEADINGS,
    MAX_TILE_PIXELS,
    GuardSpec,
    IntruderSpec,
    Level,
    Point,
    Problem,
    Ring,
    grid_shape_of,
)
from guardsim.level.watchers import check_placements, parse_ambient, parse_cameras, parse_lights

__all__ = ["MAX_OVERLAPS_LISTED", "check_level_data", "parse_level"]

#: Longest level name: it starts every summary line.
MAX_NAME_CHARS = 200
#: Pairs of holes whose boxes meet examined per vertex allowed: past ``max_vertices`` times this, the
#: level is refused instead of checked pair by pair.
PAIRS_PER_VERTEX = 2

_TOP_KEYS = {
    "name", "cell_size", "outer", "holes", "guard", "starts", "player_starts", "tile_pixels",
    "cameras", "ambient_light", "lights", "intruder",
}  # fmt: skip
_INTRUDER_KEYS = ("walk_noise", "sneak_ticks", "sneak_noise")
_MOTION_KEYS = ("move_speed", "turn_speed", "tick_hz")
_DETECTION_KEYS = ("detect_near", "detect_far", "forget", "suspicious")
_ALERT_KEYS = ("capture_radius", "search_seconds", "radio_delay", "chase_speed", "give_up_losses")
_GUARD_KEYS = {
    "view_range", "fov_degrees", "radius", "start", "heading", *_MOTION_KEYS, *_DETECTION_KEYS, *_ALERT_KEYS,
    "dark_sight",
}  # fmt: skip


def parse_level(
    data: Any,
    *,
    source: str = "<level>",
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
) -> Level:
    """Build a :class:`Level` from decoded JSON, raising :class:`LevelError` on the first problem."""
    level, problems = check_level_data(data, source=source, max_cells=max_cells, max_vertices=max_vertices)
    if problems:
        more = f" (+{len(problems) - 1} more; run guardsim validate)" if len(problems) > 1 else ""
        raise LevelError(f"{source}: {problems[0]}{more}")
    if level is None:  # check_level_data returns a level whenever it reports no problem
        raise LevelError(f"{source}: not a level")
    return level


def check_level_data(
    data: Any,
    *,
    source: str = "<level>",
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
) -> tuple[Level | None, list[Problem]]:
    """Check decoded level JSON and return the level (``None`` if invalid) and every problem found.

    Warnings a geometry library raises on the way (an overflow inside GEOS) are not printed: they join
    the problem they explain, or are dropped when the level is valid.

    Examples
    --------
    >>> level, problems = check_level_data({"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]})
    >>> level.grid_shape(), problems
    ((4, 4), [])
    >>> check_level_data({"outer": [[0, 0], [4, 0]]})[1][0].message
    'ring has 2 distinct points; a ring needs at least 3'
    """
    with captured_warnings() as caught:
        level, problems = _check(data, source, max_cells, max_vertices)
    note = warning_note(caught)
    if problems and note:
        problems[0] = problems[0]._replace(message=problems[0].message + note)
    return level, problems


def _check(data: Any, source: str, max_cells: int, max_vertices: int) -> tuple[Level | None, list[Problem]]:
    problems: list[Problem] = []
    if not isinstance(data, dict):
        return None, [Problem("", f"top level must be a JSON object, not {json_type(data)}")]
    for key in sorted(set(data) - _TOP_KEYS, key=str):
        problems.append(Problem(f"key {quoted(key)}", "unknown key", f"known keys: {', '.join(sorted(_TOP_KEYS))}"))

    name = data.get("name", Path(source).stem)
    if not isinstance(name, str):
        problems.append(Problem("name", f"must be a string, not {json_type(name)}"))
        name = Path(source).stem
    elif len(name) > MAX_NAME_CHARS:
        # Every summary line starts with the name: a long one would be echoed whole.
        problems.append(Problem("name", f"is {len(name)} characters long; at most {MAX_NAME_CHARS}"))
        name = name[:MAX_NAME_CHARS]
    elif any(ord(char) < 32 or ord(char) == 127 for char in name):
        problems.append(
            Problem("name", f"must not contain control characters (line breaks, tabs): {excerpt(name, 40)}")
        )
    cell_size = _number(data, "cell_size", 1.0, problems, positive=True)

    # Counted on the raw lists, so that a million points are refused before one is converted.
    holes_data = data.get("holes", [])
    raw_rings = [data.get("outer")] + (holes_data if isinstance(holes_data, list) else [])
    vertex_count = sum(len(ring) for ring in raw_rings if isinstance(ring, list))
    if vertex_count > max_vertices:
        problems.append(Problem("", f"{vertex_count} vertices, over the limit of {max_vertices} (max_vertices)"))
        return None, problems

    outer = _ring(data.get("outer"), "outer", problems, required=True)
    holes: list[Ring | None] = []
    if not isinstance(holes_data, list):
        problems.append(Problem("holes", f"must be a list of rings, not {json_type(holes_data)}"))
    else:
        holes = [_ring(ring, f"holes[{index}]", problems, required=True) for index, ring in enumerate(holes_data)]

    guard = _guard(data.get("guard", {}), problems)
    starts = _points(data.get("starts", []), "starts", problems)
    players = _points(data.get("player_starts", []), "player_starts", problems)
    tile_pixels = _tile_pixels(data.get("tile_pixels"), problems)
    cameras = parse_cameras(data.get("cameras", []), problems)
    lights = parse_lights(data.get("lights", []), problems)
    ambient = parse_ambient(data, problems)
    intruder = _intruder(data.get("intruder", {}), problems)

    if outer is not None and cell_size is not None:
        xs = [p[0] for p in outer]
        ys = [p[1] for p in outer]
        rows, cols = grid_shape_of((min(xs), min(ys), max(xs), max(ys)), cell_size)
        if rows * cols > max_cells:
            problems.append(
                Problem(
                    "cell_size",
                    f"grid of {rows} x {cols} = {rows * cols} cells is over the limit of {max_cells} (max_cells)",
                    "use a larger cell_size or raise the limit",
                )
            )
            return None, problems
    if outer is not None:
        check_geometry(
            outer, holes, guard, starts, problems, max_pairs=PAIRS_PER_VERTEX * max_vertices, players=players
        )
        if not problems and cameras is not None and lights is not None:
            check_placements(outer, [hole for hole in holes if hole is not None], cameras, lights, problems)
    if problems or outer is None or cell_size is None or guard is None or starts is None or players is None:
        return None, problems
    if cameras is None or lights is None or ambient is None or intruder is None:
        return None, problems
    level = Level(
        name=name,
        cell_size=cell_size,
        outer=outer,
        holes=tuple(hole for hole in holes if hole is not None),
        guard=guard,
        starts=tuple(starts),
        player_starts=tuple(players),
        source=source,
        tile_pixels=tile_pixels,
        cameras=tuple(cameras),
        ambient_light=ambient,
        lights=tuple(lights),
        intruder=intruder,
    )
    return level, problems


def _intruder(value: Any, problems: list[Problem]) -> IntruderSpec | None:
    """``intruder``: its noise keys (radii >= 0 world units; ``sneak_ticks`` a whole number from 1 to
    :data:`~guardsim.level.limits.MAX_SNEAK_TICKS`)."""
    if not isinstance(value, dict):
        problems.append(Problem("intruder", f"must be an object, not {json_type(value)}"))
        return None
    count = len(problems)
    for key in sorted(set(value) - set(_INTRUDER_KEYS), key=str):
        where = f"intruder.{key}" if str(key).isprintable() and len(str(key)) <= 40 else f"intruder.{quoted(key)}"
        problems.append(Problem(where, "unknown key", f"known keys: {', '.join(_INTRUDER_KEYS)}"))
    defaults = IntruderSpec()
    walk = _number(value, "walk_noise", defaults.walk_noise, problems, where="intruder.walk_noise", minimum=0)
    sneak = _number(value, "sneak_noise", defaults.sneak_noise, problems, where="intruder.sneak_noise", minimum=0)
    ticks = _number(
        value,
        "sneak_ticks",
        defaults.sneak_ticks,
        problems,
        where="intruder.sneak_ticks",
        minimum=1,
        maximum=MAX_SNEAK_TICKS,
    )
    if ticks is not None and ticks != int(ticks):
        problems.append(Problem("intruder.sneak_ticks", f"must be a whole number of ticks, not {ticks!r}"))
    if len(problems) > count or walk is None or sneak is None or ticks is None:
        return None
    return IntruderSpec(walk_noise=walk, sneak_ticks=int(ticks), sneak_noise=sneak)


def _tile_pixels(value: Any, problems: list[Problem]) -> tuple[int, int] | None:
    """``tile_pixels``: absent, or ``[width, height]``, whole numbers of pixels from 1 to 4096."""
    if value is None:
        return None
    if (
        isinstance(value, list)
        and len(value) == 2
        and all(isinstance(side, int | float) and not isinstance(side, bool) for side in value)
        and all(side == int(side) and 1 <= side <= MAX_TILE_PIXELS for side in value)
    ):
        return int(value[0]), int(value[1])
    problems.append(
        Problem(
            "tile_pixels",
            f"must be [width, height], whole numbers of pixels from 1 to {MAX_TILE_PIXELS}, not {excerpt(value, 40)}",
        )
    )
    return None


def _number(
    data: dict[str, Any],
    key: str,
    default: float,
    problems: list[Problem],
    *,
    where: str | None = None,
    positive: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
) -> float | None:
    try:
        # Any finite size: a view range of 1e300 means "sees everything"; only coordinates are capped.
        return finite_number(
            data.get(key, default), positive=positive, minimum=minimum, maximum=maximum, magnitude=math.inf
        )
    except NumberError as error:
        problems.append(Problem(where or key, str(error)))
        return None


def _point(value: Any, where: str, problems: list[Problem]) -> Point | None:
    if not isinstance(value, list):
        problems.append(Problem(where, f"a point must be a list [x, y], not {json_type(value)}"))
        return None
    if len(value) != 2:
        problems.append(Problem(where, f"a point must be a list of 2 numbers [x, y], not of {len(value)} items"))
        return None
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        problems.append(Problem(where, f"a point's coordinates must be numbers, not {excerpt(value, 60)}"))
        return None
    try:
        return (finite_number(value[0]), finite_number(value[1]))
    except NumberError as error:
        problems.append(Problem(where, f"coordinate {error}"))
        return None


def _points(value: Any, where: str, problems: list[Problem]) -> list[Point] | None:
    if not isinstance(value, list):
        problems.append(Problem(where, f"must be a list of points, not {json_type(value)}"))
        return None
    points = [_point(item, f"{where} point {index}", problems) for index, item in enumerate(value)]
    if any(p is None for p in points):
        return None
    return [p for p in points if p is not None]


def _ring(value: Any, where: str, problems: list[Problem], *, required: bool) -> Ring | None:
    if value is None and required:
        problems.append(Problem(where, "missing", "give a list of [x, y] points"))
        return None
    if not isinstance(value, list):
        problems.append(Problem(where, f"must be a list of [x, y] points, not {json_type(value)}"))
        return None
    points: list[Point] = []
    for index, item in enumerate(value):
        point = _point(item, f"{where} point {index}", problems)
        if point is None:
            return None
        points.append(point)
    # Consecutive duplicates and an explicit closing point carry no shape; drop them.
    distinct: list[Point] = []
    for point in points:
        if not distinct or point != distinct[-1]:
            distinct.append(point)
    if len(distinct) > 1 and distinct[0] == distinct[-1]:
        distinct.pop()
    if len(distinct) < 3:
        problems.append(Problem(where, f"ring has {len(distinct)} distinct points; a ring needs at least 3"))
        return None
    return tuple(distinct)


def _guard(value: Any, problems: list[Problem]) -> GuardSpec | None:
    if not isinstance(value, dict):
        problems.append(Problem("guard", f"must be an object, not {json_type(value)}"))
        return None
    count = len(problems)
    for key in sorted(set(value) - _GUARD_KEYS, key=str):
        # An excerpt for a key such as "\n" that would break the one-line message, or one of 100 KB.
        where = f"guard.{key}" if str(key).isprintable() and len(str(key)) <= 40 else f"guard.{quoted(key)}"
        problems.append(Problem(where, "unknown key", f"known keys: {', '.join(sorted(_GUARD_KEYS))}"))
    defaults = GuardSpec()
    view_range = _number(value, "view_range", defaults.view_range, problems, where="guard.view_range", positive=True)
    fov = _number(
        value, "fov_degrees", defaults.fov_degrees, problems, where="guard.fov_degrees", positive=True, maximum=360
    )
    radius = _number(value, "radius", defaults.radius, problems, where="guard.radius", minimum=0)
    start = None
    if "start" in value and value["start"] is not None:
        start = _point(value["start"], "guard.start", problems)
    heading = value.get("heading")
    if heading is not None and (not isinstance(heading, str) or heading not in HEADINGS):
        problems.append(
            Problem(
                "guard.heading",
                f"must be one of {', '.join(HEADINGS)}, not {quoted(heading) if isinstance(heading, str) else excerpt(heading, 40)}",
            )
        )
    motion: dict[str, Any] = {
        key: _number(
            value, key, 1.0, problems, where=f"guard.{key}", positive=True,
            maximum=MAX_TICK_HZ if key == "tick_hz" else None,
        )
        for key in _MOTION_KEYS
        if value.get(key) is not None
    }  # fmt: skip
    detection: dict[str, Any] = {}
    for key in (*_DETECTION_KEYS, *_ALERT_KEYS, "dark_sight"):
        number = None
        if key in value:
            upper = 1 if key == "suspicious" else None
            if key in ("chase_speed", "give_up_losses"):
                # A guard must move when it chases, and lose sight at least once before giving up.
                number = _number(value, key, 1.0, problems, where=f"guard.{key}", positive=True)
                if key == "give_up_losses" and number is not None:
                    if number != int(number):
                        problems.append(Problem(f"guard.{key}", f"must be a whole number of losses, not {number!r}"))
                        number = None
                    else:
                        number = int(number)
            else:
                number = _number(value, key, 0.0, problems, where=f"guard.{key}", minimum=0, maximum=upper)
        if number is not None:
            detection[key] = number
    if len(problems) > count or view_range is None or fov is None or radius is None:
        return None
    return GuardSpec(
        view_range=view_range, fov_degrees=fov, radius=radius, start=start, heading=heading, **motion, **detection
    )
