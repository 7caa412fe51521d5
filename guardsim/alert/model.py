"""The alert game's vocabulary: guard states, events, the rules' numbers and an episode's outcome.

A guard is in one of :data:`GUARD_STATES` at every tick::

    patrol --meter >= suspicious--> suspicious --meter rose 2 ticks--> investigate
      ^                              |  meter back to 0                   |  meter full, in sight
      |                              v                                    v
    return <--gave up-- search <--sight lost-- chase <--meter full, in sight (any state)
      |                  |  ^                    |
      |                  |  +--seen again--------+
      +--on the route at its phase--> patrol     +--within capture_radius--> captured (episode ends)

``investigate`` ends with a look around the noticed cell, then ``return``. A guard that is not chasing or
searching and hears a noise (``heard``: :mod:`guardsim.kernels.noise`) investigates the cell it heard,
its meter untouched. A teammate's detection,
``radio_delay`` seconds later, puts a patrolling, suspicious, investigating or returning guard in
``search`` from the last known position.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import NamedTuple

from guardsim.errors import ArgumentError
from guardsim.level.model import Level

__all__ = [
    "EVENTS",
    "GUARD_STATES",
    "INTRUDERS",
    "OUTCOMES",
    "AlertEvent",
    "AlertOutcome",
    "AlertRules",
    "Event",
    "GuardState",
]


class _Name(str, Enum):
    """A name that is its own string (``enum.StrEnum`` from Python 3.11 on)."""

    __str__ = str.__str__


class GuardState(_Name):
    """A guard's state, calm to alarmed, then back. Each is its name as a string (``GuardState.CHASE ==
    "chase"``), which is what traces and pages hold.

    >>> GuardState("search") is GuardState.SEARCH, str(GuardState.RETURN), GuardState.CHASE == "chase"
    (True, 'return', True)
    """

    PATROL = "patrol"
    SUSPICIOUS = "suspicious"
    INVESTIGATE = "investigate"
    CHASE = "chase"
    SEARCH = "search"
    RETURN = "return"


class Event(_Name):
    """What the ``events`` list of an alert trace records (a string, as :class:`GuardState`)."""

    NOTICED = "noticed"
    DETECTED = "detected"
    LOST = "lost"
    JOINED = "joined"
    CAPTURED = "captured"
    GAVE_UP = "gave_up"
    BACK_ON_ROUTE = "back_on_route"
    ARRIVED = "arrived"
    ALARM = "alarm"
    HEARD = "heard"


#: Every state a guard can be in, calm to alarmed, then back.
GUARD_STATES = tuple(GuardState)

#: What the ``events`` list of an alert trace records.
EVENTS = tuple(Event)

#: The intruder kinds, by the name ``guardsim alert --intruder`` takes.
INTRUDERS = ("route", "sneak", "evader", "still")

#: How an episode ends.
OUTCOMES = ("captured", "undetected_arrival", "escaped", "hidden", "time_limit")


@dataclass(frozen=True)
class AlertRules:
    """The alert numbers of a level's guard keys, in ticks and cells where the episode counts them.

    >>> rules = AlertRules(capture_radius=1.0, search_seconds=30.0, radio_delay=2.0, dt=0.5)
    >>> rules.search_ticks, rules.radio_ticks
    (60, 4)
    """

    capture_radius: float
    """World units between guard and intruder centres at or within which a chasing guard captures."""
    search_seconds: float
    radio_delay: float
    dt: float
    """Seconds per tick."""
    intruder_speed: float = 1.0
    """Cells the intruder may move per tick (the guard moves one); fractions accumulate."""
    chase_speed: float = 1.5
    """Cells a chasing guard runs per tick (walking: one); on the grid, chase tick ``k`` (from 1) takes
    ``floor(k * chase_speed) - floor((k - 1) * chase_speed)`` steps."""
    give_up_losses: int = 3
    """Times a guard may lose sight of the intruder it chases; at the last loss it searches and does not
    chase again."""
    walk_noise: float = 0.0
    """World units a walking step's noise carries along the grid (0: silent)."""
    sneak_noise: float = 0.0
    """World units a sneaking step's noise carries."""
    sneak_ticks: int = 2
    """Ticks a sneaking step takes."""
    cell_size: float = 1.0
    """World units per cell (noise radii are in world units)."""
    run_speed: float | None = None
    """Cells per tick an ``evader`` runs while some guard chases it (fractions accumulate, as for
    ``intruder_speed``); ``None``: it walks at ``intruder_speed`` chased or not."""

    def __post_init__(self) -> None:
        for name in ("capture_radius", "search_seconds", "radio_delay", "intruder_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ArgumentError(f"alert: {name} must be a finite number >= 0, not {value!r}")
        if not (math.isfinite(self.chase_speed) and self.chase_speed > 0):
            raise ArgumentError(f"alert: chase_speed must be a finite number > 0, not {self.chase_speed!r}")
        if not (isinstance(self.give_up_losses, int) and self.give_up_losses >= 1):
            raise ArgumentError(f"alert: give_up_losses must be a whole number >= 1, not {self.give_up_losses!r}")
        for name in ("walk_noise", "sneak_noise"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ArgumentError(f"alert: {name} must be a finite number >= 0, not {value!r}")
        if not (isinstance(self.sneak_ticks, int) and self.sneak_ticks >= 1):
            raise ArgumentError(f"alert: sneak_ticks must be a whole number >= 1, not {self.sneak_ticks!r}")
        if self.run_speed is not None and not (math.isfinite(self.run_speed) and self.run_speed > 0):
            raise ArgumentError(f"alert: run_speed must be a finite number > 0, not {self.run_speed!r}")
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ArgumentError(f"alert: dt must be a finite number > 0, not {self.dt!r}")

    @classmethod
    def of_level(
        cls, level: Level, *, intruder_speed: float | None = None, run_speed: float | None = None
    ) -> AlertRules:
        """The level's guard keys; the intruder moves at ``intruder_speed`` world units per second
        (default: the guard's walking speed), and an evader runs at ``run_speed`` while chased (default:
        it walks)."""
        from guardsim.detection import grid_tick_seconds

        dt = grid_tick_seconds(level)
        guard = level.guard
        radius = guard.capture_radius if guard.capture_radius is not None else level.cell_size
        cells_per_tick = 1.0 if intruder_speed is None else intruder_speed * dt / level.cell_size
        return cls(
            radius,
            guard.search_seconds,
            guard.radio_delay,
            dt,
            cells_per_tick,
            chase_speed=guard.chase_speed,
            give_up_losses=guard.give_up_losses,
            walk_noise=level.intruder.walk_noise,
            sneak_noise=level.intruder.sneak_noise,
            sneak_ticks=level.intruder.sneak_ticks,
            cell_size=level.cell_size,
            run_speed=None if run_speed is None else run_speed * dt / level.cell_size,
        )

    @property
    def search_ticks(self) -> int:
        """Ticks a guard searches before giving up."""
        return math.ceil(self.search_seconds / self.dt - 1e-9)

    @property
    def radio_ticks(self) -> int:
        """Ticks a detection takes to reach the other guards."""
        return math.ceil(self.radio_delay / self.dt - 1e-9)


class AlertEvent(NamedTuple):
    """Something that happened at a tick: ``guard`` is -1 for the intruder's own events; a camera's
    ``alarm`` names it after the guards (``guards + camera``)."""

    tick: int
    guard: int
    event: str


class AlertOutcome(NamedTuple):
    """How one alert episode went; times in seconds, ``None`` where it did not happen."""

    outcome: str
    """One of :data:`OUTCOMES`."""
    ticks: int
    seconds: float
    detected_at: float | None
    """First detection."""
    captured_at: float | None
    searching: float
    """Seconds during which some guard was searching."""
    reacquired_after: float | None
    """Seconds from the first loss of sight to the next detection in sight, if any."""
    gave_up_at: float | None
    back_on_route_at: float | None
    """When every guard that left its route was patrolling it again (after a detection)."""
    detections: int
    """Times the intruder was detected (first detection and each re-acquisition)."""

    def summary(self) -> str:
        """One line for a designer."""
        parts = [self.outcome.replace("_", " ")]
        for label, value in (
            ("detected at", self.detected_at),
            ("captured at", self.captured_at),
            ("search gave up at", self.gave_up_at),
            ("back on route at", self.back_on_route_at),
        ):
            if value is not None:
                parts.append(f"{label} {value:g} s")
        return ", ".join(parts) + f" ({self.ticks} ticks, {self.seconds:g} s)"
