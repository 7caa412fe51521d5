"""``guardsim optimum``: the fewest steps a guard needs to see every reachable cell, proved by search."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

import click

from guardsim.cli.common import (
    FiniteFloatRange,
    build_scene,
    cell_text,
    cli_start,
    level_options,
    load,
    parse_point,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.progress import Throttle
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.level import HEADINGS
from guardsim.optimum import DEFAULT_MEMORY_BYTES, SearchProgress, optimum_data, optimum_verdict, solve

if TYPE_CHECKING:
    from guardsim.scene import Scene

__all__ = ["DEFAULT_MAX_EXPANSIONS", "optimum"]

#: Expansions after which the command stops by default: a few minutes on this project's 2-core machine,
#: well past the 25 000 the hardest of issue 15's eight optima needs.
DEFAULT_MAX_EXPANSIONS = 2_000_000
#: Seconds between two progress lines on stderr.
PROGRESS_SECONDS = 10.0
#: Seconds before the guaranteed search's first progress line, and between two (its pairs are stored
#: in Python, some thousands a second: the 500 000-pair cap is half a minute).
PAIRS_PROGRESS_SECONDS = 2.0


class _Progress:
    """Prints where a long search is to stderr, at most every :data:`PROGRESS_SECONDS` (quiet before)."""

    def __init__(self) -> None:
        self._throttle = Throttle(PROGRESS_SECONDS)

    def __call__(self, where: SearchProgress) -> None:
        if not self._throttle.due():
            return
        click.echo(
            f"guardsim: optimum: {where.expansions} expansions, {where.nodes} nodes, "
            f"optimum between {where.lower_bound} and {where.best} steps ({where.seconds:.0f} s)",
            err=True,
        )


class _PairsProgress:
    """Where the guaranteed search is, on stderr every :data:`PAIRS_PROGRESS_SECONDS` (quiet before)."""

    def __init__(self) -> None:
        self._throttle = Throttle(PAIRS_PROGRESS_SECONDS)

    def __call__(self, pairs: int, tick: int) -> None:
        if not self._throttle.due():
            return
        click.echo(
            f"guardsim: optimum: guaranteed search at tick {tick}, {pairs} pairs stored "
            f"({self._throttle.elapsed():.0f} s)",
            err=True,
        )


def _points(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[tuple[float, float], ...]:
    return tuple(point for point in (parse_point(ctx, param, value) for value in values) if point is not None)


def _search_from(_ctx: click.Context, _param: click.Parameter, value: str | None) -> str | tuple[float, float] | None:
    if value is None or value == "all":
        return value
    return parse_point(_ctx, _param, value)


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option(
    "--start",
    multiple=True,
    callback=_points,
    metavar="X,Y",
    help="Start position in world units; repeat once per guard of a team.",
)
@click.option(
    "--heading",
    type=click.Choice(list(HEADINGS)),
    multiple=True,
    help="First heading (default: the level's, or drawn); one for every guard, or one per --start.",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed for random choices.")
@click.option(
    "--episode",
    type=click.IntRange(min=0),
    help="The start of episode K of a batch seeded with --seed, drawn as in `guardsim bench`.",
)
@click.option(
    "--search-from",
    callback=_search_from,
    metavar="X,Y|all",
    help="The guaranteed search instead: the fewest ticks until the guards are certain to have seen an "
    "intruder that started within --search-radius steps of X,Y (all: anywhere) and moves a cell a tick.",
)
@click.option(
    "--search-radius",
    type=click.IntRange(min=0, max=100_000),
    default=0,
    show_default=True,
    help="Cells (4-connected steps) around --search-from the intruder may start in.",
)
@click.option(
    "--guards",
    type=click.IntRange(min=1, max=8),
    help="Guards [default: one per --start, else 1; guards beyond the starts given start at the first]. "
    "Coverage: the fewest ticks until the team, moving at once, has seen every cell (makespan). Guaranteed "
    "search: impossible for them, the smallest team (up to 4) that can is also given.",
)
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
@level_options()
def optimum(
    level_path: str,
    start: tuple[tuple[float, float], ...],
    heading: tuple[str, ...],
    seed: int,
    episode: int | None,
    search_from: str | tuple[float, float] | None,
    search_radius: int,
    guards: int | None,
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
    With --guards K (and a --start per guard) it is the team's makespan: the fewest ticks until K guards
    moving at once have together seen every cell.
    """
    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    from guardsim.kernels.ahead import compile_ahead

    team = search_from is None and (len(start) > 1 or (guards or 1) > 1)
    compile_ahead("optimum:team" if team else "optimum")
    scene = build_scene(level, los, fov, view_range)
    if len(heading) > 1 and len(heading) != len(start):
        raise GuardsimError(f"{len(heading)} --heading options for {len(start)} --start: give one, or one per --start")
    if search_from is not None:
        _guaranteed(scene, level.name, start, heading, seed, episode, search_from, search_radius, guards, out_path)
        return
    if guards is None and len(start) > 1:
        raise GuardsimError(
            "several --start need --search-from (the guaranteed search) or --guards K (the team optimum)"
        )
    if len(start) > 1 or guards not in (None, 1):
        if weight != 1.0:
            raise GuardsimError("--weight is for one guard: the team optimum (--guards, several --start) is exact")
        teams = _team_starts(scene, start, heading, seed, episode, guards)
        _team(scene, level.name, teams, max_expansions, time_limit, memory_mb, out_path)
        return
    _, cell, first_heading = cli_start(
        scene, seed=seed, episode=episode, start=start[0] if start else None, heading=heading[0] if heading else None
    )
    result = solve(
        scene,
        cell,
        first_heading,
        max_expansions=max_expansions or None,
        time_limit=time_limit,
        memory_bytes=memory_mb * 2**20,
        progress=_Progress(),
        weight=weight,
        seed=seed,
    )
    heading_name = list(HEADINGS)[first_heading]
    click.echo(
        f"{level.name}: from {cell_text(scene.grid, cell)} facing {heading_name}: {optimum_verdict(result, weight)}"
    )
    if out_path is not None:
        data = optimum_data(result, scene, level=level.name, start=cell, heading=first_heading, weight=weight)
        write_text_atomic(out_path, json.dumps(data) + "\n")


