"""``sneak --unheard`` against the searches without ears: answers and seconds on the shipped levels.

For each level, a loop patrol of ``--guards`` guards is planned and the sneak check runs along each of
the level's two diagonals: unseen; unseen and unheard; undetected and unheard, with a walking step heard
``--walk-noise`` world units away and a sneaking step (``--sneak-ticks`` ticks) ``--sneak-noise`` away.
Prints a Markdown table: found, ticks and sneaking steps of each, and their seconds (warm: the compiled
kernels are loaded before the first row is timed).

    python benchmarks/sneak_unheard.py
    python benchmarks/sneak_unheard.py levels/square.json --walk-noise 8 --sneak-noise 2
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from guardsim import IntruderSpec, load_level
from guardsim.detection import GuardDetection
from guardsim.patrol import patrol_setup, plan_loop
from guardsim.scene import Scene
from guardsim.sneak import SneakResult, sneak_check

REPO = Path(__file__).resolve().parent.parent


def _corners(goal: np.ndarray, cols: int) -> list[tuple[int, int]]:
    cells = np.flatnonzero(goal)
    col, row = cells % cols, cells // cols
    return [(int(cells[np.argmin(key)]), int(cells[np.argmax(key)])) for key in (col + row, col - row)]


def _answer(result: SneakResult, sneak_ticks: int) -> str:
    path = result.path
    if path is None:
        return "unreachable"
    sneaks = 0 if path.gaits is None else path.gaits.count("sneak") // sneak_ticks
    heard = f", heard {path.steps_heard}" if not result.found and path.gaits is not None else ""
    return f"{'yes' if result.found else 'no'}, {path.ticks} ticks, {sneaks} sneaking{heard}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path)
    parser.add_argument("--guards", type=int, default=2)
    parser.add_argument("--walk-noise", type=float, default=8.0)
    parser.add_argument("--sneak-noise", type=float, default=2.0)
    parser.add_argument("--sneak-ticks", type=int, default=2)
    args = parser.parse_args()
    ears = IntruderSpec(walk_noise=args.walk_noise, sneak_ticks=args.sneak_ticks, sneak_noise=args.sneak_noise)
    levels = args.levels or sorted((REPO / "levels").glob("*.json"))
    print(f"walk_noise {ears.walk_noise}, sneak_noise {ears.sneak_noise}, sneak_ticks {ears.sneak_ticks}")
    print("| level | lap | from -> to | unseen | unseen, unheard | undetected, unheard | seconds (each) |")
    print("|---|---|---|---|---|---|---|")
    warmed = False
    for path in levels:
        scene = Scene.from_level(load_level(str(path)))
        setup = patrol_setup(scene, args.guards)
        patrol = plan_loop(setup, args.guards)[0].patrol
        detection = GuardDetection.of_level(scene.level)
        grid = scene.grid
        for source, target in _corners(setup.goal, grid.shape[1]):
            runs = [{}, {"unheard": True, "intruder": ears}, {"unheard": True, "intruder": ears, "undetected": True}]
            if not warmed:
                for extra in runs:
                    sneak_check(grid, setup.table, patrol, source, target, detection=detection, **extra)  # type: ignore[arg-type]
                warmed = True
            cells, seconds = [], []
            for extra in runs:
                began = time.perf_counter()
                result = sneak_check(grid, setup.table, patrol, source, target, detection=detection, **extra)  # type: ignore[arg-type]
                seconds.append(time.perf_counter() - began)
                cells.append(_answer(result, ears.sneak_ticks))
            ends = " -> ".join(str(grid.unflat(cell)) for cell in (source, target))
            print(
                f"| {scene.level.name} | {patrol.period} | {ends} | {' | '.join(cells)} | "
                f"{' / '.join(f'{s:.2f}' for s in seconds)} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
