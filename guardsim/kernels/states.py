"""The state numbering: a state is a cell and one of the four headings, numbered cell by cell.

Plain Python, elementwise on numpy arrays too; :mod:`guardsim.kernels.steps` makes the same functions
callable from compiled code. This is the only place that knows ``cell * 4 + heading``.
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np

__all__ = ["HEADINGS_PER_CELL", "cell_of_state", "heading_of_state", "state_of"]

#: A state is a cell and one of the four headings; states are numbered cell by cell.
HEADINGS_PER_CELL = 4

_Index = TypeVar("_Index", int, np.ndarray)


def state_of(cell: _Index, heading: _Index) -> _Index:
    """The state number of a flat cell index and a heading number (also elementwise on arrays).

    Examples
    --------
    >>> state_of(3, 2), cell_of_state(14), heading_of_state(14)
    (14, 3, 2)
    """
    return cell * HEADINGS_PER_CELL + heading


def cell_of_state(state: _Index) -> _Index:
    """The flat cell index of a state number."""
    return state // HEADINGS_PER_CELL


def heading_of_state(state: _Index) -> _Index:
    """The heading number of a state number."""
    return state % HEADINGS_PER_CELL
