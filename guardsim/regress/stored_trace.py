"""A stored trace checked before it is rebuilt: ``trace.schema.json`` first (types, required keys,
ranges), then what a schema cannot say (the grid's size against ``max_cells``, cells on the grid, lengths
that match), so that a hand-edited or corrupted trace is one error line, not a traceback.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from guardsim.errors import RegressionError
from guardsim.reading import excerpt
from guardsim.schema import check
from guardsim.trace import Trace

__all__ = ["trace_from_stored"]

#: Starts every error line after the file's name.
_PREFIX = "not a guardsim trace: "


def trace_from_stored(data: Any, *, source: str, max_cells: int) -> Trace:
    """The :class:`Trace` in decoded trace JSON, or a :class:`RegressionError` saying which field is
    wrong; grids larger than ``max_cells`` are refused before they are converted.

    >>> trace_from_stored({"level": "x"}, source="t.json", max_cells=100)
    Traceback (most recent call last):
    ...
    guardsim.errors.RegressionError: t.json: not a guardsim trace: missing "planner"
    """
    check(data, "trace", source=source, error=RegressionError, prefix=_PREFIX)

    def bad(message: str) -> RegressionError:
        return RegressionError(f"{source}: {_PREFIX}{message}")

    rows, cols = data["shape"]
    if rows * cols > max_cells:
        raise bad(f"shape: a grid of {rows} x {cols} cells is over the limit of {max_cells} (max_cells)")
    paths = [("path", data["path"], "headings", data["headings"])]
    team, logs = data.get("guard_paths", []), data.get("guard_headings", [])
    if len(team) != len(logs):
        raise bad(f"guard_headings: {len(logs)} lists of headings for {len(team)} guard_paths")
    if team and data.get("guards", len(team)) != len(team):
        raise bad(f"guards: {data['guards']} but guard_paths holds {len(team)} paths")
    paths += [(f"guard_paths[{n}]", path, f"guard_headings[{n}]", log) for n, (path, log) in enumerate(zip(team, logs))]
    for name, path, headings_name, headings in paths:
        if len(headings) != len(path):
            raise bad(f"{headings_name}: {len(headings)} headings for the {len(path)} ticks of {name}")
        outside = next((index for index, (col, row) in enumerate(path) if col >= cols or row >= rows), None)
        if outside is not None:
            raise bad(f"{name}[{outside}]: {excerpt(path[outside], 40)} lies outside the {rows} x {cols} grid")
    for name in ("first_seen", "goal", "traversable"):
        if any(len(row) != cols for row in data[name]) or len(data[name]) != rows:
            raise bad(f"{name}: must be {rows} rows of {cols} numbers (the shape)")
    ticks = len(data["path"])
    if data.get("poses") is not None and len(data["poses"]) != ticks:
        raise bad(
            f"poses: must be a list of one [t, x, y, heading] per tick of the path ({ticks}), not {len(data['poses'])}"
        )
    field = data.get("field")
    if field is not None and not _is_grids(field, (ticks, rows, cols)):
        raise bad(f"field: must be {ticks} grids of {rows} rows of {cols} whole numbers (one per tick of the path)")
    try:
        return Trace.from_data(data)
    except (ValueError, KeyError, TypeError, IndexError, OverflowError) as error:
        raise bad(f"{type(error).__name__}: {excerpt(str(error))}") from None


def _is_grids(value: list[Any], shape: tuple[int, int, int]) -> bool:
    """Whether ``value`` is ``shape`` of whole numbers an ``int32`` holds."""
    try:
        array = np.asarray(value)
    except (ValueError, TypeError, OverflowError):
        return False
    return (
        array.shape == shape
        and array.dtype.kind in "iu"
        and (array.size == 0 or (array.min() >= np.iinfo(np.int32).min and array.max() <= np.iinfo(np.int32).max))
    )
