"""``guardsim bounds``: lower bounds on the steps any guard with the level's vision needs from a start."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, TypeVar

import click

from guardsim.bounds import lower_bounds
from guardsim.cli.common import build_scene, cli_start, limit_options, load, parse_point, reports_errors, vision_options
from guardsim.level import HEADINGS
from guardsim.vision.table import view_table

__all__ = ["bounds", "start_options"]


F = TypeVar("F", bound=Callable[..., Any])


def start_options(command: F) -> F:
    """--start, --heading, --seed and --episode: one guard's start, chosen as by `guardsim play`."""
    for option in reversed(
        (
            click.option("--start", callback=parse_point, metavar="X,Y", help="Start position in world units."),
            click.option(
                "--heading", type=click.Choice(list(HEADINGS)), help="First heading (default: the level's, or drawn)."
            ),
            click.option(
                "--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed for random choices."
            ),
            click.option(
                "--episode",
                type=click.IntRange(min=0),
                help="The start of episode K of a batch seeded with --seed, drawn as in `guardsim bench`.",
            ),
        )
    ):
        command = option(command)
    return command


@click.command()
@click.argument("level_path", metavar="LEVEL")
@start_options
@vision_options
@limit_options
@reports_errors
def bounds(
    level_path: str,
    start: tuple[float, float] | None,
    heading: str | None,
    seed: int,
    episode: int | None,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Print lower bounds on the steps needed to see every cell reachable from a start on LEVEL.

    The eccentricity bound is the farthest any reachable cell's nearest viewpoint is; the cluster bound
    spans cells no two of which share a viewpoint; the path bound walks through some of those cells in the
    best order; the best bound is the largest (docs/bounds.md). The
    start and heading are chosen as by `guardsim play`: --start, else the level's, else drawn from --seed.
    """
    level = load(level_path, max_cells, max_vertices, max_file_bytes)
    began = time.perf_counter()
    scene = build_scene(level, los, fov, view_range)
    _, cell, first_heading = cli_start(scene, seed=seed, episode=episode, start=start, heading=heading)
    built = time.perf_counter()
    vision = scene.vision()
    view_table(scene.grid, vision)
    tabled = time.perf_counter()
    result = lower_bounds(scene, cell, first_heading, vision)
    reachable = int(scene.grid.component(*cell).sum())
    click.echo(
        f"{level.name}: from cell [{cell[0]}, {cell[1]}] facing {list(HEADINGS)[first_heading]} "
        f"({reachable} reachable cells): eccentricity bound {result.eccentricity}, "
        f"cluster bound {result.cluster} ({result.clusters} cluster{'' if result.clusters == 1 else 's'}), "
        f"path bound {result.path}, best bound {result.best} steps; "
        f"scene {built - began:.2f} s, view table {tabled - built:.2f} s, bounds {result.seconds:.3f} s"
    )
