"""Intruders to play against the guards: a scripted route, a sneaking planner, an evader, a hider.

Each moves up to its speed in cells a tick (fractions accumulate), one 4-connected step at a time,
before the guards move. ``goal`` is the cell it wants to reach (-1: none); on reaching it the intruder
leaves the level.

**Gaits.** A walking step takes one of those moves; a sneaking step from ``a`` to ``b`` takes
``sneak_ticks`` of them, the intruder in ``a`` for all but the last and in ``b`` at the last. Every step
is recorded where and when it lands (:attr:`Intruder.landed`), for the episode's ears. A ``route``
intruder walks unless its route gives a step the ``sneak`` gait; the others walk.

- ``route``: walks a given path (or the shortest path to its goal) without stopping, chased or not.
- ``sneak``: walks the fastest path no guard of the patrol sees (the sneak check's search; the closest
  call when there is none), entering the level at the tick its path starts (outside until then: no
  guard sees or catches it); chased, it flees
  as the evader does, then walks the shortest path to its goal once no guard is alarmed.
- ``evader``: walks the shortest path to its goal; chased, it makes for the cell it reaches first whose
  distance from every guard is largest, waits there while guards are alarmed, then resumes. With a
  ``run_speed`` it runs while chased: that many cells a tick instead of ``speed`` (its steps are walking
  steps, as loud).
- ``still``: stays where it is put.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple, TypeVar

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.kernels.distances import FAR, distances_from
from guardsim.kernels.steps import greedy_step

if TYPE_CHECKING:
    from guardsim.grid import CoverageGrid

__all__ = [
    "Distraction",
    "Intruder",
    "RouteCells",
    "RouteFile",
    "make_intruder",
    "read_route_cells",
    "read_route_file",
    "read_route_points",
    "route_of_path",
]


_Cell = TypeVar("_Cell")


class Intruder:
    """An intruder of one of the kinds of :data:`guardsim.alert.model.INTRUDERS`."""

    def __init__(
        self,
        kind: str,
        neighbours: np.ndarray,
        cell: int,
        *,
        goal: int = -1,
        route: Sequence[int] | None = None,
        speed: float = 1.0,
        wait_until: int = 0,
        gaits: Sequence[str] | None = None,
        sneak_ticks: int = 2,
        run_speed: float | None = None,
    ) -> None:
        self.kind = kind
        self.neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
        self.cell = int(cell)
        self.goal = int(goal)
        self.speed = float(speed)
        self.run_speed = None if run_speed is None else float(run_speed)
        self.ran = 0
        """Moves the intruder had this tick when it ran (an evader chased, with a ``run_speed``), else 0."""
        self.heading = 0
        self.gone = False
        """Whether it reached its goal and left."""
        self._credit = 0.0
        self._route = [int(c) for c in route] if route is not None else None
        # gaits[i]: the gait of the step into route[i] (the first, the entry, has none).
        self._gaits = list(gaits) if gaits is not None and route is not None else None
        if self._route is not None and self._route and self._route[0] == self.cell:
            self._route = self._route[1:]
            if self._gaits is not None:
                self._gaits = self._gaits[1:]
        self.sneak_ticks = int(sneak_ticks)
        self._sneaking = 0
        """Moves spent so far on the sneaking step under way."""
        self.landed: list[tuple[int, str]] = []
        """The steps that landed in the last tick: ``(cell, gait)``."""
        self._wait_until = wait_until
        self.present = wait_until <= 0
        """Whether it is in the level: a ``sneak`` intruder enters at its entry at tick ``wait_until`` (the
        lap tick its unseen path starts), and leaves at its goal."""
        self._fled = False
        self._hide = -1
        self._goal_field: np.ndarray | None = None

    def advance(self, tick: int, guard_cells: Sequence[int], chased: bool, alarmed: bool) -> None:
        """Move for tick ``tick``: ``chased`` when some guard chases it, ``alarmed`` when some guard is
        chasing or searching."""
        self.landed = []
        self.ran = 0
        if self.gone or self.kind == "still":
            return
        if not self.present:
            # Outside until the tick its path starts, when it stands at its entry; it moves from the next.
            self.present = tick >= self._wait_until
            return
        running = self.kind == "evader" and chased and self.run_speed is not None
        self._credit += self.run_speed if running and self.run_speed is not None else self.speed
        while self._credit >= 1.0 - 1e-9 and not self.gone:
            self._credit -= 1.0
            self.ran += 1 if running else 0
            if self._next_gait() == "sneak" and self._sneaking < self.sneak_ticks - 1:
                self._sneaking += 1  # still in the cell it sneaks from
                continue
            gait = self._next_gait()
            nxt = self._next(tick, guard_cells, chased, alarmed)
            self._sneaking = 0
            if nxt < 0 or nxt == self.cell:
                continue
            self.heading = int(np.flatnonzero(self.neighbours[self.cell] == nxt)[0])
            self.cell = nxt
            self.landed.append((nxt, gait))
            if self.cell == self.goal:
                self.gone = True
                self.present = False

    def _next(self, tick: int, guard_cells: Sequence[int], chased: bool, alarmed: bool) -> int:
        if self.kind == "route":
            return self._along_route()
        if self.kind == "sneak":
            if chased:
                self._fled = True
                return self._flee(guard_cells)
            if self._fled:
                return -1 if alarmed else self._towards_goal()
            return self._along_route()
        # evader
        if chased:
            self._hide = self._hiding_cell(guard_cells)
        if self._hide >= 0:
            if alarmed:
                return self._step_to(self._hide) if self.cell != self._hide else -1
            self._hide = -1
        return self._towards_goal()

    def _next_gait(self) -> str:
        """The gait of the next step: a route's own (a ``sneak`` intruder's planned path, until it flees),
        else walking."""
        if (self.kind == "route" or (self.kind == "sneak" and not self._fled)) and self._route and self._gaits:
            return self._gaits[0]
        return "walk"

    def _along_route(self) -> int:
        if self._route:
            if self._gaits:
                self._gaits.pop(0)
            return self._route.pop(0)
        return self._towards_goal()

    def _towards_goal(self) -> int:
        if self.goal < 0:
            return -1
        if self._goal_field is None:
            self._goal_field = distances_from(self.neighbours, np.array([self.goal], dtype=np.int64))
        return self._descend(self._goal_field)

    def _step_to(self, cell: int) -> int:
        return self._descend(distances_from(self.neighbours, np.array([cell], dtype=np.int64)))

    def _descend(self, field: np.ndarray) -> int:
        direction = greedy_step(field, self.neighbours[self.cell], self.heading)
        if direction < 0:
            return -1
        there = int(self.neighbours[self.cell, direction])
        return there if field[there] < field[self.cell] else -1

    def _hiding_cell(self, guard_cells: Sequence[int]) -> int:
        """The cell it reaches before any guard that is farthest from every guard (ties: nearest to it,
        then lowest index); its own cell when there is none."""
        own = distances_from(self.neighbours, np.array([self.cell], dtype=np.int64)).astype(np.int64)
        theirs = distances_from(self.neighbours, np.asarray(guard_cells, dtype=np.int64)).astype(np.int64)
        safe = (own < theirs) & (own < FAR)
        if not safe.any():
            return self.cell
        score = np.where(safe, theirs * (4 * own.size) - own, -1)
        return int(np.argmax(score))

    def _flee(self, guard_cells: Sequence[int]) -> int:
        return self._step_to(self._hiding_cell(guard_cells))


def route_of_path(cells: Sequence[_Cell], gaits: Sequence[str] | None) -> tuple[list[_Cell], list[str]]:
    """A path of the sneak check (flat cells per tick, and what it does in each tick after the first, as
    :attr:`guardsim.sneak.SneakPath.gaits`) as an intruder's route and the gait into each route cell: a
    sneaking step's ticks before it lands are the step's own, not waits, so they leave the route.

    >>> route_of_path([0, 0, 1, 2, 2], ("sneak", "sneak", "walk", "wait"))
    ([0, 1, 2, 2], ['walk', 'sneak', 'walk', 'walk'])
    """
    route, steps = [cells[0]], ["walk"]
    for tick in range(1, len(cells)):
        gait = "walk" if gaits is None else gaits[tick - 1]
        if gait == "sneak" and cells[tick] == cells[tick - 1]:
            continue  # still in the cell it sneaks from
        route.append(cells[tick])
        steps.append("sneak" if gait == "sneak" else "walk")
    return route, steps


def make_intruder(
    kind: str,
    neighbours: np.ndarray,
    cell: int,
    *,
    goal: int = -1,
    route: Sequence[int] | None = None,
    speed: float = 1.0,
    wait_until: int = 0,
    gaits: Sequence[str] | None = None,
    sneak_ticks: int = 2,
    run_speed: float | None = None,
) -> Intruder:
    """An intruder of ``kind`` at flat ``cell``; ``route`` is the path a ``route`` or ``sneak`` intruder walks.

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> walker = make_intruder("route", neighbours, 0, goal=2)
    >>> walker.advance(1, [], False, False); walker.cell, walker.gone
    (1, False)
    """
    from guardsim.alert.model import INTRUDERS

    if kind not in INTRUDERS:
        raise ArgumentError(f"unknown intruder {kind!r}; choose from {', '.join(INTRUDERS)}")
    return Intruder(
        kind, neighbours, cell, goal=goal, route=route, speed=speed, wait_until=wait_until, gaits=gaits,
        sneak_ticks=sneak_ticks, run_speed=run_speed,
    )  # fmt: skip


class Distraction(NamedTuple):
    """A noise the intruder makes away from itself: a thrown bottle, a slammed door."""

    point: tuple[float, float]
    """Where it lands, world units."""
    seconds: float
    """When, seconds from the start of the episode."""
    noise: float
    """How far it carries, world units along the grid."""


class RouteFile(NamedTuple):
    """What a route file holds: its waypoints in order, the gait of the step into each, its distractions."""

    points: list[tuple[float, float]]
    gaits: list[str]
    """Per point: ``walk`` or ``sneak`` (the first point's is that of no step)."""
    distractions: list[Distraction]


def read_route_file(path: str, *, sneak_ticks: int | None = None) -> RouteFile:
    """A route intruder's file: a JSON list whose items are waypoints, ``[x, y]`` (walked to) or
    ``{"to": [x, y], "gait": "sneak"}``, and distractions, ``{"throw": [x, y], "at": seconds, "noise":
    radius}``; or a sneak.json (its ``path``, and the ``gaits`` of ``sneak --unheard``, whose sneaking
    steps must take the level's ``sneak_ticks`` when given). Every fault is one
    :class:`~guardsim.errors.GuardsimError` line naming the file and the item, numbers through the one
    number parser (finite, within float range)."""
    from guardsim.errors import GuardsimError
    from guardsim.files.reading import NumberError, excerpt, finite_number, quoted, read_json_file
    from guardsim.level.model import GAITS

    data = read_json_file(path, max_file_bytes=16 * 2**20, kind="route file", error=GuardsimError)
    items = data.get("path") if isinstance(data, dict) else data
    if isinstance(items, dict):
        items = items.get("positions") or items.get("cells")
    if not isinstance(items, list) or not items:
        raise GuardsimError(f"{path}: a route file is a list of [x, y] points (or a sneak.json with a path)")
    # A sneak.json's path is [col, row] cells of the grid at its origin and cell size: their centres.
    size, origin = 1.0, (0.0, 0.0)
    cells = isinstance(data, dict) and isinstance(data.get("path"), list) and "cell_size" in data
    if cells:
        try:
            size = finite_number(data["cell_size"])
            raw = data.get("origin", [0, 0])
            if not (isinstance(raw, list) and len(raw) == 2) or size <= 0:
                raise NumberError("not an origin")
            origin = (finite_number(raw[0]), finite_number(raw[1]))
        except NumberError:
            raise GuardsimError(f"{path}: cell_size and origin: not a positive size and an [x, y] origin") from None

    def pair(value: Any, index: int, what: str) -> tuple[float, float]:
        try:
            if not (isinstance(value, list) and len(value) == 2):
                raise NumberError("not a pair")
            x, y = (finite_number(v) for v in value)
        except NumberError:
            kind = "a [col, row] pair of whole numbers" if cells else "an [x, y] pair of finite numbers"
            raise GuardsimError(f"{path}: {what} {index}: not {kind}") from None
        return (origin[0] + (x + 0.5) * size, origin[1] + (y + 0.5) * size) if cells else (x, y)

    out = RouteFile([], [], [])
    for index, item in enumerate(items):
        if isinstance(item, dict) and "throw" in item:
            unknown = sorted(set(item) - {"throw", "at", "noise"}, key=str)
            if unknown:
                raise GuardsimError(
                    f"{path}: item {index}: unknown key {quoted(str(unknown[0]))} (a throw has throw, at, noise)"
                )
            point = pair(item["throw"], index, "item")
            numbers = {}
            for key in ("at", "noise"):
                try:
                    numbers[key] = finite_number(item.get(key), minimum=0)
                except NumberError as error:
                    raise GuardsimError(f"{path}: item {index}: {key}: {error}") from None
            out.distractions.append(Distraction(point, numbers["at"], numbers["noise"]))
            continue
        gait = "walk"
        if isinstance(item, dict):
            unknown = sorted(set(item) - {"to", "gait"}, key=str)
            if unknown or "to" not in item:
                raise GuardsimError(f'{path}: item {index}: a waypoint is [x, y] or {{"to": [x, y], "gait": ...}}')
            gait = item.get("gait", "walk")
            if gait not in GAITS:
                raise GuardsimError(
                    f"{path}: item {index}: gait {quoted(gait) if isinstance(gait, str) else excerpt(gait, 40)} is not one the level allows ({', '.join(GAITS)})"
                )
            item = item["to"]
        out.points.append(pair(item, index, "point"))
        out.gaits.append(gait)
    if not out.points:
        raise GuardsimError(f"{path}: a route file needs at least one [x, y] point")
    gaits = data.get("gaits") if cells else None
    if gaits is not None:
        # sneak --unheard's path: what it does in each tick; a sneaking step's first ticks leave the route.
        if not (isinstance(gaits, list) and len(gaits) == len(out.points) - 1 and set(gaits) <= {*GAITS, "wait"}):
            raise GuardsimError(f"{path}: gaits: not one of walk, sneak, wait per tick of the path after the first")
        if sneak_ticks is not None:
            _check_sneaking_steps(path, out.points, gaits, sneak_ticks)
        points, steps = route_of_path(out.points, gaits)
        return RouteFile(points, steps, out.distractions)
    return out


def _check_sneaking_steps(path: str, points: Sequence[Any], gaits: Sequence[str], sneak_ticks: int) -> None:
    """Each sneaking step of a sneak.json's gaits stays ``sneak_ticks - 1`` ticks in its cell and lands at
    the next: a path planned with another ``sneak_ticks`` is not one this level allows."""
    from guardsim.errors import GuardsimError

    tick = 1
    while tick < len(points):
        if gaits[tick - 1] != "sneak":
            tick += 1
            continue
        lands = next((t for t in range(tick, len(points)) if points[t] != points[t - 1]), len(points) - 1)
        taken = lands - tick + 1
        if taken != sneak_ticks or any(gait != "sneak" for gait in gaits[tick - 1 : lands]):
            raise GuardsimError(
                f"{path}: gaits: the sneaking step landing at tick {lands} takes {taken} ticks; "
                f"the level's sneak_ticks is {sneak_ticks}"
            )
        tick = lands + 1


def read_route_points(path: str) -> list[tuple[float, float]]:
    """The waypoints of a route intruder's file (see :func:`read_route_file`)."""
    return read_route_file(path).points


class RouteCells(NamedTuple):
    """A route intruder's file on a grid: its flat cells, gaits and distractions."""

    cells: list[int]
    """Flat cells, each a 4-neighbour of the one before (or the same cell)."""
    gaits: list[str]
    """The gait into each cell (``walk`` or ``sneak``)."""
    distractions: list[tuple[int, int, float]]
    """Noises away from the intruder: ``(tick, cell, radius)``."""


def read_route_cells(path: str, grid: CoverageGrid, *, sneak_ticks: int | None = None, dt: float) -> RouteCells:
    """:func:`read_route_file` on ``grid`` (a :class:`~guardsim.grid.CoverageGrid`): each point the floor
    cell it is in, each throw at its tick of ``dt`` seconds; every fault (a point off the floor, a move
    that is not a 4-neighbour step) one :class:`~guardsim.errors.GuardsimError` line naming the file."""
    import itertools

    from guardsim.errors import GuardsimError

    route_file = read_route_file(path, sneak_ticks=sneak_ticks)
    route = [grid.floor_cell(point, f"{path}: point") for point in route_file.points]
    distractions = [
        (round(throw.seconds / dt), grid.floor_cell(throw.point, f"{path}: throw"), throw.noise)
        for throw in route_file.distractions
    ]
    for index, (before, after) in enumerate(itertools.pairwise(route)):
        if after != before and after not in grid.neighbours[before].tolist():
            raise GuardsimError(f"{path}: point {index + 1} is not a 4-neighbour of point {index}")
    return RouteCells(route, route_file.gaits, distractions)
