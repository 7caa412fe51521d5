"""Importers: maps from the tools designers use, converted to guardsim levels.

:func:`import_map` picks the reader by file type: Moving AI grid maps (``.map``), Tiled maps (``.tmx``,
``.tmj`` and Tiled JSON ``.json``) and images (``.png``). Every reader returns an
:class:`ImportedLevel`: a level :func:`guardsim.level.parse_level` accepts, and the list of what the
import changed (holes merged, rings split, vertices snapped).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from guardsim.errors import LevelError
from guardsim.importers.image import DEFAULT_THRESHOLD, import_image
from guardsim.importers.imported import ImportedLevel
from guardsim.importers.movingai import import_movingai
from guardsim.importers.tiled import import_tiled
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES

__all__ = ["FORMATS", "ImportedLevel", "import_image", "import_map", "import_movingai", "import_tiled"]

#: File suffix -> the kind of map read from it.
FORMATS = {
    ".map": "Moving AI grid map",
    ".tmx": "Tiled map (XML)",
    ".tmj": "Tiled map (JSON)",
    ".json": "Tiled map (JSON)",
    ".png": "image",
}


def import_map(
    path: str | os.PathLike[str],
    *,
    cell_size: float | None = None,
    threshold: int = DEFAULT_THRESHOLD,
    spawn_tiles: Iterable[int] = (),
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Convert the map at ``path`` to a level, choosing the reader by the file's suffix.

    Parameters
    ----------
    cell_size
        The level's ``cell_size`` in world units (one map cell, tile or pixel is one unit); 1 by default.
    threshold
        Images only: pixels darker than this grey level (0-255) are walls.
    spawn_tiles
        Tiled only: global tile ids that mark guard spawns.

    Raises
    ------
    LevelError
        For an unknown file type or a malformed map, naming the file and the line or field.
    """
    suffix = Path(path).suffix.lower()
    limits = {"max_cells": max_cells, "max_vertices": max_vertices, "max_file_bytes": max_file_bytes}
    size = 1.0 if cell_size is None else cell_size
    if not size > 0:
        raise LevelError(f"{path}: cell size must be positive, not {size:g}")
    if suffix == ".map":
        return import_movingai(path, cell_size=size, **limits)
    if suffix in (".tmx", ".tmj", ".json"):
        return import_tiled(path, cell_size=size, spawn_tiles=spawn_tiles, **limits)
    if suffix == ".png":
        return import_image(path, cell_size=size, threshold=threshold, **limits)
    known = ", ".join(sorted(FORMATS))
    raise LevelError(f"{path}: unknown map type {suffix or '(no suffix)'!r}; guardsim imports {known}")
