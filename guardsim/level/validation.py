"""Checking decoded level JSON: every problem with its location, before any geometry is built.

:func:`check_level_data` collects every problem in a level; :func:`parse_level` raises the first as a
:class:`~guardsim.errors.LevelError`. Sizes are checked before the work they would cost: vertices are
counted on the raw lists, the grid is sized before any ring is tested, and the overlap check of holes
stops after :data:`MAX_OVERLAPS_LISTED` overlaps or a budget of pairs.
"""

from __future__ import annotations

import contextlib
import math
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from shapely.geometry import LinearRing, Polygon
from shapely.validation import explain_validity

from guardsim.errors import LevelError
from guardsim.level.limits import DEFAULT_MAX_CELLS, DEFAULT_MAX_VERTICES
from guardsim.level.model import HEADINGS, GuardSpec, Level, Point, Problem, Ring, free_area_of, grid_shape_of
from guardsim.reading import NumberError, captured_warnings, excerpt, finite_number, json_type, quoted, warning_note

__all__ = ["MAX_OVERLAPS_LISTED", "check_level_data", "parse_level"]

#: Longest level name: it starts every summary line.
MAX_NAME_CHARS = 200
#: Overlapping pairs of holes reported before the check stops (a stack of identical holes has millions).
MAX_OVERLAPS_LISTED = 20
#: Pairs of holes whose boxes meet examined per vertex allowed: past ``max_vertices`` times this, the
#: level is refused instead of checked pair by pair.
PAIRS_PER_VERTEX = 2

_TOP_KEYS = {"name", "cell_size", "outer", "holes", "guard", "starts", "player_starts"}
_MOTION_KEYS = ("move_speed", "turn_speed", "tick_hz")
_DETECTION_KEYS = ("detect_near", "detect_far", "forget", "suspicious")
_ALERT_KEYS = ("capture_radius", "search_seconds", "radio_delay")
_GUARD_KEYS = {"view_range", "fov_degrees", "radius", "start", "heading", *_MOTION_KEYS, *_DETECTION_KEYS, *_ALERT_KEYS}


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
        _check_geometry(outer, holes, guard, starts, problems, max_pairs=PAIRS_PER_VERTEX * max_vertices, players=players)
    if problems or outer is None or cell_size is None or guard is None or starts is None or players is None:
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
    )
    return level, problems


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
        key: _number(value, key, 1.0, problems, where=f"guard.{key}", positive=True)
        for key in _MOTION_KEYS
        if value.get(key) is not None
    }
    detection: dict[str, float] = {}
    for key in (*_DETECTION_KEYS, *_ALERT_KEYS):
        number = None
        if key in value:
            upper = 1 if key == "suspicious" else None
            number = _number(value, key, 0.0, problems, where=f"guard.{key}", minimum=0, maximum=upper)
        if number is not None:
            detection[key] = number
    if len(problems) > count or view_range is None or fov is None or radius is None:
        return None
    return GuardSpec(
        view_range=view_range, fov_degrees=fov, radius=radius, start=start, heading=heading, **motion, **detection
    )


def _fmt(point: tuple[float, float]) -> str:
    return f"({point[0]:g}, {point[1]:g})"


def _nearest_vertex(ring: Ring, x: float, y: float) -> int:
    points = np.asarray(ring, dtype=float)
    return int(np.argmin((points[:, 0] - x) ** 2 + (points[:, 1] - y) ** 2))


def _collinear(ring: Ring) -> bool:
    """Whether every point of a ring lies on one line (to within float noise)."""
    points = np.asarray(ring, dtype=float)
    offsets = points - points[0]
    extent = np.abs(offsets).max()
    if not 0 < extent < np.inf:
        return bool(extent == 0)
    # Scaled to at most 1 first, so that coordinates past 1e154 cannot overflow the cross products.
    unit = offsets / extent
    direction = unit[np.argmax(np.abs(unit).sum(axis=1))]
    cross = unit[:, 0] * direction[1] - unit[:, 1] * direction[0]
    return bool(np.all(np.abs(cross) <= 1e-12))


