"""RippleFront on a converged field: the paper's greedy rule with no ripple lag.

Each tick the field D is recomputed from scratch by a multi-source breadth-first search from every
unseen goal cell over connected moves, so it is exactly the distance to the nearest unseen cell (the
value RippleFront's field tends to after enough sweeps). The move is RippleFront's: the connected
neighbour with the smallest D, ties to the current heading, then right, down, left, up. Comparing the
two shows what the ripple's lag costs. In a team, each guard's sources are its share of the unseen cells
(:mod:`guardsim.planners.team_share`), as for RippleFront.
"""

from __future__ import annotations

import numpy as np

from guardsim.planners.base import EpisodeSetup, GuardState
from guardsim.planners.ripplefront import greedy_move
from guardsim.planners.shortest_paths import distances_from
from guardsim.planners.team_share import guard_share

__all__ = ["RippleFrontExact"]


class RippleFrontExact:
    """Greedy descent on the exact distance to the nearest unseen goal cell, recomputed every tick."""

    name = "ripplefront-exact"

    def __init__(self) -> None:
        self.distance = np.zeros(0, dtype=np.int32)
        """``int32 (cells,)``: the field of the last decision (0 on its sources, ``FAR`` out of reach)."""
        self._neighbours = np.zeros((0, 4), dtype=np.int64)
        self._goal = np.zeros(0, dtype=bool)

    def reset(self, setup: EpisodeSetup) -> None:
        """Keep the grid's connectivity and the goal."""
        self.distance = np.zeros(setup.grid.size, dtype=np.int32)
        self._neighbours = setup.grid.neighbours
        self._goal = setup.goal

    def next_move(self, state: GuardState) -> int | None:
        """Recompute the field, then step to the neighbour with the smallest D."""
        targets = guard_share(self._neighbours, self._goal & ~state.seen, state.team, state.guard)
        self.distance = distances_from(self._neighbours, targets)
        return greedy_move(self.distance, self._neighbours[state.cell], state.heading)
