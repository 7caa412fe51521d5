"""``guardsim bounds``: lower bounds on the steps any guard with the level's vision needs from a start."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import click

from guardsim.bounds import lower_bounds
from guardsim.cli.common import (
    build_scene,
    cell_text,
    cli_start,
    level_options,
    load,
    parse_point,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.progress import StageLine, Throttle
from guardsim.level import HEADINGS
from guardsim.optimum import MAX_POSITIONS, SearchProgress, solve
from guardsim.search.graph import search_positions
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import view_table

if TYPE_CHECKING:
    from guardsim.scene import Scene

__all__ = ["SEARCH_EXPANSIONS", "SEARCH_POSITIONS", "bounds", "start_options"]

#: Expansions of the exact search behind the search bound, by default: about a second on a loaded
#: 2-core machine (random-32-32-20, 819 cells: 2 000 in 1.0 s, bound 118; 10 000 in 3.6 s, bound 121),
#: so that a bound stays quick on any level. Proving the optimum takes more (the arena from (24, 24):
#: about 25 000): ``--search-expansions`` raises it.
SEARCH_EXPANSIONS = 4_000
#: Seconds of search before the first progress line on stderr, and between two.
PROGRESS_SECONDS = 2.0
#: Most guard positions for which the search bound runs by default. On the shipped 60 x 60 levels (9 000
#: to 14 000 states) 20 000 expansions take 30-65 s and raise no bound.
SEARCH_POSITIONS = 6000
#: Memory for the search bound's stored nodes.
SEARCH_MEMORY_BYTES = 512 * 2**20


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
@click.option(
    "--search-expansions",
    type=click.IntRange(min=0),
    help=f"Expansions of the exact search for the search bound; 0: no search [default: {SEARCH_EXPANSIONS} "
    f"from a start with at most {SEARCH_POSITIONS} guard positions, else 0].",
)
@level_options()
def bounds(
    level_path: str,
    map_import: MapImport,
    start: tuple[float, float] | None,
    heading: str | None,
    seed: int,
    episode: int | None,
    search_expansions: int | None,
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
    progress = StageLine(sys.stderr, "bounds").start()
    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    from guardsim.kernels.ahead import compile_ahead

    progress("compiling", 0, 0)
    compile_ahead("bounds")
    progress("view table", 0, 0)
    began = time.perf_counter()
    scene = build_scene(level, los, fov, view_range)
    _, cell, first_heading = cli_start(scene, seed=seed, episode=episode, start=start, heading=heading)
    built = time.perf_counter()
    vision = scene.vision()
    view_table(scene.grid, vision)
    tabled = time.perf_counter()
    progress("bounds", 0, 0)
    result = lower_bounds(scene, cell, first_heading, vision)
    reachable = int(scene.grid.component(*cell).sum())
    progress("search bound", 0, 0)
    best, search = result.best, _search_bound(scene, vision, cell, first_heading, search_expansions)
    if search[0] is not None:
        best = max(best, search[0])
    progress.close()
    click.echo(
        f"{level.name}: from {cell_text(scene.grid, cell)} facing {list(HEADINGS)[first_heading]} "
        f"({reachable} reachable cells): eccentricity bound {result.eccentricity}, "
        f"cluster bound {result.cluster} ({result.clusters} cluster{'' if result.clusters == 1 else 's'}), "
        f"path bound {result.path}, best bound {best} steps; {search[1]}; "
        f"scene {built - began:.2f} s, view table {tabled - built:.2f} s, bounds {result.seconds:.3f} s, "
        f"search {search[2]:.2f} s"
    )


class _Progress:
    """Where the search bound's search is, on stderr every :data:`PROGRESS_SECONDS` (quiet before)."""

    def __init__(self, budget: int) -> None:
        self.budget = budget
        self._throttle = Throttle(PROGRESS_SECONDS)

    def __call__(self, where: SearchProgress) -> None:
        if not self._throttle.due():
            return
        click.echo(
            f"guardsim: bounds: search {where.expansions} of {self.budget} expansions, "
            f"bound {where.lower_bound} so far ({where.seconds:.0f} s)",
            err=True,
        )


def _search_bound(
    scene: Scene, vision: VisionFunction, cell: tuple[int, int], heading: int, expansions: int | None
) -> tuple[int | None, str, float]:
    """The exact search's proved floor after at most ``expansions`` (None: the default by level size),
    the words that say it, and its seconds."""
    positions = search_positions(scene.grid, view_table(scene.grid, vision), cell, heading)
    if expansions is None:
        expansions = SEARCH_EXPANSIONS if positions <= SEARCH_POSITIONS else 0
        if expansions == 0:
            return (
                None,
                f"search bound not run ({positions} positions, over {SEARCH_POSITIONS}: see --search-expansions)",
                0.0,
            )
    if expansions == 0:
        return None, "search bound not run (--search-expansions 0)", 0.0
    if positions > MAX_POSITIONS:
        return None, f"search bound not run ({positions} positions, over the exact search's {MAX_POSITIONS})", 0.0
    found = solve(
        scene,
        cell,
        heading,
        vision,
        max_expansions=expansions,
        memory_bytes=SEARCH_MEMORY_BYTES,
        improve=False,
        first_walk=False,
        progress=_Progress(expansions),
    )
    if found.proved:
        return (
            found.steps,
            f"search bound {found.steps} (the optimum, proved in {found.expansions} expansions)",
            found.seconds,
        )
    words = f"search bound {found.lower_bound} (stopped by {found.stopped_by} after {found.expansions} expansions"
    words += "; --search-expansions N searches further)" if found.stopped_by == "expansions" else ")"
    return found.lower_bound, words, found.seconds
