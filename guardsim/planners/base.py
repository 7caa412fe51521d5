"""What the simulation loop hands a planner, and what it expects back."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple, Protocol

import numpy as np

from guardsim.grid import CoverageGrid

__all__ = ["STAY", "EpisodeSetup", "GuardState", "Planner", "VisionFunction"]

#: ``(col, row, heading) -> flat indices of the cells seen``, ascending.
VisionFunction = Callable[[int, int, int], np.ndarray]

#: A move that keeps the guard where it is (and facing as it was) for one tick.
STAY = -1


class EpisodeSetup(NamedTuple):
    """What a planner may know before the first tick."""

    grid: CoverageGrid
    """The coverage grid, with its connectivity."""
    goal: np.ndarray
    """``bool (rows * cols,)``, read-only: the cells the episode must see (reachable from the start)."""
    vision: VisionFunction
    """Which cells a state would see: the same rule the loop uses."""
    rng: np.random.Generator
    """The episode's generator, for planners that make random choices."""
    guard: int = 0
    """This planner's guard number."""
    guards: int = 1
    """How many guards the team has."""


class GuardState(NamedTuple):
    """The world as a planner sees it at one tick. Arrays are read-only views owned by the loop."""

    tick: int
    """Ticks elapsed."""
    cell: int
    """Flat index of this guard's cell."""
    heading: int
    """This guard's heading number (0 right, 1 down, 2 left, 3 up)."""
    seen: np.ndarray
    """``bool (rows * cols,)``: cells seen so far, by any guard."""
    goal: np.ndarray
    """``bool (rows * cols,)``: the cells the episode must see."""
    guard: int = 0
    """This guard's number."""
    team: tuple[tuple[int, int], ...] = ()
    """``(cell, heading)`` of every guard, this one included, in guard order (empty for one guard)."""


class Planner(Protocol):
    """A guard behaviour. The loop owns limits and termination; the planner only picks moves.

    Every guard of a team has its own planner object; all of them decide on the same state, then all
    move at once.
    """

    name: str

    def reset(self, setup: EpisodeSetup) -> None:
        """Forget any previous episode."""

    def next_move(self, state: GuardState) -> int | None:
        """The heading number of a step to a connected neighbour, :data:`STAY`, or ``None`` if stuck."""
