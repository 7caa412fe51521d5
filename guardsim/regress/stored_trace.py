"""A stored trace checked before it is rebuilt: ``trace.schema.json`` first (types, required keys,
ranges), then what a schema cannot say (the grid's size against ``max_cells``, cells on the grid, lengths
that match), so that a hand-edited or corrupted trace is one error line, not a traceback.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from guardsim.errors import RegressionError
from guardsim.files.reading import excerpt
from guardsim.files.schema import check
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
    rows, cols = data["shape"]
    if rows * cols > max_cells:
        raise _bad(source, f"shape: a grid of {rows} x {cols} cells is over the limit of {max_cells} (max_cells)")
    _check_paths(data, rows, cols, source)
    _check_grids(data, rows, cols, source)
    try:
        return Trace.from_data(data)
    except (ValueError, KeyError, TypeError, IndexError, OverflowError) as error:
        raise _bad(source, f"{type(error).__name__}: {excerpt(str(error))}") from None


def _bad(source: str, message: str) -> RegressionError:
    return RegressionError(f"{source}: {_PREFIX}{message}")


def _check_paths(data: dict[str, Any], rows: int, cols: int, source: str) -> None:
    """The path and a team's paths: cells on the grid, one heading per tick, one heading list per path."""
    team, logs = data.get("guard_paths", []), data.get("guard_headings", [])
    if len(team) != len(logs):
        raise _bad(source, f"guard_headings: {len(logs)} lists of headings for {len(team)} guard_paths")
    if team and data.get("guards", len(team)) != len(team):
        raise _bad(source, f"guards: {data['guards']} but guard_paths holds {len(team)} paths")
    paths = [("path", data["path"], "headings", data["headings"])]
    paths += [(f"guard_paths[{n}]", path, f"guard_headings[{n}]", log) for n, (path, log) in enumerate(zip(team, logs))]
    for name, path, headings_name, headings in paths:
        if len(headings) != len(path):
            raise _bad(source, f"{headings_name}: {len(headings)} headings for the {len(path)} ticks of {name}")
        outside = next((index for index, (col, row) in enumerate(path) if col >= cols or row >= rows), None)
        if outside is not None:
            raise _bad(source, f"{name}[{outside}]: {excerpt(path[outside], 40)} lies outside the {rows} x {cols} grid")


def _check_grids(data: dict[str, Any], rows: int, cols: int, source: str) -> None:
    """The per-cell grids of ``shape``; poses and the recorded field one per tick of the path."""
    for name in ("first_seen", "goal", "traversable"):
        if len(data[name]) != rows or any(len(row) != cols for row in data[name]):
            raise _bad(source, f"{name}: must be {rows} rows of {cols} numbers (the shape)")
    ticks = len(data["path"])
    poses, field = data.get("poses"), data.get("field")
    if poses is not None and len(poses) != ticks:
        raise _bad(
            source, f"poses: must be a list of one [t, x, y, heading] per tick of the path ({ticks}), not {len(poses)}"
        )
    if field is not None and not _is_grids(field, (ticks, rows, cols)):
        raise _bad(
            source, f"field: must be {ticks} grids of {rows} rows of {cols} whole numbers (one per tick of the path)"
        )


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
