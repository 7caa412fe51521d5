"""The level model: a 2D polygon with holes, a cell size and the guard's parameters.

A level is read from JSON (see ``docs/level-format.md``). :func:`check_level_data` collects every problem
in a level with its location; :func:`load_level` raises the first as a :class:`LevelError`.
Coordinates are world units with x to the right and y down, as in Tiled and image editors.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import shapely
from shapely.geometry import LinearRing, Polygon
from shapely.validation import explain_validity

from guardsim.errors import LevelError

__all__ = [
    "DEFAULT_MAX_CELLS",
    "DEFAULT_MAX_FILE_BYTES",
    "DEFAULT_MAX_VERTICES",
    "HEADINGS",
    "GuardSpec",
    "Level",
    "Problem",
    "check_level_data",
    "level_to_data",
    "load_level",
    "parse_level",
]

#: Largest grid (rows x cols) a level may produce unless the caller raises the cap.
DEFAULT_MAX_CELLS = 1_000_000
#: Largest number of vertices over all rings.
DEFAULT_MAX_VERTICES = 100_000
#: Largest level file read.
DEFAULT_MAX_FILE_BYTES = 16 * 1024 * 1024

#: Heading names and their angle in degrees; y points down, so 90 degrees is "down" on screen.
HEADINGS = {"right": 0, "down": 90, "left": 180, "up": 270}

Point = tuple[float, float]
Ring = tuple[Point, ...]

_TOP_KEYS = {"name", "cell_size", "outer", "holes", "guard", "starts"}
_GUARD_KEYS = {"view_range", "fov_degrees", "radius", "start", "heading"}


class Problem(NamedTuple):
    """One thing wrong with a level."""

    where: str
    """Location in the file, e.g. ``holes[1] point 4 (25, 30)``; empty for the whole file."""
    message: str
    """What is wrong."""
    hint: str = ""
    """How to fix it, when there is an obvious fix."""

    def __str__(self) -> str:
        text = f"{self.where}: {self.message}" if self.where else self.message
        return f"{text} ({self.hint})" if self.hint else text


@dataclass(frozen=True)
class GuardSpec:
    """The guard's body and vision cone."""

    view_range: float = 8.0
    """How far the guard sees, in world units."""
    fov_degrees: float = 90.0
    """Full opening angle of the vision cone."""
    radius: float = 0.3
    """Radius of the guard's circle; a cell is traversable only where the circle fits."""
    start: Point | None = None
    """Start position in world units; ``None`` lets the caller draw one."""
    heading: str | None = None
    """First heading (``right``, ``down``, ``left`` or ``up``); ``None`` draws one."""


