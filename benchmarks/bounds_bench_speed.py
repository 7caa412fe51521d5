"""Time of the paper experiment with and without the lower bounds (issue 15: at most 5 s with them).

Usage::

    python benchmarks/bounds_bench_speed.py                 # 3 runs of each, the shipped levels
    python benchmarks/bounds_bench_speed.py --runs 5 --episodes 200

Runs ``guardsim bench levels/*.json --episodes N`` as a subprocess, with ``--bounds`` and with
``--no-bounds``, alternately, each into a fresh folder; prints the wall seconds of every run (the whole
command: start-up, two worker processes, writing the results), their median, and the one-minute load
average before each run. The machine is shared, so the load says how far a figure is to be trusted. Then,
in this process, the CPU time one worker spends per level on the view table (once per level and process)
and per start on :func:`guardsim.bounds.lower_bounds` (200 bench starts, after the first one).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
LEVELS = sorted((REPO / "levels").glob("*.json"))
GUARDSIM = Path(sys.executable).parent / "guardsim"


def bench_seconds(episodes: int, bounds: bool) -> float:
    """Wall seconds of one ``guardsim bench`` run over the shipped levels."""
    with tempfile.TemporaryDirectory() as folder:
        command = [str(GUARDSIM), "bench", *map(str, LEVELS), "--episodes", str(episodes), "--out", folder]
        command.append("--bounds" if bounds else "--no-bounds")
        began = time.perf_counter()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
        return time.perf_counter() - began


def per_level(episodes: int) -> None:
    """CPU milliseconds of the view table and of the bounds per start, level by level."""
    from guardsim.bounds import lower_bounds
    from guardsim.level import load_level
    from guardsim.simulation import Scene, choose_start, episode_generator
    from guardsim.vision.table import view_table

    print("\n| level | view table CPU ms | first start CPU ms | bounds CPU ms per start (median) |")
    print("| --- | --- | --- | --- |")
    for path in LEVELS:
        scene = Scene.from_level(load_level(path))
        vision = scene.vision()
        before = time.process_time()
        view_table(scene.grid, vision)
        table = time.process_time() - before
        cpu = []
        for episode in range(episodes):
            cell, heading = choose_start(scene, rng=episode_generator(0, episode))
            before = time.process_time()
            lower_bounds(scene, cell, heading, vision)
            cpu.append(time.process_time() - before)
        print(
            f"| {path.stem} | {table * 1000:.0f} | {cpu[0] * 1000:.1f} | {statistics.median(cpu[1:]) * 1000:.2f} |",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="Runs of each command.")
    parser.add_argument("--episodes", type=int, default=200, help="Episodes per level.")
    arguments = parser.parse_args()
    times: dict[bool, list[float]] = {True: [], False: []}
    print("| run | bounds | load (1 min) | seconds |")
    print("| --- | --- | --- | --- |")
    for run in range(arguments.runs):
        for bounds in (True, False):
            load = os.getloadavg()[0]
            seconds = bench_seconds(arguments.episodes, bounds)
            times[bounds].append(seconds)
            print(f"| {run + 1} | {'yes' if bounds else 'no'} | {load:.2f} | {seconds:.2f} |", flush=True)
    print(
        f"\nmedian: {statistics.median(times[True]):.2f} s with the bounds, "
        f"{statistics.median(times[False]):.2f} s without"
    )
    per_level(arguments.episodes)


if __name__ == "__main__":
    main()
