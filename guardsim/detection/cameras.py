"""Security cameras on the grid: each camera's heading at every tick of its swing, and what it sees then.

A camera's swing repeats every ``2 * (sweep / turn_speed + pause)`` seconds. On the grid that period is
rounded to the nearest whole number of ticks (at least one more than the pauses take), the pauses kept
and the turning time adjusted; :func:`camera_ticks` says so in a note when it had to. Its heading at
tick ``k`` is its heading at time ``k * dt`` of the rounded swing. It sees, at that tick, the traversable
cells whose centres lie within its range, within half its field of view of the heading, with a clear
line of sight (:class:`~guardsim.vision.point.PointSight`), exactly as a guard's cone.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from guardsim.errors import LimitError
from guardsim.kernels.meter import meter_gain, visibility
from guardsim.level import Camera, GuardSpec
from guardsim.vision.point import PointSight

__all__ = ["MAX_SWING_TICKS", "CameraSight", "camera_gains", "camera_heading", "camera_sight", "camera_ticks"]

#: Longest swing, in ticks, a camera may have: past it no joint lap could be searched anyway, and its
#: headings alone would fill memory (a turn speed of 1e-300 degrees a second is a valid number).
MAX_SWING_TICKS = 10_000_000

# Cells exactly on the cone's edge are in, as in a guard's cone.
_EDGE_TOLERANCE = 1e-9


def camera_ticks(camera: Camera, dt: float, *, name: str = "camera") -> tuple[int, str | None]:
    """The camera's period in whole ticks of ``dt`` seconds, and a note when it was rounded.

    A fixed camera (``sweep`` 0) has a period of one tick.

    >>> camera_ticks(Camera((0.0, 0.0), sweep=90, turn_speed=30, pause=1.0), 0.5)
    (16, None)
    >>> camera_ticks(Camera((0.0, 0.0), sweep=100, turn_speed=30, pause=1.0), 0.5)[0]
    17
    """
    if camera.sweep <= 0:
        return 1, None
    exact = camera.period_seconds / dt
    if not math.isfinite(exact) or exact > MAX_SWING_TICKS:
        raise LimitError(
            f"{name}'s swing of {camera.period_seconds:.4g} s is over {MAX_SWING_TICKS} ticks of {dt:g} s: "
            "turn faster, sweep less or pause less"
        )
    ticks = max(1, math.floor(exact + 0.5))
    if ticks * dt / 2 - camera.pause <= 0:
        # The pauses alone fill the rounded period: one more tick leaves the camera time to turn.
        ticks = math.floor(2 * camera.pause / dt) + 1
    if abs(ticks - exact) <= 1e-9 * max(1.0, exact):
        return ticks, None
    turn = ticks * dt / 2 - camera.pause
    return ticks, (
        f"{name}'s swing of {camera.period_seconds:.4g} s is {exact:.3g} ticks of {dt:g} s: rounded to {ticks} ticks "
        f"(turning at {camera.sweep / turn:.4g} degrees/s instead of {camera.turn_speed:g})"
    )


def camera_heading(camera: Camera, tick: int, dt: float, ticks: int) -> float:
    """Degrees the camera faces at ``tick`` of its swing rounded to ``ticks`` ticks (:func:`camera_ticks`).

    >>> camera = Camera((0.0, 0.0), heading=90, sweep=90, turn_speed=30, pause=1.0)
    >>> [camera_heading(camera, k, 0.5, 16) for k in (0, 3, 6, 7, 8, 14, 15)]
    [45.0, 90.0, 135.0, 135.0, 135.0, 45.0, 45.0]
    """
    start = camera.heading - camera.sweep / 2
    if camera.sweep <= 0:
        return float(camera.heading)
    turn = ticks * dt / 2 - camera.pause
    t = (tick % ticks) * dt
    if t < turn:
        return start + camera.sweep * t / turn
    if t < turn + camera.pause:
        return start + camera.sweep
    if t < 2 * turn + camera.pause:
        return start + camera.sweep - camera.sweep * (t - turn - camera.pause) / turn
    return start


class CameraSight(NamedTuple):
    """What one camera sees over its swing, on the grid."""

    camera: Camera
    ticks: int
    """The swing's period in ticks."""
    headings: np.ndarray
    """``float64 (ticks,)``: degrees faced at each tick of the swing."""
    cells: np.ndarray
    """``int64 (n,)``: the cells in range with a clear line of sight (all around), ascending."""
    distances: np.ndarray
    """``float64 (n,)``: their centres' distances from the camera."""
    in_cone: np.ndarray
    """``bool (ticks, n)``: which of them lie in the cone at each tick."""
    view_range: float
    detect_near: float
    detect_far: float
    note: str | None
    """Why the period was rounded, when it was."""

    def seen(self, tick: int) -> np.ndarray:
        """Flat cells seen at ``tick`` (any tick: the swing repeats), ascending."""
        return self.cells[self.in_cone[tick % self.ticks]]


def camera_sight(
    camera: Camera, guard: GuardSpec, sight: PointSight, dt: float, *, name: str = "camera"
) -> CameraSight:
    """The camera's swing on ``sight``'s grid; ``guard`` gives the defaults (view range, detect times)."""
    view_range = camera.view_range if camera.view_range is not None else guard.view_range
    ticks, note = camera_ticks(camera, dt, name=name)
    headings = np.array([camera_heading(camera, tick, dt, ticks) for tick in range(ticks)], dtype=np.float64)
    cells, distances = sight.cells(camera.position, view_range)
    grid = sight.grid
    cols = grid.shape[1]
    dx = grid.origin[0] + (cells % cols + 0.5) * grid.cell_size - camera.position[0]
    dy = grid.origin[1] + (cells // cols + 0.5) * grid.cell_size - camera.position[1]
    if camera.fov_degrees >= 360:
        in_cone = np.ones((ticks, cells.size), dtype=bool)
    else:
        radians = np.radians(headings)[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            cosine = (dx[None, :] * np.cos(radians) + dy[None, :] * np.sin(radians)) / distances[None, :]
        cos_half = math.cos(math.radians(camera.fov_degrees) / 2)
        in_cone = (distances[None, :] == 0) | (cosine >= cos_half - _EDGE_TOLERANCE)
    near = camera.detect_near if camera.detect_near is not None else guard.detect_near
    far = camera.detect_far if camera.detect_far is not None else guard.detect_far
    return CameraSight(camera, ticks, headings, cells, distances, in_cone, float(view_range), near, far, note)


def camera_gains(sight: CameraSight, light: np.ndarray, dt: float, cells: int) -> np.ndarray:
    """``float64 (ticks, cells)``: what a tick in each cell adds to the camera's meter at each tick of its
    swing (0 out of its sight or in the dark: a camera has no dark sight)."""
    out = np.zeros((sight.ticks, cells), dtype=np.float64)
    per_cell = [
        meter_gain(
            dt,
            float(d),
            sight.view_range,
            sight.detect_near,
            sight.detect_far,
            visibility(float(d), 0.0, float(light[c])),
        )
        for c, d in zip(sight.cells.tolist(), sight.distances.tolist())
    ]
    gains = np.asarray(per_cell, dtype=np.float64)
    for tick in range(sight.ticks):
        out[tick, sight.cells[sight.in_cone[tick]]] = gains[sight.in_cone[tick]]
    return out
