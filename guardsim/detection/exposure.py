"""A repeating patrol seen through the detection model: meter gains per tick, exposure, time to detection.

The gains (:class:`PatrolGains`, built by :func:`guardsim.detection.sight.patrol_gains`) are the model
applied once to every (watcher, lap tick, cell): how much a tick spent in the cell adds to the watcher's
meter (0 where the watcher does not see it, or the cell is too dark to see the intruder in). The watchers are the patrol's guards, then the level's cameras (:mod:`guardsim.detection.watch`),
over the joint lap of the patrol and the cameras' swings. The graded sneak search, the time-to-detection
map and the replay of a path all read them, so the model's numbers enter one place.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.arrays import copy_into
from guardsim.kernels.compiler import jit
from guardsim.kernels.meter import DETECTED, meter_after

__all__ = ["MAX_DENSE_NODES", "NEVER_DETECTED", "PatrolGains", "exposure_map", "time_to_detection"]

#: Most (lap tick, cell) nodes an array over all of them is built for (the dense gains are 8 bytes a
#: watcher each; :class:`guardsim.detection.sight.LapSight` holds a longer lap sparse).
MAX_DENSE_NODES = 20_000_000

#: :func:`time_to_detection` of a cell where a player standing still is never detected.
NEVER_DETECTED = -1


class PatrolGains(NamedTuple):
    """The detection model applied to a repeating patrol."""

    gain: np.ndarray
    """``float64 (guards, period, cells)``: what a tick in the cell adds to the guard's meter; 0 where
    the guard does not see the cell, ``inf`` where one tick detects."""
    fall: float
    """What a tick out of a guard's sight takes off its meter."""
    guard_cells: np.ndarray
    """``int64 (guards, period)``: each guard's flat cell at each lap tick."""
    dt: float
    """Seconds per tick."""
    cameras: int = 0
    """How many of the watchers (the last rows of :attr:`gain`) are cameras; the guards come first."""

    @property
    def seen(self) -> np.ndarray:
        """``bool (period, cells)``: whether any watcher sees the intruder in each cell at each tick (in
        its sight, and lit enough or within its dark sight)."""
        return np.asarray((self.gain > 0).any(axis=0))

    @property
    def guards(self) -> int:
        """How many of the watchers are guards."""
        return int(self.gain.shape[0]) - self.cameras


def exposure_map(gains: PatrolGains) -> np.ndarray:
    """``float64 (cells,)``: the fraction of the lap each cell is in some watcher's view (lit enough to
    see the intruder in)."""
    return gains.seen.mean(axis=0)


@jit
def _standing(gain: np.ndarray, fall: float, cell: int, entry: int, limit: int) -> int:
    """Ticks a player entering ``cell`` at lap tick ``entry`` with empty meters stands there before a meter
    fills (1 when the first tick detects); -1 when none fills within ``limit`` ticks."""
    guards, period = gain.shape[0], gain.shape[1]
    levels = np.zeros(guards)
    for tick in range(limit):
        phase = (entry + tick) % period
        for guard in range(guards):
            levels[guard] = meter_after(levels[guard], gain[guard, phase, cell], fall)
            if levels[guard] >= DETECTED:
                return tick + 1
    return -1


@jit
def _ever_detected(gain: np.ndarray, fall: float, cell: int, max_laps: int) -> int:
    """Whether a player standing in ``cell`` for ever is detected: 1, 0, or -1 when ``max_laps`` laps did not
    settle it. A lap maps the meters at its start to those at its end monotonically, so from empty meters
    the lap-start meters only rise: they reach 1 or repeat."""
    guards, period = gain.shape[0], gain.shape[1]
    levels = np.zeros(guards)
    before = np.zeros(guards)
    for _ in range(max_laps):
        copy_into(before, 0, levels)  # a slice copy would cost seconds to compile
        for phase in range(period):
            for guard in range(guards):
                levels[guard] = meter_after(levels[guard], gain[guard, phase, cell], fall)
                if levels[guard] >= DETECTED:
                    return 1
        same = True
        for guard in range(guards):
            if levels[guard] != before[guard]:
                same = False
        if same:
            return 0
    return -1


@jit
def _time_to_detection(gain: np.ndarray, fall: float, traversable: np.ndarray, max_laps: int, out: np.ndarray) -> int:
    guards, period, cells = gain.shape
    unsettled = 0
    for cell in range(cells):
        if not traversable[cell]:
            out[cell] = -2
            continue
        seen = False
        for guard in range(guards):
            for phase in range(period):
                if gain[guard, phase, cell] > 0:
                    seen = True
        if not seen:
            out[cell] = -1
            continue
        ever = _ever_detected(gain, fall, cell, max_laps)
        if ever <= 0:
            out[cell] = -1
            unsettled += ever == -1
            continue
        # Detected from one entry tick means detected from all (an earlier entrant's meters are never
        # lower), so each entry's walk below ends; the worst entry is the shortest.
        best = -1
        for entry in range(period):
            # Entering out of every guard's sight only waits, meters empty, for the next tick in sight:
            # entering then is as quick to detect and counts fewer ticks.
            in_sight = False
            for guard in range(guards):
                in_sight = in_sight or gain[guard, entry, cell] > 0
            if not in_sight:
                continue
            ticks = _standing(gain, fall, cell, entry, (max_laps + 1) * period)
            if ticks > 0 and (best < 0 or ticks < best):
                best = ticks
        out[cell] = best
    return unsettled


#: Laps a standing player's meters are followed before the time-to-detection map gives up on a cell.
MAX_STANDING_LAPS = 1000


def time_to_detection(gains: PatrolGains, traversable: np.ndarray) -> np.ndarray:
    """``int64 (cells,)``: how many ticks a player standing still in each cell lasts before detection,
    entering with empty meters at the worst tick of the lap; :data:`NEVER_DETECTED` (-1) when it is never
    detected however long it stays, -2 where no one can stand.

    Examples
    --------
    One guard, a two-tick lap, three cells: it sees cell 1 at tick 0 (one tick fills half the meter) and
    cell 2 at both ticks (a third each tick); the meter drains half a tick:

    >>> gain = np.array([[[0.0, 0.5, 1 / 3], [0.0, 0.0, 1 / 3]]])
    >>> gains = PatrolGains(gain, 0.5, np.zeros((1, 2), dtype=np.int64), 0.5)
    >>> time_to_detection(gains, np.ones(3, dtype=bool)).tolist()
    [-1, -1, 3]
    """
    out = np.empty(gains.gain.shape[2], dtype=np.int64)
    unsettled = _time_to_detection(
        np.ascontiguousarray(gains.gain),
        float(gains.fall),
        np.ascontiguousarray(traversable.ravel()),
        MAX_STANDING_LAPS,
        out,
    )
    if unsettled:
        import warnings

        warnings.warn(
            f"time to detection: {unsettled} cells' meters still rose after {MAX_STANDING_LAPS} laps; counted as never detected",
            stacklevel=2,
        )
    return out
