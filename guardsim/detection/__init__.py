"""Detection: guards notice an intruder gradually, through an awareness meter per guard.

- :mod:`~guardsim.detection.model`: the model's four numbers and the meter game code updates each tick.
- :mod:`~guardsim.detection.exposure`: the model over a repeating patrol: gains per tick, exposure and
  time-to-detection maps.
- :mod:`~guardsim.detection.sight`: the view table walked for a lap's gains (the one place), kept sparse
  (:class:`~guardsim.detection.sight.LapSight`) or dense (:func:`patrol_gains`).

See ``docs/detection.md``.
"""

from __future__ import annotations

from guardsim.detection.exposure import NEVER_DETECTED, PatrolGains, exposure_map, time_to_detection
from guardsim.detection.model import (
    INTRUDER_STATES,
    AwarenessMeter,
    DetectionModel,
    GuardDetection,
    grid_tick_seconds,
    intruder_state,
    meter_state,
    path_states,
)
from guardsim.detection.sight import patrol_gains

__all__ = [
    "INTRUDER_STATES",
    "NEVER_DETECTED",
    "AwarenessMeter",
    "DetectionModel",
    "GuardDetection",
    "PatrolGains",
    "exposure_map",
    "grid_tick_seconds",
    "intruder_state",
    "meter_state",
    "path_states",
    "patrol_gains",
    "time_to_detection",
]
