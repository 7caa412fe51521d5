"""What the simulation loop hands a planner, and what it expects back."""

from __future__ import annotations

from typing import NamedTuple, Protocol

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.vision.rules import VisionFunction

__all__ = ["STAY", "Accelerator", "EpisodeArrays", "EpisodeSetup", "GuardState", "Planner", "VisionFunction"]

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


class EpisodeArrays(NamedTuple):
    """The episode's state as the loop keeps it: arrays an :class:`Accelerator` advances in place.

    Ticks are numbered from 0 (the start); the logs hold one entry per tick up to the limit.
    """

    seen: np.ndarray
    """``bool (cells,)``: cells seen so far, by any guard."""
    first_seen: np.ndarray
    """``int64 (cells,)``: tick each cell was first seen, -1 if never."""
    goal: np.ndarray
    """``bool (cells,)``: the cells the episode must see."""
    cells: np.ndarray
    """``int64 (guards, limit + 1)``: each guard's flat cell per tick."""
    headings: np.ndarray
    """``int64 (guards, limit + 1)``: each guard's heading number per tick."""
    unseen_counts: np.ndarray
    """``int64 (limit + 1,)``: goal cells still unseen after each tick's look."""
    counters: np.ndarray
    """``int64 (3,)``: the current tick, the goal cells still unseen, the outcome (:data:`RUNNING` or an
    index into :data:`guardsim.trace.OUTCOMES`)."""


#: ``EpisodeArrays.counters`` slots, and the outcome of an episode still running.
TICK, UNSEEN, OUTCOME = 0, 1, 2
RUNNING = -1


class Accelerator(Protocol):
    """A planner's own fast path: it advances the loop's state by whole ticks, exactly as the loop would.

    A planner offers one through ``accelerator(setup)`` (returning ``None`` when it cannot serve that
    episode); the loop then asks it to advance instead of calling ``next_move`` tick by tick. The
    result must be the loop's, tick for tick: same looks, same decisions, same termination.
    """

    def advance(self, episode: EpisodeArrays, limit: int, ticks: int) -> None:
        """Run up to ``ticks`` ticks (-1: until the episode ends) and leave ``episode`` at a tick boundary,
        its outcome set when the episode ended (covered, ``limit`` reached, or stuck)."""


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
