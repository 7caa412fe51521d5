"""``guardsim fortify``: place cameras and guard posts until no player gets through, and prove it."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from guardsim.cli.common import (
    DetectionOverrides,
    level_options,
    load,
    parse_point,
)
from guardsim.cli.design_common import check_outputs
from guardsim.cli.map_options import MapImport
from guardsim.cli.patrol import output_folder
from guardsim.cli.progress import StageLine
from guardsim.errors import GuardsimError

if TYPE_CHECKING:
    from guardsim.level import Level
    from guardsim.patrol import Patrol

__all__ = ["fortify"]

Point = tuple[float, float]


def _each_point(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[Point, ...]:
    return tuple(point for point in (parse_point(ctx, param, value) for value in values) if point is not None)


def _point_pairs(
    ctx: click.Context, param: click.Parameter, values: tuple[tuple[str, str], ...]
) -> tuple[tuple[Point, Point], ...]:
    pairs = []
    for first, second in values:
        a, b = parse_point(ctx, param, first), parse_point(ctx, param, second)
        assert a is not None and b is not None
        pairs.append((a, b))
    return tuple(pairs)


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--patrol", "patrol_path", help="patrol.json of the guards already there [default: none].")
@click.option(
    "--from",
    "sources",
    multiple=True,
    callback=_each_point,
    metavar="X,Y",
    help="An entry (world units); repeatable, one --to each.",
)
@click.option(
    "--to",
    "targets",
    multiple=True,
    callback=_each_point,
    metavar="X,Y",
    help="The goal of the --from at the same place.",
)
@click.option("--cameras", type=click.IntRange(min=0), default=8, show_default=True, help="Most cameras to add.")
@click.option("--posts", type=click.IntRange(min=0), default=8, show_default=True, help="Most guard posts to add.")
@click.option(
    "--keep-open", "keep_open", type=(str, str), multiple=True, callback=_point_pairs, metavar="FROM TO",
    help="X,Y X,Y: a pair that must keep a way through; repeatable.",
)  # fmt: skip
@click.option(
    "--min-slack", "min_slacks", type=click.IntRange(min=0), multiple=True,
    help="Entry ticks each --keep-open pair keeps a way through from (one for all, or one per pair) [default: 1].",
)  # fmt: skip
@click.option("--unseen", "rule", flag_value="unseen", help="Seal against unseen paths: any sighting catches.")
@click.option(
    "--undetected", "rule", flag_value="undetected", default=True,
    help="Seal against undetected paths: a watcher's meter must fill [the default].",
)  # fmt: skip
@click.option(
    "--camera-fov",
    type=click.FloatRange(min=0, max=360, min_open=True),
    default=60.0,
    show_default=True,
    help="Candidate cameras' field of view, degrees.",
)
@click.option(
    "--camera-range",
    type=click.FloatRange(min=0, min_open=True),
    help="Candidate cameras' view range [default: the guard's].",
)
@click.option(
    "--camera-sweep",
    type=click.FloatRange(min=0, max=360),
    default=90.0,
    show_default=True,
    help="Candidate cameras' swing, degrees (0: fixed).",
)
@click.option(
    "--candidates",
    type=click.IntRange(min=0),
    default=64,
    show_default=True,
    help="Candidates considered (cameras and posts).",
)
@click.option("--max-rounds", type=click.IntRange(min=0), default=64, show_default=True, help="Search rounds at most.")
@click.option("--max-lap", type=click.IntRange(min=1), default=None, help="Longest joint lap, ticks [default: 10000].")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(file_okay=False),
    help="Folder for level.json, patrol.json, fortify.json and fortify.png.",
)
@click.option("--picture", type=str, help="Write the picture here [default: DIR/fortify.png with --out].")
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Local worker processes for the candidates.",
)
@click.option("--scheduler", metavar="ADDRESS", help="Compute the candidates on a dask.distributed scheduler.")
@level_options(detection=True)
def fortify(
    level_path: str,
    map_import: MapImport,
    patrol_path: str | None,
    sources: tuple[Point, ...],
    targets: tuple[Point, ...],
    cameras: int,
    posts: int,
    keep_open: tuple[tuple[Point, Point], ...],
    min_slacks: tuple[int, ...],
    rule: str,
    camera_fov: float,
    camera_range: float | None,
    camera_sweep: float,
    candidates: int,
    max_rounds: int,
    max_lap: int | None,
    out_dir: str | None,
    picture: str | None,
    workers: int,
    scheduler: str | None,
    detection_overrides: DetectionOverrides,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Add cameras and guard posts to LEVEL until no player gets from any --from to its --to, and prove it.

    Each round searches every pair exactly over the joint lap of the guards and watchers; a way through
    becomes a counterexample, and the candidate catching the most counterexamples is added. Once sealed,
    watchers not needed are dropped and a smaller placement is looked for. Exit 0 sealed, 1 not sealed
    within the budget, 2 bad input. See docs/fortify.md.
    """
    from guardsim.design.fortify import CameraShape, KeepOpen
    from guardsim.design.fortify import fortify as run_fortify
    from guardsim.design.fortify.outputs import fortify_summary, write_fortify_outputs
    from guardsim.detection.watch import MAX_JOINT_LAP
    from guardsim.kernels.ahead import compile_ahead
    from guardsim.pictures import write_fortify_picture
    from guardsim.scene import Scene

    slacks = _check_budget(sources, targets, cameras, posts, max_rounds, candidates, keep_open, min_slacks)
    check_outputs(picture=picture)
    progress = StageLine(sys.stderr, "fortify").start()
    level = detection_overrides.apply(load(level_path, max_cells, max_vertices, max_file_bytes, map_import))
    compile_ahead("fortify")
    options = Scene.vision_options(los, fov, view_range)
    patrol = None if patrol_path is None else _read_patrol(patrol_path, level, options)
    result = run_fortify(
        level, patrol, list(zip(sources, targets)), cameras=cameras, posts=posts,
        keep_open=[KeepOpen(a, b, s) for (a, b), s in zip(keep_open, slacks)], undetected=rule == "undetected",
        camera=CameraShape(camera_fov, camera_range, camera_sweep), candidates=candidates, max_rounds=max_rounds,
        max_lap=MAX_JOINT_LAP if max_lap is None else max_lap, scene_options=options,
        patrol_name=str(patrol_path), workers=workers, scheduler=scheduler, progress=progress,
    )  # fmt: skip
    folder: Path | None = output_folder(out_dir) if out_dir is not None else None
    if picture is None and folder is not None:
        picture = str(folder / "fortify.png")
    progress("writing", 0, 0)
    written = write_fortify_outputs(result, folder)
    if picture is not None:
        written.append(write_fortify_picture(result, picture))
    progress.close()
    for keep in result.document["keep_open"]:
        if not keep["kept"]:
            click.echo(f"guardsim: warning: {keep['message']}", err=True)
    click.echo(f"{level.name}: {fortify_summary(result)}" + (f" -> {', '.join(written)}" if written else ""))
    if not result.sealed:
        sys.exit(1)


