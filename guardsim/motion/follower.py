"""The guard's body in the physics world, steered a tick at a time toward a point or a heading.

The body is the world's kinematic guard body: guardsim sets its velocity and angular velocity, and
``space.step(dt)`` moves it. Each tick the guard turns toward its direction of travel by at most
``turn_speed * dt``; if it faces more than :data:`~guardsim.motion.parameters.STEER_DEGREES` away from
it, it turns in place, otherwise it walks (at most ``move_speed * dt``, straight at the corner) while it
finishes the turn. Arriving at a corner or a heading, the last fraction of a step or turn is taken
exactly, and the body is set on the corner (the physics step leaves it within a rounding error of it),
so that a guard standing on a cell centre facing a grid heading sees what the grid guard sees there.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from guardsim.motion.parameters import STEER_DEGREES, GuardMotion
from guardsim.world import World

__all__ = ["Follower", "Pose", "step_together"]

#: ``((x, y), heading_degrees)``.
Pose = tuple[tuple[float, float], float]


class Follower:
    """Steers ``world``'s guard body; :attr:`position` and :attr:`heading` are the body's, read each tick."""

    def __init__(
        self,
        world: World,
        motion: GuardMotion,
        position: tuple[float, float],
        heading: float,
        *,
        body: pymunk.Body | None = None,
    ) -> None:
        self.world = world
        self.motion = motion
        self.body = world.guard_body if body is None else body
        """The kinematic body steered: the world's guard body, or ``body`` (a team's other guards)."""
        self._pending: tuple[str, float, float, tuple[float, float] | None] | None = None
        self.space = world.space
        self._dt = motion.dt
        self._step = motion.step_length
        self._turn = motion.turn_step
        self.facing: float | None = None
        """A heading to turn to in place before walking on (``None``: walk)."""
        self._set(position, heading)

    def set_pace(self, factor: float) -> None:
        """Walk at ``factor`` times the motion's walking speed from now on (1: walking; a chase runs)."""
        self._step = self.motion.step_length * factor

    def _set(self, position: tuple[float, float], heading: float) -> None:
        body = self.body
        body.position = position
        body.angle = math.radians(heading % 360.0)
        body.velocity = (0.0, 0.0)
        body.angular_velocity = 0.0
        self.space.reindex_shapes_for_body(body)
        self.position = (float(position[0]), float(position[1]))
        self.heading = heading % 360.0

    def save(self) -> Pose:
        """The pose, to put back after the grid loop has moved the body while planning (between ticks,
        when the body is at rest)."""
        return self.position, self.heading

    def restore(self, pose: Pose) -> None:
        """Put the body back at rest where :meth:`save` found it."""
        self._set(*pose)

    def walk_to(self, corner: np.ndarray | tuple[float, float]) -> bool:
        """One tick toward ``corner``; returns whether the body has arrived there."""
        if self.aim_walk(corner):
            return True
        self.space.step(self._dt)
        return self.settle()

    def turn_to(self, heading: float) -> bool:
        """One tick of turning in place toward ``heading``; returns whether it faces it now."""
        self.aim_turn(heading)
        self.space.step(self._dt)
        return self.settle()

    # A tick in three parts, so that several followers in one space share one ``space.step``
    # (:func:`step_together`): aim (set the velocities), the space steps, settle (read the pose back).

    def aim_walk(self, corner: np.ndarray | tuple[float, float]) -> bool:
        """Set this tick's velocities toward ``corner``; ``True`` (and nothing set) if already there."""
        x, y = self.position
        target_x, target_y = float(corner[0]), float(corner[1])
        dx, dy = target_x - x, target_y - y
        distance = math.hypot(dx, dy)
        if distance == 0:
            return True
        travel = math.degrees(math.atan2(dy, dx)) % 360.0
        delta = _signed(travel - self.heading)
        walking = abs(delta) <= STEER_DEGREES + 1e-9
        arriving = walking and distance <= self._step
        step = (distance if arriving else self._step) if walking else 0.0
        speed = step / self._dt
        arrive = (target_x, target_y) if arriving else None
        self._aim("walk", (dx / distance * speed, dy / distance * speed), delta, travel, arrive)
        return False

    def aim_turn(self, heading: float) -> None:
        """Set this tick's velocities for turning in place toward ``heading``."""
        delta = _signed(heading - self.heading)
        self._aim("turn", (0.0, 0.0), delta, heading % 360.0, None)

    def aim_hold(self) -> None:
        """Set this tick's velocities to stand still (a body sharing a stepped space must not drift)."""
        self._aim("hold", (0.0, 0.0), 0.0, self.heading, None)

    def _aim(
        self, kind: str, velocity: tuple[float, float], delta: float, aim: float, arrive: tuple[float, float] | None
    ) -> None:
        """Set the body's velocities for this tick, turning by ``delta`` at most one tick's worth."""
        body = self.body
        turn = max(-self._turn, min(self._turn, delta))
        # Both velocities are set every tick, so they need no reset after the step; the grid loop only
        # places the body between ticks while planning, and never steps the space.
        body.velocity = velocity
        body.angular_velocity = math.radians(turn) / self._dt
        self._pending = (kind, delta, aim, arrive)

    def settle(self) -> bool:
        """After the space's step: read the pose back; a turn that reaches its aim ends exactly on it, a
        walk that reaches its corner is set on it. Returns whether the aim (corner or heading) is reached."""
        if self._pending is None:
            raise RuntimeError("settle() without an aim this tick")
        kind, delta, aim, arrive = self._pending
        self._pending = None
        body = self.body
        turned = abs(delta) <= self._turn
        if turned:
            body.angle = math.radians(aim)
            self.heading = aim
        else:
            self.heading = math.degrees(body.angle) % 360.0
        position = body.position
        self.position = (float(position[0]), float(position[1]))
        if arrive is not None:
            body.position = arrive
            self.space.reindex_shapes_for_body(body)
            self.position = arrive
        if kind == "turn" and turned:
            self.facing = None
        return arrive is not None if kind == "walk" else turned


def step_together(followers: list[Follower]) -> None:
    """One physics tick of ``followers`` that share a space and have each aimed this tick: one
    ``space.step``, every pose read back, and every body left at rest, so that whoever steps the space
    next moves none of them by this tick's velocities."""
    if not followers:
        return
    followers[0].space.step(followers[0]._dt)
    for follower in followers:
        follower.settle()
        follower.body.velocity = (0.0, 0.0)
        follower.body.angular_velocity = 0.0


def _signed(angle: float) -> float:
    """``angle`` in degrees wrapped to ``(-180, 180]``."""
    wrapped = (angle + 180.0) % 360.0 - 180.0
    return 180.0 if wrapped == -180.0 else wrapped
