"""The record of one episode, and its JSON form."""

from __future__ import annotations

import itertools
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from guardsim.scene import Scene

__all__ = ["OUTCOMES", "Trace"]

#: How an episode can end.
OUTCOMES = ("covered", "step_limit", "stuck")


@dataclass(frozen=True, eq=False)
class Trace:
    """Everything that happened in one episode; enough to redraw every frame."""

    level: str
    """Level name."""
    planner: str
    """Planner name."""
    seed: int | None
    """Seed the episode's generator came from, if any."""
    cell_size: float
    origin: tuple[float, float]
    """World position of the grid's top-left corner."""
    shape: tuple[int, int]
    """``(rows, cols)``."""
    path: tuple[tuple[int, int], ...]
    """``(col, row)`` of the guard at each tick, the start included."""
    headings: tuple[int, ...]
    """Heading number (0 right, 1 down, 2 left, 3 up) at each tick."""
    unseen_percent: tuple[float, ...]
    """Percentage of reachable cells still unseen at each tick."""
    outcome: str
    """One of :data:`OUTCOMES`."""
    reachable: int
    """Cells reachable from the start: the episode's goal."""
    unreachable: int
    """Traversable cells not reachable from the start (left out of the goal)."""
    first_seen: np.ndarray
    """``int (rows, cols)``: tick at which each cell was first seen, -1 if never."""
    goal: np.ndarray
    """``bool (rows, cols)``: the reachable cells."""
    traversable: np.ndarray
    """``bool (rows, cols)``: cells the guard could stand on."""
    guard_paths: tuple[tuple[tuple[int, int], ...], ...] = ()
    """With several guards, every guard's path (guard 0's is also :attr:`path`); empty for one guard."""
    guard_headings: tuple[tuple[int, ...], ...] = ()
    """With several guards, every guard's headings; empty for one guard."""
    guard_radius: float | None = None
    """Radius of the guard's circle in world units (``None`` in traces written before it was recorded)."""
    view_range: float | None = None
    """How far the guard saw, in world units, as simulated (overrides included)."""
    fov_degrees: float | None = None
    """The guard's field of view in degrees, as simulated."""
    line_of_sight: str | None = None
    """The line-of-sight rule simulated: ``"pymunk"`` or ``"bresenham"``."""
    planner_options: Mapping[str, Any] = field(default_factory=dict)
    """The options the planner was made with (``make_planner(planner, **planner_options)``)."""
    motion: str = "grid"
    """``"grid"`` (a step per tick) or ``"continuous"`` (the physics body, a tick per ``1 / tick_hz`` s;
    then :attr:`path`, :attr:`headings`, :attr:`unseen_percent` and :attr:`first_seen` count physics ticks,
    :attr:`path` holding the cell the body is in and :attr:`headings` the nearest heading number)."""
    move_speed: float | None = None
    """Continuous motion: walking speed, world units per second."""
    turn_speed: float | None = None
    """Continuous motion: turning speed, degrees per second."""
    tick_hz: float | None = None
    """Continuous motion: physics ticks per second."""
    seconds: float | None = None
    """Continuous motion: game time of the episode, seconds."""
    poses: np.ndarray | None = None
    """Continuous motion: ``float (ticks + 1, 4)``, ``[t, x, y, heading_degrees]`` per physics tick (world
    units; heading 0 along +x, 90 along +y, y down)."""
    measures: Mapping[str, Any] = field(default_factory=dict)
    """Continuous motion: seconds to cover and T50/T90/T99 in seconds, distance, turning (see
    ``docs/motion.md``)."""
    field: np.ndarray | None = None
    """Recorded only when asked (``Simulation(record_field=True)``, ``play --record-field``): ``int32
    (ticks + 1, rows, cols)``, guard 0's planner field D (RippleFront's distance to unseen) as the guard
    decided at each tick (the last tick, with no decision, repeats the one before); -1 where D has no value."""

    @classmethod
    def of_episode(
        cls,
        scene: Scene,
        *,
        planner: str,
        seed: int | None,
        cells: np.ndarray,
        headings: np.ndarray,
        unseen: np.ndarray,
        outcome: str,
        first_seen: np.ndarray,
        goal: np.ndarray,
        **more: Any,
    ) -> Trace:
        """The one way an episode becomes a trace: what every episode shares, from its scene and arrays.

        ``cells`` and ``headings`` are ``int (guards, ticks + 1)`` (flat cell index and heading number per
        guard and tick), ``unseen`` the count of goal cells still unseen at each tick, ``first_seen`` and
        ``goal`` flat over the grid; ``more`` sets the optional fields (planner options, continuous motion,
        the recorded field).
        """
        grid = scene.grid
        cols = grid.shape[1]
        cells = np.asarray(cells)
        paths = [tuple(zip((row % cols).tolist(), (row // cols).tolist())) for row in cells]
        turns = [tuple(row.tolist()) for row in np.asarray(headings)]
        goal_count = int(np.count_nonzero(goal))
        single = len(paths) == 1
        return cls(
            level=scene.level.name,
            planner=planner,
            seed=seed,
            cell_size=grid.cell_size,
            origin=grid.origin,
            shape=grid.shape,
            path=paths[0],
            headings=turns[0],
            unseen_percent=tuple(
                round(100.0 * count / goal_count, 4) if goal_count else 0.0 for count in np.asarray(unseen).tolist()
            ),
            outcome=outcome,
            reachable=goal_count,
            unreachable=int(grid.traversable.sum()) - goal_count,
            first_seen=np.asarray(first_seen).reshape(grid.shape).copy(),
            goal=np.asarray(goal, dtype=bool).reshape(grid.shape).copy(),
            traversable=grid.traversable.copy(),
            guard_paths=() if single else tuple(paths),
            guard_headings=() if single else tuple(turns),
            guard_radius=scene.level.guard.radius,
            view_range=scene.cone.view_range,
            fov_degrees=scene.cone.fov_degrees,
            line_of_sight=scene.line_of_sight.value,
            **more,
        )

    @property
    def guards(self) -> int:
        """Number of guards."""
        return max(1, len(self.guard_paths))

    def team_paths(self) -> tuple[tuple[tuple[int, int], ...], ...]:
        """Every guard's path, also for a single guard."""
        return self.guard_paths or (self.path,)

    def team_headings(self) -> tuple[tuple[int, ...], ...]:
        """Every guard's headings, also for a single guard."""
        return self.guard_headings or (self.headings,)

    @property
    def total_moves(self) -> int:
        """Steps actually taken, summed over the guards (a guard standing still takes none)."""
        return sum(sum(a != b for a, b in itertools.pairwise(path)) for path in self.team_paths())

    @property
    def start(self) -> tuple[int, int]:
        """``(col, row)`` of the start cell."""
        return self.path[0]

    @property
    def steps(self) -> int:
        """Ticks taken: one guard's steps, a team's makespan."""
        return len(self.path) - 1

    @property
    def covered(self) -> bool:
        """Whether every reachable cell was seen."""
        return self.outcome == "covered"

    def steps_to_fraction(self, fraction: float) -> int | None:
        """First tick at which at least ``fraction`` of the reachable cells had been seen, or ``None``."""
        ticks = np.sort(self.first_seen[self.goal & (self.first_seen >= 0)])
        needed = int(np.ceil(fraction * self.reachable - 1e-9))
        if needed <= 0:
            return 0
        if needed > ticks.size:
            return None
        return int(ticks[needed - 1])

    def to_data(self) -> dict[str, Any]:
        """The JSON-ready dictionary; see ``docs/trace-format.md``."""
        return {
            "level": self.level,
            "planner": self.planner,
            "seed": self.seed,
            "cell_size": self.cell_size,
            "origin": list(self.origin),
            "shape": list(self.shape),
            "start": list(self.start),
            "steps": self.steps,
            "covered": self.covered,
            "outcome": self.outcome,
            "reachable": self.reachable,
            "unreachable": self.unreachable,
            "path": [list(cell) for cell in self.path],
            "headings": list(self.headings),
            "unseen_percent": list(self.unseen_percent),
            "first_seen": self.first_seen.tolist(),
            "goal": self.goal.astype(int).tolist(),
            "traversable": self.traversable.astype(int).tolist(),
            **(
                {
                    "guards": self.guards,
                    "total_moves": self.total_moves,
                    "guard_paths": [[list(cell) for cell in path] for path in self.guard_paths],
                    "guard_headings": [list(log) for log in self.guard_headings],
                }
                if self.guard_paths
                else {}
            ),
            "guard_radius": self.guard_radius,
            "view_range": self.view_range,
            "fov_degrees": self.fov_degrees,
            "line_of_sight": self.line_of_sight,
            "planner_options": dict(self.planner_options),
            **(
                {
                    "motion": self.motion,
                    "move_speed": self.move_speed,
                    "turn_speed": self.turn_speed,
                    "tick_hz": self.tick_hz,
                    "seconds": self.seconds,
                    "measures": dict(self.measures),
                    "poses": [] if self.poses is None else np.round(self.poses, 6).tolist(),
                }
                if self.motion != "grid"
                else {}
            ),
            **({"field": self.field.tolist()} if self.field is not None else {}),
        }

    def to_json(self) -> str:
        """Stable JSON text: one top-level key per line, values compact, so traces diff well."""
        lines = [
            f"  {json.dumps(key)}: {json.dumps(value, separators=(',', ':'))}" for key, value in self.to_data().items()
        ]
        return "{\n" + ",\n".join(lines) + "\n}\n"

    @classmethod
    def from_data(cls, data: dict[str, Any]) -> Trace:
        """Rebuild a trace from :meth:`to_data` output."""
        return cls(
            level=data["level"],
            planner=data["planner"],
            seed=data["seed"],
            cell_size=float(data["cell_size"]),
            origin=(float(data["origin"][0]), float(data["origin"][1])),
            shape=(int(data["shape"][0]), int(data["shape"][1])),
            path=tuple((int(c), int(r)) for c, r in data["path"]),
            headings=tuple(int(h) for h in data["headings"]),
            unseen_percent=tuple(float(p) for p in data["unseen_percent"]),
            outcome=data["outcome"],
            reachable=int(data["reachable"]),
            unreachable=int(data["unreachable"]),
            first_seen=np.asarray(data["first_seen"], dtype=np.int64),
            goal=np.asarray(data["goal"], dtype=bool),
            traversable=np.asarray(data["traversable"], dtype=bool),
            guard_paths=tuple(tuple((int(c), int(r)) for c, r in path) for path in data.get("guard_paths", ())),
            guard_headings=tuple(tuple(int(h) for h in log) for log in data.get("guard_headings", ())),
            guard_radius=_optional_float(data.get("guard_radius")),
            view_range=_optional_float(data.get("view_range")),
            fov_degrees=_optional_float(data.get("fov_degrees")),
            line_of_sight=data.get("line_of_sight"),
            planner_options=dict(data.get("planner_options") or {}),
            motion=data.get("motion", "grid"),
            move_speed=_optional_float(data.get("move_speed")),
            turn_speed=_optional_float(data.get("turn_speed")),
            tick_hz=_optional_float(data.get("tick_hz")),
            seconds=_optional_float(data.get("seconds")),
            poses=None if data.get("poses") is None else np.asarray(data["poses"], dtype=np.float64).reshape(-1, 4),
            measures=dict(data.get("measures") or {}),
            field=None if data.get("field") is None else np.asarray(data["field"], dtype=np.int32),
        )


def _optional_float(value: Any) -> float | None:
    return None if value is None else float(value)