def _check_budget(
    sources: tuple[Point, ...],
    targets: tuple[Point, ...],
    cameras: int,
    posts: int,
    max_rounds: int,
    candidates: int,
    keep_open: tuple[tuple[Point, Point], ...],
    min_slacks: tuple[int, ...],
) -> list[int]:
    """Refuse pairs and budgets that cannot fortify anything; the slack each --keep-open pair needs."""
    if not sources:
        raise GuardsimError("--from: give at least one entry (--from X,Y --to X,Y)")
    if len(sources) != len(targets):
        raise GuardsimError(f"each --from needs its --to: {len(sources)} --from, {len(targets)} --to")
    if cameras + posts == 0:
        raise GuardsimError("--cameras 0 --posts 0: a budget of 0 watchers cannot fortify anything")
    if max_rounds == 0:
        raise GuardsimError("--max-rounds 0: a budget of 0 rounds cannot fortify anything")
    if candidates == 0:
        raise GuardsimError("--candidates 0: a budget of 0 candidates cannot fortify anything")
    if min_slacks and not keep_open:
        raise GuardsimError("--min-slack applies to --keep-open pairs: give --keep-open FROM TO")
    if len(min_slacks) not in (0, 1, len(keep_open)):
        raise GuardsimError(
            f"--min-slack: give one for all or one per --keep-open ({len(keep_open)}), not {len(min_slacks)}"
        )
    return list(min_slacks) * len(keep_open) if len(min_slacks) == 1 else list(min_slacks) or [1] * len(keep_open)


def _read_patrol(patrol_path: str, level: Level, options: dict[str, Any]) -> Patrol:
    from guardsim.patrol import read_patrol
    from guardsim.scene import Scene

    return read_patrol(patrol_path, Scene.from_level(level, **options).grid, level=level.name)
