"""``guardsim sneak``: can a player get from one point to another unseen by a patrol?"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

from guardsim.cli.common import (
    DetectionOverrides,
    EarsOverrides,
    build_scene,
    check_outside,
    ears_options,
    level_options,
    load,
    parse_point,
    picture_option,
    picture_path,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.patrol import output_folder
from guardsim.cli.progress import StageLine
from guardsim.errors import GuardsimError
from guardsim.pictures import write_sneak_pictures
from guardsim.sneak.run import gait_runs

if TYPE_CHECKING:
    from guardsim.scene import Scene
    from guardsim.sneak.run import SneakRun

__all__ = ["gait_runs", "sneak"]


def _each_point(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[tuple[float, float], ...]:
    """Click callback of a repeatable ``X,Y`` option."""
    return tuple(point for point in (parse_point(ctx, param, value) for value in values) if point is not None)


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option(
    "--patrol", "patrol_path", required=True, type=str, help="patrol.json (from guardsim patrol, or hand-written)."
)
@click.option(
    "--from",
    "source",
    callback=parse_point,
    metavar="X,Y",
    help="Where the player enters (world units) [default: the level's first player start].",
)
@click.option(
    "--to", "target", required=True, callback=parse_point, metavar="X,Y", help="Where the player must get to."
)
@click.option("--out", "out_dir", type=click.Path(file_okay=False), help="Folder for sneak.json and hiding.png.")
@picture_option(
    "--gif", "gif_path", "Write the guards and the intruder's path as a GIF to FILE (a bare --gif: DIR/sneak.gif)."
)
@picture_option(
    "--html",
    "html_path",
    "Write the viewer page, with the lap, the hiding spots and the intruder, to FILE (a bare --html: DIR/sneak.html).",
)
@click.option(
    "--undetected",
    is_flag=True,
    help="Search for a path no guard's awareness meter fills on (seen briefly is allowed), not an unseen one.",
)
@click.option(
    "--unheard",
    is_flag=True,
    help="Also choose a gait for every step (walk: 1 tick; sneak: --sneak-ticks) so that no guard hears one "
    "land (the level's intruder noise keys).",
)
@ears_options
@click.option(
    "--safe",
    "safe",
    multiple=True,
    callback=_each_point,
    metavar="X,Y",
    help="A safe spot to outline on DIR/sneak.html (as check --safe gives them); repeatable.",
)
@click.option(
    "--max-lap",
    type=click.IntRange(min=1),
    default=None,
    help="Longest joint lap of the patrol and the level's camera swings, in ticks [default: 10000].",
)
@level_options(detection=True)
def sneak(
    level_path: str,
    map_import: MapImport,
    patrol_path: str,
    source: tuple[float, float] | None,
    target: tuple[float, float],
    out_dir: str | None,
    gif_path: str | None,
    html_path: str | None,
    undetected: bool,
    unheard: bool,
    ears_overrides: EarsOverrides,
    safe: tuple[tuple[float, float], ...],
    max_lap: int | None,
    detection_overrides: DetectionOverrides,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Search every path from --from to --to over (cell, tick of the patrol's lap) for one no guard sees.

    The intruder steps to a 4-neighbour or waits each tick and may enter at any tick its entry cell is
    unseen. Exit status 0 either way; the answer is printed and written to DIR/sneak.json. When no
    unseen path exists, the closest call (fewest ticks in view) is given instead.

    With --undetected, the path may be seen as long as no guard's awareness meter fills (docs/detection.md):
    the fastest undetected path, else the same closest call. Either way the path is replayed through the
    meters (detected, peak awareness, risk) and the slack is counted: from how many of the lap's ticks a
    player entering gets through.

    With --unheard, the search also chooses a gait for every step, walking (one tick) or sneaking
    (--sneak-ticks ticks, in the cell it leaves for all but the last), and no guard may hear a step land
    (the level's walk_noise and sneak_noise, along the grid: docs/alert.md); the gaits are printed and in
    sneak.json.
    """
    from guardsim.detection.hearing import walks_audibly
    from guardsim.kernels.ahead import compile_ahead
    from guardsim.patrol import read_patrol
    from guardsim.sneak.run import run_sneak, sneak_endpoints, sneak_summary

    gif, html = _check_pictures(gif_path, html_path, out_dir, safe)
    progress = StageLine(sys.stderr, "sneak").start()
    level = detection_overrides.apply(load(level_path, max_cells, max_vertices, max_file_bytes, map_import))
    level = ears_overrides.apply(level)
    # Audible steps make the unheard search choose gaits: other kernels (its own plan).
    compile_ahead("sneak:unheard" if unheard and walks_audibly(level.intruder) else "sneak")
    scene = build_scene(level, los, fov, view_range)
    patrol = read_patrol(patrol_path, scene.grid, level=level.name)
    patrol.require_repeating_grid(patrol_path, "sneak")
    source, start, goal = sneak_endpoints(scene, source, target, level_name=level_path, say=click.echo)
    for point in safe:
        scene.grid.floor_cell(point, "--safe")
    run = run_sneak(
        scene, patrol, start, goal, undetected=undetected, unheard=unheard, max_lap=max_lap, patrol_name=patrol_path,
        progress=progress,
    )  # fmt: skip
    for note in run.notes:
        click.echo(f"guardsim: warning: {note}", err=True)
    progress("writing", 0, 0)
    written, warnings = _write(scene, run, start, source, target, patrol_path, max_lap, out_dir, gif, html, safe)
    progress.close()
    for warning in warnings:
        click.echo(f"guardsim: warning: {warning}", err=True)
    summary = sneak_summary(run.result, undetected=undetected, unheard=unheard)
    click.echo(f"{level.name}: {summary}" + (f" -> {', '.join(written)}" if written else ""))
    gaits = run.result.path.gaits if run.result.path is not None else None
    if gaits is not None:
        click.echo("gaits: " + gait_runs(gaits, level.intruder.sneak_ticks))


