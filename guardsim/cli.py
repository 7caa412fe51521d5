"""The ``guardsim`` command line.

Every error a user can cause is printed as one line on standard error, with exit status 2.
"""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Callable
from typing import Any, TypeVar

import click
import numpy as np

from guardsim.errors import GuardsimError
from guardsim.level import (
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_FILE_BYTES,
    DEFAULT_MAX_VERTICES,
    HEADINGS,
    Level,
    check_level_data,
    load_level,
    read_level_json,
)
from guardsim.output import atomic_path, write_text_atomic
from guardsim.planners import PLANNERS, make_planner
from guardsim.render import DEFAULT_MAX_FRAMES, GifOptions, encode_gif, render_preview
from guardsim.simulation import Scene, choose_start, episode_generator, run_episode

F = TypeVar("F", bound=Callable[..., Any])


def _reports_errors(command: F) -> F:
    """Turn guardsim's own errors into one line on stderr and exit status 2."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return command(*args, **kwargs)
        except GuardsimError as error:
            click.echo(f"guardsim: error: {error}", err=True)
            sys.exit(2)
        except KeyboardInterrupt:
            click.echo("guardsim: interrupted", err=True)
            sys.exit(130)

    return wrapper  # type: ignore[return-value]


def _parse_point(_ctx: click.Context, param: click.Parameter, value: str | None) -> tuple[float, float] | None:
    if value is None:
        return None
    try:
        x, y = (float(part) for part in value.split(","))
    except ValueError:
        raise click.BadParameter(f"expected X,Y (two numbers), got {value!r}", param=param) from None
    if not (np.isfinite(x) and np.isfinite(y)):
        raise click.BadParameter(f"expected finite numbers, got {value!r}", param=param)
    return x, y


def _limit_options(command: F) -> F:
    """Options that raise the loader's size limits."""
    command = click.option(
        "--max-file-bytes",
        type=click.IntRange(min=1),
        default=DEFAULT_MAX_FILE_BYTES,
        show_default=True,
        help="Largest level file read.",
    )(command)
    command = click.option(
        "--max-vertices",
        type=click.IntRange(min=3),
        default=DEFAULT_MAX_VERTICES,
        show_default=True,
        help="Most vertices over all rings.",
    )(command)
    command = click.option(
        "--max-cells",
        type=click.IntRange(min=1),
        default=DEFAULT_MAX_CELLS,
        show_default=True,
        help="Largest grid (rows x cols) a level may produce.",
    )(command)
    return command


def _load(path: str, max_cells: int, max_vertices: int, max_file_bytes: int) -> Level:
    return load_level(path, max_cells=max_cells, max_vertices=max_vertices, max_file_bytes=max_file_bytes)


@click.group()
@click.version_option(package_name="guardsim")
def main() -> None:
    """Coverage path planning for guards in games."""


