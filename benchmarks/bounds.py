"""Time of the lower bounds: the level's view table once, then the bounds per start.

Usage::

    python benchmarks/bounds.py                              # the shipped levels and Berlin_1_256
    python benchmarks/bounds.py --starts 50 --maps ../shared/maps/movingai/den520d.map

For each level: the seconds to build the scene and the view table (every state's visible cells and every
cell's watchers; this fills the whole vision cache, so it includes the vision of every state), then, for
``--starts`` starts and headings drawn as bench episodes 0, 1, ... of seed 0, the median and largest
seconds of :func:`guardsim.bounds.lower_bounds` with the table cached, and the median bounds. The first
start is left out of the timings (it loads the compiled functions).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
LEVELS = sorted((REPO / "levels").glob("*.json"))
MAPS = [REPO.parent / "shared" / "maps" / "movingai" / "Berlin_1_256.map"]


def load_scene(path: Path):
    """The scene of a level file or of a map imported at cell size 1."""
    from guardsim import load_level
    from guardsim.simulation import Scene

    if path.suffix == ".json":
        return Scene.from_level(load_level(path))
    from guardsim import load_level

    return Scene.from_level(load_level(path))


def measure(path: Path, starts: int) -> str:
    """One table row for a level."""
    from guardsim.bounds import lower_bounds
    from guardsim.simulation import choose_start, episode_generator
    from guardsim.vision.table import view_table

    began = time.perf_counter()
    scene = load_scene(path)
    built = time.perf_counter()
    view_table(scene.grid, scene.vision())
    tabled = time.perf_counter()
    results = []
    cpu = []
    for episode in range(starts + 1):
        cell, heading = choose_start(scene, rng=episode_generator(0, episode))
        before = time.process_time()
        results.append(lower_bounds(scene, cell, heading))
        cpu.append(time.process_time() - before)
    timed = results[1:]
    seconds = [result.seconds for result in timed]
    rows, cols = scene.grid.shape
    return (
        f"| {path.stem} | {rows} x {cols} | {int(scene.grid.traversable.sum())} | {built - began:.2f} "
        f"| {tabled - built:.2f} | {statistics.median(seconds) * 1000:.0f} | {max(seconds) * 1000:.0f} "
        f"| {statistics.median(cpu[1:]) * 1000:.1f} "
        f"| {statistics.median(result.eccentricity for result in timed):g} "
        f"| {statistics.median(result.cluster for result in timed):g} "
        f"| {statistics.median(result.path for result in timed):g} "
        f"| {statistics.median(result.best for result in timed):g} "
        f"| {statistics.median(result.clusters for result in timed):g} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=20, help="Starts timed per level.")
    parser.add_argument("--maps", type=Path, nargs="*", default=MAPS, help="Moving AI maps to time too.")
    arguments = parser.parse_args()
    print(
        "| level | grid | cells | scene s | view table s | bounds median ms | bounds max ms | bounds CPU ms "
        "| eccentricity | cluster | path | best | clusters |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for path in [*LEVELS, *arguments.maps]:
        print(measure(path, arguments.starts), flush=True)


if __name__ == "__main__":
    main()
