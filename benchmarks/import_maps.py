"""Import every shared map, validate it, and optionally play it: one table row per map.

Usage: ``python benchmarks/import_maps.py [--maps DIR] [--play] [--max-steps N] [--seed S] [--only NAME ...]``

For each Moving AI map (``DIR/movingai/*.map``) and Tiled map (``DIR/tiled/*.json`` and ``*.tmx``; the
sneaktime guard tiles 50 and 51 are the spawns) the script imports the map at cell size 1, loads the
written level back, builds its grid and prints: grid (cols x rows), cells, traversable, reachable (from
the level's start, or the largest connected area), holes, vertices and the import time (import, write
and reload; not the grid). With ``--play`` it also runs one RippleFront episode (start and heading drawn
from ``--seed`` as ``guardsim play --episode 0`` does, or the level's start when it has one) and adds
the steps, whether every reachable cell was seen, and the grid-plus-episode time.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from guardsim.importers import import_map
from guardsim.level import load_level
from guardsim.planners import RippleFront
from guardsim.simulation import Scene, choose_start, episode_generator, run_episode

MAPS = Path(__file__).resolve().parents[2] / "shared" / "maps"
SNEAKTIME_GUARD_TILES = (50, 51)


def sources(folder: Path, only: list[str]) -> list[Path]:
    found = sorted((folder / "movingai").glob("*.map")) + sorted((folder / "tiled").glob("sneaktime_*.*"))
    found = [path for path in found if path.suffix in (".map", ".json", ".tmx")]
    return [path for path in found if not only or path.stem in only or path.name in only]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", type=Path, default=MAPS, help="The shared maps folder.")
    parser.add_argument("--play", action="store_true", help="Also play one episode per map.")
    parser.add_argument("--max-steps", type=int, default=None, help="Step limit of each episode.")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", nargs="*", default=[], help="Map names (stem or file name) to run.")
    args = parser.parse_args()
    header = (
        f"{'map':<26} {'grid':>9} {'cells':>7} {'traversable':>11} {'reachable':>9} {'holes':>5} "
        f"{'vertices':>8} {'import s':>8}"
    )
    print(header + (f" {'steps':>7} {'covered':>7} {'play s':>7}" if args.play else ""))
    with tempfile.TemporaryDirectory() as scratch:
        for path in sources(args.maps, args.only):
            began = time.perf_counter()
            imported = import_map(path, spawn_tiles=SNEAKTIME_GUARD_TILES)
            written = Path(scratch) / f"{path.stem}.json"
            written.write_text(imported.to_json(), encoding="utf-8")
            level = load_level(written)
            import_seconds = time.perf_counter() - began
            began = time.perf_counter()
            scene = Scene.from_level(level)
            grid = scene.grid
            if level.guard.start is not None:
                cell, heading = choose_start(scene, rng=np.random.default_rng(args.seed), point=level.guard.start)
                reachable = int(grid.component(*cell).sum())
            else:
                cell, heading = choose_start(scene, rng=episode_generator(args.seed, 0))
                reachable = int(grid.largest_component().sum())
            rows, cols = grid.shape
            row = (
                f"{path.name:<26} {f'{cols}x{rows}':>9} {grid.size:>7} {int(grid.traversable.sum()):>11} "
                f"{reachable:>9} {len(level.holes):>5} {imported.vertices:>8} {import_seconds:>8.2f}"
            )
            if args.play:
                trace = run_episode(scene, RippleFront(), cell, heading, max_steps=args.max_steps, seed=args.seed)
                play_seconds = time.perf_counter() - began
                row += f" {trace.steps:>7} {'yes' if trace.covered else trace.outcome:>7} {play_seconds:>7.1f}"
            print(row, flush=True)


if __name__ == "__main__":
    main()
