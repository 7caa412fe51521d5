"""Spreading a team: each guard chases only the unseen cells nearer to it than to any teammate.

The targets are split by breadth-first distance from each guard's cell (a Voronoi split of the grid
along connected paths, recomputed every tick as the guards move). A cell at equal distance from several
guards goes to one of them chosen by the cell's flat index modulo their number, so that guards standing
on the same cell (same distances everywhere) still get different shares and part ways. A guard whose
share is empty chases every target, so no guard idles while cells remain unseen.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.distances import distance_fields

__all__ = ["guard_share"]


def guard_share(
    neighbours: np.ndarray, targets: np.ndarray, team: tuple[tuple[int, int], ...], guard: int
) -> np.ndarray:
    """The targets guard ``guard`` should chase.

    Parameters
    ----------
    neighbours
        ``int64 (cells, 4)``: the grid's connected neighbours.
    targets
        ``bool (cells,)``: cells still to be seen.
    team
        ``(cell, heading)`` of every guard, in guard order (``GuardState.team``).
    guard
        This guard's number.

    Returns
    -------
    numpy.ndarray
        ``bool (cells,)``: the targets nearer to this guard than to any other (a tie between ``k``
        guards goes to the ``(cell % k)``-th of them in guard order), or all of ``targets`` when that
        is none of them or the team has one guard.

    Examples
    --------
    A corridor of five cells, guards at both ends, every cell a target: the middle cell 2 is a tie
    between two guards, and ``2 % 2`` gives it to the first.

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [4, -1, 2, -1], [-1, -1, 3, -1]])
    >>> targets = np.ones(5, dtype=bool)
    >>> guard_share(neighbours, targets, ((0, 0), (4, 2)), 1).tolist()
    [False, False, False, True, True]

    Both guards on cell 2: every cell is a tie, and they take turns.

    >>> guard_share(neighbours, targets, ((2, 0), (2, 2)), 1).tolist()
    [False, True, False, True, False]
    """
    if len(team) < 2:
        return targets
    fields = distance_fields(neighbours, np.array([cell for cell, _ in team], dtype=np.int64))
    nearest = fields == fields.min(axis=0)
    tied = nearest.sum(axis=0)
    rank = np.cumsum(nearest, axis=0)[guard] - 1
    share = targets & nearest[guard] & (rank == np.arange(targets.size) % tied)
    return share if share.any() else targets
