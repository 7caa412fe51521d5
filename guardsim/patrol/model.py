"""A patrol: every guard's state at every tick, one lap of it when it repeats.

A state is a cell and a heading (:func:`guardsim.grid.state_of`). Guards move as everywhere in guardsim:
each tick a guard steps to a connected 4-neighbour, facing the way it stepped, or stays, keeping its
heading. A repeating patrol stores one lap per guard, all laps the same length (the period); guard ``g``
is in ``states[g, tick % period]`` at every tick, for ever. A patrol that does not repeat stores the
ticks walked, and ``period`` is ``None``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from guardsim.errors import PatrolError
from guardsim.grid import CoverageGrid, cell_of_state, heading_of_state, state_of
from guardsim.level import HEADINGS

__all__ = ["STRATEGIES", "Patrol"]

#: The patrol strategies, by the name ``guardsim patrol --strategy`` takes.
STRATEGIES = ("loop", "staleness", "ripplefront", "random")


@dataclass(frozen=True, eq=False)
class Patrol:
    """Every guard's state per tick.

    Examples
    --------
    >>> patrol = Patrol(np.array([[8, 12, 16, 12]]), period=4, strategy="loop")
    >>> patrol.guards, patrol.ticks, int(patrol.state(0, 5))
    (1, 4, 12)
    """

    states: np.ndarray
    """``int64 (guards, ticks)``: state number of each guard at each tick (one lap when periodic)."""
    period: int | None
    """Ticks per lap; ``None`` when the patrol does not repeat."""
    strategy: str
    """How it was made: one of :data:`STRATEGIES`, or ``"evaluate"`` for a patrol read from a file."""
    planner: str | None = None
    """For ``loop``: whose viewpoints the loop was built from (``cover`` or a planner name)."""
    team: str | None = None
    """For a team's loop: ``"shared"`` (one cycle, guards evenly spaced) or ``"split"`` (a loop each)."""
    notes: tuple[str, ...] = field(default=())
    """Why the patrol is as it is (the team comparison), for the report."""
    motion: str = "grid"
    """How the guards walk the route: ``"grid"`` (ticks) or ``"continuous"`` (scored in seconds)."""

    def __post_init__(self) -> None:
        states = np.asarray(self.states, dtype=np.int64)
        if states.ndim != 2 or states.shape[0] < 1 or states.shape[1] < 1:
            raise PatrolError("a patrol needs at least one guard and one tick")
        if self.period is not None and self.period != states.shape[1]:
            raise PatrolError(f"period {self.period} differs from the {states.shape[1]} ticks stored per guard")
        object.__setattr__(self, "states", states)

    @classmethod
    def standing(cls, grid: CoverageGrid, posts: Sequence[tuple[tuple[float, float], str]]) -> Patrol:
        """Guards that stand still: each on the cell holding a world point, facing ``"right"``, ``"down"``,
        ``"left"`` or ``"up"``.

        Raises :class:`~guardsim.errors.PointError` for a point off the floor and
        :class:`~guardsim.errors.PatrolError` for an unknown heading.

        Examples
        --------
        >>> from guardsim import Scene, load_level
        >>> grid = Scene.from_level(load_level("levels/square.json")).grid
        >>> post = Patrol.standing(grid, [((5.5, 30.5), "right"), ((40, 12), "up")])
        >>> post.guards, post.period, post.cells(grid, 0), post.headings(1)
        (2, 1, [(5, 30)], [3])
        """
        states = []
        for number, (point, heading) in enumerate(posts):
            if heading not in HEADINGS:
                raise PatrolError(f"post {number}: heading {heading!r} is not one of {', '.join(HEADINGS)}")
            cell = grid.floor_cell(point, f"post {number}")
            states.append([int(state_of(cell, HEADINGS[heading] // 90))])
        return cls(np.array(states, dtype=np.int64).reshape(len(states), 1), period=1, strategy="post")

    @property
    def guards(self) -> int:
        """Number of guards."""
        return int(self.states.shape[0])

    @property
    def ticks(self) -> int:
        """Ticks stored per guard: the period when the patrol repeats."""
        return int(self.states.shape[1])

    def state(self, guard: int, tick: int) -> int:
        """Guard ``guard``'s state at ``tick`` (laps repeat; a walked patrol stays where it ended)."""
        index = tick % self.ticks if self.period is not None else min(tick, self.ticks - 1)
        return int(self.states[guard, index])

    def cells(self, grid: CoverageGrid, guard: int) -> list[tuple[int, int]]:
        """``(col, row)`` of guard ``guard`` at each stored tick."""
        return [grid.unflat(int(cell)) for cell in cell_of_state(self.states[guard])]

    def headings(self, guard: int) -> list[int]:
        """Heading number of guard ``guard`` at each stored tick."""
        return [int(heading) for heading in heading_of_state(self.states[guard])]

    def require_repeating_grid(self, source: str, use: str) -> int:
        """The period of a patrol that repeats in grid motion, as the exact searches and the batches over
        one lap need; any other is a :class:`~guardsim.errors.PatrolError` naming ``source``, the patrol's
        file or name, and ``use``, what needs it.

        Examples
        --------
        >>> Patrol(np.array([[8, 12]]), period=None, strategy="evaluate").require_repeating_grid("p.json", "alert")
        Traceback (most recent call last):
        ...
        guardsim.errors.PatrolError: p.json: alert needs a repeating grid-motion patrol (from guardsim patrol); this one has period null
        """
        if self.motion != "grid" or self.period is None:
            problem = f"motion {self.motion!r}" if self.motion != "grid" else "period null"
            raise PatrolError(
                f"{source}: {use} needs a repeating grid-motion patrol (from guardsim patrol); this one has {problem}"
            )
        return self.period

    def unrolled(self, ticks: int) -> np.ndarray:
        """``int64 (guards, ticks)``: every guard's state for ticks ``0..ticks-1``."""
        index = np.arange(ticks)
        index = index % self.ticks if self.period is not None else np.minimum(index, self.ticks - 1)
        return self.states[:, index]
