"""Episodes per second of ``guardsim bench`` on each shipped level, with 1 and 2 workers.

Usage: ``python benchmarks/bench_throughput.py [--episodes 200] [--workers 1,2] [--repeat 3]
[--start-method forkserver] [--reference] [LEVEL ...]``

Each measurement is a fresh batch (RippleFront, default vision) into a temporary folder, timed from
starting the executor to the last row written, so it includes starting the worker processes and
building each worker's scene and vision cache, as a user's run does. The last line, ``all``, is every
level in one batch on one pool, as ``guardsim bench levels/*.json`` runs them.

For each worker count the script prints episodes per second (wall clock; the best of ``--repeat`` runs,
since the machine is shared and the best run is the least disturbed) and the CPU seconds that run used
in this process and all its worker processes (which does not depend on what else the machine is
doing). Rows are checked identical (apart from the seconds column) across worker counts.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

import psutil

from guardsim.experiment import Batch, BatchLevel, EpisodeRecord, finish_batch, run_batch, run_spec, start_batch
from guardsim.experiment.episodes import forget_scenes
from guardsim.experiment.executors import InProcess, LocalPool, default_start_method

LEVELS = sorted(Path(__file__).resolve().parent.parent.joinpath("levels").glob("*.json"))


class Measurement(NamedTuple):
    seconds: float
    """Wall time from starting the executor to the last row."""
    cpu_seconds: float
    """User + system time of this process and its worker processes over the same span."""
    rows: list[EpisodeRecord]
    """The rows, wall-time columns blanked."""


def cpu_seconds(process: psutil.Process) -> float:
    """CPU time of ``process`` and its live descendants (workers are still alive when this is called)."""
    total = 0.0
    for member in (process, *process.children(recursive=True)):
        try:
            times = member.cpu_times()
        except psutil.NoSuchProcess:
            continue
        total += times.user + times.system
    return total


def measure(
    levels: tuple[BatchLevel, ...], episodes: int, workers: int, start_method: str, reference: bool
) -> Measurement:
    """One batch of ``episodes`` per level on ``workers``, from cold (no scene cached in this process)."""
    batch = Batch(levels, ("ripplefront",), episodes, seed=0, reference=reference)
    me = psutil.Process()
    with tempfile.TemporaryDirectory() as folder:
        _, pending = start_batch(batch, Path(folder))
        forget_scenes()  # each measurement starts cold, as a new command does
        cpu_before = cpu_seconds(me)
        began = time.perf_counter()
        executor = InProcess() if workers == 1 else LocalPool(workers, start_method, preload=[run_spec.__module__])
        with executor:
            report = run_batch(pending, Path(folder), executor)
            seconds = time.perf_counter() - began
            cpu = cpu_seconds(me) - cpu_before
        assert report.not_run == 0, report.failure
        records, _ = finish_batch(batch, Path(folder))
    return Measurement(seconds, cpu, [record._replace(seconds=0.0, plan_us_per_step=None) for record in records])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path, default=LEVELS)
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement; the best is reported")
    parser.add_argument("--workers", default="1,2", help="comma-separated worker counts")
    parser.add_argument("--start-method", default=default_start_method(), choices=["fork", "forkserver", "spawn"])
    parser.add_argument("--reference", action="store_true", help="reference vision and loop instead of the fast path")
    args = parser.parse_args()
    counts = [int(count) for count in args.workers.split(",")]
    print(
        f"{args.episodes} episodes per level, best of {args.repeat}, start method {args.start_method}, "
        f"reference={args.reference}, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at start"
    )
    print(f"{'level':<14}" + "".join(f"{f'{count}w ep/s':>11}{f'{count}w CPU s':>11}" for count in counts))
    loaded = [BatchLevel.load(str(path)) for path in args.levels]
    cases = [(path.stem, (level,)) for path, level in zip(args.levels, loaded)] + [("all", tuple(loaded))]
    for name, levels in cases:
        cells = []
        rows = None
        for count in counts:
            runs = [
                measure(levels, args.episodes, count, args.start_method, args.reference) for _ in range(args.repeat)
            ]
            if rows is not None and runs[0].rows != rows:
                raise SystemExit(f"{name}: rows differ between worker counts")
            rows = runs[0].rows
            best = min(runs, key=lambda run: run.seconds)
            cells.append(f"{len(rows) / best.seconds:>11.1f}{best.cpu_seconds:>11.2f}")
        print(f"{name:<14}" + "".join(cells))


if __name__ == "__main__":
    main()
