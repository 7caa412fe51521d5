"""Screening rays against nearby walls, compiled, so that pymunk is asked only about close calls.

For a ray (eye to a cell centre) and a wall segment, two orientation tests with a safety margin decide
most cases outright: the wall's endpoints strictly on one side of the ray's line, or the ray's endpoints
strictly on one side of the wall's line, means no contact; both pairs strictly on opposite sides means a
proper crossing. Only what falls inside the margin (a ray through a wall's vertex, along a wall, ending
on one) is left to :meth:`guardsim.world.World.line_of_sight`, so the verdict on every ray is pymunk's.
The margin is many orders of magnitude above floating-point error and far below any level's detail.
"""

from __future__ import annotations

import itertools
import math
from typing import NamedTuple

import numpy as np

from guardsim.errors import LimitError
from guardsim.kernels.compiler import jit

__all__ = ["BLOCKED", "CLEAR", "CLOSE_CALL", "MAX_WALL_ENTRIES", "WallIndex", "index_walls", "screen"]

CLEAR, BLOCKED, CLOSE_CALL = 0, 1, 2


class WallIndex(NamedTuple):
    """Wall segments bucketed on a square grid, so a ray is screened only against walls near its eye.

    A NamedTuple of arrays and numbers, so compiled code takes it whole. Build it with :func:`index_walls`.
    """

    segments: np.ndarray
    """``float64 (m, 4)``: ``ax, ay, bx, by`` of every wall segment."""
    start: np.ndarray
    """``int64 (buckets + 1,)``: bucket ``b`` holds ``walls[start[b]:start[b + 1]]``."""
    walls: np.ndarray
    """``int64``: wall numbers, bucket after bucket."""
    origin_x: float
    origin_y: float
    """World position of the buckets' top-left corner."""
    bucket: float
    """Side of a bucket."""
    columns: int
    rows: int
    margin: float
    """Cross products within this of zero are close calls (left to pymunk)."""


#: Most (bucket, wall) entries a :class:`WallIndex` may hold: 64 MB, about 350 MB while it is built. A
#: wall is entered in each bucket its segment passes through, so real maps need thousands (brc202d
#: 6,753); 99,997 spikes from the middle of a 1000 x 1000 level to its rim need 7.6 million at a view
#: range of 8 and 15 million at 4.
MAX_WALL_ENTRIES = 8_000_000

#: Column strips worked on at once while the entries are listed: it bounds the temporary arrays.
_STRIPS_PER_CHUNK = 1 << 20


def index_walls(
    segments: np.ndarray,
    origin: tuple[float, float],
    extent: tuple[float, float],
    reach: float,
    *,
    max_entries: int | None = None,
) -> WallIndex:
    """Bucket ``segments`` (``float (m, 4)``) over ``extent`` (width, height) from ``origin``.

    ``reach`` is the longest ray, the side of a bucket. Each wall is entered in every bucket its segment
    passes through (with a margin of float noise), which is all :func:`screen` needs: a wall that touches a
    ray inside the eye's box of buckets passes through one of them.

    Raises :class:`~guardsim.errors.LimitError` when the index would hold more than ``max_entries``
    entries (:data:`MAX_WALL_ENTRIES` by default), counted from the segments' spans before any entry is
    listed.

    >>> index = index_walls(np.array([[1.0, 1.0, 39.0, 29.0]]), (0.0, 0.0), (40.0, 30.0), 10.0)
    >>> (index.columns, index.rows, int(index.walls.size))  # 6 of the 4 x 3 buckets of its box
    (5, 4, 6)
    """
    segments = np.ascontiguousarray(segments, dtype=np.float64).reshape(-1, 4)
    origin_x, origin_y = float(origin[0]), float(origin[1])
    # At least a 256th of the extent: a short reach on a wide level must not make billions of buckets.
    bucket = max(float(reach), max(extent) / 256, 1e-9)
    columns = math.ceil(extent[0] / bucket) + 1
    rows = math.ceil(extent[1] / bucket) + 1
    scale = max(abs(v) for v in (origin_x, origin_y, extent[0] + abs(origin_x), extent[1] + abs(origin_y), 1.0))
    # Cross products are of vectors at most `scale` long; their rounding error is ~1e-16 * scale**2.
    margin = 1e-9 * scale * scale
    limit = MAX_WALL_ENTRIES if max_entries is None else max_entries
    slots, walls = _bucket_entries(segments, origin_x, origin_y, bucket, columns, rows, limit, scale)
    order = np.argsort(slots, kind="stable")  # walls stay ascending within a bucket
    start = np.zeros(columns * rows + 1, dtype=np.int64)
    np.cumsum(np.bincount(slots, minlength=columns * rows), out=start[1:])
    return WallIndex(segments, start, walls[order], origin_x, origin_y, bucket, columns, rows, margin)


