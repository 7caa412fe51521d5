"""RippleFront on a converged field: the paper's greedy rule with no ripple lag.

Each tick the field D is recomputed from scratch by a multi-source breadth-first search from every
unseen goal cell over connected moves, so it is exactly the distance to the nearest unseen cell (the
value RippleFront's field tends to after enough sweeps). The move is RippleFront's: the connected
neighbour with the smallest D, ties to the current heading, then right, down, left, up. Comparing the
two shows what the ripple's lag costs. In a team, each guard's sources are its share of the unseen cells
(:mod:`guardsim.planners.team_share`), as for RippleFront.
"""

from __future__ import annotations

from guardsim.kernels.distances import distances_from
from guardsim.planners.base import GuardState
from guardsim.planners.ripplefront import GreedyField, greedy_move
from guardsim.planners.team_share import guard_share

__all__ = ["RippleFrontExact"]


class RippleFrontExact(GreedyField):
    """Greedy descent on the exact distance to the nearest unseen goal cell, recomputed every tick.

    Its :attr:`distance` is 0 on the field's sources and ``FAR`` out of their reach.
    """

    name = "ripplefront-exact"

    def next_move(self, state: GuardState) -> int | None:
        """Recompute the field, then step to the neighbour with the smallest D."""
        targets = guard_share(self._neighbours, self._goal & ~state.seen, state.team, state.guard)
        self.distance = distances_from(self._neighbours, targets)
        return greedy_move(self.distance, self._neighbours[state.cell], state.heading)
