"""Episodes per second of ``guardsim bench`` on each shipped level, with 1 and 2 workers.

Usage: ``python benchmarks/bench_throughput.py [--episodes 40] [--workers 1,2] [--start-method forkserver]
[--reference] [LEVEL ...]``

Each measurement is a fresh batch (RippleFront, default vision) into a temporary folder, timed from
starting the executor to the last row written, so it includes starting the worker processes and
building each worker's scene and vision cache, as a user's run does. Rows are checked identical (apart
from the seconds column) across worker counts.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from guardsim.executors import InProcess, LocalPool, default_start_method
from guardsim.experiment import Batch, BatchLevel, finish_batch, run_batch, start_batch
from guardsim.experiment.episodes import forget_scenes

LEVELS = sorted(Path(__file__).resolve().parent.parent.joinpath("levels").glob("*.json"))


def measure(level: BatchLevel, episodes: int, workers: int, start_method: str, reference: bool) -> tuple[float, list]:
    """Seconds for one batch of ``episodes`` on ``workers``, and its rows without the seconds column."""
    batch = Batch((level,), ("ripplefront",), episodes, seed=0, reference=reference)
    with tempfile.TemporaryDirectory() as folder:
        _, pending = start_batch(batch, Path(folder))
        forget_scenes()  # each measurement starts cold, as a new command does
        began = time.perf_counter()
        executor = InProcess() if workers == 1 else LocalPool(workers, start_method)
        with executor:
            report = run_batch(pending, Path(folder), executor)
        seconds = time.perf_counter() - began
        assert report.not_run == 0, report.failure
        records, _ = finish_batch(batch, Path(folder))
    return seconds, [record._replace(seconds=0.0) for record in records]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path, default=LEVELS)
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--workers", default="1,2", help="comma-separated worker counts")
    parser.add_argument("--start-method", default=default_start_method(), choices=["fork", "forkserver", "spawn"])
    parser.add_argument("--reference", action="store_true", help="reference vision instead of the fast path")
    args = parser.parse_args()
    counts = [int(count) for count in args.workers.split(",")]
    print(f"{args.episodes} episodes per level, start method {args.start_method}, reference={args.reference}")
    print(f"{'level':<20}" + "".join(f"{f'{count} worker(s) ep/s':>20}" for count in counts) + f"{'speed-up':>10}")
    for path in args.levels:
        level = BatchLevel.load(str(path))
        rates = []
        rows = None
        for count in counts:
            seconds, records = measure(level, args.episodes, count, args.start_method, args.reference)
            if rows is not None and records != rows:
                raise SystemExit(f"{path}: rows differ between worker counts")
            rows = records
            rates.append(args.episodes / seconds)
        print(f"{path.stem:<20}" + "".join(f"{rate:>20.1f}" for rate in rates) + f"{rates[-1] / rates[0]:>9.2f}x")


if __name__ == "__main__":
    main()