class _Strips(NamedTuple):
    """Segments walked left to right, cut into the column strips of buckets they span."""

    x0: np.ndarray
    y0: np.ndarray
    x1: np.ndarray
    y1: np.ndarray
    """Each segment's ends, ``x0 <= x1``."""
    first_col: np.ndarray
    """``int64``: the first column each segment spans."""
    counts: np.ndarray
    """``int64``: how many columns each segment spans."""
    origin_x: float
    origin_y: float
    bucket: float
    rows: int
    slack: float
    """Far below any level's detail, far above float error: a point on a bucket's side is in both."""


def _bucket_entries(
    segments: np.ndarray,
    origin_x: float,
    origin_y: float,
    bucket: float,
    columns: int,
    rows: int,
    max_entries: int,
    scale: float,
) -> tuple[np.ndarray, np.ndarray]:
    """``(slot, wall)`` of every bucket each segment passes through, walls in ascending order.

    A segment is cut into the column strips it spans; in each strip it covers the rows between its
    heights at the strip's two sides. Entering walls in their whole bounding box instead cost a fan of
    99,997 long spikes 120 million entries and 3 GB of Python lists, before the view table's own
    estimate was even asked.
    """
    with np.errstate(invalid="ignore", over="ignore"):
        ax, ay, bx, by = segments.T
        flip = ax > bx
        x0, y0 = np.where(flip, bx, ax), np.where(flip, by, ay)
        x1, y1 = np.where(flip, ax, bx), np.where(flip, ay, by)
        slack = 1e-9 * bucket + 1e-12 * scale
        first_col = _index_of(x0 - slack, origin_x, bucket, columns)
        counts = _index_of(x1 + slack, origin_x, bucket, columns) - first_col + 1
        rows_spanned = (
            _index_of(np.maximum(y0, y1) + slack, origin_y, bucket, rows)
            - _index_of(np.minimum(y0, y1) - slack, origin_y, bucket, rows)
            + 1
        )
    strips = _Strips(x0, y0, x1, y1, first_col, counts, origin_x, origin_y, bucket, rows, slack)
    # In each strip a straight segment meets the rows between its heights at the strip's sides, one
    # more at each side within the slack: at most the rows it spans plus 3 per strip, known before any
    # entry is listed. Past the limit, the exact count decides.
    if int((3 * counts + rows_spanned).sum()) > max_entries and _count_entries(strips, max_entries) > max_entries:
        raise LimitError(
            f"the sight index of {segments.shape[0]} wall segments would hold more than {max_entries} "
            f"entries (max_wall_entries): too many long walls for its buckets of {bucket:g} units"
        )
    slot_parts: list[np.ndarray] = []
    wall_parts: list[np.ndarray] = []
    for begin, end in _chunks(counts):
        row_first, row_last, column, wall = _strip_rows(strips, begin, end)
        spanned = row_last - row_first + 1
        strip_of = np.repeat(np.arange(spanned.size), spanned)
        row = row_first[strip_of] + np.arange(strip_of.size) - np.repeat(np.cumsum(spanned) - spanned, spanned)
        slot_parts.append(row * columns + column[strip_of])
        wall_parts.append(wall[strip_of])
    if not slot_parts:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(slot_parts), np.concatenate(wall_parts)


def _index_of(value: np.ndarray, origin: float, bucket: float, count: int) -> np.ndarray:
    """The bucket index of each coordinate, clipped to ``0 .. count - 1`` (NaN goes to 0)."""
    index = np.floor((value - origin) / bucket)
    return np.clip(np.nan_to_num(index, nan=0.0, posinf=count - 1, neginf=0.0), 0, count - 1).astype(np.int64)


def _chunks(counts: np.ndarray) -> list[tuple[int, int]]:
    """Runs of segments holding about :data:`_STRIPS_PER_CHUNK` column strips each."""
    ends = np.cumsum(counts)
    cuts = np.searchsorted(ends, np.arange(_STRIPS_PER_CHUNK, int(ends[-1]) if ends.size else 0, _STRIPS_PER_CHUNK))
    bounds = [0, *sorted({int(cut) + 1 for cut in cuts}), counts.size]
    return [(a, b) for a, b in itertools.pairwise(bounds) if a < b]


