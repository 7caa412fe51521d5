"""Moving AI benchmark grid maps (``.map``) into levels.

The format (https://movingai.com/benchmarks/formats.html) is a header of ``type octile``, ``height H``,
``width W`` and ``map``, then H rows of W characters. ``.``, ``G`` and ``S`` (swamp) are passable;
``@``, ``O`` (out of bounds), ``T`` (trees) and ``W`` (water) are not. Header keys are read by name
(``octile type`` is accepted too), CRLF line ends and a missing final newline are fine.

Each map cell is one world unit; the outer ring is the map's bounds, so everything outside the grid is
wall, and the blocked cells become holes (:func:`guardsim.importers.walls.hole_rings`). At cell size 1
with the default guard the coverage grid's traversable cells are exactly the passable cells.
"""

from __future__ import annotations

import os

import numpy as np

from guardsim.errors import LevelError
from guardsim.importers.imported import ImportedLevel, level_from_blocked_cells, read_source_text
from guardsim.importers.source import display_name, excerpt
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES

__all__ = ["BLOCKED", "PASSABLE", "import_movingai", "read_movingai"]

#: Terrain a guard can walk on.
PASSABLE = frozenset(".GS")
#: Terrain a guard cannot enter. Water (``W``) counts as blocked: a guard does not wade.
BLOCKED = frozenset("@OTW")

_HEADER_KEYS = ("type", "height", "width")
#: Longest header number read; more digits than this is past any cell limit.
_MAX_DIGITS = 18


def read_movingai(text: str, *, source: str = "<map>", max_cells: int = DEFAULT_MAX_CELLS) -> np.ndarray:
    """The passable cells of a Moving AI map as ``bool (height, width)``.

    Raises
    ------
    LevelError
        Naming ``source`` and the line (and column) at fault.

    Examples
    --------
    >>> read_movingai("type octile\\r\\nheight 2\\r\\nwidth 3\\r\\nmap\\r\\n.@T\\r\\nSG.").astype(int).tolist()
    [[1, 0, 0], [1, 1, 1]]
    """
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    header: dict[str, int | str] = {}
    grid_line = None
    for number, line in enumerate(lines, start=1):
        words = line.split()
        if not words:
            continue
        if words == ["map"]:
            grid_line = number
            break
        if len(words) == 2 and words[1] == "type":
            words = ["type", words[0]]
        if len(words) != 2 or words[0] not in _HEADER_KEYS:
            raise LevelError(
                f"{source}: line {number}: unexpected header line {excerpt(line.strip())} "
                "(expected 'type octile', 'height H', 'width W', then 'map')"
            )
        key, value = words
        if key in header:
            raise LevelError(f"{source}: line {number}: {key} given twice")
        if key == "type":
            if value != "octile":
                raise LevelError(f"{source}: line {number}: map type {value!r} is not supported (only octile)")
            header[key] = value
        elif not (value.isascii() and value.isdigit()) or int(value[:_MAX_DIGITS]) < 1:
            raise LevelError(f"{source}: line {number}: {key} must be a positive whole number, not {excerpt(value)}")
        elif len(value) > _MAX_DIGITS:
            raise LevelError(
                f"{source}: line {number}: {key} {excerpt(value)} is far over the limit of {max_cells} cells "
                "(raise it with --max-cells)"
            )
        else:
            header[key] = int(value)
    if grid_line is None:
        raise LevelError(f"{source}: no 'map' line: not a Moving AI map")
    for key in ("height", "width"):
        if key not in header:
            raise LevelError(f"{source}: the header has no {key} line")
    height, width = int(header["height"]), int(header["width"])
    if height * width > max_cells:
        raise LevelError(
            f"{source}: the map is {width} x {height} = {width * height} cells, over the limit of {max_cells} "
            "(raise it with --max-cells)"
        )
    rows = lines[grid_line:]
    while rows and not rows[-1].strip():
        rows.pop()
    if len(rows) < height:
        raise LevelError(f"{source}: line {grid_line + len(rows) + 1}: the map ends after {len(rows)} of {height} rows")
    if len(rows) > height:
        raise LevelError(f"{source}: line {grid_line + height + 1}: more rows than the height {height}")
    passable = np.zeros((height, width), dtype=bool)
    for index, row in enumerate(rows):
        number = grid_line + index + 1
        if len(row) != width:
            raise LevelError(f"{source}: line {number}: row has {len(row)} characters, the width is {width}")
        unknown = next((col for col, char in enumerate(row) if char not in PASSABLE and char not in BLOCKED), None)
        if unknown is not None:
            raise LevelError(
                f"{source}: line {number} column {unknown + 1}: unknown terrain {row[unknown]!r} "
                "(passable . G S, blocked @ O T W)"
            )
        passable[index] = [char in PASSABLE for char in row]
    return passable


def import_movingai(
    path: str | os.PathLike[str],
    *,
    cell_size: float = 1.0,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Read a ``.map`` file and convert it to a level (one map cell = one world unit)."""
    source = display_name(path)
    passable = read_movingai(read_source_text(path, max_file_bytes), source=source, max_cells=max_cells)
    level, report = level_from_blocked_cells(
        ~passable, source=source, cell_size=cell_size, max_cells=max_cells, max_vertices=max_vertices
    )
    height, width = passable.shape
    return ImportedLevel(level, "Moving AI map", (width, height), (report.describe("blocked cell runs"),))
