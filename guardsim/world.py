"""The physics world: a level turned into a real :class:`pymunk.Space`.

Every edge of the outer ring and of each hole is a static segment shape; the guard is a kinematic body
with a circle shape. All geometric questions the rest of guardsim asks (can the guard stand here, can it
move there, can it see that) are pymunk queries against the walls only.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from guardsim.errors import ArgumentError
from guardsim.level import Level

__all__ = ["GUARD_CATEGORY", "WALL_CATEGORY", "World"]

WALL_CATEGORY = 0b01
GUARD_CATEGORY = 0b10
# Queries see walls and never the guard's own circle.
_WALLS_ONLY = pymunk.ShapeFilter(mask=WALL_CATEGORY)
# In a caller's space the walls keep the caller's filters: query everything, keep the walls.
_ANYTHING = pymunk.ShapeFilter()


class World:
    """A pymunk space holding a level's walls and one guard.

    Parameters
    ----------
    level
        The level whose rings become wall segments.
    space
        A space the caller owns (a game's own), to build in instead of a new one. The level's walls are
        added to it as static segments on its static body, unless ``walls_in_space`` is true.
    walls_in_space
        With ``space``: the space already holds the walls as static segment shapes; take those (every
        static :class:`pymunk.Segment` of the space) instead of adding the level's. Other shapes in the
        space (the game's own bodies) never block the guard's sight or moves.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> world = World(parse_level({"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]}))
    >>> len(world.walls), world.line_of_sight((1, 1), (3, 3)), world.line_of_sight((1, 1), (5, 1))
    (4, True, False)
    """

    def __init__(self, level: Level, *, space: pymunk.Space | None = None, walls_in_space: bool = False) -> None:
        self.level = level
        min_x, min_y, max_x, max_y = level.bounds
        # Touching a wall is allowed; a gap this much (relative to the level's size) short of the radius is
        # rounding in decimal coordinates (5.5 - 5.2 = 0.29999999999999982), so it counts as touching.
        self.touch = 1e-9 * max(1.0, max_x - min_x, max_y - min_y)
        self.space = pymunk.Space() if space is None else space
        self.walls: list[pymunk.Segment] = []
        # In a space of guardsim's own, walls and the guard are all there is, so a first hit is a wall.
        self._shared = space is not None
        if walls_in_space:
            if space is None:
                raise ArgumentError("walls_in_space needs the space that holds the walls")
            self.walls = [
                shape
                for shape in space.shapes
                if isinstance(shape, pymunk.Segment)
                and shape.body is not None
                and shape.body.body_type == pymunk.Body.STATIC
            ]
        else:
            for ring in (level.outer, *level.holes):
                for index, start in enumerate(ring):
                    end = ring[(index + 1) % len(ring)]
                    segment = pymunk.Segment(self.space.static_body, start, end, 0.0)
                    segment.filter = pymunk.ShapeFilter(categories=WALL_CATEGORY)
                    self.walls.append(segment)
            # Added in a scrambled (fixed) order: Chipmunk's box tree degenerates when fed the segments of
            # a long ring in order (100,000 in order took 90 s to add, scrambled under a second).
            order = np.random.default_rng(0).permutation(len(self.walls))
            self.space.add(*(self.walls[index] for index in order.tolist()))
        self._wall_set = set(self.walls)
        self.guard_body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.guard_shape = pymunk.Circle(self.guard_body, max(level.guard.radius, 1e-6))
        self.guard_shape.filter = pymunk.ShapeFilter(categories=GUARD_CATEGORY)
        self.space.add(self.guard_body, self.guard_shape)

    def line_of_sight(self, eye: tuple[float, float], target: tuple[float, float]) -> bool:
        """Whether the segment from ``eye`` to ``target`` touches no wall.

        A ray that passes exactly through a wall vertex counts as blocked; a ray running along a wall
        edge (collinear with it) does not, as pymunk reports no hit for it.
        """
        if not self._shared:
            return self.space.segment_query_first(eye, target, 0.0, _WALLS_ONLY) is None
        return not any(hit.shape in self._wall_set for hit in self.space.segment_query(eye, target, 0.0, _ANYTHING))

    def fits(self, point: tuple[float, float], radius: float) -> bool:
        """Whether a circle of ``radius`` at ``point`` overlaps no wall (touching one is allowed)."""
        if radius <= 0:
            return True
        if not self._shared:
            return self.space.point_query_nearest(point, radius - self.touch, _WALLS_ONLY) is None
        return not any(
            hit.shape in self._wall_set and hit.distance < radius - self.touch
            for hit in self.space.point_query(point, radius, _ANYTHING)
        )

    def sweep_clear(self, start: tuple[float, float], end: tuple[float, float], radius: float) -> bool:
        """Whether a circle of ``radius`` can slide from ``start`` to ``end`` overlapping no wall.

        Touching a wall is allowed, as in :meth:`fits`: the move is blocked only by a wall closer to the
        path than ``radius``, whichever way it is walked. Each wall whose box overlaps the swept box is
        measured on its own: the space's segment query with a radius prunes walls by the bare centre
        line's box and would miss a ledge the circle grazes.
        """
        box = pymunk.BB(
            min(start[0], end[0]) - radius,
            min(start[1], end[1]) - radius,
            max(start[0], end[0]) + radius,
            max(start[1], end[1]) + radius,
        )
        for wall in self.space.bb_query(box, _ANYTHING if self._shared else _WALLS_ONLY):
            if wall not in self._wall_set or not isinstance(wall, pymunk.Segment):
                continue
            if (
                _segments_cross(start, end, wall.a, wall.b)
                or _segment_distance(start, end, wall.a, wall.b) < radius - self.touch
            ):
                return False
        return True

    def place_guard(self, point: tuple[float, float]) -> None:
        """Move the guard's body to ``point`` (a cell centre) and let the space know."""
        self.guard_body.position = point
        self.space.reindex_shapes_for_body(self.guard_body)


def _point_segment_distance(point: tuple[float, float], start: tuple[float, float], end: tuple[float, float]) -> float:
    """Euclidean distance from ``point`` to the segment from ``start`` to ``end``."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    length_squared = dx * dx + dy * dy
    t = 0.0 if length_squared == 0 else ((point[0] - start[0]) * dx + (point[1] - start[1]) * dy) / length_squared
    t = min(1.0, max(0.0, t))
    return math.hypot(point[0] - (start[0] + t * dx), point[1] - (start[1] + t * dy))


def _orientation(a: tuple[float, float], b: tuple[float, float], c: tuple[float, float]) -> float:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _segments_cross(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float], d: tuple[float, float]
) -> bool:
    """Whether segments ab and cd properly cross (each strictly separates the other's ends)."""
    return _orientation(a, b, c) * _orientation(a, b, d) < 0 and _orientation(c, d, a) * _orientation(c, d, b) < 0


def _segment_distance(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float], d: tuple[float, float]
) -> float:
    """Distance between segments ab and cd that do not properly cross."""
    return min(
        _point_segment_distance(a, c, d),
        _point_segment_distance(b, c, d),
        _point_segment_distance(c, a, b),
        _point_segment_distance(d, a, b),
    )
