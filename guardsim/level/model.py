"""The level model: a 2D polygon with holes, a cell size and the guard's parameters.

Coordinates are world units with x to the right and y down, as in Tiled and image editors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import shapely
from shapely.geometry import Polygon

__all__ = [
    "GAITS",
    "HEADINGS",
    "MAX_TILE_PIXELS",
    "Camera",
    "GuardSpec",
    "IntruderSpec",
    "Level",
    "Light",
    "Point",
    "Problem",
    "Ring",
    "free_area_of",
    "grid_shape_of",
]

#: Heading names and their angle in degrees; y points down, so 90 degrees is "down" on screen.
HEADINGS = {"right": 0, "down": 90, "left": 180, "up": 270}

Point = tuple[float, float]
Ring = tuple[Point, ...]


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
    move_speed: float | None = None
    """Continuous motion: walking speed, world units per second; ``None`` for guardsim.motion's default."""
    turn_speed: float | None = None
    """Continuous motion: turning speed, degrees per second; ``None`` for the default."""
    tick_hz: float | None = None
    """Continuous motion: physics ticks per second; ``None`` for the default."""
    detect_near: float = 0.25
    """Seconds in view before the guard detects an intruder standing at its feet (see guardsim.detection)."""
    detect_far: float = 1.5
    """Seconds in view before the guard detects an intruder at the edge of its view range."""
    forget: float = 4.0
    """Seconds for a full awareness meter to drain while the intruder is out of view."""
    suspicious: float = 0.5
    """Awareness level (0 to 1) at which the guard becomes suspicious."""
    capture_radius: float | None = None
    """Alert: world units within which a chasing guard captures the intruder; ``None``: one cell."""
    search_seconds: float = 30.0
    """Alert: seconds a guard searches after losing sight of the intruder before it gives up."""
    radio_delay: float = 2.0
    """Alert: seconds before a guard's detection reaches its teammates."""
    dark_sight: float = 1.0
    """World units within which the guard notices an intruder as in full light, however dark its cell."""
    chase_speed: float = 1.5
    """Alert: how much faster than walking a guard runs when it chases (on the grid, 1.5 is an extra step
    on alternate ticks)."""
    give_up_losses: int = 3
    """Alert: times a guard may lose sight of the intruder it chases; at the last loss it gives the chase
    up to a search and does not chase that intruder again."""


@dataclass(frozen=True)
class Camera:
    """A security camera: a watcher fixed at a point, its cone sweeping to and fro (see docs/cameras-light.md).

    At time 0 it faces ``heading - sweep / 2``, turns toward ``heading + sweep / 2`` at ``turn_speed``,
    waits ``pause``, turns back and waits ``pause`` again: a period of ``2 * (sweep / turn_speed + pause)``
    seconds. ``None`` for ``view_range``, ``detect_near`` or ``detect_far`` takes the guard's.

    Examples
    --------
    >>> Camera((4.0, 0.0), heading=90, sweep=60).period_seconds
    6.0
    """

    position: Point
    """World units; on the free area or on the boundary of a wall."""
    heading: float = 0.0
    """Degrees, the middle of the swing: 0 is +x, 90 is +y (down)."""
    fov_degrees: float = 60.0
    """Full opening angle of the cone."""
    view_range: float | None = None
    """How far it sees, world units; ``None``: the guard's."""
    sweep: float = 0.0
    """Total swing in degrees (0: fixed), at most 360."""
    turn_speed: float = 30.0
    """Degrees per second while turning."""
    pause: float = 1.0
    """Seconds at each end of the swing."""
    detect_near: float | None = None
    """Seconds in view before it detects an intruder at distance 0; ``None``: the guard's."""
    detect_far: float | None = None
    """Seconds in view before it detects an intruder at the edge of its range; ``None``: the guard's."""

    @property
    def period_seconds(self) -> float:
        """Seconds of one swing there and back (0 for a fixed camera)."""
        return 2 * (self.sweep / self.turn_speed + self.pause) if self.sweep > 0 else 0.0


