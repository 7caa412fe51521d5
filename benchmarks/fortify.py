"""Fortify per level: rounds, watchers, lower bound and seconds, each sealed result re-checked by sneak.

For each level (the shipped ones and four real maps by default; any map guardsim imports), a loop patrol
of ``--guards`` guards is planned (``cover`` viewpoints), the entry-goal pairs are the design report's
(each player start to the floor cell farthest from it on foot; without player starts, the two floor
cells farthest apart), and fortify runs with its defaults but ``--candidates``. A sealed result is then
re-checked by the sneak search (on the fortified level's own watch of its cameras and the patrol with
the posts) from every entry tick: it must find no path. Prints a Markdown table.

    python benchmarks/fortify.py                 # the real maps from ../shared/maps (or $GUARDSIM_SHARED/maps)
    python benchmarks/fortify.py levels/square.json --unseen --candidates 128
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from guardsim import Scene, load_level
from guardsim.design.analysis import default_pairs
from guardsim.design.fortify import fortify
from guardsim.detection import GuardDetection
from guardsim.detection.watch import lap_gains, level_watch
from guardsim.patrol import patrol_setup, plan_loop
from guardsim.sneak import find_sneak, undetected_search

REPO = Path(__file__).resolve().parent.parent
MAPS = Path(os.environ.get("GUARDSIM_SHARED") or REPO.parent / "shared") / "maps"
REAL = [
    MAPS / "movingai" / "room-64-64-8.map",
    MAPS / "tiled" / "sneaktime_tilemap1.json",
    MAPS / "tiled" / "sneaktime_tilemap4.json",
    MAPS / "tiled" / "sneaktime_tilemap10.json",
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path)
    parser.add_argument("--guards", type=int, default=1)
    parser.add_argument("--candidates", type=int, default=64)
    parser.add_argument("--unseen", action="store_true", help="Seal against unseen paths instead of undetected ones.")
    args = parser.parse_args()
    levels = args.levels or [*sorted((REPO / "levels").glob("*.json")), *(path for path in REAL if path.exists())]
    rule = "unseen" if args.unseen else "undetected"
    print("| level | floor cells | lap | rule | sealed | rounds | watchers | lower bound | gap | re-check | seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for path in levels:
        level = load_level(str(path))
        scene = Scene.from_level(level)
        setup = patrol_setup(scene, args.guards)
        patrol = plan_loop(setup, args.guards, planner="cover")[0].patrol
        pairs = default_pairs(scene, setup.goal)
        began = time.perf_counter()
        result = fortify(level, patrol, pairs, candidates=args.candidates, undetected=not args.unseen)
        seconds = time.perf_counter() - began
        document = result.document
        recheck = "-"
        if result.sealed:
            # The sneak search again, on the level and patrol fortify wrote (cameras and posts read back
            # through the level's own watch), from every entry tick of the joint lap.
            assert result.patrol is not None
            fortified = Scene.from_level(result.level)
            detection = GuardDetection.of_level(result.level)
            watch = level_watch(fortified, detection.dt)
            grid = fortified.grid
            gains, _ = lap_gains(grid, setup.table, result.patrol.states, detection, watch)
            seen = gains.seen
            ways = []
            for entry, goal in pairs:
                a, b = grid.cell_of(entry), grid.cell_of(goal)
                assert a is not None and b is not None
                source, target = grid.flat(*a), grid.flat(*b)
                if args.unseen:
                    ways.append(find_sneak(grid.neighbours, seen, source, target) is not None)
                else:
                    search = undetected_search(grid.neighbours, gains.gain, gains.fall, source, target, seen=seen)
                    ways.append(search.found >= 0)
            recheck = "way found!" if any(ways) else "no path"
        sealed = "yes" if result.sealed else f"no: {document['reason']}"
        bound = "-" if document["lower_bound"] is None else document["lower_bound"]
        gap = "-" if document["gap"] is None else document["gap"]
        print(
            f"| {path.name} | {int(scene.grid.traversable.sum())} | {document['lap']} | {rule} | {sealed} | "
            f"{document['search_rounds']} | {document['count']} | {bound} | {gap} | {recheck} | {seconds:.1f} |"
        )
        sys.stdout.flush()


if __name__ == "__main__":
    main()
