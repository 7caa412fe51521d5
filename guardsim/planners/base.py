"""What the simulation loop hands a planner, and what it expects back."""

from __future__ import annotations

from typing import NamedTuple, Protocol

import numpy as np

from guardsim.grid import CoverageGrid

__all__ = ["GuardState", "Planner"]


class GuardState(NamedTuple):
    """The world as a planner sees it at one tick. Arrays are read-only views owned by the loop."""

    tick: int
    """Ticks elapsed (= steps taken so far)."""
    cell: int
    """Flat index of the guard's cell."""
    heading: int
    """Current heading number (0 right, 1 down, 2 left, 3 up)."""
    seen: np.ndarray
    """``bool (rows * cols,)``: cells seen so far."""
    goal: np.ndarray
    """``bool (rows * cols,)``: the cells the episode must see (reachable from the start)."""


class Planner(Protocol):
    """A guard behaviour. The loop owns limits and termination; the planner only picks moves."""

    name: str

    def reset(self, grid: CoverageGrid, goal: np.ndarray) -> None:
        """Forget any previous episode; ``goal`` is the flat mask of cells to be seen."""

    def next_move(self, state: GuardState) -> int | None:
        """The heading number of the next step (a connected neighbour), or ``None`` if none is possible."""
