"""The awareness meter's rule, for plain Python and compiled code alike (importing this module registers it).

A guard's meter rises by ``gain`` at a tick the intruder is in its sight and falls by ``fall`` at a tick it
is not, staying within [0, 1]; the intruder is detected the first tick a meter reaches 1. This is the
only place that rule is written: :class:`guardsim.detection.AwarenessMeter` (game code), the graded sneak
search and the time-to-detection map all call :func:`meter_after`.
"""

from __future__ import annotations

from numba.extending import register_jitable

__all__ = ["DETECTED", "meter_after"]

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