@dataclass(frozen=True)
class Light:
    """A lamp: it lights the cells whose centres it sees within ``radius``, fading to 0 at the edge."""

    position: Point
    """World units."""
    radius: float
    """World units at which its light fades to 0."""
    intensity: float = 1.0
    """Light at its own position, in (0, 1]."""


#: The intruder's gaits: a walking step takes one tick, a sneaking step ``sneak_ticks``.
GAITS = ("walk", "sneak")


@dataclass(frozen=True)
class IntruderSpec:
    """The intruder's ears keys: how loud its steps are (the level's ``intruder`` object)."""

    walk_noise: float = 0.0
    """Radius in world units of a walking step's noise (0: silent)."""
    sneak_ticks: int = 2
    """Ticks a sneaking step takes (in its first cell for all but the last)."""
    sneak_noise: float = 0.0
    """Radius in world units of a sneaking step's noise."""


#: Largest tile side in pixels a level may record (``Level.tile_pixels``).
MAX_TILE_PIXELS = 4096


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
    intruder: IntruderSpec = field(default_factory=IntruderSpec)
    """The intruder's noise keys (hearing guards)."""
    """Designer-marked spawn points (optional)."""
    player_starts: tuple[Point, ...] = ()
    """Where the player (the intruder of ``sneak`` and ``alert``) starts, when the designer marks it."""
    source: str = "<level>"
    """Where the level was read from, for messages."""
    tile_pixels: tuple[int, int] | None = None
    """``(width, height)`` in pixels of a tile of the map the level was imported from (one tile is one
    world unit), for routes written in that map's pixels; ``None``: not known (a level drawn by hand)."""
    cameras: tuple[Camera, ...] = ()
    """Security cameras, watchers that never move (see :class:`Camera`)."""
    ambient_light: float = 1.0
    """Light everywhere, in [0, 1], before the lamps add theirs; 1 is full light (no darkness)."""
    lights: tuple[Light, ...] = ()
    """Lamps (see :class:`Light`)."""

    @property
    def lit(self) -> bool:
        """Whether every cell is in full light (ambient 1): light then changes nothing."""
        return self.ambient_light >= 1.0

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
        return free_area_of(self.outer, self.holes)

    def grid_shape(self) -> tuple[int, int]:
        """``(rows, cols)`` of the coverage grid this level produces."""
        return grid_shape_of(self.bounds, self.cell_size)


def free_area_of(outer: Ring, holes: tuple[Ring, ...] | list[Ring]) -> shapely.Geometry:
    """The outer ring's polygon minus the union of the holes' polygons.

    >>> free_area_of(((0, 0), (4, 0), (4, 4), (0, 4)), [((1, 1), (2, 1), (2, 2), (1, 2))]).area
    15.0
    """
    area = Polygon(outer)
    if not holes:
        return area
    # When the holes lie inside the outer ring and apart (touching at most at points), the polygon
    # with those holes is already the free area. Checking that costs a fraction of the union: GEOS
    # merges 24,000 disjoint holes in about 4 s, the polygon is checked in 0.2 s. It is built in one
    # call: Polygon(outer, holes) makes a Python object per hole (0.7 s for 24,000).
    coords = np.asarray([point for hole in holes for point in hole], dtype=float)
    which = np.repeat(np.arange(len(holes)), [len(hole) for hole in holes])
    rings = np.asarray(shapely.linearrings(coords, indices=which), dtype=object)
    direct = shapely.polygons(outer, holes=rings)
    if shapely.is_valid(direct):
        return direct
    return area.difference(shapely.union_all([Polygon(hole) for hole in holes]))


def grid_shape_of(bounds: tuple[float, float, float, float], cell_size: float) -> tuple[int, int]:
    """``(rows, cols)``; a span too large for a float gives a huge count, which the cell cap rejects."""
    min_x, min_y, max_x, max_y = bounds
    counts = []
    for span in (max_y - min_y, max_x - min_x):
        cells = span / cell_size
        # A small epsilon keeps a 60-unit level at cell size 1 at 60 columns despite float noise.
        counts.append(max(1, math.ceil(cells - 1e-9)) if math.isfinite(cells) and cells < 1e18 else 10**18)
    return counts[0], counts[1]
