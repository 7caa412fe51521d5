"""Routes cleaned for an engine: one-tile jogs and A-B-A spurs taken out where the guard still watches as well.

A grid patrol steps cell by cell, so its route (:func:`guardsim.patrol.export.guard_routes`) holds
staircase jogs (a one-cell sideways leg between two long ones) and spurs (a walk to a point and
straight back) that an engine's path follower would copy faithfully. :func:`clean_routes` takes them
out one at a time, greedily:

- a **jog** B-C (a leg no longer than one cell, neither end waiting) between A and D becomes the
  straight leg A-D, when the guard's disc slides from A to D touching no wall
  (:meth:`guardsim.world.World.sweep_clear`);
- a **spur** A-B-A (B a dead end the guard walks into and back out of) is cut to A, the two waits at A
  added up.

Each change is kept only if the route, replayed (:func:`guard_poses`: the guard faces the way it walks,
and turns through its ``scan`` while it waits) and looked through the guard's cone every grid tick
(:class:`guardsim.motion.PoseVision`), still sees every cell it saw before each lap and its worst
idleness in seconds grows by at most ``tolerance`` (10 % by default). Times are recomputed at the same
speed, so a cleaned route is shorter; ``tick`` becomes the fractional grid tick. A team sharing one
route keeps its phases in proportion. Routes that do not repeat (``once``) are left as they are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from guardsim.motion import PoseVision
from guardsim.patrol.export import position_at
from guardsim.patrol.scoring import score_timeline
from guardsim.scene import Scene

__all__ = ["DEFAULT_TOLERANCE", "CleanReport", "clean_routes", "guard_poses", "route_period"]

#: How much worse (a share of the worst idleness in seconds) a cleaned route may watch.
DEFAULT_TOLERANCE = 0.1


@dataclass(frozen=True)
class CleanReport:
    """What cleaning did to one route."""

    jogs: int
    spurs: int
    waypoints_before: int
    waypoints_after: int
    worst_before: float | None
    """Worst idleness in seconds of the route replayed before cleaning (``None``: a cell never seen)."""
    worst_after: float | None


def route_period(route: dict[str, Any]) -> float:
    """Seconds per lap of a ``loop`` or ``ping-pong`` route, from its waypoints."""
    points = route["waypoints"]
    if route["loop_mode"] == "ping-pong":
        return float(2 * points[-1]["time"] + points[-1]["wait"] - points[0]["wait"])
    return float(points[-1]["time"] + points[-1]["wait"])


def _heading(route: dict[str, Any], seconds: float) -> float:
    """The way the guard faces: the way it walks, its scan while it waits, its arrival heading else."""
    step = 1e-6
    here = position_at(route, seconds)
    after = position_at(route, seconds + step)
    if here != after:
        return math.degrees(math.atan2(after[1] - here[1], after[0] - here[0])) % 360.0
    points = route["waypoints"]
    nearest = min(points, key=lambda p: (p["x"] - here[0]) ** 2 + (p["y"] - here[1]) ** 2)
    scan = nearest.get("scan")
    if scan and nearest["wait"] > 0:
        into = (seconds + route["phase"]) % route["period"] - nearest["time"]
        index = min(len(scan) - 1, max(0, int(into / nearest["wait"] * len(scan))))
        return float(scan[index])
    before = position_at(route, seconds - step)
    if before != here:
        return math.degrees(math.atan2(here[1] - before[1], here[0] - before[0])) % 360.0
    return float(nearest["heading"])


def guard_poses(route: dict[str, Any], seconds_per_tick: float) -> np.ndarray:
    """``float64 (ticks, 3)``: x, y and heading of a guard on ``route`` at each grid tick of one lap."""
    ticks = max(1, math.ceil(route["period"] / seconds_per_tick - 1e-9))
    poses = np.zeros((ticks, 3))
    for tick in range(ticks):
        seconds = tick * seconds_per_tick
        x, y = position_at(route, seconds)
        poses[tick] = (x, y, _heading(route, seconds))
    return poses


class _Watch:
    """The cells a route sees each grid tick of a lap, its poses' sights kept between calls."""

    def __init__(self, scene: Scene, goal: np.ndarray, seconds_per_tick: float) -> None:
        self.vision = PoseVision(scene.world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls)
        self.goal = goal
        self.seconds_per_tick = seconds_per_tick
        self.sights: dict[tuple[float, float, float], np.ndarray] = {}
        self.size = scene.grid.size

    def timeline(self, route: dict[str, Any]) -> np.ndarray:
        poses = guard_poses(route, self.seconds_per_tick)
        timeline = np.zeros((poses.shape[0], self.size), dtype=bool)
        for tick, (x, y, heading) in enumerate(poses.tolist()):
            key = (round(x, 6), round(y, 6), round(heading, 6))
            if key not in self.sights:
                self.sights[key] = self.vision(x, y, heading)
            timeline[tick, self.sights[key]] = True
        return timeline

    def score(self, route: dict[str, Any], cells: np.ndarray) -> tuple[np.ndarray, float | None]:
        """The cells the route sees in a lap, and its worst idleness in seconds over ``cells``."""
        timeline = self.timeline(route)
        seen = timeline.any(axis=0) & self.goal
        score = score_timeline(timeline, cells, periodic=True)
        worst = None if score.worst_idleness is None else score.worst_idleness * self.seconds_per_tick
        return seen, worst


