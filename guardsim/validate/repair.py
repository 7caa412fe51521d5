"""Unambiguous repairs of a level file, for ``guardsim validate --fix OUT``.

A repair is made only where there is one right answer, and the free area it describes is unchanged:

* duplicate consecutive points and a repeated closing point are dropped;
* points in the middle of a straight edge are dropped;
* rings are oriented one way: the outer ring counter-clockwise and holes clockwise with y up
  (positive and negative shoelace area in file coordinates; on screen, with y down, the reverse);
* holes that overlap, or touch along an edge, are merged into one (cut open again where the merged
  wall would enclose a free pocket, see :func:`guardsim.importers.walls.hole_rings`);
* a hole ring that touches itself (without crossing) is split into simple rings, and an outer ring
  that touches itself around an enclosed area becomes the outer ring and a hole.

Everything else (a ring that crosses itself, a hole outside the outer ring, an unknown key, a wrong
type) needs the designer's decision and is left for ``guardsim validate`` to report.
"""

from __future__ import annotations

import copy
import math
from typing import Any, NamedTuple

import shapely
from shapely.geometry import LinearRing, Polygon

from guardsim.errors import LevelError
from guardsim.files.reading import NumberError, finite_number
from guardsim.importers.walls import hole_rings
from guardsim.level import compact_numbers

__all__ = ["MAX_PAIRS", "MAX_REPAIR_HOLES", "Repair", "repair_level_data"]

#: Most pairs of touching or overlapping holes the merge examines; past it, no hole is merged.
MAX_PAIRS = 20_000
#: Most holes a level may have for ``--fix``: the repairs are per ring in Python (about a millisecond
#: each), so 24 000 holes took a minute on a loaded machine. Levels that large come from importers,
#: which write clean rings; a hand-made one is repaired in its editor.
MAX_REPAIR_HOLES = 10_000

Point = tuple[float, float]
Ring = list[Point]


class Repair(NamedTuple):
    """One change made to a level."""

    where: str
    """The ring(s) changed, e.g. ``holes[2]`` or ``holes[0] and holes[3]``."""
    what: str
    """What was done."""

    def __str__(self) -> str:
        return f"{self.where}: {self.what}"


def repair_level_data(data: Any) -> tuple[Any, list[Repair]]:
    """A repaired copy of decoded level JSON and the repairs made (none if nothing was safe to do).

    Rings that are not lists of ``[x, y]`` number pairs are left alone: the loader reports them.

    Examples
    --------
    >>> fixed, repairs = repair_level_data({"outer": [[0, 0], [0, 4], [4, 4], [4, 2], [4, 0], [0, 0]]})
    >>> fixed["outer"], [str(r) for r in repairs]
    ([[0, 0], [4, 0], [4, 4], [0, 4]], ['outer: dropped 1 duplicate point', 'outer: dropped 1 point on a straight edge', 'outer: reversed to counter-clockwise (y up)'])
    """
    if not isinstance(data, dict):
        return data, []
    fixed = copy.deepcopy(data)
    repairs: list[Repair] = []
    outer = _read_ring(fixed.get("outer"))
    holes_data = fixed.get("holes", [])
    # Repeats of one ring cost nothing to drop (a ring written 33,000 times is repaired in a second);
    # the limit counts the different rings, whose merging is what grows.
    different = len({repr(hole) for hole in holes_data}) if isinstance(holes_data, list) else 0
    if different > MAX_REPAIR_HOLES:
        raise LevelError(
            f"--fix repairs levels of at most {MAX_REPAIR_HOLES} different holes and this one has {different}: "
            "repair it where it was made (guardsim validate without --fix lists its problems)"
        )
    read = [_read_ring(hole) for hole in holes_data] if isinstance(holes_data, list) else [None]
    if outer is None or len(_cleaned(outer, "outer", [])) < 3 or any(hole is None for hole in read):
        return fixed, []  # not rings of [x, y] numbers: the loader says what is wrong
    outer = _cleaned(outer, "outer", repairs)
    holes: list[tuple[str | None, Ring]] = [
        (f"holes[{i}]", _cleaned(hole, f"holes[{i}]", repairs)) for i, hole in enumerate(read) if hole is not None
    ]
    holes = _without_repeats(holes, repairs)
    outer, enclosed = _split_outer(outer, repairs)
    holes = _merged_holes(holes + [(None, hole) for hole in enclosed], Polygon(outer), repairs)
    outer = _oriented(outer, "outer", counter_clockwise=True, repairs=repairs)
    fixed["outer"] = compact_numbers([list(p) for p in outer])
    # Rings the merge produced are clockwise already; name them by their source for the rest.
    fixed["holes"] = compact_numbers(
        [
            [list(p) for p in (_oriented(hole, name, counter_clockwise=False, repairs=repairs) if name else hole)]
            for name, hole in holes
        ]
    )
    return fixed, repairs


