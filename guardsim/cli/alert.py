"""``guardsim alert``: guards that notice, chase, search and return, against an intruder."""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import io
import itertools
import json
import logging
import os
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from guardsim.alert.intruders import read_route_points
from guardsim.cli.common import (
    FiniteFloatRange,
    build_scene,
    detection_options,
    limit_options,
    load,
    parse_point,
    reports_errors,
    vision_options,
    with_detection,
)
from guardsim.cli.map_options import MapImport, map_options
from guardsim.cli.motion import _SPEED_HELP, _speed_options, check_motion, motion_of
from guardsim.cli.patrol import output_folder
from guardsim.cli.sneak import sneak_cell
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.motion.parameters import MOTIONS

if TYPE_CHECKING:
    from guardsim.alert import AlertEpisode, AlertOutcome, AlertRules, AlertSummary
    from guardsim.alert.batch import AlertTask
    from guardsim.detection import GuardDetection
    from guardsim.scene import Scene
    from guardsim.vision.table import ViewTable

__all__ = ["alert"]

F = TypeVar("F", bound=Callable[..., Any])

_SEARCHES = ("ripple", "diffuse", "team", "last-known", "all")


def _motion_options(command: F) -> F:
    """--motion and the guard's speeds (``play``'s and ``bench``'s; alert has its own --max-seconds)."""
    # The speeds' options and help are play's (guardsim.cli.motion), so the three commands agree.
    command = _speed_options(command, _SPEED_HELP)
    return click.option(
        "--motion",
        type=click.Choice(MOTIONS),
        default="grid",
        show_default=True,
        help="grid: a cell per tick, turning free; continuous: each guard a physics body walking its decisions "
        "at game speeds and looking from its pose every physics tick (docs/alert.md).",
    )(command)


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
@click.option("--route", "route_path", help="A route intruder's waypoints: JSON [[x, y], ...] of cell centres.")
@click.option(
    "--search",
    type=click.Choice(_SEARCHES),
    default="ripple",
    show_default=True,
    help="Search strategy once sight is lost; 'all' compares the four.",
)
@click.option("--episodes", type=click.IntRange(min=1, max=100_000), default=1, show_default=True)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed for drawn starts.")
@click.option("--max-seconds", type=FiniteFloatRange(min=0, min_open=True, max=1e6), default=300.0, show_default=True)
@click.option(
    "--intruder-speed", type=FiniteFloatRange(min=0, max=1e6), help="World units per second [default: the guard's]."
)
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
@_motion_options
@detection_options
@vision_options
@map_options
@limit_options
@reports_errors
def alert(
    level_path: str,
    map_import: MapImport,
    patrol_path: str,
    intruder: str,
    source: tuple[float, float] | None,
    target: tuple[float, float] | None,
    route_path: str | None,
    search: str,
    episodes: int,
    seed: int,
    max_seconds: float,
    intruder_speed: float | None,
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
    detect_near: float | None,
    detect_far: float | None,
    forget: float | None,
    suspicious: float | None,
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
    --gif or --html).

    Exit status: 0 every episode ran; 1 some did not run (a worker was lost; with --out, run the same
    command again to resume); 2 bad input or an output that cannot be written.
    """
    from guardsim.alert import SEARCHES, AlertRules, summarise
    from guardsim.alert.batch import done_outcome, remember_setup, tasks_of, trace_name
    from guardsim.alert.run import plan_starts
    from guardsim.detection import GuardDetection
    from guardsim.experiment.results import RUN_NAME, check_run_options
    from guardsim.patrol import read_patrol
    from guardsim.vision.table import view_table

    # Teams are fine here (each guard walks its own body): one guard is passed so that only the speeds are checked.
    check_motion(motion, 1, los, move_speed=move_speed, turn_speed=turn_speed, tick_hz=tick_hz)
    if workers is not None and scheduler is not None and scheduler != "local":
        raise GuardsimError("--workers and --scheduler exclude each other: the scheduler's workers run the episodes")
    level = with_detection(
        load(level_path, max_cells, max_vertices, max_file_bytes, map_import),
        detect_near=detect_near,
        detect_far=detect_far,
        forget=forget,
        suspicious=suspicious,
    )
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead("alert")
    scene = build_scene(level, los, fov, view_range)
    grid = scene.grid
    patrol = read_patrol(patrol_path, grid, level=level.name)
    if patrol.motion != "grid" or patrol.period is None:
        raise GuardsimError(f"{patrol_path}: alert needs a repeating grid-motion patrol (from guardsim patrol)")
    searches = list(SEARCHES) if search == "all" else [search]
    rules = AlertRules.of_level(level, intruder_speed=intruder_speed)
    detection = GuardDetection(GuardDetection.of_level(level).model, scene.cone.view_range, rules.dt)
    walking = motion_of(scene, move_speed, turn_speed, tick_hz) if motion == "continuous" else None
    start = sneak_cell(grid, source, "--from") if source is not None else None
    goal = sneak_cell(grid, target, "--to") if target is not None else None
    route = None
    if route_path is not None:
        if intruder != "route":
            raise GuardsimError("--route is the path of a route intruder: give --intruder route")
        points = read_route_points(route_path)
        route = [sneak_cell(grid, point, f"{route_path}: point") for point in points]
        for index, (before, after) in enumerate(itertools.pairwise(route)):
            if after != before and after not in grid.neighbours[before].tolist():
                raise GuardsimError(f"{route_path}: point {index + 1} is not a 4-neighbour of point {index}")
        start, goal = route[0], route[-1]
    if episodes == 1 and start is None and level.player_starts:
        # One episode enters where the level says the player starts (many draw their entries from --seed).
        source = level.player_starts[0]
        start = sneak_cell(grid, source, "the level's player start")
        click.echo(f"from the level's player start ({source[0]:g}, {source[1]:g})")
    if episodes == 1 and start is None:
        raise GuardsimError("one episode needs --from X,Y (and --to X,Y unless the intruder is still)")
    if start is not None and goal is not None and grid.component_labels[start] != grid.component_labels[goal]:
        raise GuardsimError("--to cannot be reached from --from")
    if intruder != "still" and start is not None and goal is None and route is None:
        raise GuardsimError(f"a {intruder} intruder needs --to X,Y (or --route)")
    table = view_table(grid, scene.vision())
    if episodes == 1 and intruder == "still" and goal is None:
        goal = -1
    # One episode starts at lap tick 0; many draw their phases (and any entry or goal not given) from --seed.
    starts = plan_starts(
        scene, patrol, episodes=episodes, seed=seed, source=start, target=goal, spotted=spotted,
        phase=0 if episodes == 1 else None, table=table,
    )  # fmt: skip
    tasks = tasks_of(
        scene.level, scene.rule.value, patrol, starts, searches=searches, intruder=intruder, route=route,
        max_seconds=max_seconds, rules=rules, detection=detection, spotted=spotted, trace=out_dir is not None,
        motion=walking,
    )  # fmt: skip
    folder = output_folder(out_dir) if out_dir is not None else None
    outcomes: dict[tuple[str, int], AlertOutcome] = {}
    if folder is not None:
        resuming = (folder / RUN_NAME).exists()
        # Only a continuous run records its motion, so that grid runs made before it resume as they were.
        moving = {} if walking is None else {"motion": dataclasses.asdict(walking)}
        options = _run_options(level_path, patrol_path, route_path, source, target, searches, scene, rules, detection,
                               intruder=intruder, episodes=episodes, seed=seed, max_seconds=max_seconds, spotted=spotted,
                               **moving)  # fmt: skip
        check_run_options(folder, options)
        if resuming:
            for task in tasks:
                kept = done_outcome(folder, task)
                if kept is not None:
                    outcomes[task.key] = kept
    written: list[str] = []
    first = None
    # The options the first episode runs here for (its trace, GIF and page need the episode itself): it
    # runs even when a resumed folder holds its trace, and is counted as run, not as already done.
    here = ", ".join(name for name, path in (("--trace", trace_path), ("--gif", gif_path), ("--html", html_path))
                     if path is not None)  # fmt: skip
    if here:
        first = _run_first(scene, table, tasks[0])
        if folder is not None:
            write_text_atomic(folder / trace_name(*tasks[0].key), _trace(first, scene, tasks[0]))
        outcomes.pop(tasks[0].key, None)
    done_before = len(outcomes)
    if first is not None:
        outcomes[tasks[0].key] = first.result()
    pending = [task for task in tasks if task.key not in outcomes]
    if pending:
        remember_setup(scene, table)
        _run_pending(pending, outcomes, folder, done_before=done_before, first_here=here, workers=workers,
                     scheduler=scheduler)  # fmt: skip
    elif folder is not None and len(tasks) > 1:
        ran = f", the first run here for {here}" if here else ""
        already = "all" if done_before == len(tasks) else f"{done_before} of"
        click.echo(f"{folder}: {already} {len(tasks)} episodes already done{ran}", err=True)
    runs = {name: [outcomes[(name, index)] for index in range(episodes)] for name in searches}
    rows = [summarise(name, found) for name, found in runs.items()]
    if first is not None and trace_path is not None:
        write_text_atomic(trace_path, _trace(first, scene, tasks[0]))
        written.append(trace_path)
    if folder is not None:
        summary = {
            "level": level.name,
            "patrol": patrol_path,
            "intruder": intruder,
            "episodes": episodes,
            "seed": seed,
            "summary": [row._asdict() for row in rows],
            "outcomes": {name: [o._asdict() for o in found] for name, found in runs.items()},
        }
        write_text_atomic(folder / "alert.json", json.dumps(summary, indent=1) + "\n")
        written.append(str(folder / "alert.json"))
    if first is not None and gif_path is not None:
        from guardsim.alert.gif import write_alert_gif

        write_alert_gif(gif_path, scene, table, first, suspicious=detection.model.suspicious)
        written.append(gif_path)
    if first is not None and html_path is not None:
        from guardsim.viewer.alerts import write_alert_page

        write_alert_page(html_path, scene, table, first, patrol=patrol, suspicious=detection.model.suspicious)
        written.append(html_path)
    if episodes == 1:
        for name, found in runs.items():
            prefix = f"{name}: " if len(runs) > 1 else ""
            click.echo(f"{level.name}: {prefix}{found[0].summary()}")
    else:
        click.echo(f"{level.name}: {episodes} episodes, {intruder} intruder, seed {seed}")
        click.echo(_table(rows))
    for name in written:
        click.echo(f"wrote {name}")


def _run_first(scene: Scene, table: ViewTable, task: AlertTask) -> AlertEpisode:
    from guardsim.alert import alert_episode

    episode = alert_episode(
        scene, task.patrol, intruder=task.intruder, source=task.source, target=task.target, route=task.route,
        search=task.search, phase=task.phase, max_seconds=task.max_seconds, table=table, rules=task.rules,
        detection=task.detection, spotted=task.spotted, motion=task.motion or "grid",
    )  # fmt: skip
    episode.run()
    return episode


def _trace(episode: AlertEpisode, scene: Scene, task: AlertTask) -> str:
    from guardsim.alert import alert_trace_data
    from guardsim.alert.batch import trace_text

    return trace_text(alert_trace_data(episode, scene, search=task.search, intruder=task.intruder))


def _digest(path: str) -> str:
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as error:
        raise GuardsimError(f"{path}: cannot read it: {error.strerror or error}") from None


def _run_options(
    level_path: str,
    patrol_path: str,
    route_path: str | None,
    source: tuple[float, float] | None,
    target: tuple[float, float] | None,
    searches: list[str],
    scene: Scene,
    rules: AlertRules,
    detection: GuardDetection,
    **given: object,
) -> dict[str, object]:
    """What decides the episodes' results, as recorded in the output folder's ``run.json``: a run with
    other options is not resumed there."""
    return {
        "command": "guardsim alert",
        "level": {"file": os.path.normpath(level_path), "sha256": _digest(level_path)},
        "patrol": {"file": os.path.normpath(patrol_path), "sha256": _digest(patrol_path)},
        "route": None if route_path is None else {"file": os.path.normpath(route_path), "sha256": _digest(route_path)},
        "from": None if source is None else list(source),
        "to": None if target is None else list(target),
        "searches": searches,
        **given,
        "los": scene.rule.value,
        "fov": scene.cone.fov_degrees,
        "view_range": scene.cone.view_range,
        "rules": dataclasses.asdict(rules),
        "detection": {**dataclasses.asdict(detection.model), "view_range": detection.view_range, "dt": detection.dt},
    }


def _run_pending(
    pending: list[AlertTask],
    outcomes: dict[tuple[str, int], AlertOutcome],
    folder: Path | None,
    *,
    done_before: int,
    first_here: str,
    workers: int | None,
    scheduler: str | None,
) -> None:
    """Run ``pending`` on the executor ``--workers``/``--scheduler`` ask for (:func:`guardsim.experiment.executors.make_executor`,
    as ``guardsim bench``), filling ``outcomes`` and writing each trace into ``folder`` as it comes back.
    ``done_before`` episodes were found done in ``folder``; ``first_here`` names the options the first
    episode ran for in this process (empty: it did not). On Ctrl-C or lost episodes, say how to resume
    and exit."""
    from guardsim.alert.batch import run_alert_task, trace_name
    from guardsim.cli.bench import NOT_RUN, ProgressLine
    from guardsim.experiment.executors import make_executor

    ran_here = 1 if first_here else 0
    total = done_before + ran_here + len(pending)
    with contextlib.ExitStack() as stack:
        if scheduler == "local":
            scheduler = stack.enter_context(_local_cluster(workers))
            workers = None
        if scheduler is None:
            # More processes than episodes would only cost start-up time.
            workers = min(workers or os.cpu_count() or 1, len(pending))
        executor = make_executor(workers, scheduler, preload=[run_alert_task.__module__])
        chatty = total > 1
        if chatty:
            already = f" ({done_before} already done)" if done_before else ""
            where = f" on {executor.description}"
            if first_here:
                where = f": the first here for {first_here}, {len(pending)}{where}"
            click.echo(f"running {ran_here + len(pending)} of {total} episodes{where}{already}", err=True)
        progress = ProgressLine(len(pending), sys.stderr if chatty else io.StringIO())
        resume = f"; traces in {folder}; run the same command again to resume" if folder is not None else ""
        lost = 0
        failure = ""
        try:
            with executor:
                for done in executor.run_unordered(run_alert_task, pending):
                    if done.failure is not None:
                        lost += 1
                        failure = failure or (f"{type(done.failure).__name__}: {done.failure}".splitlines() or [""])[0]
                        continue
                    task, result = done.item, done.result
                    if folder is not None and result.trace is not None:
                        write_text_atomic(folder / trace_name(*task.key), result.trace)
                    outcomes[task.key] = result.outcome
                    progress.advance(None)  # type: ignore[arg-type]  # it only counts
        except KeyboardInterrupt:
            progress.close()
            click.echo(f"guardsim: interrupted; {len(outcomes)} of {total} episodes done{resume}", err=True)
            sys.exit(130)
        finally:
            progress.close()
    if lost:
        click.echo(f"guardsim: error: {lost} episodes did not run ({failure}){resume}", err=True)
        sys.exit(NOT_RUN)


@contextlib.contextmanager
def _local_cluster(workers: int | None) -> Iterator[str]:
    """A ``distributed.LocalCluster`` of ``workers`` processes (default: the cores), one thread each, for
    ``--scheduler local``; yields its address."""
    try:
        from distributed import LocalCluster
    except ImportError:
        raise GuardsimError(
            "--scheduler local needs dask.distributed, which is not installed: pip install 'guardsim[cluster]'"
        ) from None
    count = workers or os.cpu_count() or 1
    with LocalCluster(
        n_workers=count, processes=True, threads_per_worker=1, dashboard_address=None, silence_logs=logging.ERROR
    ) as cluster:
        yield cluster.scheduler_address


def _table(rows: list[AlertSummary]) -> str:
    head = "| search | detected | captured | capture rate | to capture (s) | searching (s) | re-acquire (s) | back on route (s) | detections |"
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
