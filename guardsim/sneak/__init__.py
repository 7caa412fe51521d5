"""The sneak check: can a player cross a patrolled level unseen, and where can it hide?

- :mod:`~guardsim.sneak.search`: the exact space-time search (unseen path, closest call, hiding windows).
- :mod:`~guardsim.sneak.gif`: the intruder drawn over the patrol's frames.

See ``docs/patrols.md``.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from guardsim.errors import LimitError
from guardsim.grid import CoverageGrid
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import seen_timeline
from guardsim.sneak.search import SneakPath, closest_call, find_sneak, hiding_windows
from guardsim.vision.table import ViewTable

__all__ = [
    "MAX_SNEAK_NODES",
    "SneakPath",
    "SneakResult",
    "closest_call",
    "find_sneak",
    "hiding_windows",
    "sneak_check",
    "sneak_data",
]


class SneakResult(NamedTuple):
    """The answer of the sneak check."""

    path: SneakPath | None
    """The fastest unseen path when one exists, else the closest call; ``None`` when the target cannot
    be reached at all."""
    period: int
    seen: np.ndarray
    """``bool (period, cells)``: what the patrol sees at each tick of its lap."""
    hiding: np.ndarray
    """``int64 (cells,)``: each cell's longest unseen window (see :func:`hiding_windows`)."""

    @property
    def found(self) -> bool:
        """Whether an unseen path exists."""
        return self.path is not None and self.path.found


#: Most (cell, lap tick) nodes a sneak search may have (about 30 bytes of memory each).
MAX_SNEAK_NODES = 20_000_000


def sneak_check(grid: CoverageGrid, table: ViewTable, patrol: Patrol, source: int, target: int) -> SneakResult:
    """Search for an unseen path from cell ``source`` to cell ``target`` (flat indices) under ``patrol``.

    Raises
    ------
    LimitError
        When the period times the cells is over :data:`MAX_SNEAK_NODES`.
    """
    if patrol.period is None:
        raise ValueError("the sneak check needs a repeating patrol (its period is null)")
    nodes = patrol.period * grid.size
    if nodes > MAX_SNEAK_NODES:
        raise LimitError(
            f"the sneak search would have {nodes} (cell, lap tick) nodes ({grid.size} cells x a {patrol.period}-tick lap), "
            f"over the limit of {MAX_SNEAK_NODES}"
        )
    seen = seen_timeline(table, patrol.states, grid.size)
    path = find_sneak(grid.neighbours, seen, source, target) or closest_call(grid.neighbours, seen, source, target)
    return SneakResult(path, patrol.period, seen, hiding_windows(seen, grid.traversable))


def sneak_data(result: SneakResult, grid: CoverageGrid, **header: Any) -> dict[str, Any]:
    """sneak.json: ``found``, ``start_tick``, ``path`` (``[col, row]`` per tick), ``ticks``, the ticks in
    view (0 when found; the closest call's otherwise) and the hiding spots."""
    path = result.path
    rows, cols = grid.shape
    hiding = result.hiding.reshape(rows, cols)
    never = int(((result.hiding == result.period) & grid.traversable.ravel()).sum())
    return {
        **header,
        "period": result.period,
        "found": result.found,
        "reachable": path is not None,
        "start_tick": None if path is None else path.start_tick,
        "path": None if path is None else [list(grid.unflat(int(cell))) for cell in path.cells],
        "ticks": None if path is None else path.ticks,
        "ticks_in_view": None if path is None else path.ticks_in_view,
        "closest_call": path is not None and not path.found,
        "never_seen_cells": never,
        "longest_unseen": [[None if value < 0 else int(value) for value in row] for row in hiding.tolist()],
    }
