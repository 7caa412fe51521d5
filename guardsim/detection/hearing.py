"""Hearing over a repeating patrol: where and when the intruder's step would be heard, for the exact
sneak searches. The rule is :mod:`guardsim.kernels.noise`'s (the alert loop's too): a step making a
noise of radius ``r`` in cell ``c`` at a tick is heard by a guard whose cell at that tick is at most
``r`` world units from ``c`` along the grid's traversable cells.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.noise import heard_lap
from guardsim.kernels.states import cell_of_state
from guardsim.level.model import IntruderSpec

__all__ = ["lap_hearing", "makes_noise", "walks_audibly"]


def makes_noise(intruder: IntruderSpec) -> bool:
    """Whether some gait of ``intruder`` makes a noise at all (a radius of 0 is silent, as in the alert
    loop)."""
    return intruder.walk_noise > 0 or intruder.sneak_noise > 0


def walks_audibly(intruder: IntruderSpec) -> bool:
    """Whether a walking step of ``intruder`` makes a noise: only then may an unheard search need to sneak
    (a silent walk is never worse than sneaking) and choose a gait for each step."""
    return intruder.walk_noise > 0


def lap_hearing(neighbours: np.ndarray, states: np.ndarray, intruder: IntruderSpec, cell_size: float) -> np.ndarray:
    """``bool (2, period, cells)``: whether some guard hears a walking (``[0]``) or a sneaking (``[1]``)
    step land in each cell at each tick of the lap ``states`` (``int64 (guards, period)``, guard states).

    >>> corridor = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> states = np.array([[3 * 4]])  # one guard standing in cell 3
    >>> lap_hearing(corridor, states, IntruderSpec(walk_noise=2, sneak_noise=1), 1.0).astype(int).tolist()
    [[[0, 1, 1, 1]], [[0, 0, 1, 1]]]
    """
    states = np.asarray(states, dtype=np.int64)
    listeners = cell_of_state(states)
    heard = np.zeros((2, states.shape[1], neighbours.shape[0]), dtype=np.bool_)
    for gait, radius in enumerate((intruder.walk_noise, intruder.sneak_noise)):
        if radius > 0:  # silent, as the alert loop makes no noise of radius 0
            heard[gait] = heard_lap(neighbours, listeners, radius, cell_size)
    return heard
