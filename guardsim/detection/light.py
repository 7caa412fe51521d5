"""Light and shadow: how lit each cell of a level is, from its ambient light and its lamps.

The light of a cell is ``L = min(1, ambient_light + sum_i intensity_i * max(0, 1 - d_i / radius_i))``
over the lamps that see the cell's centre (a clear line of sight by the level's rule, all around),
``d_i`` the distance from lamp ``i`` to the centre. An intruder's visibility to a watcher is then 1
within the watcher's dark sight, else the light of its cell (:func:`guardsim.kernels.meter.visibility`),
and the meter rises in proportion (:func:`guardsim.kernels.meter.meter_gain`).
"""

from __future__ import annotations

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.level import Level
from guardsim.scene import Scene
from guardsim.vision.point import PointSight

__all__ = ["light_at", "light_map", "light_values"]


def light_values(level: Level, sight: PointSight | None) -> np.ndarray:
    """``float64 (cells,)``: the light of every cell (walls get the ambient light).

    ``sight`` may be ``None`` when the level is fully lit (``ambient_light`` 1): every cell is then 1.
    """
    grid_size = level.grid_shape()[0] * level.grid_shape()[1] if sight is None else sight.grid.size
    values = np.full(grid_size, float(level.ambient_light), dtype=np.float64)
    if level.lit or not level.lights:
        return np.minimum(values, 1.0)
    if sight is None:
        raise ArgumentError("a level with lamps and darkness needs its PointSight to light the cells")
    for lamp in level.lights:
        cells, distances = sight.cells(lamp.position, lamp.radius)
        # In lamp order, so the sum (and every result built on it) is the same bytes each run.
        values[cells] += lamp.intensity * np.maximum(0.0, 1.0 - distances / lamp.radius)
    return np.minimum(values, 1.0)


def light_map(scene: Scene) -> np.ndarray:
    """``float64 (rows, cols)``: the light of each cell of ``scene`` (a :class:`~guardsim.scene.Scene`), 0
    (dark) to 1 (full light).

    Examples
    --------
    A dark room with one lamp of radius 4 in its corner:

    >>> from guardsim import Scene, parse_level
    >>> level = parse_level({"outer": [[0, 0], [4, 0], [4, 1], [0, 1]], "ambient_light": 0.1,
    ...                      "lights": [{"position": [0, 0.5], "radius": 4}]})
    >>> light_map(Scene.from_level(level)).round(3).tolist()
    [[0.975, 0.725, 0.475, 0.225]]
    """
    return light_values(scene.level, scene_sight(scene)).reshape(scene.grid.shape)


def scene_sight(scene: Scene, reach: float | None = None) -> PointSight | None:
    """The :class:`PointSight` of a scene for its lamps and cameras, ``None`` when it needs none."""
    level = scene.level
    if not level.cameras and (level.lit or not level.lights):
        return None
    reaches = [lamp.radius for lamp in level.lights] + [
        camera.view_range if camera.view_range is not None else level.guard.view_range for camera in level.cameras
    ]
    longest = max(reaches) if reach is None else reach
    return PointSight(scene.world, scene.grid, rule=scene.rule, reach=longest)


def light_at(scene: Scene, point: tuple[float, float], light: np.ndarray | None = None) -> float:
    """The light of the cell holding ``point`` (world units): "how visible is the player there?" to a
    watcher beyond its dark sight. ``light`` is the scene's :func:`light_map`, when the caller has it.

    >>> from guardsim import Scene, parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [4, 0], [4, 1], [0, 1]], "ambient_light": 0.25}))
    >>> light_at(scene, (3.5, 0.5))
    0.25
    """
    cell = scene.grid.cell_of(point)
    if cell is None:
        raise ArgumentError(f"({point[0]:g}, {point[1]:g}) lies outside the level")
    values = light_map(scene) if light is None else light
    return float(values[cell[1], cell[0]])