def _check_pictures(
    gif_path: str | None, html_path: str | None, out_dir: str | None, safe: tuple[tuple[float, float], ...]
) -> tuple[Path | None, Path | None]:
    """The GIF and page to write; a picture named outside the --out folder is checked before the search
    (the folder is made later)."""
    gif = picture_path(gif_path, out_dir, "sneak.gif", "--gif")
    html = picture_path(html_path, out_dir, "sneak.html", "--html")
    if safe and html is None:
        raise GuardsimError("--safe outlines spots on the page: give --html")
    check_outside(out_dir, gif, html)
    return gif, html


def _write(
    scene: Scene,
    run: SneakRun,
    start: int,
    source: tuple[float, float],
    target: tuple[float, float],
    patrol_path: str,
    max_lap: int | None,
    out_dir: str | None,
    gif: Path | None,
    html: Path | None,
    safe: tuple[tuple[float, float], ...],
) -> tuple[list[str], tuple[str, ...]]:
    """Write sneak.json into --out and draw the pictures; the files written and the drawing's warnings."""
    from guardsim.sneak import sneak_data
    from guardsim.sneak.run import sneak_header

    result = run.result
    data = sneak_data(
        result, scene.grid, level=scene.level.name, patrol=patrol_path, **{"from": list(source), "to": list(target)},
        **sneak_header(scene, run.detection, max_lap),
    )  # fmt: skip
    written: list[str] = []
    heat_map = None
    if out_dir is not None:
        from guardsim.sneak.outputs import write_sneak_json

        folder = output_folder(out_dir)
        write_sneak_json(folder / "sneak.json", data)
        written.append(str(folder / "sneak.json"))
        heat_map = folder / "hiding.png"
    drawn = write_sneak_pictures(
        scene, run.table, run.patrol, result, start=start, source=source, target=target, detection=run.detection,
        never_seen=cast(int, data["never_seen_cells"]), heat_map=heat_map, gif=gif, html=html, safe=safe,
        watch=run.watch,
    )  # fmt: skip
    return written + drawn.written, tuple(drawn.warnings)
