"""Spreading a team: each guard chases only the unseen cells nearer to it than to any teammate.

The targets are split by breadth-first distance from each guard's cell (a Voronoi split of the grid
along connected paths, recomputed every tick as the guards move). A cell at equal distance from several
guards goes to the lowest-numbered of them. A guard whose share is empty chases every target, so no
guard idles while cells remain unseen.
"""

from __future__ import annotations

import numpy as np

from guardsim.planners.shortest_paths import distance_fields

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
        ``bool (cells,)``: the targets nearer to this guard than to any other (ties to the lowest
        number), or all of ``targets`` when that is none of them or the team has one guard.

    Examples
    --------
    A corridor of five cells, guards at both ends, every cell a target: the middle cell is a tie.

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [4, -1, 2, -1], [-1, -1, 3, -1]])
    >>> targets = np.ones(5, dtype=bool)
    >>> guard_share(neighbours, targets, ((0, 0), (4, 2)), 1).tolist()
    [False, False, False, True, True]
    """
    if len(team) < 2:
        return targets
    fields = distance_fields(neighbours, np.array([cell for cell, _ in team], dtype=np.int64))
    share = targets & (np.argmin(fields, axis=0) == guard)
    return share if share.any() else targets
