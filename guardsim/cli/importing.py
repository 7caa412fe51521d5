"""``guardsim import``: a designer's map (Moving AI, Tiled, PNG) converted to a level file."""

from __future__ import annotations

import sys

import click

from guardsim.cli.common import level_options
from guardsim.cli.map_options import STRICT_EXIT, MapImport
from guardsim.errors import LevelError
from guardsim.files.output import write_text_atomic
from guardsim.importers import ImportedLevel, load_level

__all__ = ["import_command"]


@click.command("import")
@click.argument("source", metavar="SOURCE")
@click.option("--out", "out_path", required=True, type=str, help="Where to write the level.")
@level_options(vision=False)
def import_command(
    source: str,
    out_path: str,
    map_import: MapImport,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Convert SOURCE to a level file and print what the import found, guessed and changed.

    SOURCE is a .map (Moving AI), .tmx/.tmj/.json (Tiled), .ldtk (LDtk) or .png (image) file. Warnings (no walls
    found, a free area open to the map's edge, ...) go to stderr; with --strict they fail the import
    with exit status 1 and nothing is written. See docs/authoring.md for how walls, floor and spawns
    are found in Tiled maps and how to mark them.
    """
    records: list[ImportedLevel] = []
    level = load_level(
        source,
        report=records.append,
        max_cells=max_cells,
        max_vertices=max_vertices,
        max_file_bytes=max_file_bytes,
        **map_import.keywords,
    )
    if not records:
        raise LevelError(f"{level.source}: already a guardsim level, not a map to import")
    imported = records[0]
    for warning in imported.warnings:
        click.echo(f"guardsim: warning: {level.source}: {warning}", err=True)
    if map_import.strict and imported.warnings:
        click.echo(
            f"guardsim: error: {level.source}: {len(imported.warnings)} import warning(s) and --strict; "
            f"{out_path} not written",
            err=True,
        )
        sys.exit(STRICT_EXIT)
    write_text_atomic(out_path, imported.to_json())
    click.echo(f"{imported.summary()} -> {out_path}")
