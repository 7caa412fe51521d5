"""Random walk: a uniformly random connected neighbour every tick, the baseline every planner must beat.

The draw comes from the episode's generator (``EpisodeSetup.rng``), so an episode is the same for the
same seed. A random walk covers a connected grid eventually (it visits every cell with probability one)
but may need far more steps than the loop's limit on large levels.
"""

from __future__ import annotations

import numpy as np

from guardsim.planners.base import EpisodeSetup, GuardState

__all__ = ["RandomWalk"]


class RandomWalk:
    """Step to a connected neighbour drawn uniformly at random."""

    name = "random-walk"

    def __init__(self) -> None:
        self._neighbours = np.zeros((0, 4), dtype=np.int64)
        self._rng = np.random.default_rng(0)

    def reset(self, setup: EpisodeSetup) -> None:
        """Keep the grid's connectivity and the episode's generator."""
        self._neighbours = setup.grid.neighbours
        self._rng = setup.rng

    def next_move(self, state: GuardState) -> int | None:
        """One of the connected directions, each with equal probability; ``None`` if there is none."""
        directions = np.flatnonzero(self._neighbours[state.cell] >= 0)
        if directions.size == 0:
            return None
        return int(directions[self._rng.integers(directions.size)])
