"""The state numbering for compiled code, and the greedy step that every walker takes.

:func:`state_of`, :func:`cell_of_state` and :func:`heading_of_state` are the plain functions of
:mod:`guardsim.kernels.states`, registered here so that compiled code may call them too (importing this
module registers them). :func:`greedy_step` likewise runs as plain Python or inside compiled code.
"""

from __future__ import annotations

import numpy as np
from numba.extending import register_jitable

from guardsim.kernels.states import cell_of_state, heading_of_state, state_of

__all__ = ["cell_of_state", "greedy_step", "heading_of_state", "state_of"]

for _plain in (state_of, cell_of_state, heading_of_state):
    register_jitable(inline="always")(_plain)


@register_jitable(inline="always")
def greedy_step(distance: np.ndarray, cell_neighbours: np.ndarray, heading: int) -> int:
    """The heading of the step to the connected neighbour with the smallest ``distance``, given a cell's
    row of neighbours (-1 where none); ties keep ``heading``, then right, down, left, up (0, 1, 2, 3);
    -1 when the cell has no neighbour.

    Examples
    --------
    The middle of a corridor of three cells, facing left, a field falling to the right:

    >>> greedy_step(np.array([2, 1, 0]), np.array([2, -1, 0, -1]), 2)
    0
    """
    best = -1
    best_distance = 0
    for choice in range(5):
        direction = heading if choice == 0 else choice - 1
        other = cell_neighbours[direction]
        if other >= 0 and (best < 0 or distance[other] < best_distance):
            best = direction
            best_distance = distance[other]
    return best
