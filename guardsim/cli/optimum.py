"""``guardsim optimum``: the fewest steps a guard needs to see every reachable cell, proved by search."""

from __future__ import annotations

import json
import time

import click

from guardsim.cli.bounds import start_options
from guardsim.cli.common import (
    FiniteFloatRange,
    build_scene,
    cli_start,
    limit_options,
    load,
    reports_errors,
    vision_options,
)
from guardsim.cli.map_options import MapImport, map_options
from guardsim.level import HEADINGS
from guardsim.optimum import DEFAULT_MEMORY_BYTES, SearchProgress, solve
from guardsim.output import write_text_atomic

__all__ = ["DEFAULT_MAX_EXPANSIONS", "optimum"]

#: Expansions after which the command stops by default: a few minutes on this project's 2-core machine,
#: well past the 25 000 the hardest of issue 15's eight optima needs.
DEFAULT_MAX_EXPANSIONS = 2_000_000
#: Seconds between two progress lines on stderr.
PROGRESS_SECONDS = 10.0


class _Progress:
    """Prints where a long search is to stderr, at most every :data:`PROGRESS_SECONDS` (quiet before)."""

    def __init__(self) -> None:
        self._next = time.perf_counter() + PROGRESS_SECONDS

    def __call__(self, where: SearchProgress) -> None:
        now = time.perf_counter()
        if now < self._next:
            return
        self._next = now + PROGRESS_SECONDS
        click.echo(
            f"guardsim: optimum: {where.expansions} expansions, {where.nodes} nodes, "
            f"optimum between {where.lower_bound} and {where.best} steps ({where.seconds:.0f} s)",
            err=True,
        )


@click.command()
@click.argument("level_path", metavar="LEVEL")
@start_options
@click.option(
    "--max-expansions",
    type=click.IntRange(min=0),
    default=DEFAULT_MAX_EXPANSIONS,
    show_default=True,
    help="Stop after this many search expansions (deterministic); 0: no limit.",
)
@click.option(
    "--time-limit",
    type=FiniteFloatRange(min=0, min_open=True),
    help="Stop after about this many seconds [default: none]. Where a timed run stops, hence its best walk "
    "and bound, can depend on the machine's speed; --max-expansions does not.",
)
@click.option(
    "--memory-mb",
    type=click.IntRange(min=16, max=2**20),
    default=DEFAULT_MEMORY_BYTES // 2**20,
    show_default=True,
    help="Most memory for the search's stored nodes; the search stops unproved when they are full.",
)
@click.option(
    "--weight",
    type=FiniteFloatRange(min=1.0),
    default=1.0,
    show_default=True,
    help="Stop once the walk found is proved at most this many times the optimum (1: the optimum itself).",
)
@click.option("--out", "out_path", type=str, help="Write the result (steps, path, proved, bounds) as JSON.")
@vision_options
@map_options
@limit_options
@reports_errors
def optimum(
    level_path: str,
    start: tuple[float, float] | None,
    heading: str | None,
    seed: int,
    episode: int | None,
    max_expansions: int,
    time_limit: float | None,
    memory_mb: int,
    weight: float,
    out_path: str | None,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
    map_import: MapImport,
) -> None:
    """Find the fewest steps after which a guard has seen every cell reachable from its start on LEVEL.

    A* over the guard's position and the cells seen so far, with the lower bounds of `guardsim bounds`
    as estimates (docs/optimum.md). It prints the optimum and proves it, or, stopped by a limit, the
    best walk found and the proved lower bound (proved: false). With --weight W it stops as soon as the
    walk in hand is proved within W times the optimum (proved: true then means within W). A search
    running longer than 10 s prints where it is to stderr every 10 s. The start and heading are chosen as by `guardsim play`.
    """
    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    from guardsim.kernels.ahead import compile_ahead

    compile_ahead("optimum")
    scene = build_scene(level, los, fov, view_range)
    _, cell, first_heading = cli_start(scene, seed=seed, episode=episode, start=start, heading=heading)
    result = solve(
        scene,
        cell,
        first_heading,
        max_expansions=max_expansions or None,
        time_limit=time_limit,
        memory_bytes=memory_mb * 2**20,
        progress=_Progress(),
        weight=weight,
    )
    names = list(HEADINGS)
    if result.proved and weight > 1.0:
        verdict = (
            f"{result.steps} steps, within {weight:g} x the optimum (optimum between {result.lower_bound} "
            f"and {result.steps})"
        )
    elif result.proved:
        verdict = f"optimum {result.steps} steps"
    else:
        verdict = f"best found {result.steps} steps (stopped by {result.stopped_by}; optimum >= {result.lower_bound})"
    click.echo(
        f"{level.name}: from cell [{cell[0]}, {cell[1]}] facing {names[first_heading]}: {verdict}; "
        f"proved: {str(result.proved).lower()}; start bound {result.root_bound}; "
        f"{result.expansions} expansions, {result.nodes} nodes, {result.seconds:.1f} s"
    )
    if out_path is not None:
        data = {
            "level": level.name,
            "start": list(cell),
            "heading": names[first_heading],
            "line_of_sight": scene.line_of_sight.value,
            "fov_degrees": scene.cone.fov_degrees,
            "view_range": scene.cone.view_range,
            "steps": result.steps,
            "proved": result.proved,
            "weight": weight,
            "lower_bound": result.lower_bound,
            "start_bound": result.root_bound,
            "stopped_by": result.stopped_by,
            "expansions": result.expansions,
            "nodes": result.nodes,
            "seconds": round(result.seconds, 3),
            "path": [list(step) for step in result.path],
        }
        write_text_atomic(out_path, json.dumps(data) + "\n")
