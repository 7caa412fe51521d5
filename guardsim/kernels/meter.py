"""The awareness meter's rule, for plain Python and compiled code alike (importing this module registers it).

A watcher's meter (a guard's or a camera's) rises by ``gain`` at a tick the intruder is in its sight and
falls by ``fall`` at a tick it is not, staying within [0, 1]; the intruder is detected the first tick a
meter reaches 1. The gain of a tick in sight at distance ``d`` is
``v * dt / (detect_near + (detect_far - detect_near) * min(d / view_range, 1))``, ``v`` the intruder's
visibility: 1 within the watcher's dark sight, else the light of its cell (0: it counts as out of
sight). This is the only place those rules are written: :class:`guardsim.detection.AwarenessMeter`
(game code), the gains of the sneak searches, the exposure and time-to-detection maps all call
:func:`visibility`, :func:`meter_gain` and :func:`meter_after`.
"""

from __future__ import annotations

import math

import numpy as np
from numba.extending import register_jitable

__all__ = ["DETECTED", "cell_gain", "meter_after", "meter_gain", "visibility"]

#: A meter at or above this is full: sums of gains such as 1/3 + 1/3 + 1/3 land a rounding error below 1.0,
#: and three ticks of a third of the way must detect.
DETECTED = 1.0 - 1e-9


@register_jitable
def meter_after(level: float, gain: float, fall: float) -> float:
    """The meter after one tick: ``level + gain`` when ``gain > 0`` (in sight), else ``level - fall``,
    clipped to [0, 1]; a level within rounding of 1 is 1.

    Examples
    --------
    >>> meter_after(0.0, 1 / 3, 0.125), meter_after(0.5, 0.0, 0.125), meter_after(0.1, 0.0, 0.125)
    (0.3333333333333333, 0.375, 0.0)
    >>> meter_after(0.0, float("inf"), 0.125)
    1.0
    """
    after = level + gain if gain > 0.0 else level - fall
    return min(1.0, max(0.0, after)) if after < DETECTED else 1.0


@register_jitable
def visibility(distance: float, dark_sight: float, light: float) -> float:
    """How visible the intruder is to a watcher ``distance`` away: 1 within ``dark_sight`` (a guard's
    nose for the dark; 0 for a camera: none), else ``light``, the light of its cell in [0, 1].

    >>> visibility(0.5, 1.0, 0.0), visibility(3.0, 1.0, 0.25), visibility(0.0, 0.0, 0.25)
    (1.0, 0.25, 0.25)
    """
    return 1.0 if dark_sight > 0.0 and distance <= dark_sight else light


@register_jitable
def meter_gain(
    dt: float, distance: float, view_range: float, detect_near: float, detect_far: float, seen: float
) -> float:
    """What a tick of ``dt`` seconds in sight at ``distance`` adds to a meter, ``seen`` being the
    intruder's :func:`visibility`; 0 when ``seen`` is 0 (out of sight), ``inf`` when one tick detects.

    >>> round(meter_gain(0.5, 4.0, 8.0, 0.25, 1.5, 1.0), 4), meter_gain(0.5, 4.0, 8.0, 0.25, 1.5, 0.0)
    (0.5714, 0.0)
    >>> meter_gain(0.5, 4.0, 8.0, 0.0, 0.0, 0.5)
    inf
    """
    if seen <= 0.0:
        return 0.0
    share = min(max(distance / view_range, 0.0), 1.0) if view_range > 0 else 1.0
    seconds = detect_near + (detect_far - detect_near) * share
    # ``seen * dt`` first: at full light it is ``dt`` exactly, so the gains of a lit level are unchanged.
    return seen * dt / seconds if seconds > 0 else math.inf


@register_jitable
def cell_gain(
    own: int, cell: int, cols: int, cell_size: float, detect_near: float, detect_far: float, view_range: float,
    dt: float, dark_sight: float, light: float,
) -> float:  # fmt: skip
    """:func:`meter_gain` of a watcher in flat cell ``own`` seeing flat cell ``cell`` (of a grid ``cols``
    wide, cells ``cell_size`` apart, ``light`` the light of ``cell``): the gain of the patrols' maps and
    searches, dense and sparse alike.

    >>> round(float(cell_gain(0, 4, 2, 1.0, 0.25, 1.5, 8.0, 0.5, 0.0, 1.0)), 4)  # two rows down: 2.0 away
    0.8889
    """
    distance = cell_size * np.hypot(cell // cols - own // cols, cell % cols - own % cols)
    return meter_gain(dt, distance, view_range, detect_near, detect_far, visibility(distance, dark_sight, light))
