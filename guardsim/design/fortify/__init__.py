"""Fortify a level: place cameras and guard posts until no player gets through, with a proof.

- :mod:`~guardsim.design.fortify.candidates`: the watchers it may add and their gains.
- :mod:`~guardsim.design.fortify.cover`: which candidates catch which ways through; the hitting sets.
- :mod:`~guardsim.design.fortify.loop`: the loop itself, :func:`fortify`.

See ``docs/fortify.md``.
"""

from __future__ import annotations

from guardsim.design.fortify.candidates import CameraShape, Candidate
from guardsim.design.fortify.loop import Counterexample, FortifyResult, KeepOpen, fortify

__all__ = ["CameraShape", "Candidate", "Counterexample", "FortifyResult", "KeepOpen", "fortify"]
