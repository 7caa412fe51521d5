"""Steps and time of RippleFront from random starts on each shipped level.

Usage: ``python benchmarks/random_starts.py [--episodes 20] [--seed 0] [--reference] [LEVEL ...]``

Episode k of a level draws its start (uniform over the largest connected area) and first heading from
``guardsim.simulation.episode_generator(seed, k)``, the same generators ``guardsim play --episode k``
uses. Prints one row per level: median and range of steps, and the wall time of all its episodes.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from guardsim import load_level
from guardsim.motion import run_episode
from guardsim.planners import RippleFront
from guardsim.simulation import Scene, choose_start, episode_generator

LEVELS = sorted(Path(__file__).resolve().parent.parent.joinpath("levels").glob("*.json"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path, default=LEVELS)
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--reference", action="store_true", help="reference vision and loop instead of the fast path")
    args = parser.parse_args()
    print(f"{'level':<20} {'episodes':>8} {'median':>7} {'min':>6} {'max':>6} {'covered':>8} {'seconds':>8}")
    for path in args.levels:
        began = time.perf_counter()
        scene = Scene.from_level(load_level(path))
        steps = []
        covered = 0
        for episode in range(args.episodes):
            cell, heading = choose_start(scene, rng=episode_generator(args.seed, episode))
            trace = run_episode(
                scene, RippleFront(), starts=[cell], headings=[heading], seed=args.seed, reference=args.reference
            )
            steps.append(trace.steps)
            covered += trace.covered
        seconds = time.perf_counter() - began
        print(
            f"{path.stem:<20} {args.episodes:>8} {statistics.median(steps):>7g} {min(steps):>6} {max(steps):>6} "
            f"{covered:>8} {seconds:>8.2f}"
        )


if __name__ == "__main__":
    main()
