"""``guardsim diff``: what an edit changed, as numbers and a picture."""

from __future__ import annotations

import json

import click

from guardsim.cli.common import level_options, load
from guardsim.cli.design_common import StepLines, check_outputs, guards_option, pair_options, pairs_of
from guardsim.cli.map_options import MapImport

__all__ = ["diff"]


@click.command()
@click.argument("old_path", metavar="OLD")
@click.argument("new_path", metavar="NEW")
@click.option("--patrol-old", type=str, help="The old version's patrol.json (give --patrol-new too).")
@click.option("--patrol-new", type=str, help="The new version's patrol.json.")
@guards_option
@pair_options
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--png", "png_path", type=str, help="Write the picture: before, after and their difference.")
@click.option("--html", "html_path", type=str, help="Write a page: both versions drawn, the difference and the table.")
@click.option("--json", "json_path", type=str, help="Write diff.json.")
@level_options(vision=False)
def diff(
    old_path: str,
    new_path: str,
    map_import: MapImport,
    patrol_old: str | None,
    patrol_new: str | None,
    guards: int,
    sources: tuple[tuple[float, float], ...],
    targets: tuple[tuple[float, float], ...],
    seed: int,
    png_path: str | None,
    html_path: str | None,
    json_path: str | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Compare two versions of a level: cells added and removed, steps to cover, idleness, each entry-goal
    pair's sneak outcome, ticks, slack, risk and peak awareness, safe and hiding spots gained and lost,
    and the difficulty score (docs/design.md). Exit status 0 either way (check --baseline gates a build).
    """
    from guardsim.design import diff as compare
    from guardsim.design import diff_data
    from guardsim.design.diff import diff_summary
    from guardsim.files.output import write_text_atomic
    from guardsim.kernels.ahead import compile_ahead
    from guardsim.pictures import write_diff_pictures

    pairs = pairs_of(sources, targets)
    check_outputs(json=json_path, png=png_path, html=html_path)
    old = load(old_path, max_cells, max_vertices, max_file_bytes, map_import)
    new = load(new_path, max_cells, max_vertices, max_file_bytes, map_import)
    compile_ahead("report")
    with StepLines() as steps:
        found = compare(
            old,
            new,
            patrol_old=patrol_old,
            patrol_new=patrol_new,
            guards=guards,
            pairs=pairs,
            seed=seed,
            progress=steps,
        )
    data = diff_data(found)
    for line in diff_summary(data, old.name):
        click.echo(line)
    written = []
    if json_path is not None:
        write_text_atomic(json_path, json.dumps(data, indent=1) + "\n")
        written.append(json_path)
    written += write_diff_pictures(found, data, png=png_path, html=html_path, title=f"{old.name}: what the edit changed")
    if written:
        click.echo(f"-> {', '.join(written)}")
