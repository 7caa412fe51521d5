"""Intruders to play against the guards: a scripted route, a sneaking planner, an evader, a hider.

Each moves up to its speed in cells a tick (fractions accumulate), one 4-connected step at a time,
before the guards move. ``goal`` is the cell it wants to reach (-1: none); on reaching it the intruder
leaves the level.

- ``route``: walks a given path (or the shortest path to its goal) without stopping, chased or not.
- ``sneak``: walks the fastest path no guard of the patrol sees (the sneak check's search; the closest
  call when there is none), entering the level at the tick its path starts (outside until then: no
  guard sees or catches it); chased, it flees
  as the evader does, then walks the shortest path to its goal once no guard is alarmed.
- ``evader``: walks the shortest path to its goal; chased, it runs for the cell it reaches first whose
  distance from every guard is largest, waits there while guards are alarmed, then resumes.
- ``still``: stays where it is put.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.kernels.distances import FAR, distances_from
from guardsim.kernels.steps import greedy_step

__all__ = ["Intruder", "make_intruder", "read_route_points"]


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
    ) -> None:
        self.kind = kind
        self.neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
        self.cell = int(cell)
        self.goal = int(goal)
        self.speed = float(speed)
        self.heading = 0
        self.gone = False
        """Whether it reached its goal and left."""
        self._credit = 0.0
        self._route = [int(c) for c in route] if route is not None else None
        if self._route is not None and self._route and self._route[0] == self.cell:
            self._route = self._route[1:]
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
        if self.gone or self.kind == "still":
            return
        if not self.present:
            # Outside until the tick its path starts, when it stands at its entry; it moves from the next.
            self.present = tick >= self._wait_until
            return
        self._credit += self.speed
        while self._credit >= 1.0 - 1e-9 and not self.gone:
            self._credit -= 1.0
            nxt = self._next(tick, guard_cells, chased, alarmed)
            if nxt < 0 or nxt == self.cell:
                continue
            self.heading = int(np.flatnonzero(self.neighbours[self.cell] == nxt)[0])
            self.cell = nxt
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

    def _along_route(self) -> int:
        if self._route:
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


def make_intruder(
    kind: str,
    neighbours: np.ndarray,
    cell: int,
    *,
    goal: int = -1,
    route: Sequence[int] | None = None,
    speed: float = 1.0,
    wait_until: int = 0,
) -> Intruder:
    """An intruder of ``kind`` at flat ``cell``; ``route`` is the path a ``route`` or ``sneak`` intruder walks.

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> walker = make_intruder("route", neighbours, 0, goal=2)
    >>> walker.advance(1, [], False, False); walker.cell, walker.gone
    (1, False)
    """
    from guardsim.alert.model import INTRUDERS

    if kind not in INTRUDERS:
        raise ValueError(f"unknown intruder {kind!r}; choose from {', '.join(INTRUDERS)}")
    return Intruder(kind, neighbours, cell, goal=goal, route=route, speed=speed, wait_until=wait_until)


def read_route_points(path: str) -> list[tuple[float, float]]:
    """The waypoints of a route intruder's file: a JSON list of ``[x, y]`` world points, or a sneak.json
    (its ``path``). Every fault is one :class:`~guardsim.errors.GuardsimError` line naming the file and
    the point, numbers through the one number parser (finite, within float range)."""
    from guardsim.errors import GuardsimError
    from guardsim.files.reading import NumberError, finite_number, read_json_file

    data = read_json_file(path, max_file_bytes=16 * 2**20, kind="route file", error=GuardsimError)
    points = data.get("path") if isinstance(data, dict) else data
    if isinstance(points, dict):
        points = points.get("positions") or points.get("cells")
    if not isinstance(points, list) or not points:
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
    out = []
    for index, point in enumerate(points):
        try:
            if not (isinstance(point, list) and len(point) == 2):
                raise NumberError("not a pair")
            x, y = (finite_number(value) for value in point)
        except NumberError:
            what = "a [col, row] pair of whole numbers" if cells else "an [x, y] pair of finite numbers"
            raise GuardsimError(f"{path}: point {index}: not {what}") from None
        out.append((origin[0] + (x + 0.5) * size, origin[1] + (y + 0.5) * size) if cells else (x, y))
    return out
