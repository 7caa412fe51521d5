"""The agent's moves: five actions, which of them move the guard, and the planner that hands them to the loop.

An action is a heading move: 0 stay, 1 right, 2 down, 3 left, 4 up. Actions 1 to 4 are guardsim's heading
numbers plus one (0 right, 1 down, 2 left, 3 up; y down). A move into a wall, or between two cells the
guard's circle cannot slide between, keeps the guard where it is, facing as it was (as "stay" does);
:func:`action_mask` says beforehand which moves would move it.
"""

from __future__ import annotations

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.planners.base import STAY, EpisodeSetup, GuardState

__all__ = ["ACTIONS", "AgentPlanner", "action_heading", "action_mask"]

#: Action names, indexed by action number.
ACTIONS: tuple[str, ...] = ("stay", "right", "down", "left", "up")


def action_heading(action: int) -> int:
    """The heading number an action moves along, or :data:`~guardsim.planners.base.STAY` for action 0.

    Examples
    --------
    >>> [action_heading(action) for action in range(len(ACTIONS))]
    [-1, 0, 1, 2, 3]
    """
    if not 0 <= action < len(ACTIONS):
        raise ArgumentError(f"action {action} is not one of 0..{len(ACTIONS) - 1} ({', '.join(ACTIONS)})")
    return STAY if action == 0 else action - 1


def action_mask(grid: CoverageGrid, cell: int) -> np.ndarray:
    """``int8 (5,)``: 1 for each action that would move the guard from flat cell ``cell`` (stay is always 1).

    ``int8`` because that is what :meth:`gymnasium.spaces.Discrete.sample` takes as ``mask``.

    Examples
    --------
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 2), dtype=bool), np.array([[1, -1, -1, -1], [-1, -1, 0, -1]]))
    >>> action_mask(grid, 0).tolist(), action_mask(grid, 1).tolist()
    ([1, 1, 0, 0, 0], [1, 0, 0, 1, 0])
    """
    mask = np.ones(len(ACTIONS), dtype=np.int8)
    mask[1:] = grid.neighbours[cell] >= 0
    return mask


class AgentPlanner:
    """A planner whose next move is chosen from outside: an environment sets it, then steps the simulation.

    Each tick the loop asks :meth:`next_move`, which returns the move set by :meth:`choose` (a blocked
    move becomes a stay) and forgets it, so a tick stepped without a choice is a stay.
    """

    name = "agent"

    def __init__(self) -> None:
        self._neighbours: np.ndarray | None = None
        self._move = STAY

    def reset(self, setup: EpisodeSetup) -> None:
        """Forget the previous episode's choice and learn the new episode's connectivity."""
        self._neighbours = setup.grid.neighbours
        self._move = STAY

    def choose(self, action: int) -> None:
        """Set the move of the next tick from an action number (0 stay, 1 right, 2 down, 3 left, 4 up)."""
        self._move = action_heading(action)

    def next_move(self, state: GuardState) -> int:
        """The chosen move, or a stay when it is blocked or nothing was chosen."""
        move, self._move = self._move, STAY
        if self._neighbours is None:
            raise RuntimeError("AgentPlanner.next_move called before reset")
        if move != STAY and self._neighbours[state.cell, move] < 0:
            return STAY
        return move
