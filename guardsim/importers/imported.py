"""What every importer produces: a validated level, and a record of what the import changed."""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from shapely.geometry import box

from guardsim.errors import LevelError
from guardsim.importers.source import display_name, read_capped_bytes
from guardsim.importers.walls import WallReport, blocked_cell_walls, hole_rings, ring_vertex_count
from guardsim.level import (
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_FILE_BYTES,
    DEFAULT_MAX_VERTICES,
    MAX_TILE_PIXELS,
    Level,
    compact_numbers,
    level_json_text,
    level_to_data,
    parse_level,
)

__all__ = [
    "ImportedLevel",
    "check_raster_limits",
    "compact_numbers",
    "counted",
    "level_from_blocked_cells",
    "level_from_walls",
    "level_json_text",
    "read_source_bytes",
    "read_source_text",
    "with_tile_pixels",
]

Point = tuple[float, float]


def with_tile_pixels(level: Level, width: float, height: float) -> Level:
    """``level`` keeping the pixels of one world unit of the map it came from (one tile or grid cell is
    one world unit: the scale of routes written for it), when they are whole numbers in range."""
    if all(side == int(side) and 1 <= side <= MAX_TILE_PIXELS for side in (width, height)):
        return replace(level, tile_pixels=(int(width), int(height)))
    return level


@dataclass(frozen=True)
class ImportedLevel:
    """A level converted from a designer's map."""

    level: Level
    """The level, already accepted by :func:`guardsim.level.parse_level`."""
    kind: str
    """What was read: ``Moving AI map``, ``Tiled map`` or ``image``."""
    map_size: tuple[int, int]
    """``(width, height)`` of the source in its own units: cells, tiles or pixels."""
    changes: tuple[str, ...]
    """What the import found, changed or left out, one phrase each (floor and wall layers, merged holes, ...)."""
    warnings: tuple[str, ...] = ()
    """Signs that the result is not the level the map's author drew (no walls found, ...), one phrase each."""
    player_starts: tuple[Point, ...] = ()
    """Where the map says the player (the intruder) starts, in world units: Tiled objects named or classed
    ``player``, ``hero``, ``PlayerStart``...; never guard spawns. Empty when the map marks none."""

    @property
    def vertices(self) -> int:
        """Vertices over the outer ring and all holes."""
        return len(self.level.outer) + ring_vertex_count(self.level.holes)

    def to_json(self) -> str:
        """The level file's text (see :func:`level_json_text`)."""
        return level_json_text(level_to_data(self.level))

    def summary(self) -> str:
        """One line: source, grid, holes, vertices and changes."""
        rows, cols = self.level.grid_shape()
        width, height = self.map_size
        left, top = self.level.bounds[:2]
        # A grid cropped to the level says where it sits: cells in patrol.json and sneak.json count from
        # there, while world units (route.json, Tiled exports) are the map's own.
        at = f" at ({left:g}, {top:g})" if (left, top) != (0, 0) else ""
        text = (
            f"{self.level.source}: {self.kind} {width} x {height} -> {cols} x {rows} grid{at} "
            f"(cell size {self.level.cell_size:g}), {len(self.level.holes)} holes, {self.vertices} vertices"
        )
        return f"{text}; {'; '.join(self.changes)}" if self.changes else text


#: Items a summary or warning names before it says how many more there are.
LISTED = 6


def listed(items: Iterable[str], most: int = LISTED) -> str:
    """Items joined for one line, the first ``most`` of them and a count of the rest, each shortened.

    >>> listed(["a", "b", "c"], 2), listed([])
    ('a, b and 1 more', 'none')
    """
    items = [item if len(item) <= 60 else item[:28] + " ... " + item[-27:] for item in items]
    if not items:
        return "none"
    shown = ", ".join(items[:most])
    return shown if len(items) <= most else f"{shown} and {len(items) - most} more"


def counted(number: int, noun: str) -> str:
    """``3 holes``, ``1 hole``: a count and its noun for a summary phrase."""
    return f"{number} {noun}{'' if number == 1 else 's'}"


#: Longest level name (the level format's limit).
MAX_NAME_CHARS = 200


