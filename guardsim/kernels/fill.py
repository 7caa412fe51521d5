"""Filling a vision state from compiled code: the cone's cells, screened against the walls near the eye.

A state is filled here when the screen settles every ray of it; a close call is left to pymunk, from
Python (:class:`guardsim.vision.cache.VisionCache`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.heap import heap_sort
from guardsim.kernels.screen import CLEAR, CLOSE_CALL, WallIndex, screen
from guardsim.kernels.steps import cell_of_state, heading_of_state
from guardsim.kernels.targets import cone_target

__all__ = ["FillArrays", "fill_many", "screen_state", "try_fill"]


class FillArrays(NamedTuple):
    """What :func:`try_fill` needs to fill a state from compiled code: the cone, the grid and the walls."""

    offsets: np.ndarray
    """``int64 (n, 2)``: every heading's cone offsets, one heading after another."""
    offsets_start: np.ndarray
    """``int64 (5,)``: heading ``h``'s offsets are ``offsets[offsets_start[h]:offsets_start[h + 1]]``."""
    traversable: np.ndarray
    """``bool (cells,)``."""
    rows: int
    cols: int
    origin_x: float
    origin_y: float
    cell_size: float
    walls: WallIndex
    stamp: np.ndarray
    """``int64 (walls + 1,)``: scratch for the screen (which walls a ray was tested against)."""
    candidates: np.ndarray
    """``int64 (widest cone,)``: scratch, the cells in the cone."""
    targets: np.ndarray
    """``float64 (widest cone, 2)``: scratch, their centres."""
    verdicts: np.ndarray
    """``int8 (widest cone,)``: scratch, the screen's verdict per ray."""


@jit
def screen_state(col: int, row: int, offsets: np.ndarray, fill: FillArrays) -> int:
    """The traversable cells in the cone (the guard's own excluded), their centres and ray verdicts,
    written into ``fill``'s scratch arrays; returns how many."""
    count = 0
    candidates, targets = fill.candidates, fill.targets
    for index in range(offsets.shape[0]):
        flat = cone_target(col, row, offsets, index, fill.rows, fill.cols, fill.traversable)
        if flat < 0:
            continue
        candidates[count] = flat
        targets[count, 0] = fill.origin_x + (flat % fill.cols + 0.5) * fill.cell_size
        targets[count, 1] = fill.origin_y + (flat // fill.cols + 0.5) * fill.cell_size
        count += 1
    if count and fill.walls.walls.shape[0]:
        screen(
            fill.origin_x + (col + 0.5) * fill.cell_size,
            fill.origin_y + (row + 0.5) * fill.cell_size,
            targets[:count],
            fill.walls,
            fill.stamp,
            fill.verdicts[:count],
        )
    return count


@jit
def try_fill(state: int, fill: FillArrays, data: np.ndarray, used: int, start: np.ndarray, length: np.ndarray) -> int:
    """Fill ``state`` without leaving compiled code when the screen settles every ray.

    Returns how many cells were stored at ``data[used:]``; -1 when a ray is a close call (pymunk must
    decide: fill it from Python) and -2 when ``data`` has no room (grow it from Python).
    """
    cell = cell_of_state(state)
    heading = heading_of_state(state)
    offsets = fill.offsets[fill.offsets_start[heading] : fill.offsets_start[heading + 1]]
    count = screen_state(cell % fill.cols, cell // fill.cols, offsets, fill)
    verdicts, candidates = fill.verdicts, fill.candidates
    visible = 1
    for index in range(count):
        if verdicts[index] == CLOSE_CALL:
            return -1
        if verdicts[index] == CLEAR:
            visible += 1
    if used + visible > data.shape[0]:
        return -2
    data[used] = cell
    position = used + 1
    for index in range(count):
        if verdicts[index] == CLEAR:
            data[position] = candidates[index]
            position += 1
    heap_sort(data, used, used + visible)
    start[state] = used
    length[state] = visible
    return visible


@jit
def fill_many(
    states: np.ndarray, fill: FillArrays, data: np.ndarray, used: int, start: np.ndarray, length: np.ndarray
) -> tuple[int, int, np.ndarray]:
    """:func:`try_fill` over ``states`` in order, skipping known ones: returns the new ``used``, where it
    stopped (``len(states)`` when done; earlier when ``data`` is full) and the close calls passed over."""
    close = np.empty(states.shape[0], dtype=np.int64)
    closes = 0
    for index in range(states.shape[0]):
        state = states[index]
        if length[state] >= 0:
            continue
        stored = try_fill(state, fill, data, used, start, length)
        if stored == -2:
            return used, index, close[:closes]
        if stored == -1:
            close[closes] = state
            closes += 1
        else:
            used += stored
    return used, states.shape[0], close[:closes]
