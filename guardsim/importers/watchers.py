"""Cameras, lamps and the ambient light of imported maps: Tiled objects and LDtk entities to level keys.

* **Tiled**: an object whose class (``type`` before Tiled 1.9) is ``camera`` or ``light`` (any case),
  its position a point object's, else the centre of its shape; its properties by the level's key names
  (``heading``, ``sweep``, ``radius``...). A camera without a ``heading`` property faces the object's
  rotation (degrees clockwise on screen: 0 is +x, 90 down, as the level's headings); a lamp without a
  ``radius`` drawn as an ellipse lights half its width. The map property ``ambient_light`` sets the
  level's.
* **LDtk**: entities named ``Camera`` and ``Light``, their fields by the same names; a level or project
  field ``ambient_light`` sets the level's.

One tile (one LDtk grid cell) is one world unit. The keys are checked as a level file's are (a camera
inside a wall is a one-line error naming ``cameras[i].position``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from guardsim.level import Level, level_to_data, parse_level
from guardsim.level.watchers import CAMERA_KEYS, LIGHT_KEYS

__all__ = ["WatcherData", "ldtk_watchers", "tiled_watchers", "with_watchers"]

#: ``(cameras, lights, ambient_light or None, labels)``: level-key dictionaries and where each came from.
WatcherData = tuple[list[dict[str, Any]], list[dict[str, Any]], float | None, list[str]]


def _keys(properties: dict[str, Any], known: tuple[str, ...]) -> dict[str, Any]:
    return {key: properties[key] for key in known if key != "position" and key in properties}


def tiled_watchers(tiled: Any) -> WatcherData:
    """The cameras and lamps of a :class:`~guardsim.importers.tiled_data.TiledMap`, in layer order."""
    cameras: list[dict[str, Any]] = []
    lights: list[dict[str, Any]] = []
    labels: list[str] = []
    scale = (float(tiled.tile_width), float(tiled.tile_height))
    for layer in tiled.object_layers:
        for item in layer.objects:
            kind = item.kind.strip().lower()
            if kind not in ("camera", "light"):
                continue
            if item.shape == "point" or not item.outline:
                x, y = item.anchor
            else:
                outline = np.asarray(item.outline, dtype=float)
                x, y = (float(value) for value in outline.mean(axis=0))
            position = [round(x / scale[0], 6), round(y / scale[1], 6)]
            if kind == "camera":
                entry = {"position": position, **_keys(item.properties, CAMERA_KEYS)}
                if "heading" not in entry:
                    entry["heading"] = float(item.rotation)
                cameras.append(entry)
            else:
                entry = {"position": position, **_keys(item.properties, LIGHT_KEYS)}
                if "radius" not in entry and item.shape == "ellipse" and item.size[0] > 0:
                    entry["radius"] = round(item.size[0] / 2 / scale[0], 6)
                lights.append(entry)
            labels.append(f"{kind} {item.name or item.id!r} in {'/'.join(layer.path)!r}")
    ambient = tiled.properties.get("ambient_light")
    return cameras, lights, ambient, labels


def ldtk_watchers(ldtk: Any, unit: float) -> WatcherData:
    """The ``Camera`` and ``Light`` entities of an :class:`~guardsim.importers.ldtk_read.LdtkLevel` (``unit``:
    pixels per world unit) and its ``ambient_light`` field."""
    cameras: list[dict[str, Any]] = []
    lights: list[dict[str, Any]] = []
    labels: list[str] = []
    for layer in ldtk.layers:
        for entity in layer.entities:
            kind = entity.identifier.strip().lower()
            if kind not in ("camera", "light"):
                continue
            values = {name: value for name, value in entity.fields if value is not None}
            position = [round(entity.centre[0] / unit, 6), round(entity.centre[1] / unit, 6)]
            known = CAMERA_KEYS if kind == "camera" else LIGHT_KEYS
            (cameras if kind == "camera" else lights).append({"position": position, **_keys(values, known)})
            labels.append(f"{entity.identifier} in {layer.identifier!r}")
    ambient = dict(ldtk.fields).get("ambient_light")
    return cameras, lights, ambient, labels


def with_watchers(
    level: Level, found: WatcherData, *, source: str, max_cells: int, max_vertices: int
) -> tuple[Level, str]:
    """``level`` with the cameras, lamps and ambient light ``found``, checked; a summary phrase ("" when
    there were none)."""
    cameras, lights, ambient, labels = found
    if not cameras and not lights and ambient is None:
        return level, ""
    data = level_to_data(level)
    if cameras:
        data["cameras"] = cameras
    if lights:
        data["lights"] = lights
    if ambient is not None:
        data["ambient_light"] = ambient
    built = parse_level(data, source=source, max_cells=max_cells, max_vertices=max_vertices)
    parts = [f"{len(cameras)} camera(s)", f"{len(lights)} light(s)"]
    if ambient is not None:
        parts.append(f"ambient light {ambient}")
    shown = ", ".join(labels[:4]) + (f" and {len(labels) - 4} more" if len(labels) > 4 else "")
    return built, ", ".join(parts) + (f" ({shown})" if shown else "")
