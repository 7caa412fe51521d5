"""Screening rays against nearby walls, compiled, so that pymunk is asked only about close calls.

For a ray (eye to a cell centre) and a wall segment, two orientation tests with a safety margin decide
most cases outright: the wall's endpoints strictly on one side of the ray's line, or the ray's endpoints
strictly on one side of the wall's line, means no contact; both pairs strictly on opposite sides means a
proper crossing. Only what falls inside the margin (a ray through a wall's vertex, along a wall, ending
on one) is left to :meth:`guardsim.world.World.line_of_sight`, so the verdict on every ray is pymunk's.
The margin is many orders of magnitude above floating-point error and far below any level's detail.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["BLOCKED", "CLEAR", "CLOSE_CALL", "WallIndex", "index_walls", "screen"]

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


def index_walls(
    segments: np.ndarray, origin: tuple[float, float], extent: tuple[float, float], reach: float
) -> WallIndex:
    """Bucket ``segments`` (``float (m, 4)``) over ``extent`` (width, height) from ``origin``.

    ``reach`` is the longest ray, the side of a bucket.
    """
    segments = np.ascontiguousarray(segments, dtype=np.float64).reshape(-1, 4)
    origin_x, origin_y = float(origin[0]), float(origin[1])
    # At least a 256th of the extent: a short reach on a wide level must not make billions of buckets.
    bucket = max(float(reach), max(extent) / 256, 1e-9)
    columns = math.ceil(extent[0] / bucket) + 1
    rows = math.ceil(extent[1] / bucket) + 1

    def col_of(x: float) -> int:
        return min(columns - 1, max(0, int((x - origin_x) // bucket)))

    def row_of(y: float) -> int:
        return min(rows - 1, max(0, int((y - origin_y) // bucket)))

    members: list[list[int]] = [[] for _ in range(columns * rows)]
    for index, (ax, ay, bx, by) in enumerate(segments.tolist()):
        for row in range(row_of(min(ay, by)), row_of(max(ay, by)) + 1):
            for col in range(col_of(min(ax, bx)), col_of(max(ax, bx)) + 1):
                members[row * columns + col].append(index)
    start = np.zeros(len(members) + 1, dtype=np.int64)
    start[1:] = np.cumsum([len(walls) for walls in members])
    walls = np.array([wall for walls in members for wall in walls], dtype=np.int64)
    scale = max(abs(v) for v in (origin_x, origin_y, extent[0] + abs(origin_x), extent[1] + abs(origin_y), 1.0))
    # Cross products are of vectors at most `scale` long; their rounding error is ~1e-16 * scale**2.
    return WallIndex(segments, start, walls, origin_x, origin_y, bucket, columns, rows, 1e-9 * scale * scale)


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
