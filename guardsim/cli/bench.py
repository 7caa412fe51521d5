"""``guardsim bench``: the paper's evaluation, many episodes per level, on local cores or a Dask cluster."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import click

from guardsim.cli.common import build_scene, level_options, load, vision_options
from guardsim.cli.map_options import MapImport
from guardsim.cli.motion import check_motion, motion_options
from guardsim.cli.progress import ProgressLine
from guardsim.errors import GuardsimError
from guardsim.experiment import (
    ERRORS_NAME,
    RESULTS_NAME,
    SUMMARY_NAME,
    Batch,
    BatchLevel,
    EpisodeRecord,
    EpisodeSpec,
    GroupSummary,
    finish_batch,
    format_table,
    read_results,
    run_batch,
    run_spec,
    start_batch,
)
from guardsim.experiment.executors import make_executor
from guardsim.planners import PLANNERS

__all__ = ["bench"]

#: Exit status when episodes did not run (a worker died, the cluster was lost): resume to run them.
NOT_RUN = 1
#: Exit status when some episode raised an error: its row says ``error``, its traceback is in
#: ``errors.log``, and running the same command again retries it.
EPISODE_ERRORS = 3

#: Upper bounds of the counts a command line may ask for: past them the plan alone would not fit in memory
#: (a batch of 10^400 episodes was a list the kernel killed the process for).
MAX_EPISODES = 1_000_000
MAX_GUARDS = 10_000
MAX_STEPS = 10**9

#: Figure files written by --plot, in the output folder.
PLOT_NAMES = ("steps.png", "steps.svg")


@click.command()
@click.argument("level_paths", metavar="LEVEL...", nargs=-1, required=True)
@click.option(
    "--episodes",
    type=click.IntRange(min=1, max=MAX_EPISODES),
    default=200,
    show_default=True,
    help="Episodes per level and planner.",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed of the batch.")
@click.option("--out", "out", type=click.Path(), default="results", show_default=True, help="Output folder.")
@click.option(
    "--planner",
    "planner_list",
    default="ripplefront",
    show_default=True,
    metavar="NAME[,NAME...]",
    help=f"Planners to compare, comma-separated; known: {', '.join(PLANNERS)}.",
)
@click.option(
    "--reference",
    is_flag=True,
    help="Run the reference vision and loop instead of the fast path (for checking it; much slower).",
)
@click.option(
    "--max-steps", type=click.IntRange(min=0, max=MAX_STEPS), help="Step limit [default: 10 per traversable cell]."
)
@click.option(
    "--guards",
    type=click.IntRange(min=1, max=MAX_GUARDS),
    default=1,
    show_default=True,
    help="Guards per team, each running the planner; steps are then the makespan.",
)
@vision_options
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes [default: all cores]; 1 runs here.")
@click.option("--scheduler", metavar="ADDRESS", help="Run on a dask.distributed scheduler, e.g. tcp://host:8786.")
@click.option("--plot", is_flag=True, help="Also draw steps.png and steps.svg: a box plot of steps per level.")
@click.option(
    "--bounds/--no-bounds",
    default=True,
    show_default=True,
    help="Compute each one-guard start's lower bounds (about 1-2 ms a start on a 60x60 level, plus the level's view table, built by one worker per level).",
)
@motion_options
@level_options(vision=False)
def bench(
    level_paths: tuple[str, ...],
    episodes: int,
    seed: int,
    out: str,
    planner_list: str,
    reference: bool,
    max_steps: int | None,
    guards: int,
    los: str,
    fov: float | None,
    view_range: float | None,
    workers: int | None,
    scheduler: str | None,
    plot: bool,
    bounds: bool,
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
    """Run --episodes episodes of each planner on each LEVEL and summarise the steps they took.

    Episode K starts from a cell drawn uniformly from the largest connected area, with a random first
    heading, both drawn from episode K's own generator; `guardsim play LEVEL --seed S --episode K`
    re-runs it alone. With --guards K, the other guards' starts follow from the same generator. For one
    guard, each row also gets the lower bounds on the steps from its start (see docs/bounds.md).
    Writes OUT/results.csv (one row per episode, appended as they finish), OUT/summary.json and, with
    --plot, OUT/steps.png and OUT/steps.svg; prints the summary table. Running the same command again
    resumes: episodes already in results.csv are skipped, and episodes that raised an error run again.

    Exit status: 0 every episode ran; 1 some did not run (resume to run them); 2 bad input or an output
    that cannot be written; 3 some episode raised an error (its traceback is in OUT/errors.log).
    """
    planners = parse_planners(planner_list)
    check_motion(
        motion, guards, los, move_speed=move_speed, turn_speed=turn_speed, tick_hz=tick_hz, max_seconds=max_seconds
    )
    if workers is not None and scheduler is not None:
        raise GuardsimError("--workers and --scheduler exclude each other: the scheduler's workers run the episodes")
    if plot:
        from guardsim.render.plots import require_matplotlib

        require_matplotlib()
    limits = {"max_cells": max_cells, "max_vertices": max_vertices, "max_file_bytes": max_file_bytes}
    levels = tuple(
        with_vision(BatchLevel.load(path, level=load(path, **limits, map_import=map_import)), los, fov, view_range)
        for path in level_paths
    )
    batch = Batch(levels, planners, episodes, seed, max_steps, reference, guards, los, fov, view_range, bounds,
                  motion, move_speed, turn_speed, tick_hz, max_seconds)  # fmt: skip
    folder = Path(out)
    done, pending = start_batch(batch, folder)
    total = len(done) + len(pending)
    began = time.perf_counter()
    if pending:
        from guardsim.kernels.ahead import compile_ahead

        compile_ahead("bench")
        run_pending(folder, pending, done_before=len(done), workers=workers, scheduler=scheduler)
    else:
        click.echo(f"{folder}: all {total} episodes already done", err=True)
    records, groups = finish_batch(batch, folder)
    written = [folder / RESULTS_NAME, folder / SUMMARY_NAME]
    if plot:
        written += draw_plot(batch, folder, records, groups)
    click.echo(format_table(groups))
    seconds = time.perf_counter() - began
    files = ", ".join(str(path) for path in written)
    click.echo(f"{len(pending)} of {total} episodes run in {seconds:.1f} s -> {files}", err=True)
    errors = sum(group.outcomes["error"] for group in groups)
    if errors:
        click.echo(
            f"guardsim: error: {errors} episodes raised an error; tracebacks in {folder / ERRORS_NAME}; "
            "run the same command again to retry them",
            err=True,
        )
        sys.exit(EPISODE_ERRORS)


def with_vision(level: BatchLevel, los: str, fov: float | None, view_range: float | None) -> BatchLevel:
    """The level with its guard changed by --los, --fov and --view-range, exactly as ``guardsim play``
    changes it (:func:`~guardsim.cli.common.build_scene`); the workers build their own scenes."""
    if los == "pymunk" and fov is None and view_range is None:
        return level
    return level._replace(level=build_scene(level.level, los, fov, view_range).level)


def parse_planners(text: str) -> tuple[str, ...]:
    """``a,b`` into planner names, each checked against :data:`~guardsim.planners.PLANNERS`."""
    names = tuple(dict.fromkeys(name.strip() for name in text.split(",")))
    for name in names:
        if name not in PLANNERS:
            raise GuardsimError(f"--planner: unknown planner {name!r}; known: {', '.join(PLANNERS)}")
    return names


def run_pending(
    folder: Path, pending: list[EpisodeSpec], *, done_before: int, workers: int | None, scheduler: str | None
) -> None:
    """Run the episodes not done yet; on Ctrl-C or lost workers, say how to resume and exit."""
    total = done_before + len(pending)
    if scheduler is None:
        # More processes than episodes would only cost start-up time.
        workers = min(workers or os.cpu_count() or 1, len(pending))
    executor = make_executor(workers, scheduler, preload=[run_spec.__module__])
    already = f" ({done_before} already done)" if done_before else ""
    click.echo(f"{folder}: running {len(pending)} of {total} episodes on {executor.description}{already}", err=True)
    progress = ProgressLine(len(pending), sys.stderr)
    resume = f"{folder / RESULTS_NAME}; run the same command again to resume"
    try:
        with executor:
            report = run_batch(pending, folder, executor, progress.advance)
    except KeyboardInterrupt:
        progress.close()
        # Counted from the file: Ctrl-C can land between a row's write and its count in the progress line.
        kept = len(read_results(folder / RESULTS_NAME))
        click.echo(f"guardsim: interrupted; {kept} of {total} episodes are in {resume}", err=True)
        sys.exit(130)
    finally:
        progress.close()
    if report.not_run:
        click.echo(
            f"guardsim: error: {report.not_run} episodes did not run ({report.failure}); "
            f"{done_before + progress.done} of {total} are in {resume}",
            err=True,
        )
        sys.exit(NOT_RUN)


def draw_plot(batch: Batch, folder: Path, records: list[EpisodeRecord], groups: list[GroupSummary]) -> list[Path]:
    """Write the box plot of steps per level and planner; returns the files written."""
    from guardsim.render.plots import StepsBox, plot_steps

    boxes = [
        StepsBox(
            group.level,
            group.planner,
            [r.steps for r in records if (r.level_file, r.planner) == (group.level_file, group.planner) and r.steps is not None],
        )
        for group in groups
    ]  # fmt: skip
    targets = [folder / name for name in PLOT_NAMES]
    what = f"Makespan of {batch.guards} guards" if batch.guards > 1 else "Steps to cover"
    plot_steps(
        boxes,
        targets,
        title=f"{what}, {batch.episodes} episodes per box (seed {batch.seed})",
        ylabel="makespan (steps)" if batch.guards > 1 else "steps to cover",
    )
    return targets
