"""Levels: the model, reading a file within limits, checking it, and writing it.

A level is read from JSON (see ``docs/level-format.md``). :func:`check_level_data` collects every problem
in a level with its location; :func:`guardsim.load_level` raises the first as a :class:`LevelError`.
Coordinates are world units with x to the right and y down, as in Tiled and image editors.

The modules, in the order the data flows: :mod:`~guardsim.level.model` (what a level is),
:mod:`~guardsim.level.limits` (the default size limits), :mod:`~guardsim.level.validation` (decoded JSON
to a level, or every problem), :mod:`~guardsim.level.loading` (a file to a level) and
:mod:`~guardsim.level.writing` (a level to a file). Every name is importable from ``guardsim.level``.
"""

from __future__ import annotations

from guardsim.errors import LevelError
from guardsim.level.limits import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES
from guardsim.level.loading import read_level_json, read_limited_bytes
from guardsim.level.model import (
    GAITS,
    HEADINGS,
    MAX_TILE_PIXELS,
    Camera,
    GuardSpec,
    IntruderSpec,
    Level,
    Light,
    Point,
    Problem,
    Ring,
    free_area_of,
    grid_shape_of,
)
from guardsim.level.validation import check_level_data, parse_level
from guardsim.level.writing import compact_numbers, level_json_text, level_to_data

# The former module's private helpers, kept importable for code written against it.
_free_area = free_area_of
_grid_shape = grid_shape_of

__all__ = [
    "DEFAULT_MAX_CELLS",
    "DEFAULT_MAX_FILE_BYTES",
    "DEFAULT_MAX_VERTICES",
    "GAITS",
    "HEADINGS",
    "MAX_TILE_PIXELS",
    "Camera",
    "GuardSpec",
    "IntruderSpec",
    "Level",
    "LevelError",
    "Light",
    "Point",
    "Problem",
    "Ring",
    "check_level_data",
    "compact_numbers",
    "free_area_of",
    "grid_shape_of",
    "level_json_text",
    "level_to_data",
    "parse_level",
    "read_level_json",
    "read_limited_bytes",
]
