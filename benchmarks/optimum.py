"""The eight known optima (issue 15): reproduce them with ``guardsim.optimum.solve`` and time it.

Usage::

    python benchmarks/optimum.py                       # all eight, at most 300 s each
    python benchmarks/optimum.py --only arena --time-limit 60

Moving AI maps from ``../shared/maps/movingai`` imported at cell size 1, the watchman-route solvers'
sight rule (``--los bresenham --fov 360``), unlimited range or 8 cells (targets with
dx^2 + dy^2 <= 64 between cell centres), one guard, cost = moves. The optima are those the MWRP-CP3
solver proves. Prints one table row per start: the optimum found, whether proved, the bound at the
start, expansions, stored nodes and seconds (view table included; the first run also compiles).
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


def scene_of(name: str, view_range: float | None):
    """The scene of a Moving AI map with the Bresenham rule and a 360-degree view."""
    from guardsim.cli.common import build_scene
    from guardsim.importers import import_map

    level = import_map(MAPS / f"{name}.map").level
    return build_scene(level, "bresenham", 360.0, view_range)


def main() -> None:
    from guardsim.optimum import solve

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--time-limit", type=float, default=300.0, help="Seconds per start.")
    parser.add_argument("--only", help="Only the cases on this map.")
    arguments = parser.parse_args()
    print("| map | start | range | known | found | proved | start bound | expansions | nodes | seconds |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, start, view_range, known in CASES:
        if arguments.only and arguments.only != name:
            continue
        began = time.perf_counter()
        scene = scene_of(name, view_range)
        result = solve(scene, start, 0, time_limit=arguments.time_limit)
        seconds = time.perf_counter() - began
        mark = "" if result.steps == known or not result.proved else " (differs!)"
        print(
            f"| {name} | {start} | {'unlimited' if view_range is None else f'{view_range:g}'} | {known} "
            f"| {result.steps}{mark} | {str(result.proved).lower()} | {result.root_bound} | {result.expansions} "
            f"| {result.nodes} | {seconds:.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
