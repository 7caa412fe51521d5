"""A stored reference trace checked before it is rebuilt: every field the comparison reads has the type
and size it must have, so that a hand-edited or corrupted reference is one error line, not a traceback.

The check covers the fields the trace format has always had; fields added later are left to
:meth:`guardsim.trace.Trace.from_data`, whose own failures are caught too.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from guardsim.errors import RegressionError
from guardsim.motion.parameters import MOTIONS
from guardsim.reading import NumberError, excerpt, finite_number, json_type
from guardsim.trace import OUTCOMES, Trace

__all__ = ["trace_from_stored"]


def trace_from_stored(data: Any, *, source: str, max_cells: int) -> Trace:
    """The :class:`Trace` in decoded reference JSON, or a :class:`RegressionError` saying which field
    is wrong; grids larger than ``max_cells`` are refused before they are converted."""

    def bad(message: str) -> RegressionError:
        return RegressionError(f"{source}: not a guardsim trace: {message}")

    if not isinstance(data, dict):
        raise bad(f"the top level is {json_type(data)}, not an object")
    for key in ("level", "planner", "outcome"):
        if not isinstance(data.get(key), str):
            raise bad(f"{key} must be a string, not {json_type(data.get(key))}")
    if data["outcome"] not in OUTCOMES:
        raise bad(f"outcome must be one of {', '.join(OUTCOMES)}, not {excerpt(data['outcome'], 40)}")
    if data.get("seed") is not None and not _is_int(data.get("seed")):
        raise bad("seed must be a whole number or null")
    cell_size: Any = data.get("cell_size")
    if not (_finite(cell_size) and cell_size > 0):
        raise bad(f"cell_size must be a positive number, not {excerpt(cell_size, 40)}")
    origin = data.get("origin")
    if not (isinstance(origin, list) and len(origin) == 2 and all(_finite(v) for v in origin)):
        raise bad(f"origin must be [x, y], not {excerpt(origin, 40)}")
    shape = data.get("shape")
    if not (isinstance(shape, list) and len(shape) == 2 and all(_is_int(v) and v > 0 for v in shape)):
        raise bad(f"shape must be [rows, cols] of positive whole numbers, not {excerpt(shape, 40)}")
    rows, cols = shape
    if rows * cols > max_cells:
        raise bad(f"a grid of {rows} x {cols} cells is over the limit of {max_cells} (max_cells)")
    for key in ("reachable", "unreachable"):
        if not (_is_int(data.get(key)) and data[key] >= 0):
            raise bad(f"{key} must be a whole number from 0, not {excerpt(data.get(key), 40)}")
    _check_path(data.get("path"), data.get("headings"), "path", "headings", rows, cols, bad)
    unseen = data.get("unseen_percent")
    if not (isinstance(unseen, list) and all(_finite(v) for v in unseen)):
        raise bad("unseen_percent must be a list of numbers")
    for key in ("first_seen", "goal", "traversable"):
        _check_grid(data.get(key), key, rows, cols, bad)
    paths, headings = data.get("guard_paths", []), data.get("guard_headings", [])
    if not (isinstance(paths, list) and isinstance(headings, list) and len(paths) == len(headings)):
        raise bad("guard_paths and guard_headings must be lists of the same length")
    for index, (path, log) in enumerate(zip(paths, headings)):
        _check_path(path, log, f"guard_paths[{index}]", f"guard_headings[{index}]", rows, cols, bad)
    if paths and data.get("guards", len(paths)) != len(paths):
        raise bad(f"guards is {excerpt(data.get('guards'), 20)} but guard_paths holds {len(paths)} paths")
    _check_motion(data, len(data["path"]), bad)
    try:
        return Trace.from_data(data)
    except (ValueError, KeyError, TypeError, IndexError, OverflowError) as error:
        raise bad(f"{type(error).__name__}: {excerpt(str(error))}") from None


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _finite(value: Any) -> bool:
    """Whether the one number parser takes ``value`` (an integer past float range is refused, not raised)."""
    try:
        finite_number(value)
    except NumberError:
        return False
    return True


def _check_path(path: Any, headings: Any, name: str, headings_name: str, rows: int, cols: int, bad: Any) -> None:
    """A non-empty list of ``[col, row]`` cells on the grid, and as many headings from 0 to 3."""
    if not isinstance(path, list) or not path:
        raise bad(f"{name} must be a non-empty list of [col, row] cells, not {excerpt(path, 40)}")
    for index, cell in enumerate(path):
        if not (isinstance(cell, list) and len(cell) == 2 and all(_is_int(v) for v in cell)):
            raise bad(f"{name}[{index}] must be [col, row], not {excerpt(cell, 40)}")
        if not (0 <= cell[0] < cols and 0 <= cell[1] < rows):
            raise bad(f"{name}[{index}] {excerpt(cell, 40)} lies outside the {rows} x {cols} grid")
    if not (isinstance(headings, list) and len(headings) == len(path)):
        raise bad(f"{headings_name} must be a list as long as {name} ({len(path)})")
    if not all(_is_int(h) and 0 <= h <= 3 for h in headings):
        raise bad(f"{headings_name} must hold heading numbers 0 to 3")


def _check_motion(data: dict[str, Any], ticks: int, bad: Any) -> None:
    """A continuous trace's rate and poses: ``[t, x, y, heading]`` of finite numbers, one per tick of the
    path (the renderer reads the pose of every tick it draws)."""
    motion = data.get("motion", "grid")
    if motion not in MOTIONS:
        raise bad(f"motion must be one of {', '.join(MOTIONS)}, not {excerpt(motion, 40)}")
    for key in ("move_speed", "turn_speed", "tick_hz"):
        value = data.get(key)
        if value is not None and not (_finite(value) and value > 0):
            raise bad(f"{key} must be a positive number, not {excerpt(value, 40)}")
    poses = data.get("poses")
    if motion == "continuous" and poses is None:
        raise bad("a continuous trace needs poses")
    if poses is None:
        return
    if not (isinstance(poses, list) and len(poses) == ticks):
        raise bad(f"poses must be a list of one [t, x, y, heading] per tick of the path ({ticks})")
    for index, pose in enumerate(poses):
        if not (isinstance(pose, list) and len(pose) == 4 and all(_finite(v) for v in pose)):
            raise bad(f"poses[{index}] must be [t, x, y, heading] of finite numbers, not {excerpt(pose, 40)}")


def _check_grid(value: Any, name: str, rows: int, cols: int, bad: Any) -> None:
    """``rows`` lists of ``cols`` whole numbers each."""
    if not (
        isinstance(value, list) and len(value) == rows and all(isinstance(r, list) and len(r) == cols for r in value)
    ):
        raise bad(f"{name} must be {rows} rows of {cols} numbers (the shape)")
    try:
        array = np.asarray(value)
    except (ValueError, TypeError, OverflowError):
        raise bad(f"{name} must hold whole numbers only") from None
    if array.dtype.kind not in "iub" or array.shape != (rows, cols):
        raise bad(f"{name} must hold whole numbers only")
