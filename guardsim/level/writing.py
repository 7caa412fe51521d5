"""Writing a level: the JSON-ready dictionary and the text of a level file, the one writer guardsim has.

``guardsim import``, ``guardsim validate --fix`` and the regression snapshots all write through here, so
every level file guardsim writes looks the same and reads back as the same level.
"""

from __future__ import annotations

import json
from typing import Any

from guardsim.level.model import Camera, GuardSpec, IntruderSpec, Level

__all__ = ["compact_numbers", "level_json_text", "level_to_data"]


def level_to_data(level: Level) -> dict[str, Any]:
    """The JSON-ready dictionary of a level (the inverse of :func:`~guardsim.level.parse_level`)."""
    guard: dict[str, Any] = {
        "view_range": level.guard.view_range,
        "fov_degrees": level.guard.fov_degrees,
        "radius": level.guard.radius,
    }
    if level.guard.start is not None:
        guard["start"] = list(level.guard.start)
    if level.guard.heading is not None:
        guard["heading"] = level.guard.heading
    for key in ("move_speed", "turn_speed", "tick_hz"):
        if getattr(level.guard, key) is not None:
            guard[key] = getattr(level.guard, key)
    defaults = GuardSpec()
    for key in (
        "detect_near", "detect_far", "forget", "suspicious", "capture_radius", "search_seconds", "radio_delay",
        "chase_speed", "give_up_losses", "dark_sight",
    ):  # fmt: skip
        if getattr(level.guard, key) != getattr(defaults, key):
            guard[key] = getattr(level.guard, key)
    data: dict[str, Any] = {
        "name": level.name,
        "cell_size": level.cell_size,
        "outer": [list(p) for p in level.outer],
        "holes": [[list(p) for p in hole] for hole in level.holes],
        "guard": guard,
    }
    if level.starts:
        data["starts"] = [list(p) for p in level.starts]
    if level.player_starts:
        data["player_starts"] = [list(p) for p in level.player_starts]
    if level.tile_pixels is not None:
        data["tile_pixels"] = list(level.tile_pixels)
    if level.cameras:
        data["cameras"] = [_camera_data(camera) for camera in level.cameras]
    if level.ambient_light != 1.0:
        data["ambient_light"] = level.ambient_light
    if level.lights:
        data["lights"] = [
            {"position": list(light.position), "radius": light.radius, "intensity": light.intensity}
            for light in level.lights
        ]
    intruder = {
        key: getattr(level.intruder, key)
        for key in ("walk_noise", "sneak_ticks", "sneak_noise")
        if getattr(level.intruder, key) != getattr(IntruderSpec(), key)
    }
    if intruder:
        data["intruder"] = intruder
    return data


def _camera_data(camera: Camera) -> dict[str, Any]:
    data: dict[str, Any] = {"position": list(camera.position)}
    for key in ("heading", "fov_degrees", "view_range", "sweep", "turn_speed", "pause", "detect_near", "detect_far"):
        if getattr(camera, key) is not None:
            data[key] = getattr(camera, key)
    return data


def level_json_text(data: dict[str, Any] | Level) -> str:
    """Level JSON as a designer would like to read it: one key per line, one hole per line, and whole
    numbers written without ``.0``. Takes decoded level JSON or a :class:`Level`.

    Examples
    --------
    >>> print(level_json_text({"outer": [[0.0, 0.0], [4.0, 0.0], [4.0, 4.5]], "holes": [[[1, 1], [2, 1], [2, 2]]]}))
    {
      "outer": [[0, 0], [4, 0], [4, 4.5]],
      "holes": [
        [[1, 1], [2, 1], [2, 2]]
      ]
    }
    <BLANKLINE>
    """
    if isinstance(data, Level):
        data = level_to_data(data)
    lines = []
    for key, value in compact_numbers(data).items():
        if key == "holes" and isinstance(value, list) and value:
            rings = ",\n".join(f"    {_dumps(ring)}" for ring in value)
            lines.append(f'  "holes": [\n{rings}\n  ]')
        else:
            lines.append(f"  {json.dumps(key)}: {_dumps(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def _dumps(value: Any) -> str:
    # allow_nan=False: a level file never holds NaN (the loader refuses it), so writing one is a bug.
    return json.dumps(value, allow_nan=False)


def compact_numbers(value: Any) -> Any:
    """Floats that are whole numbers as ints, recursively, so files read ``[12, 40]``, not ``[12.0, 40.0]``."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    if isinstance(value, list):
        return [compact_numbers(item) for item in value]
    if isinstance(value, dict):
        return {key: compact_numbers(item) for key, item in value.items()}
    return value
