"""A loop patrol walked in continuous motion, scored in seconds.

Each guard's grid loop is walked through its corners (the cells where it turns, straight runs merged,
as in route.json) by the physics follower of :mod:`guardsim.motion` at the guard's walking and turning
speeds, one physics tick at a time, back to its first corner and its first heading, so the walk repeats
exactly: one lap of poses. The route is not pulled taut (:func:`guardsim.motion.pull_route`): a taut
walk cuts the corners the loop goes round in order to look, and loses what it saw there. Walked through
its corners, the guard passes every cell centre of the loop facing the loop's heading there, and so sees
at least what the grid guard sees: every lap still sees every reachable cell. Guards whose laps are shorter than the longest stand at their first pose to the common period.
Every tick each guard looks from its pose (:class:`guardsim.motion.PoseVision`); idleness is then
scored exactly over the lap as on the grid (:func:`~guardsim.patrol.scoring.score_timeline`), in
physics ticks, and in seconds by dividing by the tick rate.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import cell_of_state, heading_of_state
from guardsim.motion import GuardMotion, PoseVision
from guardsim.motion.follower import Follower
from guardsim.patrol.export import waypoints
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import PatrolScore, score_timeline
from guardsim.scene import Scene

__all__ = ["ContinuousPatrol", "continuous_patrol"]


class ContinuousPatrol(NamedTuple):
    """A patrol walked in continuous motion, and its score."""

    poses: np.ndarray
    """``float64 (guards, ticks, 3)``: x, y and heading in degrees of each guard at each physics tick of a lap."""
    motion: GuardMotion
    score: PatrolScore
    """In physics ticks; divide by ``motion.tick_hz`` for seconds."""

    @property
    def period(self) -> int:
        """Physics ticks per lap."""
        return int(self.poses.shape[1])

    @property
    def period_seconds(self) -> float:
        """Seconds per lap."""
        return self.period / self.motion.tick_hz

    def seconds(self, ticks: float | None) -> float | None:
        """``ticks`` physics ticks in seconds."""
        return None if ticks is None else ticks / self.motion.tick_hz


def _lap(scene: Scene, motion: GuardMotion, states: np.ndarray) -> np.ndarray:
    """One guard's lap of poses, from its first state back to it."""
    grid = scene.grid
    cells = cell_of_state(states).tolist()
    start_heading = 90.0 * int(heading_of_state(int(states[0])))
    start = grid.centre(*grid.unflat(cells[0]))
    if all(cell == cells[0] for cell in cells):
        return np.array([[start[0], start[1], start_heading]])
    lap = Patrol(states[None, :], states.size, "loop")
    corners = [(point["x"], point["y"]) for point in waypoints(lap, grid, 0)]
    follower = Follower(scene.world, motion, start, start_heading)
    poses = [(follower.position[0], follower.position[1], follower.heading)]
    for corner in corners[1:]:
        arrived = False
        while not arrived:
            arrived = follower.walk_to(corner)
            poses.append((follower.position[0], follower.position[1], follower.heading))
    while abs((follower.heading - start_heading + 180.0) % 360.0 - 180.0) > 1e-9:
        follower.turn_to(start_heading)
        poses.append((follower.position[0], follower.position[1], follower.heading))
    # The last pose is the first again: the lap ends just before it.
    return np.asarray(poses[:-1], dtype=np.float64)


def continuous_patrol(
    scene: Scene, patrol: Patrol, goal: np.ndarray, motion: GuardMotion | None = None
) -> ContinuousPatrol:
    """Walk a repeating grid patrol in continuous motion and score one lap of it."""
    if patrol.period is None:
        raise ArgumentError("continuous scoring needs a repeating patrol")
    motion = motion or GuardMotion.of_guard(scene.level.guard)
    laps = [_lap(scene, motion, patrol.states[guard]) for guard in range(patrol.guards)]
    period = max(lap.shape[0] for lap in laps)
    poses = np.stack([np.concatenate([lap, np.repeat(lap[:1], period - lap.shape[0], axis=0)]) for lap in laps])
    vision = PoseVision(scene.world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls)
    timeline = np.zeros((period, scene.grid.size), dtype=bool)
    for tick in range(period):
        for guard in range(patrol.guards):
            x, y, heading = poses[guard, tick]
            timeline[tick, vision(float(x), float(y), float(heading))] = True
    score = score_timeline(timeline, goal, periodic=True)
    return ContinuousPatrol(poses, motion, score)
