"""``guardsim alert``: guards that notice, chase, search and return, against an intruder."""

from __future__ import annotations

import itertools
import json
import math
from typing import TYPE_CHECKING

import click

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
from guardsim.cli.patrol import output_folder
from guardsim.cli.sneak import sneak_cell
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic

if TYPE_CHECKING:
    from guardsim.alert import AlertSummary

__all__ = ["alert"]

_SEARCHES = ("ripple", "diffuse", "team", "last-known", "all")


def _route_file(path: str, grid_cell: object) -> list[tuple[float, float]]:
    """Waypoints of ``--route``: a JSON list of ``[x, y]`` world points, or a sneak.json (its ``path``)."""
    from guardsim.files.reading import read_json_file

    data = read_json_file(path, max_file_bytes=16 * 2**20, kind="route file", error=GuardsimError)
    points = data.get("path") if isinstance(data, dict) else data
    if isinstance(points, dict):
        points = points.get("positions") or points.get("cells")
    if not isinstance(points, list) or not points:
        raise GuardsimError(f"{path}: a route file is a list of [x, y] points (or a sneak.json with a path)")
    out = []
    for index, point in enumerate(points):
        if not (
            isinstance(point, list)
            and len(point) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in point)
        ):
            raise GuardsimError(f"{path}: point {index}: not an [x, y] pair of finite numbers")
        out.append((float(point[0]), float(point[1])))
    return out


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
@click.option("--from", "source", callback=parse_point, metavar="X,Y", help="Where the intruder enters (world units).")
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
@detection_options
@vision_options
@limit_options
@reports_errors
def alert(
    level_path: str,
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
    goal; a still intruder needs only --from.
    """
    from guardsim.alert import SEARCHES, AlertRules, alert_trace_data, run_alerts, summarise
    from guardsim.detection import GuardDetection
    from guardsim.patrol import read_patrol
    from guardsim.vision.table import view_table

    level = with_detection(
        load(level_path, max_cells, max_vertices, max_file_bytes),
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
    start = sneak_cell(grid, source, "--from") if source is not None else None
    goal = sneak_cell(grid, target, "--to") if target is not None else None
    route = None
    if route_path is not None:
        if intruder != "route":
            raise GuardsimError("--route is the path of a route intruder: give --intruder route")
        points = _route_file(route_path, grid)
        route = [sneak_cell(grid, point, f"{route_path}: point") for point in points]
        for index, (before, after) in enumerate(itertools.pairwise(route)):
            if after != before and after not in grid.neighbours[before].tolist():
                raise GuardsimError(f"{route_path}: point {index + 1} is not a 4-neighbour of point {index}")
        start, goal = route[0], route[-1]
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
    runs = run_alerts(
        scene,
        patrol,
        intruder=intruder,
        searches=searches,
        episodes=episodes,
        seed=seed,
        source=start,
        target=goal,
        max_seconds=max_seconds,
        rules=rules,
        detection=detection,
        spotted=spotted,
        phase=0 if episodes == 1 else None,
        route=route,
        table=table,
    )
    rows = [summarise(name, [e.result() for e in eps]) for name, eps in runs.items()]
    first = runs[searches[0]][0]
    written: list[str] = []
    if trace_path is not None:
        data = alert_trace_data(first, scene, search=searches[0], intruder=intruder)
        write_text_atomic(trace_path, json.dumps(data, separators=(",", ":")) + "\n")
        written.append(trace_path)
    if out_dir is not None:
        folder = output_folder(out_dir)
        for name, eps in runs.items():
            for index, episode in enumerate(eps):
                data = alert_trace_data(episode, scene, search=name, intruder=intruder)
                path = folder / f"{name}-{index:04d}.json"
                write_text_atomic(path, json.dumps(data, separators=(",", ":")) + "\n")
        summary = {
            "level": level.name,
            "patrol": patrol_path,
            "intruder": intruder,
            "episodes": episodes,
            "seed": seed,
            "summary": [row._asdict() for row in rows],
            "outcomes": {name: [e.result()._asdict() for e in eps] for name, eps in runs.items()},
        }
        write_text_atomic(folder / "alert.json", json.dumps(summary, indent=1) + "\n")
        written.append(str(folder / "alert.json"))
    if gif_path is not None:
        from guardsim.alert.gif import write_alert_gif

        write_alert_gif(gif_path, scene, table, first, suspicious=detection.model.suspicious)
        written.append(gif_path)
    if episodes == 1:
        for name, eps in runs.items():
            prefix = f"{name}: " if len(runs) > 1 else ""
            click.echo(f"{level.name}: {prefix}{eps[0].result().summary()}")
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