@main.command()
@click.argument("level_path", metavar="LEVEL", type=click.Path(dir_okay=False))
@click.option("--gif", "gif_path", type=click.Path(dir_okay=False), help="Write the episode as an animated GIF.")
@click.option("--trace", "trace_path", type=click.Path(dir_okay=False), help="Write the episode as JSON.")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed for random choices.")
@click.option("--start", callback=_parse_point, metavar="X,Y", help="Start position in world units.")
@click.option("--heading", type=click.Choice(list(HEADINGS)), help="First heading (default: the level's, or drawn).")
@click.option(
    "--episode",
    type=click.IntRange(min=0),
    help="Re-run episode K of a batch seeded with --seed: start and heading drawn as in `guardsim bench`.",
)
@click.option("--planner", type=click.Choice(list(PLANNERS)), default="ripplefront", show_default=True)
@click.option("--max-steps", type=click.IntRange(min=0), help="Step limit [default: 10 per traversable cell].")
@click.option("--sweeps-per-tick", type=click.IntRange(min=1), default=1, show_default=True)
@click.option("--stride", type=click.IntRange(min=1), help="Ticks between GIF frames [default: fit --max-frames].")
@click.option("--frame-ms", type=click.IntRange(min=10), default=60, show_default=True, help="GIF frame duration.")
@click.option("--max-frames", type=click.IntRange(min=1), default=DEFAULT_MAX_FRAMES, show_default=True)
@_limit_options
@_reports_errors
def play(
    level_path: str,
    gif_path: str | None,
    trace_path: str | None,
    seed: int,
    start: tuple[float, float] | None,
    heading: str | None,
    episode: int | None,
    planner: str,
    max_steps: int | None,
    sweeps_per_tick: int,
    stride: int | None,
    frame_ms: int,
    max_frames: int,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Walk a guard over LEVEL until it has seen every reachable cell.

    The start is --start, else the level's guard.start, else drawn from the seed; likewise the heading.
    With --episode K, both are drawn from episode K's generator unless given with --start/--heading.
    """
    level = _load(level_path, max_cells, max_vertices, max_file_bytes)
    began = time.perf_counter()
    scene = Scene.from_level(level)
    if episode is not None:
        rng = episode_generator(seed, episode)
        point, first = start, heading
    else:
        rng = np.random.default_rng(seed)
        point, first = start or level.guard.start, heading or level.guard.heading
    cell, first_heading = choose_start(scene, rng=rng, point=point, heading=first)
    guard_planner = make_planner(planner, sweeps_per_tick=sweeps_per_tick)
    trace = run_episode(scene, guard_planner, cell, first_heading, max_steps=max_steps, seed=seed)
    seconds = time.perf_counter() - began
    options = GifOptions(stride=stride, frame_ms=frame_ms, max_frames=max_frames)
    written = []
    if gif_path:
        gif = encode_gif(level, trace, options)
        with atomic_path(gif_path) as temporary:
            temporary.write_bytes(gif)
        written.append(gif_path)
    if trace_path:
        write_text_atomic(trace_path, trace.to_json())
        written.append(trace_path)
    seen_percent = 100.0 - trace.unseen_percent[-1]
    extra = f", {trace.unreachable} unreachable" if trace.unreachable else ""
    click.echo(
        f"{level.name}: {trace.outcome.replace('_', ' ')} after {trace.steps} steps, {seen_percent:.1f}% seen "
        f"({trace.reachable} reachable cells{extra}), {seconds:.2f} s"
        + (f" -> {', '.join(written)}" if written else "")
    )


@main.command()
@click.argument("level_path", metavar="LEVEL", type=click.Path(dir_okay=False))
@click.option("--png", "png_path", required=True, type=click.Path(dir_okay=False), help="Where to write the preview.")
@click.option("--start", callback=_parse_point, metavar="X,Y", help="Start position (default: the level's).")
@click.option("--size", type=click.IntRange(min=64, max=8192), default=640, show_default=True, help="Image size.")
@_limit_options
@_reports_errors
def render(
    level_path: str,
    png_path: str,
    start: tuple[float, float] | None,
    size: int,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Draw a preview of LEVEL: walls, grid, reachable and unreachable cells.

    Reachable means reachable from the start; with no start, from the largest connected area.
    """
    import imageio.v3 as iio

    level = _load(level_path, max_cells, max_vertices, max_file_bytes)
    scene = Scene.from_level(level)
    point = start or level.guard.start
    cell = None
    if point is not None:
        cell, _ = choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
        reachable = scene.grid.component(*cell)
    else:
        reachable = scene.grid.largest_component()
    image = render_preview(level, scene.grid.traversable, reachable, scene.grid.origin, start=cell, size=size)
    with atomic_path(png_path) as temporary:
        iio.imwrite(temporary, image, extension=".png")
    traversable = int(scene.grid.traversable.sum())
    rows, cols = scene.grid.shape
    click.echo(
        f"{level.name}: {rows} x {cols} cells, {traversable} traversable, {int(reachable.sum())} reachable, "
        f"{traversable - int(reachable.sum())} unreachable -> {png_path}"
    )


@main.command()
@click.argument("level_paths", metavar="LEVEL...", nargs=-1, required=True, type=click.Path(dir_okay=False))
@_limit_options
@_reports_errors
def validate(level_paths: tuple[str, ...], max_cells: int, max_vertices: int, max_file_bytes: int) -> None:
    """Report every problem in each LEVEL; exit 0 only if all are valid."""
    invalid = 0
    for path in level_paths:
        try:
            data = read_level_json(path, max_file_bytes=max_file_bytes)
        except GuardsimError as error:
            click.echo(str(error))
            invalid += 1
            continue
        level, problems = check_level_data(data, source=path, max_cells=max_cells, max_vertices=max_vertices)
        if level is not None:
            try:
                # Problems only the grid can find: a start cell where the guard does not fit.
                scene = Scene.from_level(level)
                for point in ([level.guard.start] if level.guard.start else []) + list(level.starts):
                    choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
            except GuardsimError as error:
                click.echo(str(error))
                invalid += 1
                continue
        for problem in problems:
            click.echo(f"{path}: {problem}")
        if problems:
            invalid += 1
        else:
            click.echo(f"{path}: ok")
    if invalid:
        click.echo(f"{invalid} of {len(level_paths)} level(s) invalid", err=True)
        sys.exit(2)


if __name__ == "__main__":  # pragma: no cover
    main()
