"""What a game reads from a running episode: where the guards are, what is seen, who sees a point.

:class:`EpisodeReads` is the read-only side of :class:`~guardsim.simulation.Simulation`; it reads the
episode's arrays and never changes them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.planners.base import OUTCOME, RUNNING, TICK, UNSEEN, EpisodeArrays
from guardsim.trace import OUTCOMES
from guardsim.vision.rules import VisionFunction

if TYPE_CHECKING:
    from guardsim.scene import Scene

__all__ = ["EpisodeReads"]

_HEADING_DEGREES = (0.0, 90.0, 180.0, 270.0)


class EpisodeReads:
    """The read-only properties and queries of a running episode (see :class:`~guardsim.simulation.Simulation`)."""

    scene: Scene
    vision: VisionFunction
    _seen_view: np.ndarray
    _goal_view: np.ndarray

    def _require(self) -> EpisodeArrays:
        raise NotImplementedError

    @property
    def tick(self) -> int:
        """Ticks elapsed since the start."""
        return int(self._require().counters[TICK])

    @property
    def done(self) -> bool:
        """Whether the episode has ended."""
        return int(self._require().counters[OUTCOME]) != RUNNING

    @property
    def outcome(self) -> str | None:
        """``"covered"``, ``"step_limit"`` or ``"stuck"`` once done; ``None`` while running."""
        code = int(self._require().counters[OUTCOME])
        return None if code == RUNNING else OUTCOMES[code]

    @property
    def cells(self) -> list[tuple[int, int]]:
        """``(col, row)`` of every guard now."""
        episode = self._require()
        grid = self.scene.grid
        return [grid.unflat(int(cell)) for cell in episode.cells[:, self.tick]]

    @property
    def positions(self) -> list[tuple[float, float]]:
        """World position of every guard now (its cell's centre)."""
        grid = self.scene.grid
        return [grid.centre(col, row) for col, row in self.cells]

    @property
    def headings(self) -> list[int]:
        """Heading number of every guard now (0 right, 1 down, 2 left, 3 up; y down)."""
        return [int(heading) for heading in self._require().headings[:, self.tick]]

    @property
    def heading_degrees(self) -> list[float]:
        """Heading of every guard now in degrees (0 along +x, 90 along +y)."""
        return [_HEADING_DEGREES[heading] for heading in self.headings]

    @property
    def seen(self) -> np.ndarray:
        """``bool (rows, cols)``, read-only: cells seen so far."""
        return self._seen_view.reshape(self.scene.grid.shape)

    @property
    def goal(self) -> np.ndarray:
        """``bool (rows, cols)``, read-only: the cells the episode must see (reachable from the starts)."""
        return self._goal_view.reshape(self.scene.grid.shape)

    @property
    def unseen(self) -> int:
        """Goal cells not yet seen."""
        return int(self._require().counters[UNSEEN])

    @property
    def coverage(self) -> float:
        """Fraction of the goal cells seen so far (1.0 for an empty goal)."""
        total = int(self._goal_view.sum())
        return 1.0 if total == 0 else 1.0 - self.unseen / total

    def visible_cells(self, guard: int | None = None) -> list[tuple[int, int]]:
        """``(col, row)`` of the cells guard ``guard`` sees from where it stands now.

        A lone guard needs no number; a team must say which guard (a ``ValueError`` otherwise), since
        "what is visible" differs per guard: :meth:`seen_by` answers for the whole team.
        """
        episode = self._require()
        guards = episode.cells.shape[0]
        if guard is None:
            if guards > 1:
                raise ArgumentError(f"a team of {guards} guards: say which guard (visible_cells(guard=k)), or use seen_by")
            guard = 0
        if not 0 <= guard < guards:
            raise ArgumentError(f"guard {guard} is not one of the team's {guards} guards")
        grid = self.scene.grid
        col, row = grid.unflat(int(episode.cells[guard, self.tick]))
        return [grid.unflat(int(cell)) for cell in self.vision(col, row, int(episode.headings[guard, self.tick]))]

    def seen_by(self, point: tuple[float, float]) -> list[int]:
        """The guards that see the world point ``point`` now (its cell is in their view), in order; an
        empty list when none does or the point is off the grid. ``bool(seen_by(p))``: is ``p`` seen now.
        """
        episode = self._require()
        grid = self.scene.grid
        cell = grid.cell_of(point)
        if cell is None:
            return []
        flat = grid.flat(*cell)
        seeing = []
        for guard in range(episode.cells.shape[0]):
            col, row = grid.unflat(int(episode.cells[guard, self.tick]))
            if flat in self.vision(col, row, int(episode.headings[guard, self.tick])):
                seeing.append(guard)
        return seeing

    def newly_seen(self) -> list[tuple[int, int]]:
        """``(col, row)`` of the cells first seen at this tick, by any guard."""
        episode = self._require()
        grid = self.scene.grid
        return [grid.unflat(int(cell)) for cell in np.flatnonzero(episode.first_seen == self.tick)]
