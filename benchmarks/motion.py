"""Which planner is best when turning costs time? Every planner on the shipped levels and the eight real
maps in continuous motion, beside its grid steps: the motion section of docs/results.md.

Usage::

    python benchmarks/motion.py                                  # 10 episodes a shipped level, 5 a map
    python benchmarks/motion.py --episodes 4 --map-episodes 2 --maps movingai/arena.map   # a quick look

It imports the real maps of ``benchmarks/results.py`` (``MAPS``) unless ``results/planners/maps/`` has
them already, then runs ``guardsim bench`` twice per level set with the same seed, episodes and starts:
``--motion grid`` and ``--motion continuous`` (the level's guard, default speeds: 2 units/s, 180 deg/s,
30 Hz), with ``--no-bounds``. ``random-walk`` runs with ``--random-episodes`` episodes on the shipped
levels only: it walks to the time limit (10 steps per cell at walking speed), 10-40 s of wall time an
episode. The bench folders under ``--out`` resume, so a second run only rebuilds the tables. Prints
Markdown: per level, each planner's median grid steps and turns per 100 steps, then its median seconds to
cover, T90, distance, turns per minute, U-turns and seconds turning in place, with its rank in each
model; then how the ranking changes.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from collections.abc import Sequence
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from guardsim.experiment import RESULTS_NAME, EpisodeRecord, read_results
from guardsim.planners import PLANNERS

from results import MAPS, REPO, SHARED, guardsim  # the sibling benchmark's map list and runner

LEVELS = sorted((REPO / "levels").glob("*.json"))
RANDOM = "random-walk"


def bench_pair(
    name: str, files: Sequence[Path], planners: Sequence[str], episodes: int, out: Path
) -> tuple[list[EpisodeRecord], list[str]]:
    """Grid and continuous bench of ``files``; the rows of both and the commands with their wall time."""
    rows: list[EpisodeRecord] = []
    lines = []
    for motion in ("grid", "continuous"):
        folder = out / f"{name}-{motion}"
        command, seconds = guardsim("bench", *files, "--planner", ",".join(planners), "--episodes", episodes,
                                    "--motion", motion, "--no-bounds", "--workers", "1", "--out", folder)  # fmt: skip
        rows += read_results(folder / RESULTS_NAME)
        lines.append(f"| `{command}` | {seconds:.0f} |")
        print(f"{seconds:6.0f} s  {command}", file=sys.stderr, flush=True)
    return rows, lines


def median(values: Sequence[float | None]) -> float | None:
    present = [value for value in values if value is not None]
    return statistics.median(present) if present else None


def number(value: float | None, digits: int = 1) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def level_table(level: str, rows: Sequence[EpisodeRecord]) -> tuple[list[str], dict[str, tuple[int, int]]]:
    """The Markdown table of one level; and each planner's (grid rank, continuous rank)."""
    figures = {}
    for planner in PLANNERS:
        grid = [row for row in rows if row.planner == planner and row.motion == "grid"]
        walk = [row for row in rows if row.planner == planner and row.motion == "continuous"]
        if not grid or not walk:
            continue
        steps = median([row.steps for row in grid])
        figures[planner] = {
            "episodes": len(walk),
            "covered": sum(row.outcome == "covered" for row in walk),
            "steps": steps,
            "per100": median([100 * row.turns / row.steps if row.steps and row.turns is not None else None for row in grid]),
            "seconds": median([row.game_seconds for row in walk]),
            "t90": median([row.t90_s for row in walk]),
            "distance": median([row.distance for row in walk]),
            "per_min": median([row.turns_per_minute for row in walk]),
            "u_turns": median([row.u_turns for row in walk]),
            "in_place": median([row.in_place_s for row in walk]),
            "per_step": median([row.game_seconds / g.steps for row, g in zip(walk, grid) if g.steps and row.game_seconds]),
        }  # fmt: skip
    by_steps = sorted(figures, key=lambda name: (figures[name]["steps"] or 0, name))
    by_seconds = sorted(figures, key=lambda name: (figures[name]["seconds"] or 0, name))
    ranks = {name: (by_steps.index(name) + 1, by_seconds.index(name) + 1) for name in figures}
    lines = [
        f"**{level}**",
        "",
        "| planner | grid steps | turns / 100 steps | rank | seconds | s / grid step | T90 s | distance | turns / min "
        "| U-turns | in place s | rank |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for name in by_seconds:
        f = figures[name]
        covered = "" if f["covered"] == f["episodes"] else f" ({f['episodes'] - f['covered']} not covered)"
        lines.append(
            f"| `{name}`{covered} | {number(f['steps'], 0 if float(f['steps'] or 0).is_integer() else 1)} "
            f"| {number(f['per100'])} | {ranks[name][0]} | {number(f['seconds'])} | {number(f['per_step'], 2)} "
            f"| {number(f['t90'])} | {number(f['distance'], 0)} | {number(f['per_min'])} | {number(f['u_turns'], 0)} "
            f"| {number(f['in_place'])} | {ranks[name][1]} |"
        )
    return [*lines, ""], ranks


def overview(rows: Sequence[EpisodeRecord]) -> str:
    """One line per level: each planner's median grid steps and median seconds, with both ranks; then one
    line per planner: the medians over the levels of its per-level motion figures."""
    names = [name for name in PLANNERS if any(row.planner == name for row in rows)]
    lines = ["| level | " + " | ".join(f"`{name}`" for name in names) + " |", "| --- |" + " ---: |" * len(names)]
    per_planner: dict[str, list[dict[str, float]]] = {}
    for file in dict.fromkeys(row.level_file for row in rows):
        members = [row for row in rows if row.level_file == file]
        _, ranks = level_table(members[0].level, members)
        cells = []
        for name in names:
            grid = [row for row in members if row.planner == name and row.motion == "grid"]
            walk = [row for row in members if row.planner == name and row.motion == "continuous"]
            if not grid or not walk:
                cells.append("")
                continue
            steps, seconds = median([row.steps for row in grid]), median([row.game_seconds for row in walk])
            cells.append(f"{number(steps, 0)} / {number(seconds, 0)} s ({ranks[name][0]}→{ranks[name][1]})")
            per_planner.setdefault(name, []).append({
                "per_step": (seconds or 0) / (steps or 1),
                "distance": (median([row.distance for row in walk]) or 0) / (steps or 1),
                "per_min": median([row.turns_per_minute for row in walk]) or 0,
                "u_per_min": median([60 * (row.u_turns or 0) / row.game_seconds for row in walk if row.game_seconds]) or 0,
                "in_place": median([100 * (row.in_place_s or 0) / row.game_seconds for row in walk if row.game_seconds]) or 0,
                "per100": median([100 * (row.turns or 0) / row.steps for row in grid if row.steps]) or 0,
            })  # fmt: skip
        lines.append(f"| {members[0].level} | " + " | ".join(cells) + " |")
    lines += ["", "| planner | levels | turns / 100 grid steps | s / grid step | distance / grid steps | turns / min "
              "| U-turns / min | % of time turning in place |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]  # fmt: skip
    for name, figures in per_planner.items():

        def mid(key: str, figures: list[dict[str, float]] = figures) -> float:
            return statistics.median(figure[key] for figure in figures)

        lines.append(f"| `{name}` | {len(figures)} | {mid('per100'):.1f} | {mid('per_step'):.2f} | {mid('distance'):.2f} "
                     f"| {mid('per_min'):.1f} | {mid('u_per_min'):.2f} | {mid('in_place'):.1f} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes", type=int, default=10, help="Episodes per planner on each shipped level.")
    parser.add_argument("--map-episodes", type=int, default=5, help="Episodes per planner on each map.")
    parser.add_argument("--random-episodes", type=int, default=5, help="random-walk episodes per shipped level.")
    parser.add_argument("--maps", nargs="*", default=None, help="Map files under ../shared/maps (default: MAPS).")
    parser.add_argument("--out", type=Path, default=REPO / "results" / "motion")
    args = parser.parse_args()
    maps_folder = args.out / "maps"
    maps_folder.mkdir(parents=True, exist_ok=True)
    imported = []
    for source in args.maps if args.maps is not None else MAPS:
        stem = Path(source).stem
        shared_copy = REPO / "results" / "planners" / "maps" / f"{stem}.json"
        path = shared_copy if shared_copy.exists() else maps_folder / f"{stem}.json"
        if not path.exists():
            guardsim("import", SHARED / source, "--out", path)
        imported.append(path)
    planners = [name for name in PLANNERS if name != RANDOM]
    rows, commands = bench_pair("shipped", LEVELS, planners, args.episodes, args.out)
    more, lines = bench_pair("shipped-random", LEVELS, [RANDOM], args.random_episodes, args.out)
    rows += more
    commands += lines
    if imported:
        more, lines = bench_pair("maps", imported, planners, args.map_episodes, args.out)
        rows += more
        commands += lines
    print("| command | seconds |\n| --- | ---: |")
    print("\n".join(commands) + "\n")
    all_ranks: dict[str, list[tuple[int, int]]] = {}
    best_changes = []
    for file in dict.fromkeys(row.level_file for row in rows):
        members = [row for row in rows if row.level_file == file]
        lines, ranks = level_table(members[0].level, members)
        print("\n".join(lines))
        for name, pair in ranks.items():
            all_ranks.setdefault(name, []).append(pair)
        best_grid = min(ranks, key=lambda name: ranks[name][0])
        best_walk = min(ranks, key=lambda name: ranks[name][1])
        if best_grid != best_walk:
            best_changes.append(f"{members[0].level}: `{best_grid}` on the grid, `{best_walk}` in seconds")
    print(overview(rows))
    print("| planner | levels | mean rank, grid steps | mean rank, seconds | better in seconds | worse in seconds |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, pairs in all_ranks.items():
        grid_rank = statistics.mean(pair[0] for pair in pairs)
        walk_rank = statistics.mean(pair[1] for pair in pairs)
        up = sum(pair[1] < pair[0] for pair in pairs)
        down = sum(pair[1] > pair[0] for pair in pairs)
        print(f"| `{name}` | {len(pairs)} | {grid_rank:.2f} | {walk_rank:.2f} | {up} | {down} |")
    print("\nBest planner changed on: " + ("; ".join(best_changes) if best_changes else "no level"))


if __name__ == "__main__":
    main()
