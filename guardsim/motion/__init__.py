"""Continuous motion: a guard that walks and turns at game speeds in the physics world.

- :mod:`~guardsim.motion.parameters`: :class:`GuardMotion` (walking speed, turning speed, tick rate);
- :mod:`~guardsim.motion.smoothing`: a grid route pulled taut into segments the guard's circle can walk;
- :mod:`~guardsim.motion.follower`: the pymunk body steered a tick at a time;
- :mod:`~guardsim.motion.sight`: vision from a continuous pose, fast and reference;
- :mod:`~guardsim.motion.episode`: :class:`ContinuousSimulation`, an episode tick by tick;
- :mod:`~guardsim.motion.measures`: seconds, distance and turning of a walk;
- :mod:`~guardsim.motion.run`: :func:`run_episode`, an episode to its end, on the grid or in motion.

See ``docs/motion.md``.
"""

from __future__ import annotations

from guardsim.motion.episode import ContinuousSimulation, default_max_seconds
from guardsim.motion.measures import U_TURN_DEGREES, continuous_measures, grid_measures, measures_of, summary_text
from guardsim.motion.parameters import (
    DEFAULT_MOVE_SPEED,
    DEFAULT_TICK_HZ,
    DEFAULT_TURN_SPEED,
    MOTIONS,
    STEER_DEGREES,
    GuardMotion,
)
from guardsim.motion.run import run_episode
from guardsim.motion.sight import PoseVision, pose_visible_cells
from guardsim.motion.smoothing import Waypoints, pull_route

__all__ = [
    "DEFAULT_MOVE_SPEED",
    "DEFAULT_TICK_HZ",
    "DEFAULT_TURN_SPEED",
    "MOTIONS",
    "STEER_DEGREES",
    "U_TURN_DEGREES",
    "ContinuousSimulation",
    "GuardMotion",
    "PoseVision",
    "Waypoints",
    "continuous_measures",
    "default_max_seconds",
    "grid_measures",
    "measures_of",
    "pose_visible_cells",
    "pull_route",
    "run_episode",
    "summary_text",
]
