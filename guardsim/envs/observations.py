"""What a guard observes: a stack of 0/1 planes over the grid (or a window around the guard) and its heading.

The planes, in order (:data:`CHANNELS`):

0. ``traversable``: the guard can stand there.
1. ``goal``: the cells the episode must see (those reachable from the starts).
2. ``seen``: seen so far, by any guard.
3. ``in_view``: what this guard sees from where it stands now (its vision cone at this tick).
4. ``guard``: this guard's cell.
5. ``teammates``: cells where another guard of the team stands (all 0 for a single guard).

With ``crop=r`` the planes are a ``(2r + 1) x (2r + 1)`` window centred on the guard, north up (not turned
with the heading); cells past the grid's edge read 0 in every plane, like walls.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

from guardsim.simulation import Simulation

__all__ = ["CHANNELS", "observation_space", "observe", "state_planes", "state_space"]

#: Plane names, in order.
CHANNELS: tuple[str, ...] = ("traversable", "goal", "seen", "in_view", "guard", "teammates")
TRAVERSABLE, GOAL, SEEN, IN_VIEW, GUARD, TEAMMATES = range(len(CHANNELS))


def observation_space(grid_shape: tuple[int, int], crop: int | None = None) -> spaces.Dict:
    """The space of :func:`observe`'s observations on a grid of ``(rows, cols)``.

    Examples
    --------
    >>> observation_space((3, 4))["grid"].shape, observation_space((30, 40), crop=2)["grid"].shape
    ((6, 3, 4), (6, 5, 5))
    """
    rows, cols = grid_shape if crop is None else (2 * crop + 1, 2 * crop + 1)
    return spaces.Dict(
        {
            "grid": spaces.Box(0, 1, shape=(len(CHANNELS), rows, cols), dtype=np.uint8),
            "heading": spaces.Discrete(4),
        }
    )


def observe(simulation: Simulation, guard: int, crop: int | None = None) -> dict[str, Any]:
    """Guard ``guard``'s observation now: ``{"grid": uint8 planes, "heading": heading number}``.

    Every call returns new arrays, so an observation kept by a learner never changes under it.
    """
    grid = simulation.scene.grid
    planes = np.zeros((len(CHANNELS), *grid.shape), dtype=np.uint8)
    planes[TRAVERSABLE] = grid.traversable
    planes[GOAL] = simulation.goal
    planes[SEEN] = simulation.seen
    cells, headings = simulation.cells, simulation.headings
    col, row = cells[guard]
    planes[IN_VIEW].reshape(-1)[simulation.vision(col, row, headings[guard])] = 1
    planes[GUARD, row, col] = 1
    for other, (other_col, other_row) in enumerate(cells):
        if other != guard:
            planes[TEAMMATES, other_row, other_col] = 1
    if crop is not None:
        planes = _window(planes, col, row, crop)
    return {"grid": planes, "heading": headings[guard]}


def _window(planes: np.ndarray, col: int, row: int, crop: int) -> np.ndarray:
    """The ``(2 crop + 1)``-square of ``planes`` centred on ``(col, row)``, 0 past the edges."""
    rows, cols = planes.shape[1:]
    window = np.zeros((planes.shape[0], 2 * crop + 1, 2 * crop + 1), dtype=planes.dtype)
    top, left = row - crop, col - crop
    first_row, last_row = max(top, 0), min(row + crop + 1, rows)
    first_col, last_col = max(left, 0), min(col + crop + 1, cols)
    window[:, first_row - top : last_row - top, first_col - left : last_col - left] = planes[
        :, first_row:last_row, first_col:last_col
    ]
    return window


def state_space(grid_shape: tuple[int, int]) -> spaces.Box:
    """The space of :func:`state_planes`: four 0/1 planes over the whole grid."""
    return spaces.Box(0, 1, shape=(4, *grid_shape), dtype=np.uint8)


def state_planes(simulation: Simulation) -> np.ndarray:
    """The team's global state for centralised training: ``traversable``, ``goal``, ``seen`` and ``guards``
    (every guard's cell) as ``uint8 (4, rows, cols)``."""
    grid = simulation.scene.grid
    planes = np.zeros((4, *grid.shape), dtype=np.uint8)
    planes[0] = grid.traversable
    planes[1] = simulation.goal
    planes[2] = simulation.seen
    for col, row in simulation.cells:
        planes[3, row, col] = 1
    return planes