def _team_starts(
    scene: Scene,
    start: tuple[tuple[float, float], ...],
    heading: tuple[str, ...],
    seed: int,
    episode: int | None,
    guards: int | None,
) -> list[tuple[tuple[int, int], int]]:
    """``((col, row), heading)`` of each guard: one per --start (guards beyond them at the first)."""
    count = guards if guards is not None else max(1, len(start))
    if len(start) > count:
        raise GuardsimError(f"{len(start)} --start options for --guards {count}")
    teams = []
    for index in range(count):
        point = start[index] if index < len(start) else (start[0] if start else None)
        facing = heading[index] if len(heading) > 1 and index < len(heading) else (heading[0] if heading else None)
        _, cell, first = cli_start(scene, seed=seed, episode=episode, start=point, heading=facing)
        teams.append((cell, first))
    return teams


def _team(
    scene: Scene,
    name: str,
    teams: list[tuple[tuple[int, int], int]],
    max_expansions: int,
    time_limit: float | None,
    memory_mb: int,
    out_path: str | None,
) -> None:
    """Several guards: the team optimum (makespan), printed and written."""
    from guardsim.optimum.team import solve_team, team_optimum_data

    result = solve_team(
        scene,
        teams,
        max_expansions=max_expansions or None,
        time_limit=time_limit,
        memory_bytes=memory_mb * 2**20,
        progress=_Progress(),
    )
    names = list(HEADINGS)
    where = ", ".join(f"{cell_text(scene.grid, cell)} facing {names[facing]}" for cell, facing in teams)
    if result.proved:
        verdict = f"optimum {result.steps} ticks"
    else:
        verdict = f"best found {result.steps} ticks (stopped by {result.stopped_by}; optimum >= {result.lower_bound})"
    walks = "+".join(str(len(path) - 1) for path in result.paths)
    click.echo(
        f"{name}: {len(teams)} guards from {where}: {verdict} (walks of {walks} steps); "
        f"proved: {str(result.proved).lower()}; start bound {result.root_bound}; "
        f"{result.expansions} expansions, {result.nodes} nodes, {result.seconds:.1f} s"
    )
    if out_path is not None:
        data = team_optimum_data(result, scene, level=name, starts=teams)
        write_text_atomic(out_path, json.dumps(data) + "\n")


def _guaranteed(
    scene: Scene,
    name: str,
    start: tuple[tuple[float, float], ...],
    heading: tuple[str, ...],
    seed: int,
    episode: int | None,
    search_from: str | tuple[float, float],
    radius: int,
    guards: int | None,
    out_path: str | None,
) -> None:
    """``--search-from``: the guaranteed search, printed and written."""
    from guardsim.optimum.guaranteed import guaranteed_data, guaranteed_search, search_region, smallest_team
    from guardsim.vision.table import view_table

    grid = scene.grid
    teams = _team_starts(scene, start, heading, seed, episode, guards)
    count = len(teams)
    if search_from == "all":
        region = search_region(grid, None, 0)
        where = "anywhere"
    else:
        assert isinstance(search_from, tuple)
        centre = grid.unflat(grid.floor_cell(search_from, "--search-from"))
        region = search_region(grid, centre, radius)
        where = f"within {radius} steps of {cell_text(grid, centre)}"
    table = view_table(grid, scene.vision())
    told = _PairsProgress()
    result = guaranteed_search(grid, table, teams, region, progress=told)
    team = None
    if result.proved and result.impossible:
        team = smallest_team(grid, table, teams[0], region, progress=told)
    if not result.proved:
        verdict = f"not settled: {result.pairs} (guards, set) pairs stored"
    elif result.impossible:
        if team is None:
            smallest = "more than 4 guards"
        elif not team[1].proved:
            smallest = f"whether {team[0]} guards can is not settled ({team[1].pairs} pairs stored)"
        else:
            smallest = f"{team[0]} guards (from the first start) can, in {team[1].steps} ticks"
        verdict = f"impossible: {count} guard{'s' if count > 1 else ''} can never be certain; {smallest}"
    else:
        verdict = f"certain after {result.steps} ticks"
    click.echo(
        f"{name}: guaranteed search, intruder starting {where}, {count} guard{'s' if count > 1 else ''}: "
        f"{verdict}; proved: {str(result.proved).lower()}; {result.pairs} pairs, {result.seconds:.1f} s"
    )
    if out_path is not None:
        data = guaranteed_data(
            result, level=name, search_from=search_from, radius=radius, teams=teams, smallest_team=team
        )
        write_text_atomic(out_path, json.dumps(data) + "\n")