def level_name(text: str) -> str:
    """A map's name (file stem, LDtk level identifier...) as a level name: control characters made spaces
    and cut to the level format's :data:`MAX_NAME_CHARS`, since a map may legally name things longer.

    >>> len(level_name("L" * 300)), level_name("a" + chr(9) + "b")
    (200, 'a b')
    """
    clean = "".join(" " if ord(char) < 32 or ord(char) == 127 else char for char in text)
    return clean if len(clean) <= MAX_NAME_CHARS else clean[: MAX_NAME_CHARS - 4] + " ..."


def level_from_walls(
    walls: Sequence[shapely.Geometry],
    bounds: tuple[float, float, float, float],
    *,
    name: str,
    source: str,
    cell_size: float,
    cut_step: float | None = 1.0,
    starts: Sequence[Point] = (),
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
) -> tuple[Level, WallReport]:
    """A level whose outer ring is the rectangle ``bounds`` and whose holes are ``walls`` cleaned up.

    The first start, if any, becomes ``guard.start``. Raises :class:`~guardsim.errors.LevelError` (naming
    ``source``) if the result breaks a loader rule or limit.
    """
    min_x, min_y, max_x, max_y = bounds
    rings, report = hole_rings(walls, box(*bounds), cut_step=cut_step)
    data: dict[str, Any] = {
        "name": level_name(name),
        "cell_size": cell_size,
        "outer": [[min_x, min_y], [max_x, min_y], [max_x, max_y], [min_x, max_y]],
        "holes": [[list(point) for point in ring] for ring in rings],
    }
    if starts:
        data["guard"] = {"start": list(starts[0])}
        data["starts"] = [list(point) for point in starts]
    return parse_level(data, source=source, max_cells=max_cells, max_vertices=max_vertices), report


def read_source_bytes(path: str | os.PathLike[str], max_file_bytes: int = DEFAULT_MAX_FILE_BYTES) -> bytes:
    """A map file's bytes, every way of failing a :class:`LevelError` naming the file."""
    return read_capped_bytes(path, max_file_bytes=max_file_bytes, kind="map")


def read_source_text(path: str | os.PathLike[str], max_file_bytes: int = DEFAULT_MAX_FILE_BYTES) -> str:
    """A map file as UTF-8 text (see :func:`read_source_bytes`)."""
    try:
        return read_source_bytes(path, max_file_bytes).decode("utf-8")
    except UnicodeDecodeError as error:
        raise LevelError(f"{display_name(path)}: not a text file (byte {error.start} is not UTF-8)") from None


def level_from_blocked_cells(
    blocked: np.ndarray,
    *,
    source: str,
    cell_size: float,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
) -> tuple[Level, WallReport]:
    """A level one world unit per cell of ``bool (rows, cols)`` ``blocked``, its bounds the outer ring.

    The name is the source file's name without its suffix.
    """
    if blocked.all():
        raise LevelError(f"{source}: every cell is blocked: no free area")
    check_raster_limits(blocked, source=source, max_vertices=max_vertices)
    height, width = blocked.shape
    return level_from_walls(
        blocked_cell_walls(blocked),
        (0.0, 0.0, float(width), float(height)),
        name=Path(source).stem,
        source=source,
        cell_size=cell_size,
        max_cells=max_cells,
        max_vertices=max_vertices,
    )


def raster_vertex_count(blocked: np.ndarray) -> int:
    """Corners of the outline of the ``True`` cells: the vertices their holes will have, give or take cuts.

    Each grid point where one or three of the four cells around it are blocked is one corner; where two
    diagonal cells are, two. Counting costs one pass over the mask, so a limit trips before any geometry.

    >>> raster_vertex_count(np.array([[True, False], [False, True]]))
    8
    """
    mask = np.pad(np.asarray(blocked, dtype=bool), 1)
    a, b, c, d = mask[:-1, :-1], mask[:-1, 1:], mask[1:, :-1], mask[1:, 1:]
    count = a.astype(np.int8) + b + c + d
    diagonal = (count == 2) & (a == d)
    return int(np.count_nonzero((count == 1) | (count == 3)) + 2 * np.count_nonzero(diagonal))


def check_raster_limits(blocked: np.ndarray, *, source: str, max_vertices: int) -> None:
    """A :class:`LevelError` naming ``--max-vertices`` if the blocked cells' outline needs more vertices."""
    vertices = raster_vertex_count(blocked) + 4
    if vertices > max_vertices:
        rows, cols = blocked.shape
        raise LevelError(
            f"{source}: the walls of this {cols} x {rows} map need about {vertices} vertices, over the limit of "
            f"{max_vertices} (raise it with --max-vertices)"
        )
