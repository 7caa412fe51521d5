"""Boustrophedon coverage without vision: visit every reachable cell, as a robot vacuum cleaner does.

After BA* (Viet, Dang, Chung, Nguyen and Dang, "BA*: an online complete coverage algorithm for cleaning
robots", Applied Intelligence 2013): the guard sweeps in lanes, going up or down a column while the next
cell is unvisited, stepping sideways to the next column at the end of a lane (continuing in the same
sideways direction while it can) and reversing its lane direction there. When no neighbour is unvisited
it walks a shortest path to the nearest unvisited cell (BA* plans that leg with A* to a backtracking
point; on a grid of unit steps a breadth-first field gives the same length) and sweeps on from there.

The planner ignores what the guard sees: it knows only the grid, its own visits and, in a team, where
its teammates stand (their cells count as visited, like cleaned floor on a shared map). Having stood on
every reachable cell it has seen every one, so the loop always ends the episode as covered.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.distances import distances_from
from guardsim.planners.base import EpisodeSetup, GuardState
from guardsim.planners.ripplefront import greedy_move

__all__ = ["Sweep"]

RIGHT, DOWN, LEFT, UP = range(4)


class Sweep:
    """Vision-blind boustrophedon lanes with shortest-path jumps to the nearest unvisited cell."""

    name = "sweep"

    def __init__(self) -> None:
        self.visited = np.zeros(0, dtype=bool)
        """``bool (cells,)``: cells this guard or a teammate has stood on."""
        self._neighbours = np.zeros((0, 4), dtype=np.int64)
        self._lane = UP
        self._side = RIGHT

    def reset(self, setup: EpisodeSetup) -> None:
        """Nothing visited; lanes start upward, sideways steps rightward."""
        self._neighbours = setup.grid.neighbours
        self._reachable = setup.goal
        self.visited = np.zeros(setup.grid.size, dtype=bool)
        self._lane, self._side = UP, RIGHT

    def next_move(self, state: GuardState) -> int | None:
        """Continue the lane, else step sideways and turn the lane, else head for the nearest unvisited cell."""
        self.visited[state.cell] = True
        for cell, _ in state.team:
            self.visited[cell] = True
        around = self._neighbours[state.cell]

        def fresh(direction: int) -> bool:
            return bool(around[direction] >= 0 and not self.visited[around[direction]])

        for lane in (self._lane, self._lane ^ 2):
            if fresh(lane):
                self._lane = lane
                return lane
        for side in (self._side, self._side ^ 2):
            if fresh(side):
                self._side, self._lane = side, self._lane ^ 2
                return side
        unvisited = self._reachable & ~self.visited
        if not unvisited.any():
            return None
        return greedy_move(distances_from(self._neighbours, unvisited), around, state.heading)
