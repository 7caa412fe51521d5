"""``guardsim patrol``: a repeating patrol of a level, its idleness, and the route for a game or editor."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from guardsim.cli.common import build_scene, limit_options, load, reports_errors, vision_options
from guardsim.errors import GuardsimError
from guardsim.output import write_text_atomic
from guardsim.planners import PLANNERS

__all__ = ["motion_check", "output_folder", "patrol", "tiled_source_of"]

_STRATEGIES = ("loop", "staleness", "ripplefront", "random")
_CONTINUOUS = "--motion continuous is not yet supported for patrol (grid motion only, in ticks)"


def motion_check(motion: str) -> None:
    """Refuse continuous motion until guardsim.motion can drive patrols (one line, exit status 2)."""
    if motion == "continuous":
        raise GuardsimError(_CONTINUOUS)


def output_folder(path: str) -> Path:
    """The ``--out`` folder, made if missing; one error line when it cannot be."""
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise GuardsimError(f"{path}: cannot make the output folder: {error.strerror or error}") from None
    return folder


def tiled_source_of(level_path: str, tiled_source: str | None) -> str | None:
    """The Tiled map a level came from: ``--tiled-source``, else LEVEL itself when it is a Tiled map."""
    if tiled_source is not None:
        return tiled_source
    suffix = Path(level_path).suffix.lower()
    if suffix in (".tmx", ".tmj"):
        return level_path
    if suffix == ".json":
        try:
            head = Path(level_path).read_bytes()[:65536]
        except OSError:
            return None
        if b'"orientation"' in head and b'"outer"' not in head:
            return level_path
    return None


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option(
    "--out", "out_dir", required=True, type=click.Path(file_okay=False), help="Folder for patrol.json and idleness.png."
)
@click.option("--guards", type=click.IntRange(min=1, max=64), default=1, show_default=True)
@click.option("--strategy", type=click.Choice(_STRATEGIES), default="loop", show_default=True)
@click.option(
    "--planner",
    type=click.Choice(["auto", "cover", *PLANNERS]),
    default="auto",
    show_default=True,
    help="loop: viewpoints from the set cover, from that planner's coverage walk, or the better of cover and tour (auto).",
)
@click.option("--motion", type=click.Choice(["grid", "continuous"]), default="grid", show_default=True)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Start and random choices.")
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
@click.option("--gif", "gif", is_flag=True, help="Write DIR/patrol.gif: one lap.")
@click.option("--html", "html", is_flag=True, help="Write DIR/patrol.html: one lap in the viewer.")
@click.option("--export", "export_path", type=str, help="Write the route as waypoints (route.json).")
@click.option(
    "--speed",
    type=click.FloatRange(min=0, min_open=True, max=1e6),
    default=2.0,
    show_default=True,
    help="World units per second, for times.",
)
@click.option(
    "--tiled-out",
    "tiled_out",
    type=str,
    help="Write a copy of the Tiled map with a 'guardsim' route layer (.tmx or .tmj).",
)
@click.option("--tiled-source", "tiled_source_path", type=str, help="The Tiled map a JSON level was imported from.")
@vision_options
@limit_options
@reports_errors
def patrol(
    level_path: str,
    out_dir: str,
    guards: int,
    strategy: str,
    planner: str,
    motion: str,
    seed: int,
    laps: int,
    warmup_laps: int,
    compare: bool,
    evaluate_path: str | None,
    gif: bool,
    html: bool,
    export_path: str | None,
    speed: float,
    tiled_out: str | None,
    tiled_source_path: str | None,
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
    motion_check(motion)
    from guardsim.patrol import patrol_data, patrol_setup, plan_loop, plan_patrol, read_patrol, score_patrol
    from guardsim.patrol.scoring import NEVER

    tiled_source = tiled_source_of(level_path, tiled_source_path)
    if tiled_out and tiled_source is None:
        raise GuardsimError(
            f"{level_path}: --tiled-out needs the Tiled map the level came from: LEVEL is a guardsim level, so give --tiled-source MAP.tmx"
        )
    level = load(level_path, max_cells, max_vertices, max_file_bytes)
    scene = build_scene(level, los, fov, view_range)
    folder = output_folder(out_dir)
    setup = patrol_setup(scene, guards, seed=seed)
    extra: dict[str, object] = {}
    if evaluate_path is not None:
        chosen = read_patrol(evaluate_path, scene.grid)
        score = score_patrol(setup.table, chosen, setup.goal, warmup=0)
        warmup = 0
        what = f"{Path(evaluate_path).name} evaluated"
    else:
        loop_plan, team_scores = plan_loop(setup, guards, planner=planner)
        lap = loop_plan.patrol.ticks
        if strategy == "loop":
            plan = loop_plan
        else:
            plan = plan_patrol(setup, strategy, laps=laps, warmup_laps=warmup_laps, lap=lap)
        chosen, score, warmup = plan
        what = f"{strategy} patrol"
        if strategy != "loop":
            extra["warmup_ticks"] = warmup
        if compare:
            rows = [("loop", loop_plan.score, loop_plan.patrol.period)]
            for other in _STRATEGIES[1:]:
                result = (
                    plan
                    if other == strategy
                    else plan_patrol(setup, other, laps=laps, warmup_laps=warmup_laps, lap=lap)
                )
                rows.append((other, result.score, None))
            click.echo(f"{'strategy':<12} {'worst':>8} {'mean':>9} {'period':>7}")
            for name, row_score, period in rows:
                worst = "never" if row_score.worst_idleness is None else str(row_score.worst_idleness)
                mean = "-" if row_score.mean_idleness is None else f"{row_score.mean_idleness:.1f}"
                click.echo(f"{name:<12} {worst:>8} {mean:>9} {period if period is not None else '-':>7}")
            extra["compare"] = {
                name: {"worst_idleness": row_score.worst_idleness, "mean_idleness": row_score.mean_idleness}
                for name, row_score, _ in rows
            }
        if guards > 1 and strategy == "loop":
            extra["team_compare"] = {
                name: {"worst_idleness": team_score.worst_idleness, "mean_idleness": team_score.mean_idleness}
                for name, team_score in team_scores.items()
            }
    data = patrol_data(chosen, score, scene.grid, level=level.name, motion=motion, extra=extra)
    written = [str(folder / "patrol.json")]
    write_text_atomic(folder / "patrol.json", json.dumps(data, separators=(",", ":")) + "\n")
    try:
        from guardsim.patrol.heatmap import write_heat_map

        gaps = score.worst_gap.reshape(scene.grid.shape).astype(float)
        never = gaps == NEVER
        gaps[(gaps < 0)] = float("nan")
        title = f"{level.name}: {what}, worst gap per cell (worst {score.worst_idleness}, mean {_mean(score.mean_idleness)})"
        write_heat_map(
            folder / "idleness.png", level, scene.grid, gaps, title=title, unit="ticks unseen in a row", never=never
        )
        written.append(str(folder / "idleness.png"))
    except GuardsimError as error:
        click.echo(f"guardsim: warning: idleness.png not written: {error}", err=True)
    if gif or html:
        from guardsim.patrol.replay import patrol_trace

        ticks = (
            chosen.ticks if chosen.period is not None else min(chosen.ticks - warmup - 1, max(1, chosen.ticks // 12))
        )
        trace = patrol_trace(
            scene, setup.table, chosen, setup.goal, start=warmup, ticks=ticks, label=f"patrol {chosen.strategy}"
        )
        if gif:
            from guardsim.render.gif import write_gif

            write_gif(folder / "patrol.gif", level, trace)
            written.append(str(folder / "patrol.gif"))
        if html:
            from guardsim.viewer import write_viewer

            write_viewer(folder / "patrol.html", level, trace)
            written.append(str(folder / "patrol.html"))
    if export_path:
        from guardsim.patrol.export import route_data

        write_text_atomic(
            export_path, json.dumps(route_data(chosen, scene.grid, level=level.name, speed=speed), indent=1) + "\n"
        )
        written.append(export_path)
    if tiled_out:
        from guardsim.output import atomic_path
        from guardsim.patrol.export import tiled_with_routes
        from guardsim.reading import read_limited_bytes

        assert tiled_source is not None
        source_bytes = read_limited_bytes(tiled_source, max_file_bytes=max_file_bytes, kind="Tiled map")
        copy = tiled_with_routes(tiled_source, tiled_out, chosen, scene.grid, speed=speed, source_bytes=source_bytes)
        with atomic_path(tiled_out) as temporary:
            temporary.write_bytes(copy)
        written.append(tiled_out)
    team = f", {guards} guards" if chosen.guards > 1 else ""
    if chosen.team:
        team += f" ({chosen.team})"
    period_text = f", period {chosen.period} ticks" if chosen.period is not None else ""
    worst = (
        "never seen: " + str(score.never_seen) + " cells"
        if score.worst_idleness is None
        else f"worst idleness {score.worst_idleness} ticks"
    )
    click.echo(
        f"{level.name}: {what}{team}{period_text}, {worst}, mean {_mean(score.mean_idleness)} -> {', '.join(written)}"
    )
    for note in chosen.notes:
        click.echo(f"  {note}")
    sys.stdout.flush()


def _mean(value: float | None) -> str:
    return "-" if value is None else f"{value:.1f}"
