"""``guardsim patrol``: a repeating patrol of a level, its idleness, and the route for a game or editor.

The work is :func:`guardsim.patrol.job.run_patrol` and its pictures
:func:`guardsim.pictures.write_patrol_pictures`; this module parses the options and prints.
"""

from __future__ import annotations

import sys
from pathlib import Path

import click

from guardsim.cli.common import (
    build_scene,
    check_outside,
    level_options,
    load,
    parse_point,
    picture_option,
    picture_path,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.progress import StageLine
from guardsim.cli.types import FiniteFloatRange
from guardsim.errors import GuardsimError
from guardsim.patrol.job import PatrolJob, check_job, run_patrol, tiled_source_of, write_patrol_files
from guardsim.patrol.model import STRATEGIES
from guardsim.pictures import write_patrol_pictures
from guardsim.planners import PLANNERS

__all__ = ["output_folder", "patrol"]


def output_folder(path: str) -> Path:
    """The ``--out`` folder, made if missing; one error line when it cannot be."""
    if not path.strip():
        raise GuardsimError("--out: expected a folder name, got an empty text")
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise GuardsimError(f"{path}: cannot make the output folder: {error.strerror or error}") from None
    return folder


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option(
    "--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Folder for patrol.json and idleness.png."
)
@click.option("--guards", type=click.IntRange(min=1, max=64), default=1, show_default=True)
@click.option("--strategy", type=click.Choice(STRATEGIES), default="loop", show_default=True)
@click.option(
    "--planner",
    type=click.Choice(["auto", "cover", *PLANNERS]),
    default="auto",
    show_default=True,
    help="loop: viewpoints from the set cover, from that planner's coverage walk, or the best of cover, tour and frontier (auto; of cover and frontier on grids over 60 x 60 cells, cover alone over 300 x 300).",
)
@click.option("--motion", type=click.Choice(["grid", "continuous"]), default="grid", show_default=True)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Start and random choices.")
@click.option(
    "--start",
    callback=parse_point,
    metavar="X,Y",
    help="Where the first guard starts (world units), as in play; the patrol watches the cells reachable from there [default: the level's guard.start, else drawn from --seed].",
)
@click.option(
    "--laps",
    type=click.IntRange(min=1),
    default=10,
    show_default=True,
    help="Loop laps a walked strategy is scored over.",
)
@click.option("--warmup-laps", type=click.IntRange(min=0), default=2, show_default=True)
@click.option("--compare", is_flag=True, help="Also print every strategy's worst and mean idleness.")
@click.option(
    "--evaluate",
    "evaluate_path",
    type=str,
    help="Score this patrol.json (hand-written ones too) instead of making one.",
)
@picture_option("--gif", "gif_path", "Write one lap as a GIF to FILE (a bare --gif: DIR/patrol.gif).")
@picture_option("--html", "html_path", "Write one lap in the viewer page to FILE (a bare --html: DIR/patrol.html).")
@click.option("--export", "export_path", type=str, help="Write the route as waypoints (route.json).")
@click.option(
    "--speed",
    type=FiniteFloatRange(min=0, min_open=True, max=1e6),
    help="World units per second: route times, and the walk in continuous motion [default: the level guard's move_speed, else 2].",
)
@click.option(
    "--tiled-out",
    "tiled_out",
    type=str,
    help="Write a copy of the Tiled map with a 'guardsim' route layer (.tmx or .tmj).",
)
@click.option("--tiled-source", "tiled_source_path", type=str, help="The Tiled map a JSON level was imported from.")
@click.option(
    "--godot",
    "godot_out",
    type=str,
    help="Write the routes as a Godot scene (.tscn): a Path2D and PathFollow2D per guard.",
)
@click.option(
    "--clean",
    is_flag=True,
    help="Take one-tile jogs and A-B-A spurs out of the exported routes where the guard still watches as well.",
)
@click.option(
    "--clean-tolerance",
    type=FiniteFloatRange(min=0, max=10),
    default=0.1,
    show_default=True,
    help="--clean: how much worse (a share) the worst idleness of a cleaned route may be.",
)
@click.option("--godot-version", type=click.Choice(["4", "3"]), default="4", show_default=True)
@click.option(
    "--units",
    type=click.Choice(["world", "pixels", "tiles"]),
    default="world",
    show_default=True,
    help="route.json's units.",
)
@click.option(
    "--axis", type=click.Choice(["y-down", "y-up"]), default="y-down", show_default=True, help="route.json's y axis."
)
@click.option(
    "--pixels-per-unit",
    type=FiniteFloatRange(min=0, min_open=True, max=1e6),
    help="Pixels per world unit for --units pixels and --godot [default: the Tiled map's tile size, else 32].",
)
@click.option(
    "--memory-mb",
    type=click.IntRange(min=64, max=2**20),
    default=2048,
    show_default=True,
    help="Memory budget: a level whose patrol would need more is refused before any work.",
)
@level_options()
def patrol(
    level_path: str,
    map_import: MapImport,
    out_dir: str,
    guards: int,
    strategy: str,
    planner: str,
    motion: str,
    seed: int,
    start: tuple[float, float] | None,
    laps: int,
    warmup_laps: int,
    compare: bool,
    evaluate_path: str | None,
    gif_path: str | None,
    html_path: str | None,
    export_path: str | None,
    speed: float | None,
    tiled_out: str | None,
    tiled_source_path: str | None,
    godot_out: str | None,
    godot_version: str,
    clean: bool,
    clean_tolerance: float,
    units: str,
    axis: str,
    pixels_per_unit: float | None,
    memory_mb: int,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Build a repeating patrol of LEVEL and score it by idleness (ticks a cell goes unwatched).

    loop (default) walks a closed route per guard that sees every reachable cell each lap; a team
    tries one shared cycle with the guards evenly spaced and split loops, and keeps the lower worst
    idleness. staleness, ripplefront and random are the walked baselines. See docs/patrols.md.
    """
    job = PatrolJob(
        guards=guards,
        strategy=strategy,
        planner=planner,
        motion=motion,
        seed=seed,
        start=start,
        laps=laps,
        warmup_laps=warmup_laps,
        compare=compare,
        evaluate_path=evaluate_path,
        export_path=export_path,
        speed=speed,
        tiled_out=tiled_out,
        tiled_source=tiled_source_of(level_path, tiled_source_path),
        godot_out=godot_out,
        godot_version=int(godot_version),
        clean=clean,
        clean_tolerance=clean_tolerance,
        units=units,
        axis=axis,
        pixels_per_unit=pixels_per_unit,
        max_file_bytes=max_file_bytes,
        memory_bytes=memory_mb * 2**20,
    )
    check_job(job)
    gif = picture_path(gif_path, out_dir, "patrol.gif", "--gif")
    html = picture_path(html_path, out_dir, "patrol.html", "--html")
    check_outside(out_dir, export_path, tiled_out, godot_out, gif, html)
    with StageLine(sys.stderr, "patrol") as progress:
        progress("reading the level", 0, 0)
        level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
        from guardsim.kernels.ahead import compile_ahead

        progress("compiling", 0, 0)
        compile_ahead("patrol:team" if guards > 1 else "patrol")
        progress("building the scene", 0, 0)
        scene = build_scene(level, los, fov, view_range)
        done = run_patrol(scene, job, progress=progress)
        folder = output_folder(out_dir)
        files = write_patrol_files(scene, folder, done, job, progress=progress)
        progress("drawing", 0, 0)
        drawn = write_patrol_pictures(scene, done, heat_map=folder / "idleness.png", gif=gif, html=html)
    for warning in (*files.warnings, *drawn.warnings):
        click.echo(f"guardsim: warning: {warning}", err=True)
    for line in done.printed(files, drawn.written):
        click.echo(line)
    sys.stdout.flush()