def _read_ring(value: Any) -> Ring | None:
    """The points of a ring, or ``None`` if it is not a list of finite ``[x, y]`` numbers."""
    if not isinstance(value, list):
        return None
    points = []
    for item in value:
        if not (isinstance(item, list) and len(item) == 2):
            return None
        # Coordinates past the loader's bound are the loader's to report: GEOS loses every digit of the
        # level's size next to 1e40 and "repairs" the ring into another one. The loader's own parser
        # decides, so an integer no float holds (10**400) is left to it rather than raised here.
        try:
            points.append((finite_number(item[0]), finite_number(item[1])))
        except NumberError:
            return None
    return points


def _cleaned(ring: Ring, where: str, repairs: list[Repair]) -> Ring:
    """Drop duplicate points (and the closing point), then points in the middle of straight edges."""
    distinct: Ring = []
    for point in ring:
        if not distinct or point != distinct[-1]:
            distinct.append(point)
    while len(distinct) > 1 and distinct[0] == distinct[-1]:
        distinct.pop()
    if len(distinct) < len(ring):
        count = len(ring) - len(distinct)
        repairs.append(Repair(where, f"dropped {count} duplicate point{'s' if count != 1 else ''}"))
    # One pass with a stack (a point goes when it lies straight between the last kept point and the
    # next one), then the seam where the ring closes: linear, where deleting and rescanning was
    # quadratic (a 20,000-point ring took 14 s).
    straight: Ring = []
    for point in distinct:
        while len(straight) >= 2 and _passes_straight(straight[-2], straight[-1], point):
            straight.pop()
        straight.append(point)
    changed = True
    while changed and len(straight) > 3:
        changed = False
        if _passes_straight(straight[-2], straight[-1], straight[0]):
            straight.pop()
            changed = True
        elif _passes_straight(straight[-1], straight[0], straight[1]):
            straight.pop(0)
            changed = True
    if len(straight) < len(distinct):
        count = len(distinct) - len(straight)
        repairs.append(Repair(where, f"dropped {count} point{'s' if count != 1 else ''} on a straight edge"))
    return straight


def _ring_key(ring: Ring) -> tuple[Point, ...]:
    """The same tuple for every way of writing one ring: started at its least point, turning one way."""
    start = ring.index(min(ring))
    turned = ring[start:] + ring[:start]
    backwards = [turned[0], *turned[:0:-1]]
    return tuple(min(turned, backwards))


def _without_repeats(holes: list[tuple[str | None, Ring]], repairs: list[Repair]) -> list[tuple[str | None, Ring]]:
    """Holes that repeat an earlier hole's ring (in any start or direction) dropped: the walls are the same."""
    first: dict[tuple[Point, ...], str | None] = {}
    kept = []
    for name, ring in holes:
        if len(ring) < 3:
            kept.append((name, ring))
            continue
        earlier = first.setdefault(_ring_key(ring), name)
        if earlier is name:
            kept.append((name, ring))
    dropped = len(holes) - len(kept)
    if dropped:
        repairs.append(
            Repair("holes", f"dropped {dropped} hole{'s' if dropped != 1 else ''} repeating an earlier ring")
        )
    return kept


def _passes_straight(before: Point, here: Point, after: Point) -> bool:
    """Whether ``here`` lies on the segment from ``before`` to ``after`` (a spike back is not straight)."""
    ax, ay = here[0] - before[0], here[1] - before[1]
    bx, by = after[0] - here[0], after[1] - here[1]
    return ax * by - ay * bx == 0 and ax * bx + ay * by > 0


def _signed_area(ring: Ring) -> float:
    return sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring, ring[1:] + ring[:1])) / 2


def _oriented(ring: Ring, where: str, *, counter_clockwise: bool, repairs: list[Repair]) -> Ring:
    area = _signed_area(ring)
    if area == 0 or (area > 0) == counter_clockwise:
        return ring
    turn = "counter-clockwise" if counter_clockwise else "clockwise"
    repairs.append(Repair(where, f"reversed to {turn} (y up)"))
    return [ring[0], *ring[:0:-1]]


def _touches_itself_only(ring: Ring) -> bool:
    """Whether a non-simple ring only touches itself (the pieces keep one orientation) rather than crossing."""
    if len(ring) < 3 or LinearRing(ring).is_simple:
        return False
    valid = shapely.make_valid(Polygon(ring))
    return math.isclose(valid.area, abs(_signed_area(ring)), rel_tol=1e-9) and valid.area > 0


