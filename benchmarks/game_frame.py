"""The guards' step in a game's frame: wall time of :meth:`guardsim.alert.GameGuards.frame` with 3 guards
on Square (60 x 60), at 60 frames a second, against a player walking a seeded random path (docs/alert.md).

Usage::

    python benchmarks/game_frame.py [--seconds 120] [--motion grid|continuous]

Prints the median, 99th percentile and worst frame time over every frame, and the same over the frames
that complete a grid tick (the guards decide, look and move then; the other frames only move the drawn
poses between ticks).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=120.0, help="Game seconds to play.")
    parser.add_argument("--motion", default="grid", choices=("grid", "continuous"))
    args = parser.parse_args()
    import numpy as np

    import guardsim
    from guardsim.alert import GameGuards
    from guardsim.patrol.plan import patrol_setup, plan_patrol

    scene = guardsim.Scene.from_level(guardsim.load_level(str(REPO / "levels" / "square.json")))
    patrol = plan_patrol(patrol_setup(scene, 3, seed=0), "loop").patrol
    grid = scene.grid
    free = np.flatnonzero(grid.traversable.ravel())
    generator = np.random.default_rng(0)
    start = grid.centre(*grid.unflat(int(free[generator.integers(free.size)])))
    guards = GameGuards(scene, patrol, player=start, motion=args.motion)
    fps, speed = 60, 2.0
    x, y = start
    goal = start
    frames, ticking, alarmed, restarts = [], [], [], 0
    for _ in range(int(args.seconds * fps)):
        if abs(goal[0] - x) + abs(goal[1] - y) < 0.1:
            goal = grid.centre(*grid.unflat(int(free[generator.integers(free.size)])))
        # Straight at the goal, one axis at a time, staying on the floor.
        for axis in (0, 1):
            delta = max(-speed / fps, min(speed / fps, goal[axis] - (x, y)[axis]))
            moved = (x + delta, y) if axis == 0 else (x, y + delta)
            cell = grid.cell_of(moved)
            if cell is not None and grid.traversable[cell[1], cell[0]]:
                x, y = moved
            else:
                goal = (x, y)
        tick = guards.episode.tick
        began = time.perf_counter()
        frame = guards.frame((x, y), 1.0 / fps)
        spent = time.perf_counter() - began
        frames.append(spent)
        if frame.tick != tick:
            ticking.append(spent)
            if any(state != "patrol" for state in frame.states):
                alarmed.append(spent)
        if frame.done:
            restarts += 1
            guards = GameGuards(scene, patrol, player=(x, y), motion=args.motion, phase=restarts * 37)
    for label, times in (
        ("every frame", frames),
        ("frames completing a tick", ticking),
        ("frames completing a tick with some guard off patrol", alarmed),
    ):
        if not times:
            continue
        times = sorted(times)
        print(
            f"{label}: {len(times)} frames, median {1000 * statistics.median(times):.3f} ms, 99th percentile "
            f"{1000 * times[int(0.99 * (len(times) - 1))]:.3f} ms, worst {1000 * times[-1]:.3f} ms"
        )
    print(f"3 guards on Square (60 x 60), {args.motion} motion, {args.seconds:g} game s, {restarts} captures")


if __name__ == "__main__":
    main()