def _strip_rows(strips: _Strips, begin: int, end: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For every column strip of segments ``begin:end``: its first and last row, its column, its wall."""
    counts = strips.counts[begin:end]
    wall = np.repeat(np.arange(begin, end), counts)
    column = strips.first_col[wall] + np.arange(wall.size) - np.repeat(np.cumsum(counts) - counts, counts)
    bucket, slack = strips.bucket, strips.slack
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        x0, y0, x1, y1 = strips.x0[wall], strips.y0[wall], strips.x1[wall], strips.y1[wall]
        left = np.maximum(x0, strips.origin_x + column * bucket - slack)
        right = np.minimum(x1, strips.origin_x + (column + 1) * bucket + slack)
        width = x1 - x0
        upright = ~(width > 0)  # a vertical segment (or one too long for floats) spans its whole height
        t_left = np.where(upright, 0.0, (left - x0) / np.where(upright, 1.0, width))
        t_right = np.where(upright, 1.0, (right - x0) / np.where(upright, 1.0, width))
        y_left = y0 + np.clip(t_left, 0.0, 1.0) * (y1 - y0)
        y_right = y0 + np.clip(t_right, 0.0, 1.0) * (y1 - y0)
        low = np.minimum(y_left, y_right) - slack
        high = np.maximum(y_left, y_right) + slack
        # A height that overflowed (coordinates near 1e308) falls back to the segment's whole height.
        low = np.where(np.isfinite(low), low, np.minimum(y0, y1) - slack)
        high = np.where(np.isfinite(high), high, np.maximum(y0, y1) + slack)
    first = _index_of(low, strips.origin_y, bucket, strips.rows)
    return first, _index_of(high, strips.origin_y, bucket, strips.rows), column, wall


def _count_entries(strips: _Strips, max_entries: int) -> int:
    """The entries :func:`_bucket_entries` would list, counted chunk by chunk without listing them;
    stops once past ``max_entries``."""
    total = 0
    for begin, end in _chunks(strips.counts):
        row_first, row_last, _, _ = _strip_rows(strips, begin, end)
        total += int((row_last - row_first + 1).sum())
        if total > max_entries:
            break
    return total


@jit
def screen(
    eye_x: float, eye_y: float, targets: np.ndarray, wall_index: WallIndex, stamp: np.ndarray, verdicts: np.ndarray
) -> None:
    """Write into ``verdicts`` the verdict on each ray from the eye to a row of ``targets``.

    :data:`CLEAR` (touches no wall), :data:`BLOCKED` (properly crosses one) or :data:`CLOSE_CALL` (within
    the margin of a wall: ask pymunk). ``stamp`` is scratch space of ``len(walls) + 1`` integers kept
    between calls.
    """
    segments, bucket_start, bucket_walls = wall_index.segments, wall_index.start, wall_index.walls
    origin_x, origin_y, bucket, columns, rows, margin = (
        wall_index.origin_x, wall_index.origin_y, wall_index.bucket, wall_index.columns, wall_index.rows,
        wall_index.margin,
    )  # fmt: skip
    reach = 0.0
    for ray in range(targets.shape[0]):
        reach = max(reach, abs(targets[ray, 0] - eye_x), abs(targets[ray, 1] - eye_y))
    first_col = max(0, int((eye_x - reach - origin_x) // bucket))
    last_col = min(columns - 1, int((eye_x + reach - origin_x) // bucket))
    first_row = max(0, int((eye_y - reach - origin_y) // bucket))
    last_row = min(rows - 1, int((eye_y + reach - origin_y) // bucket))
    stamp[-1] += 1
    current = stamp[-1]
    for index in range(targets.shape[0]):
        verdicts[index] = CLEAR
    for row in range(first_row, last_row + 1):
        for col in range(first_col, last_col + 1):
            slot = row * columns + col
            for position in range(bucket_start[slot], bucket_start[slot + 1]):
                wall = bucket_walls[position]
                if stamp[wall] == current:
                    continue
                stamp[wall] = current
                ax = segments[wall, 0]
                ay = segments[wall, 1]
                bx = segments[wall, 2]
                by = segments[wall, 3]
                wall_dx = bx - ax
                wall_dy = by - ay
                # The eye's side of the wall's line is the same for every ray.
                eye_side = wall_dx * (eye_y - ay) - wall_dy * (eye_x - ax)
                for index in range(targets.shape[0]):
                    if verdicts[index] == BLOCKED:
                        continue
                    ray_dx = targets[index, 0] - eye_x
                    ray_dy = targets[index, 1] - eye_y
                    side_a = ray_dx * (ay - eye_y) - ray_dy * (ax - eye_x)
                    side_b = ray_dx * (by - eye_y) - ray_dy * (bx - eye_x)
                    if (side_a > margin and side_b > margin) or (side_a < -margin and side_b < -margin):
                        continue
                    target_side = wall_dx * (targets[index, 1] - ay) - wall_dy * (targets[index, 0] - ax)
                    if (eye_side > margin and target_side > margin) or (eye_side < -margin and target_side < -margin):
                        continue
                    crossing = ((side_a > margin and side_b < -margin) or (side_a < -margin and side_b > margin)) and (
                        (eye_side > margin and target_side < -margin) or (eye_side < -margin and target_side > margin)
                    )
                    verdicts[index] = BLOCKED if crossing else CLOSE_CALL