def _split_outer(outer: Ring, repairs: list[Repair]) -> tuple[Ring, list[Ring]]:
    """An outer ring touching itself around enclosed areas: the outer ring proper and those areas as holes."""
    if not _touches_itself_only(outer):
        return outer, []
    valid = shapely.make_valid(Polygon(outer))
    if not isinstance(valid, Polygon):
        return outer, []  # two rooms meeting at a point: which is the level is the designer's call
    holes = [[(float(x), float(y)) for x, y in interior.coords[:-1]] for interior in valid.interiors]
    repairs.append(
        Repair(
            "outer",
            f"split where it touches itself into the outer ring and {len(holes)} hole{'s' if len(holes) != 1 else ''}",
        )
    )
    # The pinch point is left in the middle of a straight edge; it goes as part of the split.
    exterior = _cleaned([(float(x), float(y)) for x, y in valid.exterior.coords[:-1]], "outer", [])
    return exterior, [_oriented(_cleaned(hole, "outer", []), "", counter_clockwise=False, repairs=[]) for hole in holes]


def _merged_holes(
    holes: list[tuple[str | None, Ring]], outer: Polygon, repairs: list[Repair]
) -> list[tuple[str | None, Ring]]:
    """Holes with self-touching ones split and overlapping or edge-touching ones merged (inside ``outer`` only).

    Each hole is ``(name, ring)``; rings made here have no name.
    """
    if not outer.is_valid:
        return holes
    polygons: list[shapely.Geometry | None] = []
    split: set[int] = set()
    for index, (name, hole) in enumerate(holes):
        if len(hole) >= 3 and LinearRing(hole).is_simple and Polygon(hole).area > 0:
            polygons.append(Polygon(hole))
        elif _touches_itself_only(hole) and outer.covers(valid := shapely.make_valid(Polygon(hole))):
            # Only inside the outer ring: a ring reaching far outside is the loader's to report.
            polygons.append(valid)
            split.add(index)
            repairs.append(Repair(name or "outer", "split where it touches itself"))
        else:
            polygons.append(None)
    groups = _groups(polygons, outer)
    result: list[tuple[str | None, Ring]] = []
    done: set[int] = set()
    for index, named in enumerate(holes):
        if index in done:
            continue
        group = groups.get(index, [index])
        done.update(group)
        if len(group) == 1 and index not in split:
            result.append(named)
            continue
        members: list[shapely.Geometry] = [shape for i in group if (shape := polygons[i]) is not None]
        rings, _ = hole_rings(members, outer)
        if (
            index not in split
            and len(rings) >= len(group)
            and shapely.area(shapely.union_all(members)) == sum(shapely.area(m) for m in members)
        ):
            # Walls that only share edges and cannot become fewer rings (a band cut open around a pocket) stay.
            result.extend(holes[i] for i in group)
            continue
        result.extend((None, list(ring)) for ring in rings)
        if len(group) > 1:
            names = " and ".join(holes[i][0] or "the area the outer ring enclosed" for i in group)
            count = "one hole" if len(rings) == 1 else f"{len(rings)} holes"
            repairs.append(Repair(names, f"merged (they overlap or share an edge) into {count}"))
    return result


def _groups(polygons: list[shapely.Geometry | None], outer: Polygon) -> dict[int, list[int]]:
    """Connected groups of holes that overlap or share an edge, each inside ``outer``; index -> its group."""
    usable = [i for i, p in enumerate(polygons) if p is not None and outer.covers(p)]
    parent = {i: i for i in usable}

    def root(i: int) -> int:
        while parent[i] != i:
            i = parent[i]
        return i

    if len(usable) < 2:
        return {}
    shapes: list[shapely.Geometry] = [shape for i in usable if (shape := polygons[i]) is not None]
    tree = shapely.STRtree(shapes)
    pairs: list[tuple[int, int]] = []
    for a, shape in enumerate(shapes):
        others = tree.query(shape, predicate="intersects")
        pairs += [(a, int(b)) for b in others if a < b]
        if len(pairs) > MAX_PAIRS:
            # A stack of thousands of overlapping holes: merging it is the designer's job; the check
            # in guardsim validate lists the first overlaps.
            return {}
    for a, b in pairs:
        first, second = polygons[usable[a]], polygons[usable[b]]
        shared = first.intersection(second)  # type: ignore[union-attr]
        if shared.area > 0 or shared.length > 0:
            parent[root(usable[a])] = root(usable[b])
    groups: dict[int, list[int]] = {}
    for i in usable:
        groups.setdefault(root(i), []).append(i)
    return {i: sorted(group) for group in groups.values() for i in group}
