"""The geometry checks of a level: simple rings, holes inside the outer ring and not overlapping, starts
on the free area; each problem located at the vertex or point it is about.

The overlap check of holes stops after :data:`MAX_OVERLAPS_LISTED` overlaps or a budget of pairs.
"""

from __future__ import annotations

import contextlib

import numpy as np
import shapely
from shapely.geometry import LinearRing, Polygon
from shapely.validation import explain_validity

from guardsim.files.reading import excerpt
from guardsim.level.model import GuardSpec, Point, Problem, Ring

__all__ = ["MAX_OVERLAPS_LISTED", "check_geometry"]

#: Overlapping pairs of holes reported before the check stops (a stack of identical holes has millions).
MAX_OVERLAPS_LISTED = 20


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


def check_geometry(
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
    # The holes lie inside the outer ring and apart, so the free area is the outer ring's area less
    # theirs, and a point is on it when it is inside the outer ring and on no hole: no union of the
    # holes is needed (GEOS takes seconds to merge ten thousand touching ones).
    kept = np.asarray([polygon for _, polygon in valid_holes], dtype=object)
    free = shapely.area(outer_polygon) - float(shapely.area(kept).sum()) if kept.size else shapely.area(outer_polygon)
    if valid_holes and free <= 1e-12 * shapely.area(outer_polygon):
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
        elif not outer_polygon.contains(shapely.Point(point)) or (
            kept.size and bool(shapely.intersects_xy(kept, *point).any())
        ):
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
