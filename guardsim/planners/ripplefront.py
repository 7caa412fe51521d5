"""RippleFront: greedy descent on a distance-to-unseen field that ripples one sweep per tick.

Every cell has D, the number of 4-connected steps to the nearest unseen cell. Unseen cells have D = 0.
Each tick the field is swept ``sweeps_per_tick`` times; a sweep sets every seen cell to one more than the
smallest D among its connected neighbours, using the previous sweep's values (a synchronous, Jacobi
update). The field is never recomputed from scratch, so after the guard sees new cells the change
spreads outward one cell per sweep: it ripples. The guard then steps to the connected neighbour with
the smallest D.

Ties between equal neighbours go to the current heading (keep walking straight), then to the first of
right, down, left, up.

In a team of several guards each guard's field treats as unseen only its share of the unseen cells,
those nearer to it than to any teammate (:mod:`guardsim.planners.team_share`), so the guards spread out
instead of chasing the same frontier. One guard's field is the paper's, unchanged.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.kernels.distances import FAR
from guardsim.kernels.steps import greedy_step
from guardsim.planners.base import EpisodeSetup, GuardState
from guardsim.planners.ripplefront_compiled import CompiledRippleFront
from guardsim.planners.team_share import guard_share
from guardsim.vision.cache import VisionCache

__all__ = ["FAR", "GreedyField", "RippleFront", "ripple_sweep"]


def ripple_sweep(distance: np.ndarray, seen: np.ndarray, neighbours: np.ndarray) -> np.ndarray:
    """One synchronous sweep of the field over every cell (the reference; cost grows with the map).

    Parameters
    ----------
    distance
        ``int32 (n,)``: D before the sweep.
    seen
        ``bool (n,)``: cells seen so far.
    neighbours
        ``int (n, 4)``: connected neighbour per direction, -1 where none.

    Returns
    -------
    numpy.ndarray
        ``int32 (n,)``: D after the sweep.

    Examples
    --------
    A corridor of four cells, the right-most one still unseen, starting from an all-zero field:

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> seen = np.array([True, True, True, False])
    >>> field = np.zeros(4, dtype=np.int32)
    >>> for _ in range(3):
    ...     field = ripple_sweep(field, seen, neighbours)
    ...     print(field.tolist())
    [1, 1, 1, 0]
    [2, 2, 1, 0]
    [3, 2, 1, 0]
    """
    padded = np.append(distance, FAR)
    nearest = padded[neighbours].min(axis=1)
    return np.where(seen, np.minimum(nearest + 1, FAR), 0).astype(np.int32)


class GreedyField:
    """What the RippleFront planners share: a field D over the grid's cells that the guard steps down.

    Subclasses set :attr:`distance` in ``next_move`` and pick the step with :func:`greedy_move`.
    """

    def __init__(self) -> None:
        self.distance = np.zeros(0, dtype=np.int32)
        """``int32 (cells,)``: the field D of the last decision."""
        self._neighbours = np.zeros((0, 4), dtype=np.int64)
        self._goal = np.zeros(0, dtype=bool)

    def reset(self, setup: EpisodeSetup) -> None:
        """Start every cell at D = 0, as if all were unseen; keep the grid's connectivity and the goal."""
        self.distance = np.zeros(setup.grid.size, dtype=np.int32)
        self._neighbours = setup.grid.neighbours
        self._goal = setup.goal


class RippleFront(GreedyField):
    """The paper's planner: ripple the field, then step down it greedily.

    Parameters
    ----------
    sweeps_per_tick
        Sweeps of the field before each decision; 1 is the paper's ripple, a large number approaches a
        fully converged field.
    """

    name = "ripplefront"

    def __init__(self, sweeps_per_tick: int = 1) -> None:
        if sweeps_per_tick < 1:
            raise ArgumentError("sweeps_per_tick must be at least 1")
        super().__init__()
        self.sweeps_per_tick = sweeps_per_tick
        self._accelerator: CompiledRippleFront | None = None

    @property
    def options(self) -> dict[str, Any]:
        """The options this planner was made with."""
        return {"sweeps_per_tick": self.sweeps_per_tick}

    def reset(self, setup: EpisodeSetup) -> None:
        """Start every cell at D = 0; see :meth:`GreedyField.reset`."""
        super().reset(setup)
        self._accelerator = None

    def accelerator(self, setup: EpisodeSetup) -> CompiledRippleFront | None:
        """The compiled tick (:mod:`guardsim.planners.ripplefront_compiled`) for a lone guard seeing
        through the level's vision cache; ``None`` otherwise, and for subclasses that decide differently.

        Call after :meth:`reset`; the accelerator and :meth:`next_move` share the field.
        """
        if setup.guards != 1 or not isinstance(setup.vision, VisionCache):
            return None
        if type(self).next_move is not RippleFront.next_move:
            return None
        self._accelerator = CompiledRippleFront(
            setup.grid.neighbours, setup.vision, self.distance, self.sweeps_per_tick
        )
        return self._accelerator

    def next_move(self, state: GuardState) -> int | None:
        """Sweep, then return the heading toward the connected neighbour with the smallest D."""
        if self._accelerator is not None:
            self._accelerator.stale = True
        done = state.seen
        if state.team:
            done = ~guard_share(self._neighbours, self._goal & ~state.seen, state.team, state.guard)
        for _ in range(self.sweeps_per_tick):
            # In place: an accelerator shares this array.
            self.distance[:] = ripple_sweep(self.distance, done, self._neighbours)
        return greedy_move(self.distance, self._neighbours[state.cell], state.heading)


def greedy_move(distance: np.ndarray, cell_neighbours: np.ndarray, heading: int) -> int | None:
    """The heading toward the smallest D among connected neighbours (:func:`~guardsim.kernels.steps.greedy_step`);
    None when there is none."""
    move = greedy_step(distance, cell_neighbours, heading)
    return None if move < 0 else move
