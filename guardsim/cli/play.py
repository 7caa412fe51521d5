"""``guardsim play``: one episode, as a summary line, a GIF and a trace."""

from __future__ import annotations

import sys
import time

import click

from guardsim.cli.common import (
    build_scene,
    gif_suffix,
    level_options,
    load,
    parse_point,
    vision_options,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.motion import check_motion, check_speed_up, motion_of, motion_options, speed_up_option
from guardsim.cli.progress import StageLine
from guardsim.files.output import write_text_atomic
from guardsim.level import HEADINGS
from guardsim.motion.run import play_episode, play_summary
from guardsim.pictures import write_play_pictures
from guardsim.planners import FIELD_PLANNERS, PLANNERS
from guardsim.render.timeline import DEFAULT_MAX_FRAMES, GifOptions

__all__ = ["play"]


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--gif", "gif_path", type=str, callback=gif_suffix, help="Write the episode as an animated GIF (.gif).")
@click.option("--html", "html_path", type=str, help="Write the episode as an interactive page (one offline file).")
@click.option("--trace", "trace_path", type=str, help="Write the episode as JSON.")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed for random choices.")
@click.option("--start", callback=parse_point, metavar="X,Y", help="Start position in world units.")
@click.option("--heading", type=click.Choice(list(HEADINGS)), help="First heading (default: the level's, or drawn).")
@click.option(
    "--episode",
    type=click.IntRange(min=0),
    help="Re-run episode K of a batch seeded with --seed: start and heading drawn as in `guardsim bench`.",
)
@click.option("--planner", type=click.Choice(list(PLANNERS)), default="ripplefront", show_default=True)
@click.option(
    "--guards",
    type=click.IntRange(min=1, max=10_000),
    default=1,
    show_default=True,
    help="Team size: the other guards start at cells drawn from the first guard's connected area.",
)
@click.option(
    "--max-steps", type=click.IntRange(min=0, max=10**9), help="Step limit [default: 10 per traversable cell]."
)
@click.option("--sweeps-per-tick", type=click.IntRange(min=1), default=1, show_default=True)
@click.option(
    "--record-field",
    is_flag=True,
    help="Record the planner's field D at every tick in the trace (the viewer's field layer; large).",
)
@click.option(
    "--reference",
    is_flag=True,
    help="Use the reference vision (a ray per cell per tick) and full-grid field sweeps, for checking.",
)
@click.option("--stride", type=click.IntRange(min=1), help="Ticks between GIF frames [default: fit --max-frames].")
@click.option("--frame-ms", type=click.IntRange(min=10), default=60, show_default=True, help="GIF frame duration.")
@click.option("--max-frames", type=click.IntRange(min=1), default=DEFAULT_MAX_FRAMES, show_default=True)
@click.option(
    "--size",
    type=click.IntRange(min=64, max=8192),
    metavar="PX",
    help="Longest side of the GIF's map in pixels [default: at least 6 pixels a cell, up to 1600].",
)
@speed_up_option
@vision_options
@motion_options
@level_options(vision=False)
def play(
    level_path: str,
    gif_path: str | None,
    html_path: str | None,
    trace_path: str | None,
    seed: int,
    start: tuple[float, float] | None,
    heading: str | None,
    episode: int | None,
    planner: str,
    guards: int,
    max_steps: int | None,
    sweeps_per_tick: int,
    record_field: bool,
    reference: bool,
    stride: int | None,
    frame_ms: int,
    max_frames: int,
    size: int | None,
    speed_up: float | None,
    los: str,
    fov: float | None,
    view_range: float | None,
    motion: str,
    move_speed: float | None,
    turn_speed: float | None,
    tick_hz: float | None,
    max_seconds: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
    map_import: MapImport,
) -> None:
    """Walk a guard over LEVEL until it has seen every reachable cell.

    The start is --start, else the level's guard.start, else drawn from the seed; likewise the heading.
    With --episode K, both are drawn from episode K's generator unless given with --start/--heading.
    With --guards K, the other guards' starts and headings are drawn next from the same generator, which
    then feeds the planners, as in `guardsim bench`.
    """
    check_motion(
        motion, guards, los, move_speed=move_speed, turn_speed=turn_speed, tick_hz=tick_hz, max_seconds=max_seconds
    )
    check_speed_up(motion, speed_up)
    if record_field and planner not in FIELD_PLANNERS:
        raise click.BadParameter(f"planner {planner} keeps no field to record", param_hint="--record-field")
    # A big map spends seconds loading, seeing, walking and drawing: the stage line keeps it from silence.
    progress = StageLine(sys.stderr, "play").start()
    progress("loading the level", 0, 0)
    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead(f"play:{planner}")
    began = time.perf_counter()
    progress("building the scene", 0, 0)
    scene = build_scene(level, los, fov, view_range)
    walk = motion_of(scene, move_speed, turn_speed, tick_hz) if motion == "continuous" else "grid"
    progress("walking the episode", 0, 0)
    trace = play_episode(
        scene, planner, seed=seed, episode=episode, start=start, heading=heading, guards=guards, max_steps=max_steps,
        sweeps_per_tick=sweeps_per_tick, record_field=record_field, reference=reference, motion=walk,
        max_seconds=max_seconds,
    )  # fmt: skip
    seconds = time.perf_counter() - began
    gif_options = GifOptions(stride=stride, frame_ms=frame_ms, max_frames=max_frames, size=size, speed_up=speed_up)
    written = write_play_pictures(
        level, trace, gif=gif_path, html=html_path, gif_options=gif_options, progress=progress
    )
    if trace_path:
        progress("writing the trace", 0, 0)
        write_text_atomic(trace_path, trace.to_json())
        written.append(trace_path)
    progress.close()
    click.echo(play_summary(level.name, trace, seconds, written))
