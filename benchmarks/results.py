"""Every planner compared on the shipped levels and real maps: the tables and figures of docs/results.md.

Usage::

    python benchmarks/results.py                       # everything (about 10 minutes on 2 shared cores)
    python benchmarks/results.py --episodes 10 --map-episodes 5 --guards 1 --maps arena.map   # a quick look

What it does, printing each command with its wall time:

1. imports the real maps (``MAPS``, from ``--shared``) with ``guardsim import MAP --out OUT/maps/NAME.json``
   (printed as ``MAPS/movingai/NAME.map``: the maps are third-party data, not in the repository);
2. runs ``guardsim bench`` with every planner on the shipped levels (``--episodes`` per planner, default
   50) and on the imported maps (``--map-episodes``, default 20), once per team size of ``--guards``
   (default 1, 2 and 4), each into its own folder under ``--out``. A folder that already holds the run
   resumes (and returns at once; the time printed is then the resume's), so running the script again
   only rebuilds the tables and figures;
3. runs each planner from the six starts whose optimum under the grid solvers' sight rule
   (``--los bresenham --fov 360``) is known (MWRP-CP3, ICAPS 2026), with the Python API, as
   ``guardsim play MAP.json --los bresenham --fov 360 --start X.5,Y.5 --heading right --planner P``;
4. prints Markdown: an overview (median steps and steps / best lower bound per level and planner), one
   table per level (one guard: covered, median steps, T90, steps / bound, planning time per step; teams:
   makespan and total moves), the optimum table, and whether ``tour`` beats ``ripplefront`` everywhere;
   and writes one box plot per level (planners side by side, grouped by team size) to ``--figures``.

All medians are over the episodes of one level and planner; an episode stopped by the step limit counts
with the limit (only random-walk reaches it). Times are wall time on a shared machine: compare them
within a table, not across runs.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np

from guardsim import load_level
from guardsim.bounds import lower_bounds
from guardsim.cli.common import build_scene
from guardsim.experiment import RESULTS_NAME, EpisodeRecord, read_results
from guardsim.motion import run_episode
from guardsim.planners import PLANNERS, make_planner
from guardsim.render.plots import StepsBox, plot_steps
from guardsim.simulation import Scene, choose_start, episode_generator

REPO = Path(__file__).resolve().parent.parent
LEVELS = sorted((REPO / "levels").glob("*.json"))
SHARED = REPO.parent / "shared" / "maps"
#: Small and medium real maps: six Moving AI benchmark maps of several kinds and one Tiled game level.
MAPS = (
    "movingai/arena.map",
    "movingai/den101d.map",
    "movingai/maze-32-32-4.map",
    "movingai/lak307d.map",
    "movingai/room-64-64-8.map",
    "movingai/den020d.map",
    "movingai/ht_chantry.map",
    "tiled/sneaktime_tilemap10.json",
)
#: (map stem, (x, y) start cell from the top-left, optimal steps) under --los bresenham --fov 360.
OPTIMA = (
    ("maze-32-32-4", (1, 1), 210),
    ("maze-32-32-4", (15, 16), 235),
    ("arena", (3, 1), 61),
    ("arena", (24, 24), 59),
    ("den101d", (21, 2), 152),
    ("den101d", (36, 20), 167),
)
PLANNER_NAMES = tuple(PLANNERS)


def guardsim(*arguments: str | Path) -> tuple[str, float]:
    """Run the installed ``guardsim`` with ``arguments``; returns the command line and its wall time."""
    script = Path(sys.executable).with_name("guardsim")
    command = [str(script) if script.exists() else "guardsim", *map(str, arguments)]
    began = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    shown = " ".join(["guardsim", *(_relative(str(argument)) for argument in arguments)])
    return shown, time.perf_counter() - began


def _relative(text: str) -> str:
    """Paths under the repository written as from the repository; paths under the shared maps folder as
    ``MAPS/...`` (the maps are not in the repository: docs/results.md says where they come from)."""
    for root, name in ((REPO, ""), (SHARED, "MAPS/")):
        prefix = str(root) + os.sep
        if text.startswith(prefix):
            return name + text[len(prefix) :]
    return text


class LevelSet(NamedTuple):
    """Level files benched together."""

    name: str
    """Folder name prefix."""
    title: str
    """Section heading."""
    files: list[Path]
    episodes: int


def run_benches(sets: Sequence[LevelSet], teams: Sequence[int], out: Path) -> tuple[list[EpisodeRecord], list[str]]:
    """Bench every set for every team size; returns every row and the Markdown lines of the commands."""
    records: list[EpisodeRecord] = []
    lines = []
    for level_set in sets:
        for guards in teams:
            folder = out / f"{level_set.name}-{guards}-guards"
            command, seconds = guardsim(
                "bench", *level_set.files, "--planner", ",".join(PLANNER_NAMES), "--episodes", level_set.episodes,
                "--guards", guards, "--out", folder,
            )  # fmt: skip
            records += read_results(folder / RESULTS_NAME)
            lines.append(f"| `{command}` | {seconds:.0f} |")
            print(f"{seconds:6.0f} s  {command}", file=sys.stderr, flush=True)
    return records, lines


def median(values: Sequence[float]) -> float | None:
    """The median, or ``None`` for no values."""
    return statistics.median(values) if values else None


def number(value: float | None, digits: int = 1) -> str:
    """A table cell: ``-`` for nothing, whole numbers without decimals, others with ``digits``."""
    if value is None:
        return "-"
    return f"{int(value)}" if float(value).is_integer() else f"{value:.{digits}f}"


class Group(NamedTuple):
    """The rows of one level, planner and team size, summarised."""

    episodes: int
    covered: int
    steps: float | None
    t90: float | None
    moves: float | None
    ratio: float | None
    plan_us: float | None

    @classmethod
    def of(cls, rows: Sequence[EpisodeRecord]) -> Group:
        return cls(
            len(rows),
            sum(row.outcome == "covered" for row in rows),
            median([row.steps for row in rows if row.steps is not None]),
            median([row.t90 for row in rows if row.t90 is not None]),
            median([row.total_moves for row in rows if row.total_moves is not None]),
            median([ratio for ratio in (row.bound_ratio for row in rows) if ratio is not None]),
            median([row.plan_us_per_step for row in rows if row.plan_us_per_step is not None]),
        )


def group_rows(records: Sequence[EpisodeRecord]) -> dict[tuple[str, str, int], Group]:
    """``(level_file, planner, guards)`` -> :class:`Group`."""
    members: dict[tuple[str, str, int], list[EpisodeRecord]] = {}
    for record in records:
        members.setdefault((record.level_file, record.planner, record.guards), []).append(record)
    return {key: Group.of(rows) for key, rows in members.items()}


def overview(levels: dict[str, str], groups: dict[tuple[str, str, int], Group]) -> list[str]:
    """Median steps and steps / best bound per level (rows) and planner (columns), one guard; best in bold."""
    lines = ["| level | " + " | ".join(PLANNER_NAMES) + " |", "| --- |" + " ---: |" * len(PLANNER_NAMES)]
    for file, name in levels.items():
        found = {planner: groups.get((file, planner, 1)) for planner in PLANNER_NAMES}
        best = min((group.steps for group in found.values() if group and group.steps is not None), default=None)
        cells = []
        for group in found.values():
            if group is None or group.steps is None:
                cells.append("-")
                continue
            text = f"{number(group.steps)} ({number(group.ratio, 2)})"
            cells.append(f"**{text}**" if group.steps == best else text)
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines


def level_tables(file: str, teams: Sequence[int], groups: dict[tuple[str, str, int], Group]) -> list[str]:
    """The one-guard table and the team table of one level."""
    lines = ["| planner | covered | steps | T90 | steps / bound | µs per step |", "| --- |" + " ---: |" * 5]
    for planner in PLANNER_NAMES:
        group = groups.get((file, planner, 1))
        if group is None:
            continue
        lines.append(
            f"| {planner} | {group.covered}/{group.episodes} | {number(group.steps)} | {number(group.t90)} "
            f"| {number(group.ratio, 2)} | {number(group.plan_us, 1)} |"
        )
    sizes = [size for size in teams if size > 1]
    if not sizes:
        return lines
    header = ["planner", *(f"{size} {'guard' if size == 1 else 'guards'}: makespan" for size in teams)]
    header += [f"{size} guards: moves" for size in sizes] + ["covered (" + ", ".join(map(str, teams)) + " guards)"]
    lines += ["", "| " + " | ".join(header) + " |", "| --- |" + " ---: |" * (len(header) - 1)]
    for planner in PLANNER_NAMES:
        found = [groups.get((file, planner, size)) for size in teams]
        cells = [number(group.steps if group else None) for group in found]
        cells += [number(group.moves if group else None) for group, size in zip(found, teams) if size > 1]
        cells.append(", ".join(f"{group.covered}/{group.episodes}" if group else "-" for group in found))
        lines.append(f"| {planner} | " + " | ".join(cells) + " |")
    return lines


def draw_figure(
    file: str, name: str, records: Sequence[EpisodeRecord], teams: Sequence[int], target: Path, episodes: int
) -> None:
    """One box per planner and team size of one level."""
    boxes = [
        StepsBox(
            f"{size} guard{'s' if size > 1 else ''}",
            planner,
            [r.steps for r in records if (r.level_file, r.planner, r.guards) == (file, planner, size) and r.steps is not None],
        )
        for size in teams
        for planner in PLANNER_NAMES
    ]  # fmt: skip
    plot_steps(
        [box for box in boxes if box.steps],
        [target],
        title=f"{name}: {episodes} episodes per box",
        ylabel="steps to cover (a team's makespan)",
    )


def grid_size(file: str) -> str:
    """``rows x cols grid, N traversable cells`` of a level file."""
    grid = Scene.from_level(load_level(file)).grid
    return f"{grid.shape[0]} x {grid.shape[1]} grid, {int(grid.traversable.sum())} traversable cells"


def optimum_table(maps: Path, seed: int) -> list[str]:
    """Each planner's steps from the starts with known optima, under --los bresenham --fov 360."""
    header = ["map", "start", "optimum", "best bound", *PLANNER_NAMES, "seconds"]
    lines = ["| " + " | ".join(header) + " |", "| --- | --- |" + " ---: |" * (len(header) - 2)]
    scenes = {}
    for stem, (x, y), optimum in OPTIMA:
        began = time.perf_counter()
        if stem not in scenes:
            scenes[stem] = build_scene(load_level(maps / f"{stem}.json"), "bresenham", 360.0)
        scene = scenes[stem]
        cell, heading = choose_start(scene, rng=np.random.default_rng(0), point=(x + 0.5, y + 0.5), heading="right")
        if cell != (x, y):
            raise SystemExit(f"{stem}: start ({x}, {y}) landed in cell {cell}")
        bounds = lower_bounds(scene, cell, heading)
        runs = []
        for planner in PLANNER_NAMES:
            trace = run_episode(
                scene,
                make_planner(planner),
                starts=[cell],
                headings=[heading],
                rng=episode_generator(seed, 0),
                seed=seed,
            )
            if trace.covered and trace.steps < optimum:
                raise SystemExit(
                    f"{stem} from {cell}: {planner} took {trace.steps} < optimum {optimum}: not the same rules"
                )
            runs.append((trace.steps, trace.covered))
        best = min(steps for steps, covered in runs if covered)
        cells = []
        for steps, covered in runs:
            text = f"{steps}{'' if covered else ' (limit)'} ({steps / optimum:.2f})"
            cells.append(f"**{text}**" if covered and steps == best else text)
        lines.append(
            f"| {stem} | ({x}, {y}) | {optimum} | {bounds.best} ({bounds.best / optimum:.2f}) | "
            + " | ".join(cells)
            + f" | {time.perf_counter() - began:.1f} |"
        )
    return lines