def _ring_problem(ring: Ring, where: str) -> Problem | None:
    """Why a ring is not a simple polygon boundary, located at the nearest vertex, or ``None``."""
    try:
        if _collinear(ring):
            return Problem(where, "ring encloses no area (all its points lie on one line)")
        if LinearRing(ring).is_simple:
            return None
        reason = explain_validity(Polygon(ring))
    except (shapely.errors.ShapelyError, ValueError) as error:
        return Problem(where, f"not a valid ring: {excerpt(str(error))}")
    # explain_validity reports e.g. "Self-intersection[12.5 3]"; point at the vertex nearest to it.
    x, y = ring[0]
    if "[" in reason:
        with contextlib.suppress(ValueError):
            x, y = (float(v) for v in reason[reason.index("[") + 1 : reason.index("]")].split()[:2])
    index = _nearest_vertex(ring, x, y)
    return Problem(
        f"{where} point {index} {_fmt(ring[index])}",
        f"ring crosses or touches itself near {_fmt((x, y))}",
        "split it into separate rings or move the point",
    )


def _hole_polygons(rings: list[Ring]) -> tuple[np.ndarray, np.ndarray]:
    """Every hole's polygon, built in one call, and which holes :func:`_ring_problem` must look at.

    A ring that is simple and encloses an area above float noise has no problem; only the others
    (crossing, touching or collinear) go through the per-ring check. One Python-level shapely call per
    hole cost about 0.2 ms each, seconds for a level of 24,000 holes.
    """
    if not rings:
        return np.empty(0, dtype=object), np.empty(0, dtype=bool)
    coords = np.asarray([point for ring in rings for point in ring], dtype=float)
    which = np.repeat(np.arange(len(rings)), [len(ring) for ring in rings])
    polygons = np.asarray(shapely.polygons(shapely.linearrings(coords, indices=which)), dtype=object)
    # A collinear ring (to _collinear's 1e-12 of its extent) encloses at most ~1e-11 of its extent
    # squared; 1e-9 leaves a wide margin, and a ring caught here only pays the exact check.
    xmin, ymin, xmax, ymax = shapely.bounds(polygons).T
    with np.errstate(over="ignore", invalid="ignore"):  # coordinates near 1e300: suspect, checked exactly
        extent = np.maximum(xmax - xmin, ymax - ymin)
        flat = ~(shapely.area(polygons) > 1e-9 * extent * extent)
    suspect = ~shapely.is_simple(shapely.get_exterior_ring(polygons)) | flat
    return polygons, suspect


