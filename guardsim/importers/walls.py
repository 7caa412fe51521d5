"""Walls into holes: blocked cells and drawn wall shapes become the clean rings a level needs.

A level's holes must be simple rings that do not overlap (``docs/level-format.md``). What designers draw
is rarely that: wall rectangles overlap, a hand-drawn polygon touches itself, and a band of wall around a
room encloses a free pocket, which a single ring cannot describe. :func:`hole_rings` takes any pile of
wall polygons and returns rings the loader accepts, covering exactly the same area, and a
:class:`WallReport` saying what it changed:

* overlapping and touching pieces are merged (a shapely union);
* self-touching or self-crossing pieces are split into valid ones (``shapely.make_valid``);
* a wall that encloses a free pocket is cut in two along a vertical line through the pocket, as often
  as needed, so that no hole has a hole of its own (the pieces touch along the cut, which the loader
  allows, and the free area is unchanged);
* collinear vertices are dropped, so a run of 50 blocked cells is one edge, not 50.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple, cast

import numpy as np
import shapely
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry
from shapely.geometry.polygon import orient

__all__ = ["WallReport", "blocked_cell_walls", "hole_rings", "ring_vertex_count", "snap_points"]

Point = tuple[float, float]
Ring = tuple[Point, ...]


class WallReport(NamedTuple):
    """What :func:`hole_rings` did to the walls it was given."""

    pieces: int
    """Wall pieces given (cell runs, wall objects, ...)."""
    holes: int
    """Hole rings produced."""
    merged: int
    """Pieces that overlapped or touched another piece and were merged into it."""
    split: int
    """Pieces whose ring touched or crossed itself, split into valid polygons."""
    cut: int
    """Cuts through walls that enclosed a free pocket, so that every hole is a simple ring."""
    dropped: int
    """Pieces with no area inside the outer ring, left out."""

    def describe(self, pieces_name: str = "wall pieces") -> str:
        """One phrase for a summary line, e.g. ``merged 32 wall pieces into 11 holes, split 1 ring, ...``."""
        parts = [f"merged {self.pieces} {pieces_name} into {self.holes} holes"]
        parts.append(f"split {self.split} self-touching ring{'s' if self.split != 1 else ''}")
        if self.cut:
            parts.append(f"cut {self.cut} enclosing wall{'s' if self.cut != 1 else ''} open")
        if self.dropped:
            parts.append(f"dropped {self.dropped} piece{'s' if self.dropped != 1 else ''} outside the level")
        return ", ".join(parts)


def blocked_cell_walls(blocked: np.ndarray, *, origin: Point = (0.0, 0.0), cell_size: float = 1.0) -> list[Polygon]:
    """Rectangles covering the ``True`` cells of a ``bool (rows, cols)`` mask, one per run in a row.

    Row ``r``, column ``c`` is the square ``origin + (c, r) * cell_size`` to ``origin + (c + 1, r + 1) *
    cell_size``. Runs, not cells, keep the union in :func:`hole_rings` fast on 512 x 512 maps.

    Examples
    --------
    >>> [p.bounds for p in blocked_cell_walls(np.array([[True, True, False], [False, False, True]]))]
    [(0.0, 0.0, 2.0, 1.0), (2.0, 1.0, 3.0, 2.0)]
    """
    mask = np.asarray(blocked, dtype=bool)
    edges = np.diff(np.pad(mask.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    run_rows, run_starts = np.nonzero(edges == 1)
    _, run_ends = np.nonzero(edges == -1)
    x0, y0 = origin
    return list(
        shapely.box(
            x0 + run_starts * cell_size,
            y0 + run_rows * cell_size,
            x0 + run_ends * cell_size,
            y0 + (run_rows + 1) * cell_size,
        )
    )


def snap_points(points: np.ndarray, step: float, tolerance: float) -> tuple[np.ndarray, int]:
    """Move each coordinate within ``tolerance`` of a multiple of ``step`` onto it.

    Returns the snapped ``float (n, 2)`` points and how many points moved. Hand-placed vertices a pixel
    off the tile grid land on it; vertices meant to be off the grid (further than ``tolerance``) stay.

    Examples
    --------
    >>> snapped, moved = snap_points(np.array([[63.4, 10.0], [64.0, 128.2]]) / 64, 0.5, 1 / 32)
    >>> (snapped * 64).round(3).tolist(), moved
    ([[64.0, 10.0], [64.0, 128.0]], 2)
    """
    points = np.asarray(points, dtype=float)
    nearest = np.round(points / step) * step
    close = np.abs(points - nearest) <= tolerance
    moved = close & (points != nearest)
    return np.where(close, nearest, points), int(moved.any(axis=1).sum())


def hole_rings(
    walls: Sequence[shapely.Geometry],
    outer: Polygon,
    *,
    cut_step: float | None = 1.0,
) -> tuple[tuple[Ring, ...], WallReport]:
    """Clean, non-overlapping simple hole rings covering the walls' area inside ``outer``.

    Parameters
    ----------
    walls
        Wall polygons in any state: overlapping, touching, self-touching, partly outside ``outer``.
    outer
        The level's outer ring as a polygon; walls are clipped to it.
    cut_step
        Cuts through enclosing walls go along a multiple of this where one passes through the pocket
        (keeping coordinates on the grid), else through the pocket's middle.

    Returns
    -------
    rings, report
        Rings without a closing point, each clockwise with y up (counter-clockwise on screen, y down),
        ordered by their top-left corner; and what was changed.

    Examples
    --------
    >>> rings, report = hole_rings([box(1, 1, 3, 2), box(2, 1, 4, 2)], box(0, 0, 5, 5))
    >>> rings, report.merged
    ((((1.0, 1.0), (1.0, 2.0), (4.0, 2.0), (4.0, 1.0)),), 1)
    """
    pieces: list[Polygon] = []
    split = dropped = 0
    for given in walls:
        wall = cast(BaseGeometry, given)
        if not wall.is_valid:
            split += 1
            wall = shapely.make_valid(wall)
        parts = [part for part in _polygons(wall.intersection(outer)) if part.area > 0]
        if not parts:
            dropped += 1
        pieces.extend(parts)
    merged_parts = _polygons(shapely.union_all(pieces)) if pieces else []
    holes: list[Polygon] = []
    cuts = 0
    for polygon in merged_parts:
        opened, polygon_cuts = _open_pockets(polygon, cut_step)
        holes.extend(opened)
        cuts += polygon_cuts
    cleaned = [orient(shapely.simplify(hole, 0), sign=-1.0) for hole in holes]
    cleaned = [hole for hole in cleaned if isinstance(hole, Polygon) and not hole.is_empty and hole.area > 0]
    cleaned.sort(key=lambda p: (p.bounds[1], p.bounds[0], p.bounds[3], p.bounds[2]))
    rings = tuple(_ring(hole) for hole in cleaned)
    report = WallReport(
        pieces=len(walls),
        holes=len(rings),
        merged=max(0, len(pieces) - len(merged_parts)),
        split=split,
        cut=cuts,
        dropped=dropped,
    )
    return rings, report


def ring_vertex_count(rings: Sequence[Ring]) -> int:
    """Vertices over all rings."""
    return sum(len(ring) for ring in rings)


def _polygons(geometry: shapely.Geometry) -> list[Polygon]:
    """The polygons of any geometry (lines and points left over by clipping are dropped)."""
    return [part for part in shapely.get_parts(geometry) if isinstance(part, Polygon)] if geometry is not None else []


def _open_pockets(polygon: Polygon, step: float | None) -> tuple[list[Polygon], int]:
    """Cut ``polygon`` until no piece has an interior ring; the pieces and the number of cuts."""
    done: list[Polygon] = []
    work = [polygon]
    cuts = 0
    while work:
        piece = work.pop()
        if not piece.interiors:
            done.append(piece)
            continue
        x = _cut_position(piece.interiors[0].bounds, step)
        min_x, min_y, max_x, max_y = piece.bounds
        for side in (box(min_x - 1, min_y - 1, x, max_y + 1), box(x, min_y - 1, max_x + 1, max_y + 1)):
            work.extend(part for part in _polygons(piece.intersection(side)) if part.area > 0)
        cuts += 1
    return done, cuts


def _cut_position(bounds: tuple[float, float, float, float], step: float | None) -> float:
    """An x strictly inside the pocket: on the ``step`` grid if one fits, else the pocket's middle."""
    low, _, high, _ = bounds
    middle = (low + high) / 2
    if step:
        for candidate in (
            round(middle / step) * step,
            math.floor(middle / step) * step,
            math.ceil(middle / step) * step,
        ):
            if low < candidate < high:
                return float(candidate)
    return middle


def _ring(polygon: Polygon) -> Ring:
    """The exterior without its closing point, starting at its top-left vertex so output is canonical."""
    coords = [(float(x), float(y)) for x, y in polygon.exterior.coords[:-1]]
    first = min(range(len(coords)), key=lambda i: (coords[i][1], coords[i][0]))
    return tuple(coords[first:] + coords[:first])