def tour_against_ripplefront(levels: dict[str, str], groups: dict[tuple[str, str, int], Group]) -> list[str]:
    """Per level with both planners' one-guard rows: does tour's median beat RippleFront's?"""
    lines = []
    for file, name in levels.items():
        tour, ripple = groups.get((file, "tour", 1)), groups.get((file, "ripplefront", 1))
        if tour is None or ripple is None or tour.steps is None or ripple.steps is None:
            continue
        verdict = "beats" if tour.steps < ripple.steps else "does NOT beat"
        lines.append(f"- {name}: tour {number(tour.steps)} {verdict} ripplefront {number(ripple.steps)}")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/planners"), help="Bench output folders.")
    parser.add_argument("--figures", type=Path, default=REPO / "docs" / "images" / "results")
    parser.add_argument("--episodes", type=int, default=50, help="Episodes per planner on each shipped level.")
    parser.add_argument("--map-episodes", type=int, default=20, help="Episodes per planner on each real map.")
    parser.add_argument("--guards", default="1,2,4", help="Team sizes, comma-separated.")
    parser.add_argument("--shared", type=Path, default=SHARED, help="The shared maps folder.")
    parser.add_argument("--maps", nargs="*", default=None, help="Map files under --shared (default: MAPS).")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the optimum table's random walk.")
    args = parser.parse_args()
    teams = sorted({int(size) for size in args.guards.split(",")})
    began = time.perf_counter()
    print(f"Machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the start.\n")
    maps_folder = args.out / "maps"
    maps_folder.mkdir(parents=True, exist_ok=True)
    commands = ["| command | seconds |", "| --- | ---: |"]
    imported = []
    for source in args.maps if args.maps is not None else MAPS:
        path = maps_folder / f"{Path(source).stem}.json"
        command, seconds = guardsim("import", args.shared / source, "--out", path)
        commands.append(f"| `{command}` | {seconds:.1f} |")
        imported.append(path)
    sets = [
        LevelSet("shipped", "Shipped levels", LEVELS, args.episodes),
        LevelSet("maps", "Real maps", imported, args.map_episodes),
    ]
    records, bench_lines = run_benches(sets, teams, args.out)
    commands += bench_lines
    groups = group_rows(records)
    names = {record.level_file: record.level for record in records}
    files = [os.path.normpath(str(file)) for level_set in sets for file in level_set.files]
    levels = {file: names[file] for file in files if file in names}
    print("## Commands\n")
    print("\n".join(commands))
    print("\n## Overview: median steps (steps / best lower bound), one guard\n")
    print("\n".join(overview(levels, groups)))
    print("\n## Does tour beat ripplefront?\n")
    print("\n".join(tour_against_ripplefront(levels, groups)))
    args.figures.mkdir(parents=True, exist_ok=True)
    for level_set in sets:
        print(f"\n## {level_set.title}: {level_set.episodes} episodes per planner and team size\n")
        for file in map(os.path.normpath, map(str, level_set.files)):
            if file not in levels:
                continue
            stem = Path(file).stem
            draw_figure(file, levels[file], records, teams, args.figures / f"{stem}.png", level_set.episodes)
            print(f"### {levels[file]}\n\n`{_relative(os.path.abspath(file))}`: {grid_size(file)}.\n")
            print(f"![{levels[file]}: steps per planner and team size](images/results/{stem}.png)\n")
            print("\n".join(level_tables(file, teams, groups)) + "\n")
    if all((maps_folder / f"{stem}.json").exists() for stem, _, _ in OPTIMA):
        began_optima = time.perf_counter()
        print("## Known optima\n")
        print("One guard with `--los bresenham --fov 360`; each cell: steps (steps / optimum), best in bold.\n")
        print("\n".join(optimum_table(maps_folder, args.seed)))
        print(f"\n({time.perf_counter() - began_optima:.0f} s for the optimum table)")
    print(f"\nTotal: {time.perf_counter() - began:.0f} s.")


if __name__ == "__main__":
    main()
