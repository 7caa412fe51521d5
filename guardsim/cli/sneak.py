"""``guardsim sneak``: can a player get from one point to another unseen by a patrol?"""

from __future__ import annotations

import sys

import click

from guardsim.cli.common import (
    DetectionOverrides,
    build_scene,
    detection_options,
    limit_options,
    load,
    parse_point,
    reports_errors,
    vision_options,
)
from guardsim.cli.map_options import MapImport, map_options
from guardsim.cli.patrol import output_folder
from guardsim.cli.progress import StageLine
from guardsim.errors import GuardsimError
from guardsim.grid import CoverageGrid

__all__ = ["sneak", "sneak_cell"]


def _each_point(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[tuple[float, float], ...]:
    """Click callback of a repeatable ``X,Y`` option."""
    return tuple(point for point in (parse_point(ctx, param, value) for value in values) if point is not None)


def sneak_cell(scene_grid: CoverageGrid, point: tuple[float, float], option: str) -> int:
    """The flat cell of a point given as ``option``, or a one-line error saying why it cannot be used."""
    cell = scene_grid.cell_of(point)
    where = f"{option} {point[0]:g},{point[1]:g}"
    if cell is None:
        raise GuardsimError(f"{where} lies outside the level")
    if not scene_grid.traversable[cell[1], cell[0]]:
        raise GuardsimError(f"{where} is in cell [{cell[0]}, {cell[1]}], where a guard-sized intruder does not fit")
    return scene_grid.flat(*cell)


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
@click.option("--gif", is_flag=True, help="Write DIR/sneak.gif: the guards and the intruder's path.")
@click.option(
    "--html", is_flag=True, help="Write DIR/sneak.html: the viewer, with the lap, the hiding spots and the intruder."
)
@click.option(
    "--undetected",
    is_flag=True,
    help="Search for a path no guard's awareness meter fills on (seen briefly is allowed), not an unseen one.",
)
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
    gif: bool,
    html: bool,
    undetected: bool,
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
    """
    from guardsim.detection import GuardDetection
    from guardsim.detection.watch import MAX_JOINT_LAP, level_watch
    from guardsim.patrol import read_patrol
    from guardsim.sneak import sneak_check, sneak_data
    from guardsim.vision.table import view_table

    if (gif or html) and out_dir is None:
        raise GuardsimError("--gif and --html write into the --out folder: give --out DIR")
    if safe and not html:
        raise GuardsimError("--safe outlines spots on the page: give --html")
    progress = StageLine(sys.stderr, "sneak").start()
    level = detection_overrides.apply(load(level_path, max_cells, max_vertices, max_file_bytes, map_import))
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead("sneak")
    scene = build_scene(level, los, fov, view_range)
    grid = scene.grid
    patrol = read_patrol(patrol_path, grid, level=level.name)
    if patrol.motion != "grid":
        raise GuardsimError(
            f"{patrol_path}: motion is {patrol.motion!r}: the sneak check runs on grid-motion patrols (ticks) only"
        )
    if patrol.period is None:
        raise GuardsimError(f"{patrol_path}: period is null: the sneak check needs a repeating patrol")
    if source is None:
        if not level.player_starts:
            raise GuardsimError(f"{level_path}: the level marks no player start: give --from X,Y")
        source = level.player_starts[0]
        click.echo(f"from the level's player start ({source[0]:g}, {source[1]:g})")
    start, goal = sneak_cell(grid, source, "--from"), sneak_cell(grid, target, "--to")
    if grid.component_labels[start] != grid.component_labels[goal]:
        raise GuardsimError(
            f"--to {target[0]:g},{target[1]:g} cannot be reached from --from {source[0]:g},{source[1]:g} at all"
        )
    for point in safe:
        sneak_cell(grid, point, "--safe")
    table = view_table(grid, scene.vision())
    detection = GuardDetection.of_level(scene.level)
    limit = MAX_JOINT_LAP if max_lap is None else max_lap
    watch = level_watch(scene, detection.dt, max_lap=limit) if level.cameras or not level.lit else None
    for note in () if watch is None else watch.notes:
        click.echo(f"guardsim: warning: {note}", err=True)
    progress("searching" + (" for an undetected path" if undetected else " for an unseen path"), 0, 0)
    result = sneak_check(
        grid, table, patrol, start, goal, detection=detection, undetected=undetected, watch=watch,
        max_lap=limit,
    )  # fmt: skip
    if result.lap is not None:
        patrol = result.lap
    progress("writing", 0, 0)
    path = result.path
    assert path is not None
    data = sneak_data(result, grid, level=level.name, patrol=patrol_path, **{"from": list(source), "to": list(target)})
    written: list[str] = []
    if out_dir is not None:
        from guardsim.sneak.outputs import write_sneak_outputs

        written, warnings = write_sneak_outputs(
            output_folder(out_dir),
            scene,
            table,
            patrol,
            result,
            data,
            start=start,
            source=source,
            target=target,
            detection=detection,
            gif=gif,
            html=html,
            safe=safe,
            watch=watch,
        )
        progress.close()
        for warning in warnings:
            click.echo(f"guardsim: warning: {warning}", err=True)
    progress.close()
    rule = "undetected" if undetected else "unseen"
    if path.found:
        answer = f"sneaks: {rule} from tick {path.start_tick} of the lap, {path.ticks} ticks"
    else:
        answer = (
            f"caught: no {rule} path; the closest call is seen for {path.ticks_in_view} ticks ({path.ticks} ticks long)"
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
