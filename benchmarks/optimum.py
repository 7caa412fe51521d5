"""The eight known optima (issue 15): reproduce them with ``guardsim.optimum.solve`` and time it.

Usage::

    python benchmarks/optimum.py                       # all eight, at most 300 s each
    python benchmarks/optimum.py --only arena --time-limit 60
    python benchmarks/optimum.py --planners --only maze-32-32-4   # every planner against the optimum
    python benchmarks/optimum.py --planners --tiny                # the same on the tests' tiny levels
    python benchmarks/optimum.py --planners --real                # small real maps, bench starts 0-2

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

#: Small real maps whose optima the search proves from bench starts in seconds (tried and unproved in
#: 60 s from the same starts: room-32-32-4, random-32-32-20, room-64-64-8, ht_chantry,
#: lt_undercitydungeon).
REAL_MAPS = ("maze-32-32-2", "den020d", "den207d")


def scene_of(name: str, view_range: float | None):
    """The scene of a Moving AI map with the Bresenham rule and a 360-degree view."""
    from guardsim.cli.common import build_scene
    from guardsim.importers import import_map

    level = import_map(MAPS / f"{name}.map").level
    return build_scene(level, "bresenham", 360.0, view_range)


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
    from guardsim.planners import PLANNERS, make_planner
    from guardsim.simulation import run_episode

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


def main() -> None:
    from guardsim.optimum import solve

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--time-limit", type=float, default=300.0, help="Seconds per start.")
    parser.add_argument("--only", help="Only the cases on this map.")
    parser.add_argument("--planners", action="store_true", help="Also every planner against the proved optima.")
    parser.add_argument("--tiny", action="store_true", help="The tests' tiny levels instead of the maps.")
    parser.add_argument("--real", action="store_true", help="Small real maps from bench starts 0-2.")
    arguments = parser.parse_args()
    proved = []
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
