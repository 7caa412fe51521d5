"""Unseen against undetected sneaks: a table per level, and the seconds the sneak check takes.

For each level (the shipped ones by default; any map guardsim imports), a loop patrol of ``--guards``
guards is planned, then the sneak check runs from each end of the level's two diagonals to the other,
once for an unseen path and once for an undetected one (the level's detection keys, defaults 0.25 / 1.5
/ 4 s). Prints a Markdown table: found, ticks, peak awareness, risk and slack for both rules, and the
check's own seconds (warm: the compiled kernels are loaded before the first row is timed).

    python benchmarks/sneak.py
    python benchmarks/sneak.py ../shared/maps/movingai/arena.map --guards 3
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from guardsim import load_level
from guardsim.detection import GuardDetection
from guardsim.patrol import patrol_setup, plan_loop
from guardsim.scene import Scene
from guardsim.sneak import sneak_check

REPO = Path(__file__).resolve().parent.parent


def _corners(goal: np.ndarray, cols: int) -> list[tuple[int, int]]:
    """The goal cells at the ends of each diagonal (col + row, then col - row)."""
    cells = np.flatnonzero(goal)
    col, row = cells % cols, cells // cols
    return [(int(cells[np.argmin(key)]), int(cells[np.argmax(key)])) for key in (col + row, col - row)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path)
    parser.add_argument("--guards", type=int, default=2)
    args = parser.parse_args()
    levels = args.levels or sorted((REPO / "levels").glob("*.json"))
    print(
        "| level | cells | guards | lap | from -> to | unseen: found, ticks, slack | undetected: found, ticks, peak, risk, slack | seconds (unseen / undetected) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    warmed = False
    for path in levels:
        level = load_level(str(path))
        scene = Scene.from_level(level)
        setup = patrol_setup(scene, args.guards)
        patrol = plan_loop(setup, args.guards)[0].patrol
        detection = GuardDetection.of_level(scene.level)
        grid = scene.grid
        for source, target in _corners(setup.goal, grid.shape[1]):
            if not warmed:
                sneak_check(grid, setup.table, patrol, source, target, detection=detection, undetected=True)
                warmed = True
            rows = []
            for undetected in (False, True):
                began = time.perf_counter()
                result = sneak_check(
                    grid, setup.table, patrol, source, target, detection=detection, undetected=undetected
                )
                seconds = time.perf_counter() - began
                assert result.path is not None and result.grade is not None
                rows.append((result, seconds))
            (plain, plain_s), (graded, graded_s) = rows
            assert plain.path is not None and graded.path is not None and graded.grade is not None
            where = f"{list(grid.unflat(source))} -> {list(grid.unflat(target))}"
            unseen = f"{'yes' if plain.found else 'no'}, {plain.path.ticks}, {plain.slack}"
            undetected_cell = (
                f"{'yes' if graded.found else 'no'}, {graded.path.ticks}, {graded.grade.peak:.2f}, "
                f"{graded.grade.risk:.3f}, {graded.slack}"
            )
            print(
                f"| {level.name} | {int(grid.traversable.sum())} | {patrol.guards} | {patrol.period} | {where} | "
                f"{unseen} | {undetected_cell} | {plain_s:.2f} / {graded_s:.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
