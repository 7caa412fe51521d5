"""The exceptions guardsim raises on purpose.

Every error a user can cause (a bad level file, a limit exceeded, an output that cannot be written)
is a :class:`GuardsimError`. The CLI prints its message as one line and exits with status 2; anything
else escaping the library is a bug.
"""

from __future__ import annotations

__all__ = [
    "ArgumentError",
    "CheckError",
    "GuardsimError",
    "LevelError",
    "LimitError",
    "OutputError",
    "PatrolError",
    "PlannerError",
    "PointError",
    "RegressionError",
    "TraceError",
]


class GuardsimError(Exception):
    """Base class of every error guardsim reports to its user."""


class LevelError(GuardsimError):
    """A level file cannot be read or describes an impossible level.

    The message names the file and, where it applies, the ring and point at fault.
    """


class LimitError(GuardsimError):
    """A configured size limit (cells, vertices, file size, frames) would be exceeded."""


class OutputError(GuardsimError):
    """An output file cannot be written."""


class RegressionError(GuardsimError):
    """Stored regression references (``guardsim regress``) are missing a file or cannot be read."""


class PatrolError(GuardsimError):
    """A patrol file cannot be read or describes a patrol the level does not allow."""


class TraceError(GuardsimError):
    """A trace file cannot be read as the trace it claims to be, or does not fit the level given with it."""


class CheckError(GuardsimError):
    """A checks file or a rule cannot be used (bad input, not a broken rule)."""


class ArgumentError(GuardsimError, ValueError):
    """A value handed to a library function is out of its range or does not fit the level (a seed below 0,
    a guard count of 0, an action outside the action space). Also a ``ValueError``, the exception Python
    code expects for a bad value."""


class PointError(GuardsimError):
    """A point given in world coordinates (an entry, a goal, a post) is off the level or where a guard does
    not fit; the message names what the point is."""


class PlannerError(GuardsimError, KeyError):
    """An unknown planner name (also a ``KeyError``, as a lookup by name that failed)."""

    # KeyError would quote the message; this is a sentence.
    __str__ = Exception.__str__
