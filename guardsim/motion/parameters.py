"""A guard's motion in game terms: how fast it walks and turns, and how often the physics ticks."""

from __future__ import annotations

import math
from dataclasses import dataclass

from guardsim.errors import ArgumentError
from guardsim.level import GuardSpec

__all__ = ["DEFAULT_MOVE_SPEED", "DEFAULT_TICK_HZ", "DEFAULT_TURN_SPEED", "MOTIONS", "STEER_DEGREES", "GuardMotion"]

#: The two motion models: the paper's grid steps, or the physics body at game speeds (docs/motion.md).
MOTIONS = ("grid", "continuous")

#: World units per second: a patrolling walk (1.5-2 m/s) on levels whose unit is about a metre.
DEFAULT_MOVE_SPEED = 2.0
#: Degrees per second: a U-turn in one second, as stealth-game guards turn on patrol.
DEFAULT_TURN_SPEED = 180.0
#: Physics ticks per second (``space.step(1 / tick_hz)``).
DEFAULT_TICK_HZ = 30.0
#: A guard facing more than this far from its direction of travel stops and turns in place; within it,
#: it walks while it finishes the turn.
STEER_DEGREES = 45.0


@dataclass(frozen=True)
class GuardMotion:
    """How a guard moves in continuous motion.

    Examples
    --------
    >>> motion = GuardMotion(move_speed=1.5)
    >>> motion.turn_speed, round(motion.dt, 4), motion.step_length, motion.turn_step
    (180.0, 0.0333, 0.05, 6.0)
    """

    move_speed: float = DEFAULT_MOVE_SPEED
    """Walking speed, world units per second."""
    turn_speed: float = DEFAULT_TURN_SPEED
    """Turning speed, degrees per second."""
    tick_hz: float = DEFAULT_TICK_HZ
    """Physics ticks per second."""

    def __post_init__(self) -> None:
        for name in ("move_speed", "turn_speed", "tick_hz"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ArgumentError(f"{name} must be a positive finite number, not {value!r}")

    @classmethod
    def of_guard(
        cls,
        guard: GuardSpec,
        *,
        move_speed: float | None = None,
        turn_speed: float | None = None,
        tick_hz: float | None = None,
    ) -> GuardMotion:
        """The motion given, else the level guard's ``move_speed``/``turn_speed``/``tick_hz``, else the defaults."""

        def pick(given: float | None, name: str, default: float) -> float:
            if given is not None:
                return float(given)
            level_value = getattr(guard, name, None)
            return default if level_value is None else float(level_value)

        return cls(
            pick(move_speed, "move_speed", DEFAULT_MOVE_SPEED),
            pick(turn_speed, "turn_speed", DEFAULT_TURN_SPEED),
            pick(tick_hz, "tick_hz", DEFAULT_TICK_HZ),
        )

    @property
    def dt(self) -> float:
        """Seconds per physics tick."""
        return 1.0 / self.tick_hz

    @property
    def step_length(self) -> float:
        """Farthest the guard walks in one tick, world units."""
        return self.move_speed / self.tick_hz

    @property
    def turn_step(self) -> float:
        """Most the guard turns in one tick, degrees."""
        return self.turn_speed / self.tick_hz
