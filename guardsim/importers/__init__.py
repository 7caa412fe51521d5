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
from collections.abc import Iterable
from pathlib import Path

from guardsim.errors import LevelError
from guardsim.importers.guard_fit import check_guard_fits
from guardsim.importers.image import DEFAULT_THRESHOLD, import_image
from guardsim.importers.imported import ImportedLevel
from guardsim.importers.ldtk import import_ldtk, is_ldtk_file
from guardsim.importers.loading import ImportOptions, load_level, unknown_type
from guardsim.importers.movingai import import_movingai
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
    *,
    cell_size: float | None = None,
    threshold: int = DEFAULT_THRESHOLD,
    spawn_tiles: Iterable[int] = (),
    wall_layers: Iterable[str] = (),
    floor_layers: Iterable[str] = (),
    wall_tiles: Iterable[int] = (),
    wall_properties: Iterable[str] = (),
    wall_classes: Iterable[str] = (),
    view: str = "auto",
    wall_values: Iterable[int | str] = (),
    level: str | None = None,
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
    wall_layers, floor_layers, wall_tiles
        Tiled only: layers that are walls or floor and tile ids that are walls, replacing the guesses.
    wall_properties, wall_classes
        Tiled only: ``NAME`` or ``NAME=VALUE`` properties, and classes, that make tiles and objects walls
        (the properties replace the guess from property names).
    view
        Tiled only: ``"auto"`` refuses a map that looks drawn from the side (a platformer); ``"top-down"``
        imports it as seen from above.
    wall_values, level
        LDtk only: IntGrid values (numbers or names) that are walls, replacing the guess from value names,
        and the identifier of the level to import (the first by default).

    Raises
    ------
    LevelError
        For an unknown file type or a malformed map, naming the file and the line or field.
    """
    imported = _dispatch(
        path,
        cell_size=cell_size,
        threshold=threshold,
        spawn_tiles=spawn_tiles,
        wall_layers=wall_layers,
        floor_layers=floor_layers,
        wall_tiles=wall_tiles,
        wall_properties=wall_properties,
        wall_classes=wall_classes,
        view=view,
        wall_values=wall_values,
        level=level,
        max_cells=max_cells,
        max_vertices=max_vertices,
        max_file_bytes=max_file_bytes,
    )
    return check_guard_fits(imported)


def _dispatch(
    path: str | os.PathLike[str],
    *,
    cell_size: float | None,
    threshold: int,
    spawn_tiles: Iterable[int],
    wall_layers: Iterable[str],
    floor_layers: Iterable[str],
    wall_tiles: Iterable[int],
    wall_properties: Iterable[str],
    wall_classes: Iterable[str],
    view: str,
    wall_values: Iterable[int | str],
    level: str | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> ImportedLevel:
    spawn_tiles, wall_tiles, wall_values = tuple(spawn_tiles), tuple(wall_tiles), tuple(wall_values)
    wall_layers, floor_layers = tuple(wall_layers), tuple(floor_layers)
    wall_properties, wall_classes = tuple(wall_properties), tuple(wall_classes)
    suffix = Path(path).suffix.lower()
    ldtk = suffix == ".ldtk" or (suffix == ".json" and is_ldtk_file(path, max_file_bytes=max_file_bytes))
    tiled = not ldtk and suffix in (".tmx", ".tmj", ".json")
    # An option the map's reader does not read would be ignored without a word: say so instead.
    misplaced = [
        (name, "LDtk projects")
        for name, given in (("--wall-value", wall_values), ("--level", level is not None))
        if given and not ldtk
    ] + [
        (name, "Tiled maps")
        for name, given in (
            ("--spawn-tile", spawn_tiles),
            ("--wall-tile", wall_tiles),
            ("--wall-property", wall_properties),
            ("--wall-class", wall_classes),
            ("--wall-layer", wall_layers),
            ("--floor-layer", floor_layers),
        )
        if given and not tiled and suffix in FORMATS
    ]
    if misplaced:
        name, kind = misplaced[0]
        what = "an LDtk project" if ldtk else f"a {FORMATS.get(suffix, 'map')}"
        raise LevelError(f"{display_name(path)}: {name} is for {kind}, and this is {what}")
    limits = {"max_cells": max_cells, "max_vertices": max_vertices, "max_file_bytes": max_file_bytes}
    size = 1.0 if cell_size is None else cell_size
    if not 0 < size < float("inf"):
        raise LevelError(f"{display_name(path)}: cell size must be a positive number, not {size:g}")
    if suffix == ".map":
        return import_movingai(path, cell_size=size, **limits)
    if ldtk:
        return import_ldtk(path, cell_size=size, wall_values=wall_values, level=level, **limits)
    if suffix in (".tmx", ".tmj", ".json"):
        return import_tiled(
            path,
            cell_size=size,
            spawn_tiles=spawn_tiles,
            wall_layers=wall_layers,
            floor_layers=floor_layers,
            wall_tiles=wall_tiles,
            wall_properties=wall_properties,
            wall_classes=wall_classes,
            view=view,
            **limits,
        )
    if suffix == ".png":
        return import_image(path, cell_size=size, threshold=threshold, **limits)
    raise unknown_type(display_name(path), suffix)
