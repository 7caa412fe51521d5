"""Patrol strategies on the shipped levels: worst and mean idleness, and the sneak check, with timings.

Usage: ``python benchmarks/patrol.py [--guards 1,2] [--laps 10] [--out DIR] [--continuous] [LEVEL ...]``

For every level and team size it makes the loop patrol (``guardsim patrol``'s default) and runs the three
walked strategies for ``--laps`` laps of that loop after two laps of warm-up, exactly as
``guardsim patrol --compare`` does, and prints one markdown row per level and team: the loop's period
and team choice, then each strategy's worst and mean idleness in ticks. It also runs the
sneak check for two entry/exit pairs per level (the goal's opposite corners along both diagonals)
under the loop patrol and, with ``--out``, writes a GIF of each answer there. The seconds are wall
time on this machine (shared, so indicative only); every other figure is deterministic. With
``--continuous`` it prints instead each loop walked in continuous motion and scored in seconds.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from guardsim import load_level
from guardsim.detection import GuardDetection
from guardsim.patrol import patrol_setup, plan_loop, plan_patrol
from guardsim.patrol.replay import patrol_trace
from guardsim.scene import Scene
from guardsim.sneak import sneak_check

REPO = Path(__file__).resolve().parent.parent


def _corners(scene: Scene, goal: np.ndarray) -> list[tuple[int, int]]:
    """Two entry/exit pairs: the goal cells at the ends of each diagonal (col + row, then col - row)."""
    grid = scene.grid
    cells = np.flatnonzero(goal)
    cols, rows = cells % grid.shape[1], cells // grid.shape[1]
    pairs = []
    for key in (cols + rows, cols - rows):
        pairs.append((int(cells[np.argmin(key)]), int(cells[np.argmax(key)])))
    return pairs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path)
    parser.add_argument("--guards", default="1,2")
    parser.add_argument("--laps", type=int, default=10)
    parser.add_argument("--out", type=Path, help="Folder for the sneak GIFs.")
    parser.add_argument(
        "--continuous", action="store_true", help="Only the loops walked in continuous motion, in seconds."
    )
    args = parser.parse_args()
    levels = args.levels or sorted((REPO / "levels").glob("*.json"))
    teams = [int(part) for part in args.guards.split(",")]
    if args.continuous:
        _continuous(levels, teams)
        return
    print(
        "| level | guards | loop period | team | loop worst / mean | staleness worst / mean | ripplefront worst / mean | random worst / mean | seconds |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    sneaks = []
    for path in levels:
        level = load_level(path)
        scene = Scene.from_level(level)
        for guards in teams:
            began = time.perf_counter()
            setup = patrol_setup(scene, guards)
            loop, _ = plan_loop(setup, guards)
            cells = [f"{loop.score.worst_idleness} / {loop.score.mean_idleness:.1f}"]
            for strategy in ("staleness", "ripplefront", "random"):
                walked = plan_patrol(setup, strategy, laps=args.laps, lap=loop.patrol.ticks)
                cells.append(f"{walked.score.worst_idleness} / {walked.score.mean_idleness:.1f}")
            seconds = time.perf_counter() - began
            team = loop.patrol.team or "-"
            print(
                f"| {level.name} | {guards} | {loop.patrol.period} | {team} | "
                + " | ".join(cells)
                + f" | {seconds:.1f} |"
            )
            for number, (source, target) in enumerate(_corners(scene, setup.goal)):
                began = time.perf_counter()
                result = sneak_check(
                    scene.grid, setup.table, loop.patrol, source, target, detection=GuardDetection.of_level(scene.level)
                )
                seconds = time.perf_counter() - began
                assert result.path is not None
                answer = (
                    f"sneaks in {result.path.ticks} ticks from lap tick {result.path.start_tick}"
                    if result.found
                    else f"caught; closest call {result.path.ticks_in_view} ticks in view"
                )
                a, b = scene.grid.centre(*scene.grid.unflat(source)), scene.grid.centre(*scene.grid.unflat(target))
                sneaks.append(
                    f"| {level.name} | {guards} | {a[0]:g},{a[1]:g} -> {b[0]:g},{b[1]:g} | {answer} | {seconds:.2f} |"
                )
                if args.out is not None:
                    from guardsim.render.sneak import write_sneak_gif

                    args.out.mkdir(parents=True, exist_ok=True)
                    trace = patrol_trace(
                        scene,
                        setup.table,
                        loop.patrol,
                        setup.goal,
                        start=result.path.start_tick,
                        ticks=result.path.ticks,
                        label="sneak",
                    )
                    intruder = [scene.grid.unflat(int(cell)) for cell in result.path.cells]
                    seen = {
                        t
                        for t, c in enumerate(result.path.cells)
                        if result.seen[(result.path.start_tick + t) % result.period, c]
                    }
                    write_sneak_gif(
                        args.out / f"{path.stem}-{guards}-guards-sneak-{number + 1}.gif",
                        level,
                        trace,
                        intruder,
                        seen_ticks=seen,
                    )
    if sneaks:
        print()
        print("| level | guards | from -> to | sneak under the loop patrol | seconds |")
        print("|---|---|---|---|---|")
        for row in sneaks:
            print(row)


def _continuous(levels: list[Path], teams: list[int]) -> None:
    """The loop patrols walked by guardsim.motion (default speeds), as ``patrol --motion continuous``."""
    from guardsim.patrol.continuous import continuous_patrol

    print(
        "| level | guards | grid period (ticks) | grid worst (ticks) | lap (s) | worst idleness (s) | mean idleness (s) | never seen | seconds |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for path in levels:
        level = load_level(path)
        scene = Scene.from_level(level)
        for guards in teams:
            began = time.perf_counter()
            setup = patrol_setup(scene, guards)
            loop, _ = plan_loop(setup, guards)
            walked = continuous_patrol(scene, loop.patrol, setup.goal)
            worst, mean = walked.seconds(walked.score.worst_idleness), walked.seconds(walked.score.mean_idleness)
            print(
                f"| {level.name} | {guards} | {loop.patrol.period} | {loop.score.worst_idleness} | {walked.period_seconds:.1f} | "
                f"{worst:.1f} | {mean:.1f} | {walked.score.never_seen} | {time.perf_counter() - began:.1f} |"
            )


if __name__ == "__main__":
    main()
