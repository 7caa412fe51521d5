"""The eight known optima (issue 15): reproduce them with ``guardsim.optimum.solve`` and time it.

Usage::

    python benchmarks/optimum.py                       # all eight, at most 300 s each
    python benchmarks/optimum.py --only arena --time-limit 60
    python benchmarks/optimum.py --planners --only maze-32-32-4   # every planner against the optimum
    python benchmarks/optimum.py --planners --tiny                # the same on the tests' tiny levels
    python benchmarks/optimum.py --planners --real                # small real maps, bench starts 0-2
    python benchmarks/optimum.py --hard                           # issue 28's six hard instances
    python benchmarks/optimum.py --weights --time-limit 120       # --weight W on den101d (21, 2), range 8
    python benchmarks/optimum.py --guards 2                       # the team optimum (makespan) table
    python benchmarks/optimum.py --guards 2 --only lak105d --max-expansions 20000

Moving AI maps from ``../shared/maps/movingai`` imported at cell size 1, the watchman-route solvers'
sight rule (``--los bresenham --fov 360``), unlimited range or 8 cells (targets with
dx^2 + dy^2 <= 64 between cell centres), one guard, cost = moves. The optima are those the MWRP-CP3
solver proves. Prints one table row per start: the optimum found, whether proved, the bound at the
start, expansions, stored nodes and seconds (view table included; the first run also compiles).

With ``--planners``, a second table for the starts proved: every planner's steps from that start
(seed 0; the ratio to the optimum in brackets) and the best static bound (eccentricity, cluster, path:
:func:`guardsim.bounds.lower_bounds`; ``guardsim bounds`` adds the search bound, which is the optimum
itself on every proved row).
``--tiny`` runs the short-sighted tiny levels of ``tests/test_bounds.py`` (the paper's cone, heading in
the state) from four spread starts each, facing down, instead of the maps. ``--real`` runs the small
Moving AI maps of :data:`REAL_MAPS` (same sight rule, unlimited range) from the starts of bench episodes
0-2 of seed 0 (``guardsim optimum MAP --episode K``): those where the search proves the optimum within
the time limit.

``--hard`` runs the six instances of issue 28 (:data:`HARD_CASES`: four at range 8 that MWRP-CP3 proves
in 49.9 s or leaves open, two unlimited), each at most ``--time-limit`` seconds, after a warm-up solve that
loads the compiled kernels; seconds are the solver's own (``result.seconds``, view table included), the
gap is ``(found - lower bound) / found``.

With ``--guards 2``, the team table (:func:`guardsim.optimum.team.solve_team`, the makespan, same sight
rule, unlimited range): the fixed two-agent scenarios of MWRP-CP3's ``configs/`` and, on each map of its
published two-agent results, ``--draws`` start pairs drawn as its experiment draws them (random border
cells, :func:`border_cells`) from seed 0. MWRP-CP3's results record neither the starts nor the makespans
of those runs, only the times, so its column is the median of its published times on the map (over its
own random starts, ``experiments/results/*.csv``), not a time on the same instance. Maps the shared
folder lacks (den202d, lak105d, custom-*) are read from a local fetch of the MWRP-CP3 repository
(``--mwrp-repo``, a git directory; never committed here). The search stops after ``--max-expansions``
(a count, so the table is the same on every machine). Seconds are the solver's own, after a warm-up
solve that compiles the kernels.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
MAPS = REPO.parent / "shared" / "maps" / "movingai"

#: (map, start cell (x, y), view range in cells or None for unlimited, known optimum)
CASES: list[tuple[str, tuple[int, int], float | None, int]] = [
    ("maze-32-32-4", (1, 1), None, 210),
    ("maze-32-32-4", (15, 16), None, 235),
    ("arena", (3, 1), None, 61),
    ("arena", (24, 24), None, 59),
    ("den101d", (21, 2), None, 152),
    ("den101d", (36, 20), None, 167),
    ("maze-32-32-4", (1, 1), 8.0, 210),
    ("maze-32-32-4", (15, 16), 8.0, 235),
]

#: The hard instances of issue 28: (map, start (x, y), view range or None, MWRP-CP3 on this machine:
#: its optimum and seconds, or the lower bound it had when it stopped unproved).
HARD_CASES: list[tuple[str, tuple[int, int], float | None, str]] = [
    ("den101d", (21, 2), 8.0, "192 proved in 49.9 s"),
    ("den101d", (36, 20), 8.0, "unproved in 150 s (bound >= 193)"),
    ("arena", (3, 1), 8.0, "unproved in 150 s (bound >= 113)"),
    ("arena", (24, 24), 8.0, "unproved in 150 s (bound >= 112)"),
    ("room-32-32-4", (3, 0), None, "unproved in 300 s (bound >= 159)"),
    ("random-32-32-20", (0, 0), None, "unproved in 240 s (bound >= 62)"),
]

#: The weights of ``--weights``.
WEIGHTS = (1.0, 1.05, 1.2, 1.5, 2.0)

#: Seconds at which ``--hard`` reports the proved bound the search had reached.
BOUND_MARKS = (10.0, 30.0, 100.0)

#: Small real maps whose optima the search proves from bench starts in seconds (tried and unproved in
#: 60 s from the same starts: room-32-32-4, random-32-32-20, room-64-64-8, ht_chantry,
#: lt_undercitydungeon).
REAL_MAPS = ("maze-32-32-2", "den020d", "den207d")

#: MWRP-CP3's fixed scenarios (its ``configs/``): (map, starts (x, y), config file); ``--guards K`` takes
#: those with at least K agents, their first K.
TEAM_CASES: list[tuple[str, list[tuple[int, int]], str]] = [
    ("custom-11-11", [(0, 0), (10, 10)], "configs/maze/11_by_11_multi.json"),
    ("custom-13-13", [(0, 0), (0, 12)], "configs/maze/13_by_13_maze.json"),
    ("custom-19-19", [(0, 0), (0, 18)], "configs/maze/19_by_19_maze.json"),
    ("lak105d", [(4, 23), (23, 5)], "configs/games/lak105.json"),
    ("maze-32-32-2", [(1, 1), (1, 31)], "configs/maze/big_maze_tight_duo.json"),
    ("maze-32-32-2", [(1, 1), (31, 31), (1, 31)], "configs/maze/3232maze.json"),
    ("maze-32-32-2", [(1, 1), (31, 31), (1, 31), (31, 1)], "configs/maze/big_maze_tight.json"),
    ("maze-32-32-4", [(1, 1), (28, 28)], "configs/maze/big_maze.json"),
    ("den101d", [(11, 40), (62, 2), (22, 7)], "configs/games/den101d.json"),
    ("den207d", [(31, 43), (17, 27), (29, 15), (5, 5)], "configs/games/den207.json"),
]
#: MWRP-CP3's published two-agent medians (MWRP_CP3 rows, seconds) and where its repository keeps them.
TEAM_PUBLISHED: dict[str, tuple[float, str]] = {
    "den202d": (0.0375, "game_map_scaling_merged.csv"),
    "lak105d": (0.101, "game_map_scaling_merged.csv"),
    "maze-32-32-2": (8.367, "maze_map_scaling.csv"),
    "den101d": (9.536, "game_map_scaling_merged.csv"),
    "custom-11-11": (0.067, "maze_map_scaling.csv"),
    "custom-13-13": (0.101, "maze_map_scaling.csv"),
    "custom-19-19": (0.057, "maze_map_scaling.csv"),
}
#: Where the MWRP-CP3 repository keeps the maps the shared folder lacks.
MWRP_MAPS = {
    "den202d": "maps/den202d.map",
    "lak105d": "maps/maps2/lak105d.map",
    "custom-11-11": "maps/custom-11-11.map",
    "custom-13-13": "maps/custom-13-13.map",
    "custom-19-19": "maps/custom-19-19.map",
}
MWRP_REPO = REPO.parent / ".mirror" / "srikarg89+MWRP-CP3" / "repo"


def scene_of(name: str, view_range: float | None, path: Path | None = None, fov: float = 360.0):
    """The scene of a Moving AI map with the Bresenham rule and a 360-degree view (or a ``fov`` cone)."""
    from guardsim import load_level
    from guardsim.cli.common import build_scene

    level = load_level(path or MAPS / f"{name}.map")
    return build_scene(level, "bresenham", fov, view_range)


def map_file(name: str, repo: Path, folder: Path) -> Path:
    """The shared copy of a map, else the MWRP-CP3 repository's (``git show`` into ``folder``)."""
    import subprocess

    shared = MAPS / f"{name}.map"
    if shared.exists():
        return shared
    copy = folder / f"{name}.map"
    text = subprocess.run(
        ["git", "--git-dir", str(repo), "show", f"HEAD:{MWRP_MAPS[name]}"], capture_output=True, check=True
    ).stdout
    copy.write_bytes(text)
    return copy


