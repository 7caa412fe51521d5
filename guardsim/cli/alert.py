"""``guardsim alert``: guards that notice, chase, search and return, against an intruder.

The command checks its options, plans and runs the batch through :mod:`guardsim.alert.batch_run` and prints.
"""

from __future__ import annotations

import dataclasses
import io
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click

from guardsim.cli.common import (
    DetectionOverrides,
    EarsOverrides,
    FiniteFloatRange,
    build_scene,
    ears_options,
    level_options,
    load,
    parse_point,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.motion import alert_motion_options, check_motion, motion_of
from guardsim.cli.patrol import output_folder
from guardsim.cli.progress import PLAIN_EVERY_SECONDS, ProgressLine, StageLine, Throttle
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic

if TYPE_CHECKING:
    from guardsim.alert import AlertSummary
    from guardsim.alert.batch_run import AlertBatch, AlertBatchRun
    from guardsim.patrol import Patrol

__all__ = ["alert"]

_SEARCHES = ("ripple", "diffuse", "team", "last-known", "all")


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--patrol", "patrol_path", required=True, help="patrol.json (from guardsim patrol): the guards' routes.")
@click.option(
    "--intruder",
    type=click.Choice(["route", "sneak", "evader", "still"]),
    default="evader",
    show_default=True,
    help="How the intruder plays (docs/alert.md).",
)
@click.option(
    "--from",
    "source",
    callback=parse_point,
    metavar="X,Y",
    help="Where the intruder enters (world units) [one episode: default the level's first player start].",
)
@click.option("--to", "target", callback=parse_point, metavar="X,Y", help="Where the intruder is going.")
@click.option(
    "--route",
    "route_path",
    help='A route intruder\'s waypoints: JSON [[x, y], ...] of cell centres; a waypoint {"to": [x, y], "gait": '
    '"sneak"} sneaks there; an item {"throw": [x, y], "at": seconds, "noise": radius} is a distraction.',
)
@click.option(
    "--search",
    type=click.Choice(_SEARCHES),
    default="ripple",
    show_default=True,
    help="Search strategy once sight is lost; 'all' compares the four.",
)
@click.option(
    "--episodes",
    type=click.IntRange(min=1, max=100_000),
    help="Episodes whose entries, goals and patrol phases are drawn from --seed, one as any other number "
    "[default: one episode from --from (or the level's player start) at lap tick 0].",
)
@click.option(
    "--episode",
    type=click.IntRange(min=0, max=99_999),
    metavar="K",
    help="Run episode K of a batch seeded with --seed again, alone (its phase, entry and goal drawn as the "
    "batch draws them; an episode trace records K and the seed): for its --trace, --gif or --html.",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed for drawn starts.")
@click.option("--max-seconds", type=FiniteFloatRange(min=0, min_open=True, max=1e6), default=300.0, show_default=True)
@click.option(
    "--intruder-speed", type=FiniteFloatRange(min=0, max=1e6), help="World units per second [default: the guard's]."
)
@click.option(
    "--run-speed",
    type=FiniteFloatRange(min=0, min_open=True, max=1e6),
    help="World units per second an evader runs while chased [default: it walks at --intruder-speed].",
)
@ears_options
@click.option(
    "--spotted",
    is_flag=True,
    help="The intruder starts detected by the guards that see it (drawn entries: in some guard's view).",
)
@click.option("--out", "out_dir", type=click.Path(file_okay=False), help="Folder: a trace per episode and alert.json.")
@click.option("--trace", "trace_path", help="Write the (first) episode's trace as JSON.")
@click.option("--gif", "gif_path", help="Write the (first) episode as a GIF.")
@click.option(
    "--html", "html_path", help="Write the (first) episode as the interactive viewer page (states, meters, search)."
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    help="Local worker processes for --episodes [default: all cores]; 1 runs here.",
)
@click.option(
    "--scheduler",
    metavar="ADDRESS|local",
    help="Run --episodes on a dask.distributed scheduler, e.g. tcp://host:8786; 'local' starts a local "
    "cluster of --workers processes.",
)
@alert_motion_options
@level_options(detection=True)
def alert(
    level_path: str,
    map_import: MapImport,
    patrol_path: str,
    intruder: str,
    source: tuple[float, float] | None,
    target: tuple[float, float] | None,
    route_path: str | None,
    search: str,
    episodes: int | None,
    episode: int | None,
    seed: int,
    max_seconds: float,
    intruder_speed: float | None,
    run_speed: float | None,
    ears_overrides: EarsOverrides,
    spotted: bool,
    out_dir: str | None,
    trace_path: str | None,
    gif_path: str | None,
    html_path: str | None,
    workers: int | None,
    scheduler: str | None,
    motion: str,
    move_speed: float | None,
    turn_speed: float | None,
    tick_hz: float | None,
    detection_overrides: DetectionOverrides,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Play patrolling guards with awareness meters against an intruder: they notice, investigate,
    chase, search where it may have gone, give up and walk back onto their routes.

    One episode prints its outcome; with --episodes N (drawn entries, goals and patrol phases from
    --seed, the same for every strategy) a table per search strategy. --from/--to fix the entry and
    goal; a still intruder needs only --from. Episodes run on --workers local processes or a Dask
    --scheduler, with the same results wherever they run. With --out DIR, running the same command
    again resumes: episodes whose trace is in DIR are not run again (but the first, for --trace,
    --gif or --html). --episode K runs episode K of such a batch again, alone, exactly as the batch ran it.

    Exit status: 0 every episode ran; 1 some did not run (a worker was lost; with --out, run the same
    command again to resume); 2 bad input or an output that cannot be written.
    """
    from guardsim.alert.batch_run import alert_run_options, plan_alert_batch
    from guardsim.kernels.ahead import compile_ahead
    from guardsim.patrol import read_patrol

    _check_options(motion, los, move_speed, turn_speed, tick_hz, episode, episodes, out_dir, workers, scheduler)
    stage = StageLine(sys.stderr, "alert").start()
    level = detection_overrides.apply(load(level_path, max_cells, max_vertices, max_file_bytes, map_import))
    ears = {key: value for key, value in dataclasses.asdict(ears_overrides).items() if value is not None}
    level = ears_overrides.apply(level)
    compile_ahead("alert")
    scene = build_scene(level, los, fov, view_range)
    patrol = read_patrol(patrol_path, scene.grid, level=level.name)
    walking = motion_of(scene, move_speed, turn_speed, tick_hz) if motion == "continuous" else None
    stage("planning the episodes", 0, 0)
    batch = plan_alert_batch(
        scene, patrol, patrol_name=patrol_path, intruder=intruder, source=source, target=target, route_path=route_path,
        search=search, episodes=episodes, episode=episode, seed=seed, max_seconds=max_seconds,
        intruder_speed=intruder_speed, run_speed=run_speed, spotted=spotted, motion=walking, trace=out_dir is not None,
        say=click.echo,
    )  # fmt: skip
    folder = output_folder(out_dir) if out_dir is not None else None
    # Only a continuous run records its motion, so that grid runs made before it resume as they were.
    moving = {} if walking is None else {"motion": dataclasses.asdict(walking)}
    options = alert_run_options(batch, level_path, patrol_path, route_path, source, target, intruder=intruder,
                                episodes=batch.episodes, seed=seed, max_seconds=max_seconds, spotted=spotted,
                                **moving, **ears)  # fmt: skip
    # The options the first episode runs here for (its trace, GIF and page need the episode itself).
    here = ", ".join(name for name, path in (("--trace", trace_path), ("--gif", gif_path), ("--html", html_path))
                     if path is not None)  # fmt: skip
    stage("running the episodes", 0, 0)
    done = _run(batch, folder, options if folder is not None else None, here, workers, scheduler, stage)
    with StageLine(sys.stderr, "alert") as writing:
        writing("writing", 0, 0)
        written = _write(batch, done, folder, patrol, patrol_path, intruder, seed, trace_path, gif_path, html_path)
    if batch.episodes == 1:
        runs = done.runs(batch)
        for name, found in runs.items():
            prefix = f"{name}: " if len(runs) > 1 else ""
            if episode is not None:
                prefix += f"episode {episode} of seed {seed}: "
            click.echo(f"{level.name}: {prefix}{found[0].summary()}")
    else:
        click.echo(f"{level.name}: {batch.episodes} episodes, {intruder} intruder, seed {seed}")
        click.echo(_table(done.summaries(batch)))
    for name in written:
        click.echo(f"wrote {name}")


def _check_options(
    motion: str,
    los: str,
    move_speed: float | None,
    turn_speed: float | None,
    tick_hz: float | None,
    episode: int | None,
    episodes: int | None,
    out_dir: str | None,
    workers: int | None,
    scheduler: str | None,
) -> None:
    # Teams are fine here (each guard walks its own body): one guard is passed so that only the speeds are checked.
    check_motion(motion, 1, los, move_speed=move_speed, turn_speed=turn_speed, tick_hz=tick_hz)
    if episode is not None and (episodes is not None or out_dir is not None):
        raise GuardsimError(
            f"--episode {episode} runs one episode of a batch again: give it without --episodes and --out "
            "(write it with --trace, --gif or --html)"
        )
    if workers is not None and scheduler is not None and scheduler != "local":
        raise GuardsimError("--workers and --scheduler exclude each other: the scheduler's workers run the episodes")


def _run(
    batch: AlertBatch,
    folder: Path | None,
    options: dict[str, object] | None,
    here: str,
    workers: int | None,
    scheduler: str | None,
    stage: StageLine,
) -> AlertBatchRun:
    """Run the batch with a progress line (``stage`` until the workers start, then a count of episodes);
    say how to resume and exit when episodes were lost or the run was interrupted."""
    from guardsim.alert.batch_run import run_alert_batch
    from guardsim.cli.bench import NOT_RUN

    progress: list[ProgressLine] = []

    # On a terminal the count of episodes is redrawn in place; elsewhere the stage line keeps saying how
    # many are done every 2 s (an episode whose intruder plans a sneak path on a big map takes seconds).
    plain = not sys.stderr.isatty()
    running = "running the episodes"
    # A new count at most every 2 s: plain lines are drawn whenever the text changes.
    throttle = Throttle(PLAIN_EVERY_SECONDS)

    def starting(to_run: int, total: int, done_before: int, where: str) -> None:
        if plain:
            stage(running, 0, to_run)
        else:
            stage.close()
        chatty = total > 1
        if chatty:
            already = f" ({done_before} already done)" if done_before else ""
            where = f" on {where}"
            if here:
                where = f": the first here for {here}, {to_run}{where}"
            click.echo(f"running {(1 if here else 0) + to_run} of {total} episodes{where}{already}", err=True)
        progress.append(ProgressLine(to_run, sys.stderr if chatty else io.StringIO()))

    def advance() -> None:
        progress[0].advance(None)  # type: ignore[arg-type]  # it only counts
        if plain and throttle.due():
            stage(running, progress[0].done, progress[0].total)

    done = run_alert_batch(batch, folder=folder, options=options, here=bool(here), workers=workers,
                           scheduler=scheduler, starting=starting, advance=advance)  # fmt: skip
    stage.close()
    for line in progress:
        line.close()
    total = len(batch.tasks)
    resume = f"; traces in {folder}; run the same command again to resume" if folder is not None else ""
    if done.interrupted:
        click.echo(f"guardsim: interrupted; {len(done.outcomes)} of {total} episodes done{resume}", err=True)
        sys.exit(130)
    if done.lost:
        click.echo(f"guardsim: error: {done.lost} episodes did not run ({done.failure}){resume}", err=True)
        sys.exit(NOT_RUN)
    if not progress and folder is not None and total > 1:
        ran = f", the first run here for {here}" if here else ""
        already = "all" if done.done_before == total else f"{done.done_before} of"
        click.echo(f"{folder}: {already} {total} episodes already done{ran}", err=True)
    return done


def _write(
    batch: AlertBatch,
    done: AlertBatchRun,
    folder: Path | None,
    patrol: Patrol,
    patrol_path: str,
    intruder: str,
    seed: int,
    trace_path: str | None,
    gif_path: str | None,
    html_path: str | None,
) -> list[str]:
    """Write the first episode's trace, the folder's alert.json, the GIF and the page; the files written."""
    from guardsim.alert.batch import episode_trace
    from guardsim.alert.batch_run import write_alert_json

    written: list[str] = []
    first, suspicious = done.first, batch.detection.model.suspicious
    if first is not None and trace_path is not None:
        write_text_atomic(trace_path, episode_trace(first, batch.scene, batch.tasks[0]))
        written.append(trace_path)
    if folder is not None:
        written.append(str(write_alert_json(folder, batch, done, patrol=patrol_path, intruder=intruder, seed=seed)))
    if first is not None and gif_path is not None:
        from guardsim.render.alert import write_alert_gif

        write_alert_gif(gif_path, batch.scene, batch.table, first, suspicious=suspicious)
        written.append(gif_path)
    if first is not None and html_path is not None:
        from guardsim.viewer.alerts import write_alert_page

        write_alert_page(html_path, batch.scene, batch.table, first, patrol=patrol, suspicious=suspicious)
        written.append(html_path)
    return written


def _table(rows: list[AlertSummary]) -> str:
    head = "| search | detected | captured | capture rate (of detected) | to capture (s) | searching (s) | re-acquire (s) | back on route (s) | detections |"
    lines = [head, "|" + " --- |" * 9]

    def fmt(value: float | None) -> str:
        return "-" if value is None else f"{value:g}"

    for row in rows:
        lines.append(
            f"| {row.search} | {row.detected}/{row.episodes} | {row.captured} | {row.capture_rate:.2f} | "
            f"{fmt(row.time_to_capture)} | {fmt(row.searching)} | {fmt(row.reacquire)} | {fmt(row.back_on_route)} | "
            f"{fmt(row.detections)} |"
        )
    return "\n".join(lines)
