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

import numba
import numpy as np

__all__ = ["BLOCKED", "CLEAR", "CLOSE_CALL", "WallIndex", "screen", "screen_rays"]

CLEAR, BLOCKED, CLOSE_CALL = 0, 1, 2


class WallIndex:
    """Wall segments bucketed on a square grid, so a ray is screened only against walls near its eye.

    Parameters
    ----------
    segments
        ``float (m, 4)``: ``ax, ay, bx, by`` of every wall segment.
    origin
        World position of the buckets' top-left corner.
    extent
        ``(width, height)`` covered by the buckets.
    reach
        The longest ray: the side of a bucket.
    """

    def __init__(
        self, segments: np.ndarray, origin: tuple[float, float], extent: tuple[float, float], reach: float
    ) -> None:
        self.segments = np.ascontiguousarray(segments, dtype=np.float64)
        self.origin = (float(origin[0]), float(origin[1]))
        # At least a 256th of the extent: a short reach on a wide level must not make billions of buckets.
        self.bucket = max(float(reach), max(extent) / 256, 1e-9)
        self.columns = math.ceil(extent[0] / self.bucket) + 1
        self.rows = math.ceil(extent[1] / self.bucket) + 1
        members: list[list[int]] = [[] for _ in range(self.columns * self.rows)]
        for index, (ax, ay, bx, by) in enumerate(self.segments.tolist()):
            for row in range(self._row(min(ay, by)), self._row(max(ay, by)) + 1):
                for col in range(self._col(min(ax, bx)), self._col(max(ax, bx)) + 1):
                    members[row * self.columns + col].append(index)
        self.start = np.zeros(len(members) + 1, dtype=np.int64)
        self.start[1:] = np.cumsum([len(walls) for walls in members])
        self.walls = np.array([wall for walls in members for wall in walls], dtype=np.int64)
        scale = max(
            abs(v) for v in (*self.origin, extent[0] + abs(self.origin[0]), extent[1] + abs(self.origin[1]), 1.0)
        )
        # Cross products are of vectors at most `scale` long; their rounding error is ~1e-16 * scale**2.
        self.margin = 1e-9 * scale * scale

    def _col(self, x: float) -> int:
        return min(self.columns - 1, max(0, int((x - self.origin[0]) // self.bucket)))

    def _row(self, y: float) -> int:
        return min(self.rows - 1, max(0, int((y - self.origin[1]) // self.bucket)))


@numba.njit(cache=True, nogil=True)
def screen(
    eye_x: float,
    eye_y: float,
    targets: np.ndarray,
    segments: np.ndarray,
    bucket_start: np.ndarray,
    bucket_walls: np.ndarray,
    origin_x: float,
    origin_y: float,
    bucket: float,
    columns: int,
    rows: int,
    margin: float,
    stamp: np.ndarray,
    verdicts: np.ndarray,
) -> None:
    """Write into ``verdicts`` the verdict on each ray from the eye to a row of ``targets``."""
    reach = 0.0
    for index in range(targets.shape[0]):
        reach = max(reach, abs(targets[index, 0] - eye_x), abs(targets[index, 1] - eye_y))
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


def screen_rays(index: WallIndex, eye: tuple[float, float], targets: np.ndarray, stamp: np.ndarray) -> np.ndarray:
    """Verdict per ray from ``eye`` to each row of ``targets`` (``float (k, 2)``).

    Returns
    -------
    numpy.ndarray
        ``int8 (k,)``: :data:`CLEAR` (touches no wall), :data:`BLOCKED` (properly crosses one) or
        :data:`CLOSE_CALL` (within the margin of a wall: ask pymunk). ``stamp`` is scratch space of
        ``len(walls) + 1`` integers kept between calls.
    """
    verdicts = np.zeros(targets.shape[0], dtype=np.int8)
    if targets.shape[0] and index.walls.size:
        screen(
            float(eye[0]),
            float(eye[1]),
            targets,
            index.segments,
            index.start,
            index.walls,
            index.origin[0],
            index.origin[1],
            index.bucket,
            index.columns,
            index.rows,
            index.margin,
            stamp,
            verdicts,
        )
    return verdicts