def border_cells(path: Path) -> list[tuple[int, int]]:
    """The cells MWRP-CP3's experiment draws starts from (``experiments/main_experiment.py``): on game maps
    (den, lak) the free cells on the map's edge or next (8 ways) to the blocked region joined to the edge;
    on the others the free cells within 2 of the edge. ``.`` is free, anything else blocked."""
    lines = [line.strip() for line in path.read_text().splitlines()[4:] if line.strip()]
    free = [[c == "." for c in line] for line in lines]
    rows, cols = len(free), len(free[0])
    edge = [(x, y) for y in range(rows) for x in range(cols) if x in (0, cols - 1) or y in (0, rows - 1)]
    if not path.stem.startswith(("den", "lak")):
        return [
            (x, y) for y in range(rows) for x in range(cols) if free[y][x] and min(x, y, cols - 1 - x, rows - 1 - y) < 2
        ]
    cells = {(x, y) for x, y in edge if free[y][x]}
    stack = [(x, y) for x, y in edge if not free[y][x]]
    reached = set(stack)
    while stack:
        x, y = stack.pop()
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                nx, ny = x + dx, y + dy
                if 0 <= nx < cols and 0 <= ny < rows and free[ny][nx]:
                    cells.add((nx, ny))
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            nx, ny = x + dx, y + dy
            if 0 <= nx < cols and 0 <= ny < rows and not free[ny][nx] and (nx, ny) not in reached:
                reached.add((nx, ny))
                stack.append((nx, ny))
    return sorted(cells)


