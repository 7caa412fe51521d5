"""One entry point for every command: a guardsim level file or any map, loaded in memory.

:func:`load_level` (``guardsim.load_level``) is what every command calls on its LEVEL argument. A ``.json`` file is a guardsim level when it has an ``outer`` ring, a Tiled map
when it has an ``orientation`` (or ``"type": "map"``) and an LDtk project when it has LDtk's
``__header__`` (or ``jsonVersion`` and ``defs``); ``.tmx``/``.tmj``, ``.ldtk``, ``.map`` and ``.png`` are
imported with the options of :class:`ImportOptions`. Any other
file that is not JSON gets one line saying which formats guardsim reads.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import shapely.errors

from guardsim.errors import LevelError
from guardsim.files.reading import parse_json
from guardsim.importers.imported import ImportedLevel
from guardsim.importers.ldtk_read import is_ldtk_json
from guardsim.importers.options import ImportOptions
from guardsim.importers.source import MAX_JSON_DEPTH, display_name, quiet, read_capped_bytes
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES, Level, parse_level

__all__ = ["ImportOptions", "is_map_json", "is_tiled_json", "load_level", "unknown_type"]


#: Files guardsim is sometimes handed but does not read, and what they are.
FOREIGN = {
    ".tscn": "a Godot scene",
    ".scn": "a Godot scene",
    ".escn": "a Godot scene",
    ".tres": "a Godot resource",
    ".res": "a Godot resource",
    ".godot": "a Godot project",
    ".gd": "a Godot script",
    ".ldtkl": "an LDtk level file: import the .ldtk project beside it, with --level NAME",
    ".tsx": "a Tiled tileset: import a map that uses it",
    ".tsj": "a Tiled tileset: import a map that uses it",
    ".tx": "a Tiled template: import a map that uses it",
    ".tj": "a Tiled template: import a map that uses it",
    ".tiled-project": "a Tiled project: import one of its maps",
}


def unknown_type(source: str, suffix: str, *, is_json: bool = True) -> LevelError:
    """The one-line error for a file of a type guardsim does not read, listing the formats it reads."""
    from guardsim.importers import FORMATS

    kinds: dict[str, list[str]] = {}
    for known, kind in FORMATS.items():
        kinds.setdefault(kind, []).append(known)
    listed = ", ".join(f"{kind} {'/'.join(suffixes)}" for kind, suffixes in kinds.items())
    what = f" ({FOREIGN[suffix]})" if suffix in FOREIGN else "" if is_json else " and not JSON"
    return LevelError(
        f"{source}: unknown map type {suffix or '(no suffix)'!r}{what}; guardsim reads guardsim levels (.json) and "
        f"imports {listed}"
    )


def _text(data: bytes, source: str) -> str:
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise LevelError(f"{source}: not UTF-8 text (byte {error.start})") from None


def is_tiled_json(data: object) -> bool:
    """Whether decoded JSON is a Tiled map (an ``orientation`` or ``"type": "map"``), not a guardsim level."""
    return isinstance(data, dict) and ("orientation" in data or data.get("type") == "map") and "outer" not in data


def is_map_json(data: object) -> bool:
    """Whether decoded JSON is a map to import (Tiled or LDtk), not a guardsim level."""
    return is_tiled_json(data) or is_ldtk_json(data)


def load_level(
    path: str | os.PathLike[str],
    *,
    report: Callable[[ImportedLevel], object] | None = None,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    **import_options: Any,
) -> Level:
    """The level in ``path``: a guardsim level file, or any map the commands accept, imported in memory.

    The one way to load a level. A ``.json`` file is a guardsim level when it has an ``outer`` ring and
    a Tiled or LDtk map otherwise; ``.tmx``/``.tmj``, ``.ldtk``, ``.map`` (Moving AI) and ``.png`` are
    maps. ``import_options`` are the options of ``guardsim import``, the fields of
    :class:`~guardsim.importers.options.ImportOptions` (``cell_size``, ``threshold``, ``spawn_tiles``,
    ``wall_layers``, ... each documented there with its flag). ``report``, when given, receives the :class:`~guardsim.importers.ImportedLevel` of an
    imported map (what the import found, guessed and changed, and its warnings); a level file has none.

    Raises
    ------
    LevelError
        One line naming the file for every way the file or the map can be wrong, including a file that
        is not a regular file, more than ``max_file_bytes`` bytes, or limits that would be passed.
    TypeError
        For an import option that does not exist.

    Examples
    --------
    >>> load_level("levels/square.json").name
    'Square'
    >>> records = []
    >>> level = load_level("tests/data/maps/cases/house_lawn.tmj", cell_size=0.5, report=records.append)
    >>> level.cell_size, records[0].kind
    (0.5, 'Tiled map')
    """
    from guardsim.importers import FORMATS, _import_map

    options = ImportOptions(**import_options)
    source = display_name(path)
    suffix = Path(path).suffix.lower()
    if suffix in FOREIGN:
        raise unknown_type(source, suffix)
    if suffix in (".json", "") or suffix not in FORMATS:
        data = read_capped_bytes(path, max_file_bytes=max_file_bytes, kind="level file")
        head = data.lstrip()[:1]
        if suffix not in FORMATS and head not in (b"{", b"["):
            raise unknown_type(source, suffix, is_json=False)
        # NaN and Infinity decode here so that the level check can name the field holding one; a map is
        # read again, strictly, by its importer.
        try:
            value = parse_json(_text(data, source), source=source, max_depth=MAX_JSON_DEPTH, allow_non_finite=True)
        except LevelError:
            if suffix in ("", ".json"):
                raise
            raise unknown_type(source, suffix, is_json=False) from None
        if not is_map_json(value):
            return parse_level(value, source=source, max_cells=max_cells, max_vertices=max_vertices)
    notes: list[str] = []
    try:
        with quiet(notes):
            imported = _import_map(
                path, options, max_cells=max_cells, max_vertices=max_vertices, max_file_bytes=max_file_bytes
            )
    except MemoryError:
        raise LevelError(
            f"{source}: out of memory while importing it; lower --max-cells ({max_cells}) or --max-vertices "
            f"({max_vertices})"
        ) from None
    except shapely.errors.GEOSException as error:
        raise LevelError(f"{source}: the map's geometry cannot be built ({str(error)[:80]})") from None
    if notes:
        imported = dataclasses.replace(imported, changes=(*imported.changes, *notes))
    if report is not None:
        report(imported)
    return imported.level