def _retimed(route: dict[str, Any], points: list[dict[str, Any]], speed: float, seconds_per_tick: float) -> dict[str, Any]:
    timed: list[dict[str, Any]] = []
    time = 0.0
    for index, point in enumerate(points):
        if index:
            before = timed[-1]
            time += before["wait"] + math.hypot(point["x"] - before["x"], point["y"] - before["y"]) / speed
        timed.append({**point, "time": round(time, 6), "tick": round(time / seconds_per_tick, 3)})
    retimed = {**route, "waypoints": timed}
    retimed["period"] = round(route_period(retimed), 6)
    return retimed


def _candidates(points: list[dict[str, Any]], cell: float) -> list[tuple[str, int]]:
    """(kind, index) of every spur tip and every jog's first point, in route order."""
    found: list[tuple[str, int]] = []
    place = [(p["x"], p["y"]) for p in points]
    for index in range(1, len(points) - 1):
        if place[index - 1] == place[index + 1] and place[index] != place[index - 1]:
            found.append(("spur", index))
        if index + 2 < len(points):
            leg = math.dist(place[index], place[index + 1])
            quiet = points[index]["wait"] == 0 and points[index + 1]["wait"] == 0
            if 0 < leg <= cell + 1e-9 and quiet:
                found.append(("jog", index))
    return found


def _changed(points: list[dict[str, Any]], kind: str, index: int) -> list[dict[str, Any]]:
    if kind == "spur":
        back = points[index + 1]
        merged = {**points[index - 1], "wait": round(points[index - 1]["wait"] + back["wait"], 6)}
        if "scan" in back and "scan" not in merged:
            merged["scan"] = back["scan"]
        return [*points[: index - 1], merged, *points[index + 2 :]]
    return [*points[:index], *points[index + 2 :]]


def _clean_one(
    scene: Scene, watch: _Watch, route: dict[str, Any], speed: float, tolerance: float
) -> tuple[dict[str, Any], CleanReport]:
    seconds_per_tick = watch.seconds_per_tick
    seen, _ = watch.score(route, watch.goal)
    _, worst = watch.score(route, seen)
    best = route
    points = route["waypoints"]
    counts = {"jog": 0, "spur": 0}
    radius = scene.level.guard.radius
    changed = True
    while changed:
        changed = False
        for kind, index in _candidates(points, scene.grid.cell_size):
            trial = _changed(points, kind, index)
            if len(trial) < 2 or (best["loop_mode"] == "loop" and (trial[0]["x"], trial[0]["y"]) != (trial[-1]["x"], trial[-1]["y"])):
                continue
            if kind == "jog":
                a, d = points[index - 1], points[index + 2]
                if not scene.world.sweep_clear((a["x"], a["y"]), (d["x"], d["y"]), radius):
                    continue
            candidate = _retimed(best, trial, speed, seconds_per_tick)
            now_seen, now_worst = watch.score(candidate, seen)
            if now_seen[seen].all() and (worst is None or (now_worst is not None and now_worst <= worst * (1 + tolerance))):
                best, points, changed = candidate, trial, True
                counts[kind] += 1
                break
    _, final = watch.score(best, seen)
    return best, CleanReport(counts["jog"], counts["spur"], len(route["waypoints"]), len(points), worst, final)


def clean_routes(
    scene: Scene,
    routes: list[dict[str, Any]],
    goal: np.ndarray,
    *,
    speed: float,
    tolerance: float = DEFAULT_TOLERANCE,
) -> tuple[list[dict[str, Any]], list[CleanReport | None]]:
    """Each route of :func:`~guardsim.patrol.export.guard_routes` cleaned (see the module docstring),
    and what was done to each (``None`` for a route left as it was: ``once``, or shared with an
    earlier guard)."""
    seconds_per_tick = scene.grid.cell_size / speed
    watch = _Watch(scene, np.asarray(goal, dtype=bool), seconds_per_tick)
    cleaned: list[dict[str, Any]] = []
    reports: list[CleanReport | None] = []
    done: dict[int, tuple[dict[str, Any], float, float]] = {}
    for route in routes:
        if route["loop_mode"] == "once":
            cleaned.append(route)
            reports.append(None)
            continue
        key = id(route["waypoints"])
        if key in done:
            # A teammate on the same route: the same cleaned waypoints, its phase kept in proportion.
            first, before, after = done[key]
            cleaned.append({**first, "phase": round(route["phase"] * after / before, 6)})
            reports.append(None)
            continue
        before = route_period(route)
        result, report = _clean_one(scene, watch, {**route, "phase": 0.0}, speed, tolerance)
        after = route_period(result)
        result = {**result, "phase": round(route["phase"] * after / before, 6)}
        done[key] = (result, before, after)
        cleaned.append(result)
        reports.append(report)
    return cleaned, reports
