"""Importers: maps from the tools designers use, converted to guardsim levels.

One reader per file type: Moving AI grid maps (``.map``), Tiled maps (``.tmx``,
``.tmj`` and Tiled JSON ``.json``), LDtk projects (``.ldtk``, or a ``.json`` holding one) and images
(``.png``). Every reader returns an :class:`ImportedLevel`: a level :func:`guardsim.level.parse_level`
accepts, the list of what the import found and changed (floor and wall layers, holes merged, vertices
snapped) and its warnings.
:func:`load_level` (``guardsim.load_level``) loads a guardsim level file or any of these maps, and is
the one way in: the import's record reaches its ``report`` callback.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from guardsim.errors import LevelError
from guardsim.importers.guard_fit import check_guard_fits
from guardsim.importers.image import import_image
from guardsim.importers.imported import ImportedLevel
from guardsim.importers.ldtk import import_ldtk, is_ldtk_file
from guardsim.importers.loading import load_level, unknown_type
from guardsim.importers.movingai import import_movingai
from guardsim.importers.options import READERS, ImportOptions
from guardsim.importers.source import display_name
from guardsim.importers.tiled import import_tiled
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES

__all__ = [
    "FORMATS",
    "ImportOptions",
    "ImportedLevel",
    "import_image",
    "import_ldtk",
    "import_movingai",
    "import_tiled",
    "load_level",
]

#: File suffix -> the kind of map read from it.
FORMATS = {
    ".map": "Moving AI grid map",
    ".tmx": "Tiled map (XML)",
    ".tmj": "Tiled map (JSON)",
    ".json": "Tiled map (JSON)",
    ".ldtk": "LDtk project",
    ".png": "image",
}


def _import_map(
    path: str | os.PathLike[str],
    options: ImportOptions,
    *,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Convert the map at ``path`` to a level with ``options``, choosing the reader by the file's suffix.

    Raises
    ------
    LevelError
        For an unknown file type, an option its reader does not take, or a malformed map, naming the file
        and the line or field.
    """
    limits: dict[str, Any] = {"max_cells": max_cells, "max_vertices": max_vertices, "max_file_bytes": max_file_bytes}
    return check_guard_fits(_dispatch(path, options, limits))


def _dispatch(path: str | os.PathLike[str], options: ImportOptions, limits: dict[str, Any]) -> ImportedLevel:
    suffix = Path(path).suffix.lower()
    ldtk = suffix == ".ldtk" or (suffix == ".json" and is_ldtk_file(path, max_file_bytes=limits["max_file_bytes"]))
    tiled = not ldtk and suffix in (".tmx", ".tmj", ".json")
    # An option the map's reader does not read would be ignored without a word: say so instead (LDtk's
    # first; another reader's options only on a file of a type guardsim reads).
    taken = {"ldtk": ldtk, "tiled": tiled or suffix not in FORMATS, "image": suffix == ".png" or suffix not in FORMATS}
    given = sorted(options.given(), key=lambda option: option[1] != "ldtk")
    misplaced = [(flag, READERS[reader]) for flag, reader in given if not taken[reader]]
    if misplaced:
        name, kind = misplaced[0]
        what = "an LDtk project" if ldtk else f"a {FORMATS.get(suffix, 'map')}"
        raise LevelError(f"{display_name(path)}: {name} is for {kind}, and this is {what}")
    size = 1.0 if options.cell_size is None else options.cell_size
    if not 0 < size < float("inf"):
        raise LevelError(f"{display_name(path)}: cell size must be a positive number, not {size:g}")
    if suffix == ".map":
        return import_movingai(path, cell_size=size, **limits)
    if ldtk:
        return import_ldtk(path, cell_size=size, **options.for_reader("ldtk"), **limits)
    if tiled:
        return import_tiled(path, cell_size=size, **options.for_reader("tiled"), **limits)
    if suffix == ".png":
        return import_image(path, cell_size=size, **options.for_reader("image"), **limits)
    raise unknown_type(display_name(path), suffix)
