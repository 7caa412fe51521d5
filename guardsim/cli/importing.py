"""``guardsim import``: a designer's map (Moving AI, Tiled, PNG) converted to a level file."""

from __future__ import annotations

import click

from guardsim.cli.common import limit_options, reports_errors
from guardsim.importers import import_map
from guardsim.importers.image import DEFAULT_THRESHOLD
from guardsim.output import write_text_atomic

__all__ = ["import_command"]


@click.command("import")
@click.argument("source", metavar="SOURCE")
@click.option("--out", "out_path", required=True, type=str, help="Where to write the level.")
@click.option(
    "--cell-size",
    type=click.FloatRange(min=0, min_open=True),
    help="The level's cell_size in world units; one map cell, tile or pixel is one unit. [default: 1]",
)
@click.option(
    "--threshold",
    type=click.IntRange(0, 256),
    default=DEFAULT_THRESHOLD,
    show_default=True,
    help="Images: pixels darker than this grey level (0-255) are walls.",
)
@click.option(
    "--spawn-tile",
    "spawn_tiles",
    type=click.IntRange(min=1),
    multiple=True,
    metavar="GID",
    help="Tiled: a global tile id that marks a guard spawn (repeatable), for tilesets without a 'guard' class.",
)
@limit_options
@reports_errors
def import_command(
    source: str,
    out_path: str,
    cell_size: float | None,
    threshold: int,
    spawn_tiles: tuple[int, ...],
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Convert SOURCE to a level file and print what the import changed.

    The reader is chosen by SOURCE's suffix: .map (Moving AI), .tmx/.tmj/.json (Tiled), .png (image).
    See docs/authoring.md for how to mark floor, walls, boundary and guard spawns in Tiled.
    """
    imported = import_map(
        source,
        cell_size=cell_size,
        threshold=threshold,
        spawn_tiles=spawn_tiles,
        max_cells=max_cells,
        max_vertices=max_vertices,
        max_file_bytes=max_file_bytes,
    )
    write_text_atomic(out_path, imported.to_json())
    click.echo(f"{imported.summary()} -> {out_path}")
