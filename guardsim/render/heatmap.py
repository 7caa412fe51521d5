"""Heat maps over the level drawing: each cell's worst unwatched gap, or a hiding spot's longest window.

matplotlib is optional (``pip install 'guardsim[plot]'``) and imported only when a map is drawn.
"""

from __future__ import annotations

import os

import numpy as np

from guardsim.errors import GuardsimError
from guardsim.files.output import atomic_path
from guardsim.grid import CoverageGrid
from guardsim.level import Level

__all__ = ["write_heat_map"]


def write_heat_map(
    path: str | os.PathLike[str],
    level: Level,
    grid: CoverageGrid,
    values: np.ndarray,
    *,
    title: str,
    unit: str,
    never: np.ndarray | None = None,
    marks: list[tuple[list[tuple[int, int]], str, str]] | None = None,
) -> None:
    """Draw ``values`` (``float (rows, cols)``, NaN where nothing is drawn) over the level and write a PNG.

    ``never`` marks cells drawn hatched in black (never seen); ``marks`` are cell paths drawn as lines,
    each ``(cells, colour, label)``.
    """
    try:
        # The figure alone, without pyplot: pyplot's import (its backends and state) is half a second of
        # every patrol command, and a figure draws to PNG through its own Agg canvas.
        from matplotlib.figure import Figure
    except ImportError:
        raise GuardsimError(
            "the heat map needs matplotlib, which is not installed: pip install 'guardsim[plot]'"
        ) from None
    min_x, min_y, max_x, max_y = level.bounds
    rows, cols = grid.shape
    size = grid.cell_size
    extent = (grid.origin[0], grid.origin[0] + cols * size, grid.origin[1] + rows * size, grid.origin[1])
    figure = Figure(figsize=(7.5, 6.5), dpi=110)
    axes = figure.subplots()
    image = axes.imshow(np.ma.masked_invalid(values), cmap="viridis", extent=extent, interpolation="nearest")
    if never is not None and never.any():
        axes.imshow(
            np.ma.masked_where(~never, np.ones_like(values)),
            cmap="gray",
            vmin=0,
            vmax=2,
            extent=extent,
            interpolation="nearest",
        )
    for ring in (level.outer, *level.holes):
        xs = [point[0] for point in ring] + [ring[0][0]]
        ys = [point[1] for point in ring] + [ring[0][1]]
        axes.fill(xs, ys, color="#3a3a3a", alpha=0.9 if ring is not level.outer else 0.0, linewidth=0)
        axes.plot(xs, ys, color="black", linewidth=1.0)
    for cells, colour, label in marks or []:
        xs = [grid.origin[0] + (col + 0.5) * size for col, _ in cells]
        ys = [grid.origin[1] + (row + 0.5) * size for _, row in cells]
        axes.plot(xs, ys, color=colour, linewidth=2.0, label=label)
        axes.plot(xs[:1], ys[:1], "o", color=colour)
        axes.plot(xs[-1:], ys[-1:], "s", color=colour)
    if marks:
        axes.legend(loc="upper right", fontsize=8)
    axes.set_xlim(min_x, max_x)
    axes.set_ylim(max_y, min_y)
    axes.set_aspect("equal")
    axes.set_title(title, fontsize=10)
    bar = figure.colorbar(image, ax=axes, shrink=0.85)
    bar.set_label(unit)
    figure.tight_layout()
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format="png")