def team_rows(arguments: argparse.Namespace) -> None:
    """The team table: MWRP-CP3's fixed scenarios, then start pairs drawn on its published maps."""
    import statistics
    import tempfile

    import numpy as np

    from guardsim.optimum.team import solve_team

    guards = arguments.guards
    warm = scene_of("maze-32-32-4", None)
    solve_team(warm, [((1, 1), 0)] * guards)  # compiles the kernels: the times below are warm
    cases: list[tuple[str, list[tuple[int, int]], str]] = [
        (name, starts[:guards], source if len(starts) == guards else f"{source}, its first {guards} agents")
        for name, starts, source in TEAM_CASES
        if len(starts) >= guards
    ]
    rng = np.random.default_rng(0)
    print("| map | starts (x, y) | source | optimum | proved | start bound | expansions | nodes | seconds "
          "| starts reversed | MWRP-CP3 median (s, its own random starts) |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as folder:
        for name in TEAM_PUBLISHED:
            if name in ("custom-11-11", "custom-13-13", "custom-19-19"):
                continue
            path = map_file(name, arguments.mwrp_repo, Path(folder))
            scene = scene_of(name, None, path)
            pool = [cell for cell in border_cells(path) if scene.grid.traversable[cell[1], cell[0]]]
            drawn = 0
            while drawn < arguments.draws:
                picks = [pool[int(i)] for i in rng.choice(len(pool), size=guards, replace=False)]
                component = scene.grid.component(*picks[0])
                if all(component[y, x] for x, y in picks):
                    cases.append((name, picks, f"drawn on the border, seed 0, draw {drawn}"))
                    drawn += 1
        seconds: dict[str, list[float]] = {}
        done: set[tuple[str, tuple[tuple[int, int], ...]]] = set()
        for name, starts, source in cases:
            if (arguments.only and arguments.only != name) or (name, tuple(starts)) in done:
                continue  # another scenario's first K agents may be the same instance
            done.add((name, tuple(starts)))
            path = map_file(name, arguments.mwrp_repo, Path(folder))
            scene = scene_of(name, arguments.view_range, path, arguments.fov)
            result = solve_team(
                scene, [(start, 0) for start in starts], max_expansions=arguments.max_expansions or None
            )
            seconds.setdefault(name, []).append(result.seconds)
            # The order of the starts changes the search, never the answer: a check of the search.
            backwards = solve_team(
                scene, [(start, 0) for start in reversed(starts)], max_expansions=arguments.max_expansions or None
            )
            agree = "same" if (backwards.steps, backwards.proved) == (result.steps, result.proved) else "DIFFERS"
            if not (result.proved and backwards.proved):
                agree = "-"
            published = TEAM_PUBLISHED.get(name)
            verdict = str(result.steps) if result.proved else f"{result.lower_bound}..{result.steps}"
            print(
                f"| {name} | {', '.join(map(str, starts))} | {source} | {verdict} | {str(result.proved).lower()} "
                f"| {result.root_bound} | {result.expansions} | {result.nodes} | {result.seconds:.2f} | {agree} "
                f"| {'' if published is None or guards != 2 or arguments.fov != 360 else f'{published[0]:g}'} |",
                flush=True,
            )
    print()
    for name, times in seconds.items():
        print(f"{name}: median {statistics.median(times):.2f} s over {len(times)} sets of starts")


def tiny_cases() -> list[tuple[str, object, tuple[int, int]]]:
    """(name, scene, start) of the tests' short-sighted tiny levels, four spread starts each."""
    import sys

    sys.path.insert(0, str(REPO))
    from tests.common import scene_from
    from tests.test_bounds import SHORT_SIGHTED, starts

    cases = []
    for name, data in SHORT_SIGHTED.items():
        scene = scene_from(data)
        cases.extend((name, scene, start) for start in starts(scene, most=4))
    return cases


def planner_rows(cases: list[tuple[str, object, tuple[int, int], int, int]]) -> None:
    """Every planner's steps and ratio, and the best bound, for proved (name, scene, start, heading, optimum)."""
    from guardsim.bounds import lower_bounds
    from guardsim.motion import run_episode
    from guardsim.planners import PLANNERS, make_planner

    names = list(PLANNERS)
    print("\n| level | start | optimum | " + " | ".join(names) + " | best static bound |")
    print("| --- | --- | --- | " + " | ".join("---" for _ in names) + " | --- |")
    for name, scene, start, heading, optimum in cases:
        cells = []
        for planner in names:
            trace = run_episode(scene, make_planner(planner), starts=[start], headings=[heading], seed=0)  # type: ignore[arg-type]
            steps = len(trace.path) - 1
            mark = "" if trace.outcome == "covered" else " (not covered)"
            cells.append(f"{steps} ({steps / max(optimum, 1):.2f}){mark}")
        bound = lower_bounds(scene, start, heading).best  # type: ignore[arg-type]
        print(
            f"| {name} | {start} | {optimum} | " + " | ".join(cells) + f" | {bound} ({bound / max(optimum, 1):.2f}) |",
            flush=True,
        )


def hard_rows(time_limit: float, only: str | None) -> None:
    """The table of :data:`HARD_CASES` (``--hard``), with the proved bound as the search went."""
    import numpy as np

    from guardsim.optimum import SearchProgress, solve
    from guardsim.search.astar import greedy_walk
    from guardsim.search.graph import build_search_graph
    from guardsim.search.improve import improve_route
    from guardsim.search.pattern import build_patterns
    from guardsim.vision.table import view_table

    # Load (or compile) the kernels, the walk improvement's too: the rows are warm.
    warm = scene_of("maze-32-32-4", None)
    solve(warm, (1, 1), 0)
    graph = build_search_graph(warm.grid, view_table(warm.grid, warm.vision()), (1, 1), 0)
    improve_route(
        graph, greedy_walk(graph.successors, graph.views, graph.full, graph.start)[0], 1, np.random.default_rng(0)
    )
    build_patterns(graph, 2, most_entries=4 * graph.positions)
    marks = [mark for mark in BOUND_MARKS if mark < time_limit]
    print(
        "| map | start | range | MWRP-CP3 | found | proved | lower bound | gap | start bound | "
        + "".join(f"bound at {mark:g} s | " for mark in marks)
        + "expansions | nodes | seconds |"
    )
    print("|" + " --- |" * (12 + len(marks)))
    for name, start, view_range, anchor in HARD_CASES:
        if only and only != name:
            continue
        seen: list[SearchProgress] = []
        result = solve(scene_of(name, view_range), start, 0, time_limit=time_limit, progress=seen.append)
        gap = (result.steps - result.lower_bound) / result.steps
        at = []
        for mark in marks:
            before = [where.lower_bound for where in seen if where.seconds <= mark]
            at.append(str(before[-1]) if before and not result.seconds <= mark else "")
        print(
            f"| {name} | {start} | {'unlimited' if view_range is None else f'{view_range:g}'} | {anchor} "
            f"| {result.steps} | {str(result.proved).lower()} | {result.lower_bound} | {100 * gap:.1f} % "
            f"| {result.root_bound} | "
            + "".join(f"{bound} | " for bound in at)
            + f"{result.expansions} | {result.nodes} | {result.seconds:.1f} |",
            flush=True,
        )


def weight_rows(time_limit: float) -> None:
    """``--weights``: weighted A* (``--weight W``) on den101d from (21, 2) at range 8 (optimum 192)."""
    from guardsim.optimum import solve

    solve(scene_of("maze-32-32-4", None), (1, 1), 0)  # warm
    scene = scene_of("den101d", 8.0)
    print("| W | found | proved | lower bound | expansions | seconds |")
    print("| --- | --- | --- | --- | --- | --- |")
    for weight in WEIGHTS:
        result = solve(scene, (21, 2), 0, time_limit=time_limit, weight=weight)
        print(
            f"| {weight:g} | {result.steps} | {str(result.proved).lower()} | {result.lower_bound} "
            f"| {result.expansions} | {result.seconds:.1f} |",
            flush=True,
        )


def main() -> None:
    from guardsim.optimum import solve

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--time-limit", type=float, default=300.0, help="Seconds per start.")
    parser.add_argument("--only", help="Only the cases on this map.")
    parser.add_argument("--planners", action="store_true", help="Also every planner against the proved optima.")
    parser.add_argument("--tiny", action="store_true", help="The tests' tiny levels instead of the maps.")
    parser.add_argument("--real", action="store_true", help="Small real maps from bench starts 0-2.")
    parser.add_argument("--hard", action="store_true", help="Issue 28's six hard instances.")
    parser.add_argument("--weights", action="store_true", help="Weighted A* on den101d (21, 2) at range 8.")
    parser.add_argument("--guards", type=int, default=1, help="Above 1: the team optimum (makespan) table.")
    parser.add_argument("--draws", type=int, default=3, help="Start pairs drawn per published map (--guards).")
    parser.add_argument(
        "--max-expansions", type=int, default=200_000, help="Expansions per team search (--guards); 0: no limit."
    )
    parser.add_argument("--mwrp-repo", type=Path, default=MWRP_REPO, help="A fetched MWRP-CP3 git directory.")
    parser.add_argument("--fov", type=float, default=360.0, help="The guards' field of view (--guards; 90: a cone).")
    parser.add_argument("--view-range", type=float, help="The guards' view range in cells (--guards; default none).")
    arguments = parser.parse_args()
    if arguments.guards > 1:
        team_rows(arguments)
        return
    proved = []
    if arguments.hard:
        hard_rows(arguments.time_limit, arguments.only)
        return
    if arguments.weights:
        weight_rows(arguments.time_limit)
        return
    if arguments.real:
        from guardsim.starts import episode_start

        print("| map | start | heading | optimum | proved | start bound | expansions | nodes | seconds |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
        for name in REAL_MAPS:
            scene = scene_of(name, None)
            for episode in range(3):
                _, start, heading = episode_start(scene, seed=0, episode=episode)  # type: ignore[arg-type]
                result = solve(scene, start, heading, time_limit=arguments.time_limit)  # type: ignore[arg-type]
                print(
                    f"| {name} | {start} | {heading} | {result.steps} | {str(result.proved).lower()} "
                    f"| {result.root_bound} | {result.expansions} | {result.nodes} | {result.seconds:.1f} |",
                    flush=True,
                )
                if result.proved:
                    proved.append((name, scene, start, heading, result.steps))
        if arguments.planners:
            planner_rows(proved)
        return
    if arguments.tiny:
        print("| level | start | optimum | proved | start bound | expansions | nodes | seconds |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        for name, scene, start in tiny_cases():
            result = solve(scene, start, 1, time_limit=arguments.time_limit)  # type: ignore[arg-type]
            print(
                f"| {name} | {start} | {result.steps} | {str(result.proved).lower()} | {result.root_bound} "
                f"| {result.expansions} | {result.nodes} | {result.seconds:.2f} |"
            )
            if result.proved:
                proved.append((name, scene, start, 1, result.steps))
        if arguments.planners:
            planner_rows(proved)
        return
    print("| map | start | range | known | found | proved | start bound | expansions | nodes | seconds |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, start, view_range, known in CASES:
        if arguments.only and arguments.only != name:
            continue
        began = time.perf_counter()
        scene = scene_of(name, view_range)
        result = solve(scene, start, 0, time_limit=arguments.time_limit)
        seconds = time.perf_counter() - began
        if result.proved:
            label = name if view_range is None else f"{name} range {view_range:g}"
            proved.append((label, scene, start, 0, result.steps))
        mark = "" if result.steps == known or not result.proved else " (differs!)"
        print(
            f"| {name} | {start} | {'unlimited' if view_range is None else f'{view_range:g}'} | {known} "
            f"| {result.steps}{mark} | {str(result.proved).lower()} | {result.root_bound} | {result.expansions} "
            f"| {result.nodes} | {seconds:.1f} |",
            flush=True,
        )
    if arguments.planners:
        planner_rows(proved)


if __name__ == "__main__":
    main()
