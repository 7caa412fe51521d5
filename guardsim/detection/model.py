"""The detection model: how quickly a guard notices an intruder in its sight, and how quickly it forgets.

Each guard keeps an awareness meter in [0, 1]. At each tick of ``dt`` seconds the intruder is in the
guard's sight (the coverage vision rule: cone, range, walls, line of sight), the meter rises by
``dt / (detect_near + (detect_far - detect_near) * d / view_range)``, ``d`` being the distance from the
guard to the intruder; at a tick it is out of sight the meter falls by ``dt / forget``. The intruder is
detected the first tick a meter reaches 1. ``detect_near = detect_far = 0`` is "seen is caught".
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.kernels.meter import DETECTED, meter_after, meter_gain, visibility
from guardsim.level.model import GuardSpec, Level

__all__ = [
    "INTRUDER_STATES",
    "AwarenessMeter",
    "DetectionModel",
    "GuardDetection",
    "grid_tick_seconds",
    "intruder_state",
    "meter_state",
    "path_states",
]

#: What a guard (or the team) makes of the intruder at a tick, from calm to caught.
INTRUDER_STATES = ("unseen", "in view", "suspicious", "detected")

IntruderState = Literal["unseen", "in view", "suspicious", "detected"]


@dataclass(frozen=True)
class DetectionModel:
    """The four detection numbers of a guard (the level's guard keys of the same names).

    Examples
    --------
    A guard 4 units from the intruder, with a view range of 8, needs 0.875 s to detect it; at a grid
    tick of 0.5 s the meter rises by 4/7 of the way each tick:

    >>> model = DetectionModel()
    >>> model.seconds_to_detect(4.0, 8.0), round(model.gain(0.5, 4.0, 8.0), 4), model.fall(0.5)
    (0.875, 0.5714, 0.125)
    >>> DetectionModel(detect_near=0, detect_far=0).gain(0.5, 4.0, 8.0)
    inf
    """

    detect_near: float = 0.25
    """Seconds in sight before an intruder at distance 0 is detected."""
    detect_far: float = 1.5
    """Seconds in sight before an intruder at the edge of the view range is detected."""
    forget: float = 4.0
    """Seconds for a full meter to drain to 0 out of sight."""
    suspicious: float = 0.5
    """The level at which the guard becomes suspicious."""
    dark_sight: float = 1.0
    """World units within which the intruder is seen as in full light (0 for a camera: no dark sight)."""

    def __post_init__(self) -> None:
        for name in ("detect_near", "detect_far", "forget", "suspicious", "dark_sight"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ArgumentError(f"detection: {name} must be a finite number >= 0, not {value!r}")
        if self.suspicious > 1:
            raise ArgumentError(f"detection: suspicious must be at most 1, not {self.suspicious!r}")

    @classmethod
    def of_guard(cls, guard: GuardSpec) -> DetectionModel:
        """The model of a level's guard keys."""
        return cls(guard.detect_near, guard.detect_far, guard.forget, guard.suspicious, guard.dark_sight)

    @property
    def instant(self) -> bool:
        """Whether one tick in sight detects at any distance ("seen is caught")."""
        return self.detect_near == 0 and self.detect_far == 0

    def seconds_to_detect(self, distance: float, view_range: float) -> float:
        """Seconds in sight before an intruder at ``distance`` is detected (from an empty meter)."""
        share = min(max(distance / view_range, 0.0), 1.0) if view_range > 0 else 1.0
        return self.detect_near + (self.detect_far - self.detect_near) * share

    def gain(self, dt: float, distance: float, view_range: float, light: float = 1.0) -> float:
        """How much a tick of ``dt`` seconds in sight at ``distance`` adds to the meter (``inf``: all of it),
        the intruder's cell lit at ``light`` (0 beyond :attr:`dark_sight`: nothing, as out of sight)."""
        seen = visibility(distance, self.dark_sight, light)
        return meter_gain(dt, distance, view_range, self.detect_near, self.detect_far, seen)

    def fall(self, dt: float) -> float:
        """How much a tick of ``dt`` seconds out of sight takes off the meter."""
        return dt / self.forget if self.forget > 0 else math.inf


class AwarenessMeter:
    """One guard's awareness of one intruder, for game code: call :meth:`update` once a tick.

    Examples
    --------
    A guard with a view range of 8 sees the intruder 2 units away for three half-second ticks, then
    loses it for two:

    >>> meter = AwarenessMeter(DetectionModel(), view_range=8.0)
    >>> [round(meter.update(0.5, True, 2.0), 3) for _ in range(3)]
    [0.889, 1.0, 1.0]
    >>> meter.detected, [round(meter.update(0.5, False), 3) for _ in range(2)], meter.detected
    (True, [0.875, 0.75], True)
    """

    def __init__(self, model: DetectionModel, view_range: float) -> None:
        self.model = model
        self.view_range = float(view_range)
        self.level = 0.0
        """The meter, in [0, 1]."""
        self.peak = 0.0
        """The highest level so far."""
        self.detected = False
        """Whether the meter has been full since the last :meth:`reset` (stays true as it drains)."""

    def reset(self) -> None:
        """An empty meter, as at the start."""
        self.level = self.peak = 0.0
        self.detected = False

    def update(self, dt: float, in_sight: bool, distance: float = 0.0, light: float = 1.0) -> float:
        """Advance ``dt`` seconds with the intruder in sight at ``distance`` or not, its cell lit at
        ``light``; returns the level. In the dark beyond the watcher's dark sight it counts as out of sight.

        >>> meter = AwarenessMeter(DetectionModel(), view_range=8.0)
        >>> meter.update(0.5, True, 4.0, light=0.0), round(meter.update(0.5, True, 4.0, light=0.5), 4)
        (0.0, 0.2857)
        """
        gain = self.model.gain(dt, distance, self.view_range, light) if in_sight else 0.0
        self.level = meter_after(self.level, gain, self.model.fall(dt))
        self.peak = max(self.peak, self.level)
        self.detected = self.detected or self.level >= DETECTED
        return self.level

    @property
    def suspicious(self) -> bool:
        """Whether the level is at or above the model's ``suspicious`` level (and above 0)."""
        return self.level > 0 and self.level >= self.model.suspicious


def intruder_state(
    levels: list[float] | tuple[float, ...], in_view: bool, suspicious: float, detected: bool
) -> IntruderState:
    """The intruder's state at a tick: ``detected`` once any meter has been full, else ``suspicious``
    when a meter is at or above ``suspicious`` (and above 0), else ``in view`` when a guard sees it,
    else ``unseen``.

    >>> intruder_state([0.2, 0.6], False, 0.5, False), intruder_state([0.2], True, 0.5, False)
    ('suspicious', 'in view')
    """
    if detected:
        return "detected"
    if any(level > 0 and level >= suspicious for level in levels):
        return "suspicious"
    return "in view" if in_view else "unseen"


def path_states(
    meters: np.ndarray, in_view: Sequence[bool] | np.ndarray, detected_at: int | None, suspicious: float
) -> list[IntruderState]:
    """The intruder's state at each tick of a graded path (:func:`intruder_state`):
    ``meters`` ``(ticks + 1, guards)`` and ``in_view`` from its :class:`~guardsim.sneak.PathGrade`."""
    return [
        intruder_state(
            [float(v) for v in meters[tick]],
            bool(in_view[tick]),
            suspicious,
            detected_at is not None and tick >= detected_at,
        )
        for tick in range(len(meters))
    ]


def meter_state(level: float, suspicious: float) -> IntruderState:
    """The state one meter's level says by itself, which colours its bar's fill: ``detected`` full,
    ``suspicious`` at or above ``suspicious``, ``in view`` above 0, ``unseen`` empty."""
    if level >= DETECTED:
        return "detected"
    if level > 0 and level >= suspicious:
        return "suspicious"
    return "in view" if level > 0 else "unseen"


def grid_tick_seconds(level: Level) -> float:
    """Seconds per grid tick: one cell at the guard's walking speed (``move_speed``, default 2 units/s)."""
    from guardsim.motion.parameters import DEFAULT_MOVE_SPEED

    speed = level.guard.move_speed if level.guard.move_speed is not None else DEFAULT_MOVE_SPEED
    return level.cell_size / speed


class GuardDetection(NamedTuple):
    """The detection model with what it needs from the level: the view range its ``detect_far`` refers to
    and the seconds per tick."""

    model: DetectionModel
    view_range: float
    """World units: the distance at which ``detect_far`` applies (the scene's view range)."""
    dt: float
    """Seconds per tick."""

    @classmethod
    def of_level(cls, level: Level) -> GuardDetection:
        """The level's guard keys, its view range and the grid tick (:func:`grid_tick_seconds`).

        >>> from guardsim.level import parse_level
        >>> GuardDetection.of_level(parse_level({"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]}))[1:]
        (8.0, 0.5)
        """
        return cls(DetectionModel.of_guard(level.guard), float(level.guard.view_range), grid_tick_seconds(level))
