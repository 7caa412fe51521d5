"""``guardsim report``: how hard a level is, from measures with a source, and one score from 0 to 100."""

from __future__ import annotations

import json

import click

from guardsim.cli.common import level_options, load
from guardsim.cli.design_common import StepLines, check_outputs, guards_option, pair_options, pairs_of
from guardsim.cli.map_options import MapImport
from guardsim.design.report import MAX_ALERT_EPISODES

__all__ = ["report"]


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--patrol", "patrol_path", type=str, help="patrol.json [default: the loop patrol of --guards guards].")
@guards_option
@pair_options
@click.option(
    "--alert",
    "alert",
    type=click.IntRange(min=0, max=MAX_ALERT_EPISODES),
    default=0,
    help="Run N seeded alert episodes for the capture rate.",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--html", "html_path", type=str, help="Write the report as a page (the level, the paths, the formula).")
@click.option("--json", "json_path", type=str, help="Write report.json.")
@level_options(vision=False)
def report(
    level_path: str,
    map_import: MapImport,
    patrol_path: str | None,
    guards: int,
    sources: tuple[tuple[float, float], ...],
    targets: tuple[tuple[float, float], ...],
    alert: int,
    seed: int,
    html_path: str | None,
    json_path: str | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Measure how hard LEVEL is for a player sneaking past its patrol, and score it from 0 to 100.

    Per entry-goal pair: the sneak outcome (undetected rule), slack, the straight walk's entry ticks
    (walking the fewest steps, never waiting, unseen), peak awareness, the path-distance
    risk of the best path and the distinct ways through; over the level: the floor never watched and
    each guard's turns, backtracks and loop length; with --alert N, the capture rate of N seeded alert
    episodes. The score's formula is printed with its parts (docs/design.md).
    """
    from guardsim.design import analyse, report_data, report_of
    from guardsim.files.output import write_text_atomic
    from guardsim.kernels.ahead import compile_ahead

    pairs = pairs_of(sources, targets)
    check_outputs(json=json_path, html=html_path)
    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    compile_ahead("report")
    with StepLines() as steps:
        analysis = analyse(level, patrol=patrol_path, guards=guards, pairs=pairs, seed=seed, progress=steps)
        found = report_of(analysis, alert=alert, seed=seed, progress=steps)
    data = report_data(found)
    if pairs is None:
        # Say where the sneak figures come from: a designer reading them should know the points were picked.
        click.echo("  pairs: none given (--from X,Y --to X,Y), so from each player start, else the floor's far end, to the cell farthest on foot")
    for pair in data["pairs"]:
        where = f"{pair['from'][0]:g},{pair['from'][1]:g} -> {pair['to'][0]:g},{pair['to'][1]:g}"
        if pair["outcome"] in ("unreachable", "unchecked"):
            click.echo(f"  {where}: {pair['outcome']} ({pair.get('note', '')})")
            continue
        click.echo(
            f"  {where}: {pair['outcome']}, {pair['ticks']} ticks; slack {pair['slack']}/{pair['period']}; "
            f"straight walk {pair['direct']}/{pair['period']}; peak awareness {pair['peak_awareness']:.2f}; path-distance risk {pair['path_distance_risk']:.2f}; "
            f"{pair['ways']} way(s) through"
        )
    for index, guard in enumerate(data["guards"]):
        click.echo(
            f"  guard {index}: loop {guard['loop_length']} moves over {guard['cells']} cells, "
            f"{guard['turns']} turns, {guard['backtracks']} backtracks"
        )
    click.echo(f"  floor never watched: {100 * data['never_watched']:.1f}%")
    if data["capture_rate"] is not None:
        click.echo(f"  capture rate: {data['capture_rate']:.2f} of {alert} alert episodes")
    parts = ", ".join(f"{name} {value:.2f}" for name, value in data["parts"].items())
    click.echo(f"{level.name}: difficulty {data['score']}/100 ({parts}); {data['formula']}")
    written = []
    if json_path is not None:
        write_text_atomic(json_path, json.dumps(data, indent=1) + "\n")
        written.append(json_path)
    if html_path is not None:
        from guardsim.viewer.serve import analysis_payload, static_page

        write_text_atomic(html_path, static_page(f"{level.name}: difficulty", [analysis_payload(analysis, data)]))
        written.append(html_path)
    if written:
        click.echo(f"-> {', '.join(written)}")