@dataclass(frozen=True)
class Level:
    """A validated level."""

    name: str
    cell_size: float
    outer: Ring
    """Outer boundary, counter-clockwise on screen is not required: any orientation."""
    holes: tuple[Ring, ...] = ()
    """Walls inside the outer ring, each a closed ring."""
    guard: GuardSpec = field(default_factory=GuardSpec)
    starts: tuple[Point, ...] = ()
    """Designer-marked spawn points (optional)."""
    source: str = "<level>"
    """Where the level was read from, for messages."""

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(min_x, min_y, max_x, max_y)`` of the outer ring."""
        xs = [p[0] for p in self.outer]
        ys = [p[1] for p in self.outer]
        return min(xs), min(ys), max(xs), max(ys)

    def free_area(self) -> shapely.Geometry:
        """The free area (outer ring minus holes) as a valid shapely geometry.

        Holes may touch the outer ring or each other (walls attached to walls); the difference keeps
        the result valid where ``Polygon(outer, holes)`` would not be.
        """
        return _free_area(self.outer, self.holes)

    def grid_shape(self) -> tuple[int, int]:
        """``(rows, cols)`` of the coverage grid this level produces."""
        return _grid_shape(self.bounds, self.cell_size)


def _free_area(outer: Ring, holes: tuple[Ring, ...] | list[Ring]) -> shapely.Geometry:
    walls = shapely.union_all([Polygon(hole) for hole in holes]) if holes else None
    area = Polygon(outer)
    return area.difference(walls) if walls is not None else area


def _grid_shape(bounds: tuple[float, float, float, float], cell_size: float) -> tuple[int, int]:
    """``(rows, cols)``; a span too large for a float gives a huge count, which the cell cap rejects."""
    min_x, min_y, max_x, max_y = bounds
    counts = []
    for span in (max_y - min_y, max_x - min_x):
        cells = span / cell_size
        # A small epsilon keeps a 60-unit level at cell size 1 at 60 columns despite float noise.
        counts.append(max(1, math.ceil(cells - 1e-9)) if math.isfinite(cells) and cells < 1e18 else 10**18)
    return counts[0], counts[1]


def load_level(
    path: str | os.PathLike[str],
    *,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> Level:
    """Read and validate a level file.

    Raises
    ------
    LevelError
        With a message naming the file and the first problem found.
    """
    data = read_level_json(path, max_file_bytes=max_file_bytes)
    return parse_level(data, source=str(path), max_cells=max_cells, max_vertices=max_vertices)


def read_limited_bytes(path: str | os.PathLike[str], *, max_file_bytes: int, kind: str = "level file") -> bytes:
    """A file's bytes, every way of failing (missing, a folder, unreadable, too large) a one-line
    :class:`LevelError` naming the file; ``kind`` names what a folder is not (``level file``, ``map``)."""
    source = str(path)
    try:
        size = Path(path).stat().st_size
        if size > max_file_bytes:
            raise LevelError(
                f"{source}: file is {size} bytes, over the limit of {max_file_bytes} (raise it with --max-file-bytes)"
            )
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise LevelError(f"{source}: no such file") from None
    except IsADirectoryError:
        raise LevelError(f"{source}: is a directory, not a {kind}") from None
    except OSError as error:
        raise LevelError(f"{source}: cannot read: {error.strerror or error}") from None


def read_level_json(path: str | os.PathLike[str], *, max_file_bytes: int = DEFAULT_MAX_FILE_BYTES) -> Any:
    """Read a JSON file, turning every way it can fail into a :class:`LevelError`."""
    source = str(path)
    try:
        text = read_limited_bytes(path, max_file_bytes=max_file_bytes).decode("utf-8")
    except UnicodeDecodeError as error:
        raise LevelError(f"{source}: not UTF-8 text (byte {error.start})") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as error:
        raise LevelError(f"{source}: not valid JSON: {error.msg} at line {error.lineno} column {error.colno}") from None
    except RecursionError:
        raise LevelError(f"{source}: not valid JSON: nested too deeply") from None
    except ValueError as error:
        # e.g. an integer with more digits than Python converts by default.
        raise LevelError(f"{source}: not valid JSON: {error}") from None


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
    assert level is not None  # check_level_data returns a level whenever it reports no problem
    return level


def check_level_data(
    data: Any,
    *,
    source: str = "<level>",
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
) -> tuple[Level | None, list[Problem]]:
    """Check decoded level JSON and return the level (``None`` if invalid) and every problem found.

    Examples
    --------
    >>> level, problems = check_level_data({"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]})
    >>> level.grid_shape(), problems
    ((4, 4), [])
    >>> check_level_data({"outer": [[0, 0], [4, 0]]})[1][0].message
    'ring has 2 distinct points; a ring needs at least 3'
    """
    problems: list[Problem] = []
    if not isinstance(data, dict):
        return None, [Problem("", f"top level must be a JSON object, not {_json_type(data)}")]
    for key in sorted(set(data) - _TOP_KEYS, key=str):
        problems.append(Problem(f"key {key!r}", "unknown key", f"known keys: {', '.join(sorted(_TOP_KEYS))}"))

    name = data.get("name", Path(source).stem)
    if not isinstance(name, str):
        problems.append(Problem("name", f"must be a string, not {_json_type(name)}"))
        name = Path(source).stem
    cell_size = _number(data, "cell_size", 1.0, problems, positive=True)

    outer = _ring(data.get("outer"), "outer", problems, required=True)
    holes_data = data.get("holes", [])
    holes: list[Ring | None] = []
    if not isinstance(holes_data, list):
        problems.append(Problem("holes", f"must be a list of rings, not {_json_type(holes_data)}"))
    else:
        holes = [_ring(ring, f"holes[{index}]", problems, required=True) for index, ring in enumerate(holes_data)]

    guard = _guard(data.get("guard", {}), problems)
    starts = _points(data.get("starts", []), "starts", problems)

    vertex_count = (len(outer) if outer else 0) + sum(len(hole) for hole in holes if hole)
    if vertex_count > max_vertices:
        problems.append(
            Problem("", f"{vertex_count} vertices, over the limit of {max_vertices}", "raise it with --max-vertices")
        )
        return None, problems

    if outer is not None:
        _check_geometry(outer, holes, guard, starts, problems)
        if cell_size is not None:
            xs = [p[0] for p in outer]
            ys = [p[1] for p in outer]
            rows, cols = _grid_shape((min(xs), min(ys), max(xs), max(ys)), cell_size)
            if rows * cols > max_cells:
                problems.append(
                    Problem(
                        "cell_size",
                        f"grid of {rows} x {cols} = {rows * cols} cells is over the limit of {max_cells}",
                        "use a larger cell_size or raise the limit with --max-cells",
                    )
                )
    if problems or outer is None or cell_size is None or guard is None or starts is None:
        return None, problems
    level = Level(
        name=name,
        cell_size=cell_size,
        outer=outer,
        holes=tuple(hole for hole in holes if hole is not None),
        guard=guard,
        starts=tuple(starts),
        source=source,
    )
    return level, problems


def level_to_data(level: Level) -> dict[str, Any]:
    """The JSON-ready dictionary of a level (the inverse of :func:`parse_level`)."""
    guard: dict[str, Any] = {
        "view_range": level.guard.view_range,
        "fov_degrees": level.guard.fov_degrees,
        "radius": level.guard.radius,
    }
    if level.guard.start is not None:
        guard["start"] = list(level.guard.start)
    if level.guard.heading is not None:
        guard["heading"] = level.guard.heading
    data: dict[str, Any] = {
        "name": level.name,
        "cell_size": level.cell_size,
        "outer": [list(p) for p in level.outer],
        "holes": [[list(p) for p in hole] for hole in level.holes],
        "guard": guard,
    }
    if level.starts:
        data["starts"] = [list(p) for p in level.starts]
    return data


def _json_type(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


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
    where = where or key
    value = data.get(key, default)
    if not _is_number(value):
        problems.append(Problem(where, f"must be a number, not {_json_type(value)}"))
        return None
    try:
        value = float(value)
    except OverflowError:
        problems.append(Problem(where, "number too large"))
        return None
    if not math.isfinite(value):
        problems.append(Problem(where, f"must be a finite number, not {value}"))
        return None
    if positive and value <= 0:
        problems.append(Problem(where, f"must be positive, not {value:g}"))
        return None
    if minimum is not None and value < minimum:
        problems.append(Problem(where, f"must be at least {minimum:g}, not {value:g}"))
        return None
    if maximum is not None and value > maximum:
        problems.append(Problem(where, f"must be at most {maximum:g}, not {value:g}"))
        return None
    return value


def _point(value: Any, where: str, problems: list[Problem]) -> Point | None:
    if not isinstance(value, list):
        problems.append(Problem(where, f"a point must be a list [x, y], not {_json_type(value)}"))
        return None
    if len(value) != 2:
        problems.append(Problem(where, f"a point must be a list of 2 numbers [x, y], not of {len(value)} items"))
        return None
    if not all(_is_number(v) for v in value):
        problems.append(Problem(where, "a point's coordinates must be numbers"))
        return None
    try:
        x, y = float(value[0]), float(value[1])
    except OverflowError:
        problems.append(Problem(where, "coordinate too large"))
        return None
    if not (math.isfinite(x) and math.isfinite(y)):
        problems.append(Problem(where, f"coordinates must be finite numbers, not ({x}, {y})"))
        return None
    return (x, y)


def _points(value: Any, where: str, problems: list[Problem]) -> list[Point] | None:
    if not isinstance(value, list):
        problems.append(Problem(where, f"must be a list of points, not {_json_type(value)}"))
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
        problems.append(Problem(where, f"must be a list of [x, y] points, not {_json_type(value)}"))
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
        problems.append(Problem("guard", f"must be an object, not {_json_type(value)}"))
        return None
    count = len(problems)
    for key in sorted(set(value) - _GUARD_KEYS, key=str):
        # repr() for a key such as "\n" that would break the one-line message.
        where = f"guard.{key}" if str(key).isprintable() else f"guard.{key!r}"
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
        problems.append(Problem("guard.heading", f"must be one of {', '.join(HEADINGS)}, not {heading!r}"))
    if len(problems) > count or view_range is None or fov is None or radius is None:
        return None
    return GuardSpec(view_range=view_range, fov_degrees=fov, radius=radius, start=start, heading=heading)


def _fmt(point: tuple[float, float]) -> str:
    return f"({point[0]:g}, {point[1]:g})"


def _nearest_vertex(ring: Ring, x: float, y: float) -> int:
    return min(range(len(ring)), key=lambda i: (ring[i][0] - x) ** 2 + (ring[i][1] - y) ** 2)


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
        with np.errstate(all="ignore"):
            if _collinear(ring):
                return Problem(where, "ring encloses no area (all its points lie on one line)")
            if LinearRing(ring).is_simple:
                return None
            reason = explain_validity(Polygon(ring))
    except (shapely.errors.ShapelyError, ValueError) as error:
        return Problem(where, f"not a valid ring: {error}")
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


def _check_geometry(
    outer: Ring,
    holes: list[Ring | None],
    guard: GuardSpec | None,
    starts: list[Point] | None,
    problems: list[Problem],
) -> None:
    outer_problem = _ring_problem(outer, "outer")
    if outer_problem:
        problems.append(outer_problem)
        return
    outer_polygon = Polygon(outer)
    valid_holes: list[tuple[int, Polygon]] = []
    for index, hole in enumerate(holes):
        if hole is None:
            continue
        where = f"holes[{index}]"
        hole_problem = _ring_problem(hole, where)
        if hole_problem:
            problems.append(hole_problem)
            continue
        hole_polygon = Polygon(hole)
        if not outer_polygon.covers(hole_polygon):
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
    # designer drew. `guardsim import` merges them and says so.
    if len(valid_holes) > 1:
        polygons = [polygon for _, polygon in valid_holes]
        tree = shapely.STRtree(polygons)
        left, right = tree.query(polygons, predicate="intersects")
        for a, b in zip(left.tolist(), right.tolist()):
            if a >= b:
                continue
            overlap = polygons[a].intersection(polygons[b])
            if overlap.area > 0:
                point = overlap.representative_point()
                problems.append(
                    Problem(
                        f"holes[{valid_holes[a][0]}] and holes[{valid_holes[b][0]}]",
                        f"holes overlap near {_fmt((point.x, point.y))}",
                        "merge them into one ring",
                    )
                )
    free_area = _free_area(outer, [tuple(polygon.exterior.coords) for _, polygon in valid_holes])
    candidates: list[tuple[str, Point]] = []
    if guard is not None and guard.start is not None:
        candidates.append(("guard.start", guard.start))
    candidates += [(f"starts point {i}", p) for i, p in enumerate(starts or [])]
    for where, point in candidates:
        if not outer_polygon.covers(shapely.Point(point)):
            problems.append(Problem(f"{where} {_fmt(point)}", "start lies outside the level"))
        elif not free_area.contains(shapely.Point(point)):
            problems.append(Problem(f"{where} {_fmt(point)}", "start lies inside a wall"))
