"""What a guard sees, as a polygon: its vision cone clipped by the walls, from pymunk ray casts.

The simulation marks a cell seen when the segment from the eye to the cell's centre is clear, within the
view range and the field of view. The region of all such points is the *visibility polygon* cut to the
cone's wedge; drawing it shows exactly where the guard can see, never through a wall nor off the map.

It is found by casting rays with the world's segment queries: evenly spaced rays across the wedge (so
the arc at the view range is round), and a pair of rays just either side of every wall vertex in range
and in the wedge (so the shadow edges fall exactly at the corners that cast them). Each ray stops at the
first wall it meets.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from guardsim.world import WALL_CATEGORY, World

__all__ = ["SightCaster"]

#: Angle between evenly spaced rays, in degrees: the arc at the view range is drawn as a polygon with
#: this step (an error under 0.05 % of the range).
ARC_STEP_DEGREES = 2.0
#: Rays at wall vertices are cast this far either side of the vertex, in radians.
_VERTEX_NUDGE = 1e-4
_WALLS_ONLY = pymunk.ShapeFilter(mask=WALL_CATEGORY)


class SightCaster:
    """Visibility polygons in one level's world.

    Parameters
    ----------
    world
        The level's physics world; only its wall segments are queried.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> level = parse_level({"outer": [[0, 0], [10, 0], [10, 10], [0, 10]],
    ...                      "holes": [[[4, 4], [6, 4], [6, 6], [4, 6]]]})
    >>> caster = SightCaster(World(level))
    >>> polygon = caster.polygon((2.0, 5.0), 0.0, 90.0, 20.0)
    >>> max(x for x, _ in polygon) < 10.0 + 1e-9  # the outer wall stops every ray
    True
    """

    def __init__(self, world: World) -> None:
        self.space = world.space
        rings = (world.level.outer, *world.level.holes)
        self.vertices = np.asarray([point for ring in rings for point in ring], dtype=float).reshape(-1, 2)

    def polygon(
        self, eye: tuple[float, float], heading_degrees: float, fov_degrees: float, view_range: float
    ) -> list[tuple[float, float]]:
        """The region the guard at ``eye`` sees, as a ring of world points in angle order.

        ``heading_degrees`` runs clockwise on screen from +x (y points down). Below 360 degrees the eye
        is the ring's first point; at 360 degrees the ring goes round it.
        """
        full = fov_degrees >= 360
        half = math.pi if full else math.radians(fov_degrees) / 2
        centre = math.radians(heading_degrees)
        steps = max(2, math.ceil(2 * math.degrees(half) / ARC_STEP_DEGREES))
        offsets = [-half + 2 * half * k / steps for k in range(steps + (0 if full else 1))]
        offsets.extend(self._vertex_offsets(eye, centre, half, view_range, full))
        offsets.sort()
        ring = [] if full else [eye]
        for offset in offsets:
            angle = centre + offset
            end = (eye[0] + view_range * math.cos(angle), eye[1] + view_range * math.sin(angle))
            hit = self.space.segment_query_first(eye, end, 0.0, _WALLS_ONLY)
            ring.append(end if hit is None else (float(hit.point.x), float(hit.point.y)))
        return ring

    def _vertex_offsets(
        self, eye: tuple[float, float], centre: float, half: float, view_range: float, full: bool
    ) -> list[float]:
        """Angle offsets from the heading of the rays just either side of each vertex in the cone."""
        if not len(self.vertices):
            return []
        delta = self.vertices - np.asarray(eye)
        distance = np.hypot(delta[:, 0], delta[:, 1])
        near = (distance <= view_range) & (distance > 0)
        angles = np.arctan2(delta[near, 1], delta[near, 0]) - centre
        angles = (angles + math.pi) % (2 * math.pi) - math.pi
        angles = np.concatenate([angles - _VERTEX_NUDGE, angles + _VERTEX_NUDGE])
        if not full:
            angles = angles[np.abs(angles) < half]
        return sorted({round(float(a), 12) for a in angles})
