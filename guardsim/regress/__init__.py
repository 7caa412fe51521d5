"""Regression references: re-play a level from fixed seeds and compare it with what was stored.

The data flows through three modules: :mod:`guardsim.regress.references` reads and writes a level's
stored references (manifest, level snapshot, traces, key frames), :mod:`guardsim.regress.replay`
re-plays the episodes and compares them, and :mod:`guardsim.regress.frames` compares key frames and
draws the diff image. ``docs/regression.md`` describes the command built on this, ``guardsim regress``.
"""

from __future__ import annotations

from guardsim.regress.frames import Tolerance, compare_frames
from guardsim.regress.references import KEY_PERCENTS, REFERENCE_FRAME_SIZE, MotionOverride, ReplaySpec, default_specs
from guardsim.regress.replay import EpisodeResult, FrameDifference, LevelResult, regress_level, replay_trace

__all__ = [
    "KEY_PERCENTS",
    "REFERENCE_FRAME_SIZE",
    "EpisodeResult",
    "FrameDifference",
    "LevelResult",
    "MotionOverride",
    "ReplaySpec",
    "Tolerance",
    "compare_frames",
    "default_specs",
    "regress_level",
    "replay_trace",
]
