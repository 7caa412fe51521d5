"""``guardsim render``: a level preview for designers, optionally with what a guard sees from one spot."""

from __future__ import annotations

import click

from guardsim.cli.common import level_options, load, parse_point
from guardsim.cli.map_options import MapImport
from guardsim.level import HEADINGS

__all__ = ["render"]


def parse_cone(
    _ctx: click.Context, param: click.Parameter, value: str | None
) -> tuple[tuple[float, float], str] | None:
    """Click callback: ``X,Y,HEADING`` into a point and a heading name."""
    if value is None:
        return None
    parts = value.split(",")
    if len(parts) != 3 or parts[2].strip() not in HEADINGS:
        raise click.BadParameter(
            f"expected X,Y,HEADING with HEADING one of {', '.join(HEADINGS)}, got {value!r}", param=param
        )
    point = parse_point(_ctx, param, ",".join(parts[:2]))
    assert point is not None  # parse_point returns a point for any string it accepts
    return point, parts[2].strip()


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--png", "png_path", required=True, type=str, help="Where to write the preview.")
@click.option("--start", callback=parse_point, metavar="X,Y", help="Start position (default: the level's).")
@click.option(
    "--cone",
    callback=parse_cone,
    metavar="X,Y,HEADING",
    help="Overlay what a guard standing at X,Y facing HEADING (right, down, left, up) sees.",
)
@click.option(
    "--size",
    type=click.IntRange(min=64, max=8192),
    metavar="PX",
    help="Longest side of the map in pixels [default: 640, or 6 pixels a cell if more, up to 1600].",
)
@level_options(vision=False)
def render(
    level_path: str,
    png_path: str,
    start: tuple[float, float] | None,
    cone: tuple[tuple[float, float], str] | None,
    size: int | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
    map_import: MapImport,
) -> None:
    """Draw a preview of LEVEL: walls, grid, reachable and unreachable cells, coordinate rulers, a legend.

    Reachable means reachable from the start; with no start, from the largest connected area.
    """
    from guardsim.render.level_preview import write_level_preview

    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    summary = write_level_preview(png_path, level, start=start, cone=cone, size=size, level_name=level_path)
    click.echo(f"{level.name}: {summary} -> {png_path}")
