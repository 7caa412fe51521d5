"""Time of the paper experiment with and without the lower bounds (issue 15: at most 5 s with them).

Usage::

    python benchmarks/bounds_bench_speed.py                 # 3 runs of each, the shipped levels
    python benchmarks/bounds_bench_speed.py --runs 5 --episodes 200 --workers 2 --no-levels

Runs ``guardsim bench levels/*.json --episodes N`` as a subprocess, with ``--bounds`` and with
``--no-bounds``, alternately, each into a fresh folder; prints the wall seconds of every run (the whole
command: start-up, the worker processes, writing the results), the CPU seconds (user + system) of the
command and of every process it started, their medians, and the one-minute load average before each
run. The machine is shared, so the load says how far a wall figure is to be trusted; the CPU seconds
depend on it far less. Then, in this process, the CPU time one worker spends per level on the view
table (once per level and process) and per start on :func:`guardsim.bounds.lower_bounds` (200 bench
starts, after the first one).

The CPU seconds count processes that outlive the command too (a fork server is orphaned when the
command exits): this process becomes their "subreaper" (Linux ``PR_SET_CHILD_SUBREAPER``) and waits for
them, so ``RUSAGE_CHILDREN`` holds them all. Elsewhere only the command and the workers it waited for
count.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
LEVELS = sorted((REPO / "levels").glob("*.json"))
GUARDSIM = Path(sys.executable).parent / "guardsim"


def adopt_orphans() -> None:
    """Become the subreaper of the processes started from here, so that their CPU time reaches us."""
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)  # 36 is PR_SET_CHILD_SUBREAPER


def children_cpu() -> float:
    """User + system CPU seconds of the waited-for processes started from here, and their descendants."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def bench_seconds(guardsim: str, episodes: int, bounds: bool, workers: int | None) -> tuple[float, float]:
    """Wall seconds and CPU seconds of one ``guardsim bench`` run over the shipped levels."""
    with tempfile.TemporaryDirectory() as folder:
        command = [guardsim, "bench", *map(str, LEVELS), "--episodes", str(episodes), "--out", folder]
        command.append("--bounds" if bounds else "--no-bounds")
        if workers is not None:
            command += ["--workers", str(workers)]
        cpu = children_cpu()
        began = time.perf_counter()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
        wall = time.perf_counter() - began
        while True:  # orphans of the command, now ours
            try:
                os.wait()
            except ChildProcessError:
                break
        return wall, children_cpu() - cpu


def per_level(episodes: int) -> None:
    """CPU milliseconds of the view table and of the bounds per start, level by level."""
    from guardsim import load_level
    from guardsim.bounds import lower_bounds
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
    parser.add_argument("--workers", type=int, help="Passed to guardsim bench [default: its own].")
    parser.add_argument(
        "--guardsim",
        action="append",
        help="The guardsim command to time; give it twice to time two (an older checkout's) in turn "
        "[default: this environment's].",
    )
    parser.add_argument("--no-levels", action="store_true", help="Skip the per-level CPU table.")
    arguments = parser.parse_args()
    commands = arguments.guardsim or [str(GUARDSIM)]
    adopt_orphans()
    times: dict[tuple[str, bool], list[tuple[float, float]]] = {}
    print("| run | command | bounds | load (1 min) | wall s | CPU s |")
    print("| --- | --- | --- | --- | --- | --- |")
    for run in range(arguments.runs):
        for command in commands:
            for bounds in (True, False):
                load = os.getloadavg()[0]
                wall, cpu = bench_seconds(command, arguments.episodes, bounds, arguments.workers)
                times.setdefault((command, bounds), []).append((wall, cpu))
                print(
                    f"| {run + 1} | {command} | {'yes' if bounds else 'no'} | {load:.2f} | {wall:.2f} | {cpu:.2f} |",
                    flush=True,
                )
    print()
    for (command, bounds), runs in times.items():
        wall = statistics.median(w for w, _ in runs)
        cpu = statistics.median(c for _, c in runs)
        print(f"median, {command}, {'with' if bounds else 'without'} the bounds: {wall:.2f} s wall, {cpu:.2f} CPU s")
    if not arguments.no_levels:
        per_level(arguments.episodes)


if __name__ == "__main__":
    main()
