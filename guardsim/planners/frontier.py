"""Frontier-based exploration (Yamauchi 1997), with vision cones.

Yamauchi's robot drives to the nearest frontier, a reachable place on the boundary between explored and
unexplored space, and picks a new one when it gets there ("A frontier-based approach for autonomous
exploration", CIRA 1997; with several robots sharing one map, "Frontier-based exploration using multiple
robots", Agents 1998). With a cone, a frontier is a *state* (cell and heading) from which at least one
unseen goal cell would be seen. The guard walks a shortest path to the nearest such state (ties to the
state that would see the most unseen cells, then the lowest state number) and picks a new target when
the current one would no longer see anything unseen. A team simply shares the seen cells.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import heading_of_state
from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import FAR, distances_from
from guardsim.planners.base import EpisodeSetup, GuardState
from guardsim.planners.ripplefront import greedy_move
from guardsim.vision.table import UnseenTally, ViewTable, view_table

__all__ = ["Frontier", "nearest_frontier", "nearest_frontier_kernel"]


@jit
def nearest_frontier_kernel(entry: np.ndarray, counts: np.ndarray, distance: np.ndarray, far: int) -> int:
    """Compiled :func:`nearest_frontier` over the entry cells, for other compiled loops."""
    best = -1
    best_steps = far
    best_count = 0
    for state in range(counts.shape[0]):
        if counts[state] <= 0 or entry[state] < 0:
            continue
        steps = distance[entry[state]]
        if steps < best_steps or (steps == best_steps and counts[state] > best_count):
            best, best_steps, best_count = state, steps, counts[state]
    return best


def nearest_frontier(table: ViewTable, counts: np.ndarray, distance: np.ndarray) -> int:
    """The frontier state nearest to the guard, or -1 if no reachable state sees an unseen cell.

    Ties go to the state that would see the most unseen cells, then to the lowest state number.

    Parameters
    ----------
    table
        The level's view table.
    counts
        ``int32 (states,)``: unseen goal cells each state would see.
    distance
        ``int32 (cells,)``: steps from the guard's cell to each cell (``FAR`` out of reach).
    """
    return int(nearest_frontier_kernel(table.entry, counts, distance, int(FAR)))


class Frontier:
    """Walk to the nearest state that would see something unseen; pick a new one when it would not."""

    name = "frontier"

    def __init__(self) -> None:
        self.target = -1
        """State the guard is walking to, -1 before the first choice."""
        self._field = np.zeros(0, dtype=np.int32)
        self._neighbours = np.zeros((0, 4), dtype=np.int64)

    def reset(self, setup: EpisodeSetup) -> None:
        """Load the level's view table (built once per level) and count what each state would see."""
        self._neighbours = setup.grid.neighbours
        self._table = view_table(setup.grid, setup.vision)
        self._tally = UnseenTally(self._table, setup.goal)
        self.target = -1

    def next_move(self, state: GuardState) -> int | None:
        """The next step of a shortest path into the target state; ``None`` when no frontier is left."""
        self._tally.update(state.seen)
        if self.target < 0 or self._tally.counts[self.target] == 0:
            self.target = nearest_frontier(
                self._table, self._tally.counts, distances_from(self._neighbours, np.array([state.cell]))
            )
            if self.target < 0:
                return None
            self._field = distances_from(self._neighbours, np.array([self._table.entry[self.target]]))
        if state.cell == self._table.entry[self.target]:
            return int(heading_of_state(self.target))
        return greedy_move(self._field, self._neighbours[state.cell], state.heading)
