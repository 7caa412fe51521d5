"""``guardsim sneak``: can a player get from one point to another unseen by a patrol?"""

from __future__ import annotations

import itertools
import sys
from typing import cast

import click

from guardsim.cli.common import (
    DetectionOverrides,
    EarsOverrides,
    build_scene,
    detection_options,
    ears_options,
    limit_options,
    load,
    parse_point,
    picture_option,
    picture_path,
    reports_errors,
    vision_options,
)
from guardsim.cli.map_options import MapImport, map_options
from guardsim.cli.patrol import output_folder
from guardsim.cli.progress import StageLine
from guardsim.errors import GuardsimError
from guardsim.pictures import write_sneak_pictures

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
@detection_options
@vision_options
@map_options
@limit_options
@reports_errors
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
    from guardsim.patrol import read_patrol
    from guardsim.sneak import sneak_data
    from guardsim.sneak.run import check_sneak_patrol, run_sneak, sneak_header

    gif = picture_path(gif_path, out_dir, "sneak.gif", "--gif")
    html = picture_path(html_path, out_dir, "sneak.html", "--html")
    if safe and html is None:
        raise GuardsimError("--safe outlines spots on the page: give --html")
    from pathlib import Path

    from guardsim.files.output import check_writable

    # A picture named outside the --out folder is checked before the search (the folder is made later).
    inside = None if out_dir is None else Path(out_dir).resolve()
    for named in (gif, html):
        if named is not None and (inside is None or not named.resolve().is_relative_to(inside)):
            check_writable(named)
    progress = StageLine(sys.stderr, "sneak").start()
    level = detection_overrides.apply(load(level_path, max_cells, max_vertices, max_file_bytes, map_import))
    level = ears_overrides.apply(level)
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead("sneak")
    scene = build_scene(level, los, fov, view_range)
    grid = scene.grid
    patrol = read_patrol(patrol_path, grid, level=level.name)
    check_sneak_patrol(patrol, patrol_path)
    if source is None:
        if not level.player_starts:
            raise GuardsimError(f"{level_path}: the level marks no player start: give --from X,Y")
        source = level.player_starts[0]
        click.echo(f"from the level's player start ({source[0]:g}, {source[1]:g})")
    start, goal = grid.floor_cell(source, "--from"), grid.floor_cell(target, "--to")
    if grid.component_labels[start] != grid.component_labels[goal]:
        raise GuardsimError(
            f"--to {target[0]:g},{target[1]:g} cannot be reached from --from {source[0]:g},{source[1]:g} at all"
        )
    for point in safe:
        grid.floor_cell(point, "--safe")
    run = run_sneak(
        scene, patrol, start, goal, undetected=undetected, unheard=unheard, max_lap=max_lap, patrol_name=patrol_path,
        progress=progress,
    )  # fmt: skip
    for note in run.notes:
        click.echo(f"guardsim: warning: {note}", err=True)
    result, patrol, table, detection, watch = run.result, run.patrol, run.table, run.detection, run.watch
    rule = ("undetected" if undetected else "unseen") + (", unheard" if unheard else "")
    progress("writing", 0, 0)
    path = result.path
    assert path is not None
    data = sneak_data(
        result, grid, level=level.name, patrol=patrol_path, **{"from": list(source), "to": list(target)},
        **sneak_header(scene, detection, max_lap),
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
        scene, table, patrol, result, start=start, source=source, target=target, detection=detection,
        never_seen=cast(int, data["never_seen_cells"]), heat_map=heat_map, gif=gif, html=html, safe=safe, watch=watch,
    )  # fmt: skip
    written += drawn.written
    progress.close()
    for warning in drawn.warnings:
        click.echo(f"guardsim: warning: {warning}", err=True)
    if path.found:
        answer = f"sneaks: {rule} from tick {path.start_tick} of the lap, {path.ticks} ticks"
    else:
        heard = f" and heard {path.steps_heard} times" if unheard else ""
        answer = (
            f"caught: no {rule} path; the closest call is seen for {path.ticks_in_view} ticks{heard} "
            f"({path.ticks} ticks long)"
        )
    grade = result.grade
    assert grade is not None
    peaks = grade.peak_by_guard
    guards = len(peaks) - result.sight.cameras
    peak = ", ".join(f"{value:.2f}" for value in peaks[:guards])
    if result.sight.cameras:
        peak += "; by camera: " + ", ".join(f"{value:.2f}" for value in peaks[guards:])
    graded = (
        f"detected: {'yes, at tick ' + str(grade.detected_at) if grade.detected else 'no'}; "
        f"peak awareness {grade.peak:.2f} (by guard: {peak}); risk {grade.risk:.2f}; "
        f"slack {result.slack}/{result.period} entry ticks"
    )
    click.echo(f"{level.name}: {answer}; {graded}" + (f" -> {', '.join(written)}" if written else ""))
    if path.gaits is not None:
        click.echo("gaits: " + gait_runs(path.gaits, level.intruder.sneak_ticks))


def gait_runs(gaits: tuple[str, ...], sneak_ticks: int) -> str:
    """A path's gaits per tick as runs in order: ``walk x2, sneak x5 (2 ticks each), wait 3 ticks``."""
    runs: list[str] = []
    for gait, ticks in ((gait, len(list(run))) for gait, run in itertools.groupby(gaits)):
        if gait == "wait":
            runs.append(f"wait {ticks} tick{'s' if ticks != 1 else ''}")
        elif gait == "sneak":
            runs.append(f"sneak x{ticks // sneak_ticks} ({sneak_ticks} tick{'s' if sneak_ticks != 1 else ''} each)")
        else:
            runs.append(f"walk x{ticks}")
    return ", ".join(runs) if runs else "none (it enters at its goal)"
