"""``guardsim alert``: guards that notice, chase, search and return, against an intruder.

The command checks its options, builds the episodes and prints; :mod:`guardsim.cli.alert_batch` runs them.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import click

from guardsim.alert.intruders import read_route_file
from guardsim.cli.alert_batch import episode_trace, run_first, run_options, run_pending
from guardsim.cli.common import (
    DetectionOverrides,
    EarsOverrides,
    FiniteFloatRange,
    build_scene,
    detection_options,
    ears_options,
    limit_options,
    load,
    parse_point,
    reports_errors,
    vision_options,
)
from guardsim.cli.map_options import MapImport, map_options
from guardsim.cli.motion import _SPEED_HELP, _speed_options, check_motion, motion_of
from guardsim.cli.patrol import output_folder
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.motion.parameters import MOTIONS

if TYPE_CHECKING:
    from guardsim.alert import AlertOutcome, AlertSummary

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
    from guardsim.alert import SEARCHES, AlertRules, summarise
    from guardsim.alert.batch import done_outcome, remember_setup, tasks_of, trace_name
    from guardsim.alert.run import plan_starts
    from guardsim.detection import GuardDetection
    from guardsim.experiment.results import RUN_NAME, check_run_options
    from guardsim.patrol import read_patrol
    from guardsim.vision.table import view_table

    # Teams are fine here (each guard walks its own body): one guard is passed so that only the speeds are checked.
    check_motion(motion, 1, los, move_speed=move_speed, turn_speed=turn_speed, tick_hz=tick_hz)
    if episode is not None and (episodes is not None or out_dir is not None):
        raise GuardsimError(
            f"--episode {episode} runs one episode of a batch again: give it without --episodes and --out "
            "(write it with --trace, --gif or --html)"
        )
    if workers is not None and scheduler is not None and scheduler != "local":
        raise GuardsimError("--workers and --scheduler exclude each other: the scheduler's workers run the episodes")
    level = detection_overrides.apply(load(level_path, max_cells, max_vertices, max_file_bytes, map_import))
    ears = {key: value for key, value in dataclasses.asdict(ears_overrides).items() if value is not None}
    level = ears_overrides.apply(level)
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead("alert")
    scene = build_scene(level, los, fov, view_range)
    grid = scene.grid
    patrol = read_patrol(patrol_path, grid, level=level.name)
    if patrol.motion != "grid" or patrol.period is None:
        raise GuardsimError(f"{patrol_path}: alert needs a repeating grid-motion patrol (from guardsim patrol)")
    searches = list(SEARCHES) if search == "all" else [search]
    rules = AlertRules.of_level(level, intruder_speed=intruder_speed, run_speed=run_speed)
    detection = GuardDetection(GuardDetection.of_level(level).model, scene.cone.view_range, rules.dt)
    walking = motion_of(scene, move_speed, turn_speed, tick_hz) if motion == "continuous" else None
    start = grid.floor_cell(source, "--from") if source is not None else None
    goal = grid.floor_cell(target, "--to") if target is not None else None
    route = gaits = None
    distractions: list[tuple[int, int, float]] = []
    if route_path is not None:
        if intruder != "route":
            raise GuardsimError("--route is the path of a route intruder: give --intruder route")
        route_file = read_route_file(route_path, sneak_ticks=level.intruder.sneak_ticks)
        points, gaits = route_file.points, route_file.gaits
        route = [grid.floor_cell(point, f"{route_path}: point") for point in points]
        for throw in route_file.distractions:
            cell = grid.floor_cell(throw.point, f"{route_path}: throw")
            distractions.append((round(throw.seconds / rules.dt), cell, throw.noise))
        for index, (before, after) in enumerate(itertools.pairwise(route)):
            if after != before and after not in grid.neighbours[before].tolist():
                raise GuardsimError(f"{route_path}: point {index + 1} is not a 4-neighbour of point {index}")
        start, goal = route[0], route[-1]
    # Without --episodes and --episode, one episode at the given entry and lap tick 0; a batch, even of one
    # episode (and a rerun episode of one), draws what it is not given from the seed.
    alone = episodes is None and episode is None
    episodes = 1 if episodes is None else episodes
    if alone and start is None and level.player_starts:
        # One episode enters where the level says the player starts (many draw their entries from --seed).
        source = level.player_starts[0]
        start = grid.floor_cell(source, "the level's player start")
        click.echo(f"from the level's player start ({source[0]:g}, {source[1]:g})")
    if alone and start is None:
        raise GuardsimError("one episode needs --from X,Y (and --to X,Y unless the intruder is still)")
    if start is not None and goal is not None and grid.component_labels[start] != grid.component_labels[goal]:
        raise GuardsimError("--to cannot be reached from --from")
    if intruder != "still" and start is not None and goal is None and route is None:
        raise GuardsimError(f"a {intruder} intruder needs --to X,Y (or --route)")
    table = view_table(grid, scene.vision())
    if alone and intruder == "still" and goal is None:
        goal = -1
    # One episode starts at lap tick 0; many draw their phases (and any entry or goal not given) from --seed.
    # Episode K's start is the K-th drawn from the seed's one generator, however many follow it.
    first_index = 0 if episode is None else episode
    starts = plan_starts(
        scene, patrol, episodes=first_index + episodes, seed=seed, source=start, target=goal, spotted=spotted,
        phase=0 if alone else None, table=table,
    )[first_index:]  # fmt: skip
    tasks = tasks_of(
        scene.level, scene.rule.value, patrol, starts, searches=searches, intruder=intruder, route=route,
        max_seconds=max_seconds, rules=rules, detection=detection, spotted=spotted, trace=out_dir is not None,
        motion=walking, gaits=gaits, distractions=distractions, seed=None if alone else seed, first=first_index,
    )  # fmt: skip
    folder = output_folder(out_dir) if out_dir is not None else None
    outcomes: dict[tuple[str, int], AlertOutcome] = {}
    if folder is not None:
        resuming = (folder / RUN_NAME).exists()
        # Only a continuous run records its motion, so that grid runs made before it resume as they were.
        moving = {} if walking is None else {"motion": dataclasses.asdict(walking)}
        options = run_options(level_path, patrol_path, route_path, source, target, searches, scene, rules, detection,
                              intruder=intruder, episodes=episodes, seed=seed, max_seconds=max_seconds, spotted=spotted,
                              **moving, **ears)  # fmt: skip
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
        first = run_first(scene, table, tasks[0])
        if folder is not None:
            write_text_atomic(folder / trace_name(*tasks[0].key), episode_trace(first, scene, tasks[0]))
        outcomes.pop(tasks[0].key, None)
    done_before = len(outcomes)
    if first is not None:
        outcomes[tasks[0].key] = first.result()
    pending = [task for task in tasks if task.key not in outcomes]
    if pending:
        remember_setup(scene, table)
        run_pending(pending, outcomes, folder, done_before=done_before, first_here=here, workers=workers,
                    scheduler=scheduler)  # fmt: skip
    elif folder is not None and len(tasks) > 1:
        ran = f", the first run here for {here}" if here else ""
        already = "all" if done_before == len(tasks) else f"{done_before} of"
        click.echo(f"{folder}: {already} {len(tasks)} episodes already done{ran}", err=True)
    runs = {name: [outcomes[(name, first_index + index)] for index in range(episodes)] for name in searches}
    rows = [summarise(name, found) for name, found in runs.items()]
    if first is not None and trace_path is not None:
        write_text_atomic(trace_path, episode_trace(first, scene, tasks[0]))
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
        from guardsim.render.alert import write_alert_gif

        write_alert_gif(gif_path, scene, table, first, suspicious=detection.model.suspicious)
        written.append(gif_path)
    if first is not None and html_path is not None:
        from guardsim.viewer.alerts import write_alert_page

        write_alert_page(html_path, scene, table, first, patrol=patrol, suspicious=detection.model.suspicious)
        written.append(html_path)
    if episodes == 1:
        for name, found in runs.items():
            prefix = f"{name}: " if len(runs) > 1 else ""
            if episode is not None:
                prefix += f"episode {episode} of seed {seed}: "
            click.echo(f"{level.name}: {prefix}{found[0].summary()}")
    else:
        click.echo(f"{level.name}: {episodes} episodes, {intruder} intruder, seed {seed}")
        click.echo(_table(rows))
    for name in written:
        click.echo(f"wrote {name}")


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