def _check_geometry(
    outer: Ring,
    holes: list[Ring | None],
    guard: GuardSpec | None,
    starts: list[Point] | None,
    problems: list[Problem],
    *,
    max_pairs: int,
    players: list[Point] | None = None,
) -> None:
    outer_problem = _ring_problem(outer, "outer")
    if outer_problem:
        problems.append(outer_problem)
        return
    outer_polygon = Polygon(outer)
    shapely.prepare(outer_polygon)
    valid_holes: list[tuple[int, Polygon]] = []
    given = [(index, hole) for index, hole in enumerate(holes) if hole is not None]
    hole_polygons, suspect = _hole_polygons([hole for _, hole in given])
    # Only rings known to be simple are tested all at once: a predicate on a crossing ring may raise.
    covered = np.zeros(len(given), dtype=bool)
    covered[~suspect] = shapely.covers(outer_polygon, hole_polygons[~suspect])
    for (index, hole), hole_polygon, odd, inside in zip(given, hole_polygons, suspect, covered):
        where = f"holes[{index}]"
        if odd:
            hole_problem = _ring_problem(hole, where)
            if hole_problem:
                problems.append(hole_problem)
                continue
            inside = outer_polygon.covers(hole_polygon)
        if not inside:
            outside = next((i for i, p in enumerate(hole) if not outer_polygon.covers(shapely.Point(p))), None)
            if outside is None:
                problems.append(Problem(where, "hole crosses the outer ring", "keep holes inside the outer ring"))
            else:
                problems.append(
                    Problem(
                        f"{where} point {outside} {_fmt(hole[outside])}",
                        "hole point lies outside the outer ring",
                        "keep holes inside the outer ring",
                    )
                )
            continue
        valid_holes.append((index, hole_polygon))
    # Overlapping holes are rejected rather than merged: a silent merge would change the level the
    # designer drew. `guardsim import` and `guardsim validate --fix` merge them and say so.
    if len(valid_holes) > 1 and _overlap_problems(valid_holes, problems, max_pairs=max_pairs):
        return  # the free area of a stack of overlapping holes is not worth its cost: the level is invalid
    free_area = free_area_of(outer, [ring for index, _ in valid_holes if (ring := holes[index]) is not None])
    if valid_holes and shapely.area(free_area) <= 1e-12 * shapely.area(outer_polygon):
        problems.append(Problem("holes", "the holes cover the whole outer ring: the level has no free area"))
        return
    candidates: list[tuple[str, Point]] = []
    if guard is not None and guard.start is not None:
        candidates.append(("guard.start", guard.start))
    candidates += [(f"starts point {i}", p) for i, p in enumerate(starts or [])]
    candidates += [(f"player_starts point {i}", p) for i, p in enumerate(players or [])]
    for where, point in candidates:
        if not outer_polygon.covers(shapely.Point(point)):
            problems.append(Problem(f"{where} {_fmt(point)}", "start lies outside the level"))
        elif not shapely.contains(free_area, shapely.Point(point)):
            problems.append(Problem(f"{where} {_fmt(point)}", "start lies inside a wall"))


def _overlap_problems(valid_holes: list[tuple[int, Polygon]], problems: list[Problem], *, max_pairs: int) -> bool:
    """Add a problem per overlapping pair of holes (at most :data:`MAX_OVERLAPS_LISTED`); whether any.

    Pairs are taken hole by hole from an STRtree, never all at once: 33,000 identical holes would be
    544 million pairs. Identical rings are caught first by their sorted coordinates.
    """
    polygons = [polygon for _, polygon in valid_holes]
    found = 0
    first_of: dict[bytes, int] = {}
    for position, polygon in enumerate(polygons):
        key = np.sort(shapely.get_coordinates(polygon)[:-1], axis=0).tobytes()
        earlier = first_of.setdefault(key, position)
        if earlier != position:
            found += 1
            if found <= MAX_OVERLAPS_LISTED:
                problems.append(
                    Problem(
                        f"holes[{valid_holes[earlier][0]}] and holes[{valid_holes[position][0]}]",
                        "holes are the same ring",
                        "delete one of them",
                    )
                )
    if found > MAX_OVERLAPS_LISTED:
        problems.append(Problem("holes", f"{found - MAX_OVERLAPS_LISTED} more holes repeat an earlier ring"))
    if found:
        return True
    tree = shapely.STRtree(polygons)
    examined = 0
    for a, polygon in enumerate(polygons):
        others = tree.query(polygon, predicate="intersects")
        examined += len(others)
        if examined > max_pairs:
            problems.append(
                Problem(
                    "holes",
                    f"over {max_pairs} pairs of holes meet, more than the overlap check examines "
                    "(2 per vertex of max_vertices)",
                    "merge touching holes into larger rings",
                )
            )
            return True
        for b in sorted(int(other) for other in others):
            if a >= b:
                continue
            overlap = polygon.intersection(polygons[b])
            if overlap.area > 0:
                found += 1
                if found > MAX_OVERLAPS_LISTED:
                    problems.append(Problem("holes", "more holes overlap; the first ones are listed above"))
                    return True
                point = overlap.representative_point()
                problems.append(
                    Problem(
                        f"holes[{valid_holes[a][0]}] and holes[{valid_holes[b][0]}]",
                        f"holes overlap near {_fmt((point.x, point.y))}",
                        "merge them into one ring",
                    )
                )
    return found > 0
