"""The line-of-sight rules a guard can see by."""

from __future__ import annotations

import enum
from collections.abc import Callable

import numpy as np

__all__ = ["LineOfSight", "VisionFunction"]

#: ``(col, row, heading) -> flat indices of the cells seen``, ascending.
VisionFunction = Callable[[int, int, int], np.ndarray]


class LineOfSight(str, enum.Enum):
    """How the segment from the eye to a cell centre is judged clear.

    A ``str`` enum, so a rule compares equal to its name (``LineOfSight("bresenham")``) and reads back
    from a trace or the command line as it was written.

    Examples
    --------
    >>> LineOfSight("bresenham") is LineOfSight.BRESENHAM, LineOfSight.PYMUNK.value
    (True, 'pymunk')
    """

    PYMUNK = "pymunk"
    """A pymunk segment query against the level's walls (the default)."""
    BRESENHAM = "bresenham"
    """Every cell of the integer Bresenham line between the two cells is traversable (grid solvers' rule)."""

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Every rule's name, default first."""
        return tuple(rule.value for rule in cls)
