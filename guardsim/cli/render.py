"""``guardsim render``: a level preview for designers."""

from __future__ import annotations

import click
import numpy as np

from guardsim.cli.common import limit_options, load, parse_point, reports_errors
from guardsim.output import atomic_path
from guardsim.render import render_preview
from guardsim.simulation import Scene, choose_start

__all__ = ["render"]


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--png", "png_path", required=True, type=str, help="Where to write the preview.")
@click.option("--start", callback=parse_point, metavar="X,Y", help="Start position (default: the level's).")
@click.option("--size", type=click.IntRange(min=64, max=8192), default=640, show_default=True, help="Image size.")
@limit_options
@reports_errors
def render(
    level_path: str,
    png_path: str,
    start: tuple[float, float] | None,
    size: int,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Draw a preview of LEVEL: walls, grid, reachable and unreachable cells.

    Reachable means reachable from the start; with no start, from the largest connected area.
    """
    import imageio.v3 as iio

    level = load(level_path, max_cells, max_vertices, max_file_bytes)
    scene = Scene.from_level(level)
    point = start or level.guard.start
    cell = None
    if point is not None:
        cell, _ = choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
        reachable = scene.grid.component(*cell)
    else:
        reachable = scene.grid.largest_component()
    image = render_preview(level, scene.grid.traversable, reachable, scene.grid.origin, start=cell, size=size)
    with atomic_path(png_path) as temporary:
        iio.imwrite(temporary, image, extension=".png")
    traversable = int(scene.grid.traversable.sum())
    rows, cols = scene.grid.shape
    click.echo(
        f"{level.name}: {rows} x {cols} cells, {traversable} traversable, {int(reachable.sum())} reachable, "
        f"{traversable - int(reachable.sum())} unreachable -> {png_path}"
    )
