"""Fuzz every command with generated inputs and count what each does, per input kind and command.

Usage::

    python benchmarks/fuzz.py --cases 20000            # every kind, spread evenly
    python benchmarks/fuzz.py --cases 500 --kinds level,trace --seed 3

Cases come from ``tests/fuzz_cases.py`` (the generators and the rule ``tests/test_fuzz.py`` checks in
CI). Each runs in a worker process watched from here: a case that runs past ``--timeout`` seconds
(20) is a ``hang`` and one whose worker passes ``--max-rss`` (2 GB) is ``memory``; the worker is then
killed and replaced. Prints one row per (kind, command) with the count of each outcome, the first
example of each failure, and the totals. The importer kinds (movingai, png, tmx, tiled-json) are
counted like the others; their fixes belong to guardsim/importers/.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import tempfile
import time
from collections import Counter, defaultdict
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests.fuzz_cases import KINDS, Templates, cases, generate, make_templates, run_in_process  # noqa: E402

OUTCOMES = (
    "ok", "traceback", "hang", "memory", "huge-line", "multi-line", "unnamed", "unplaced", "accepted-bad", "wrong-result",
    "half-written", "warning", "bad-status",
)  # fmt: skip


def _worker(connection: Connection, templates: Templates) -> None:
    import numpy as np

    while True:
        job = connection.recv()
        if job is None:
            return
        kind, command, seed = job
        case = generate(kind, command, np.random.default_rng(seed), templates)
        with tempfile.TemporaryDirectory() as folder:
            outcome = run_in_process(case, Path(folder))
        connection.send((outcome, case.note))


class Worker:
    """A child process running cases, and the watch kept on it."""

    def __init__(self, templates: Templates) -> None:
        context = multiprocessing.get_context("spawn")
        self.connection, child = context.Pipe()
        # Not a daemon: a bench case may start a pool of its own, which a daemon process cannot.
        self.process = context.Process(target=_worker, args=(child, templates), daemon=False)
        self.process.start()

    def rss(self) -> int:
        """Resident memory of the child in bytes (0 where /proc is missing)."""
        try:
            with open(f"/proc/{self.process.pid}/status", encoding="ascii") as status:
                for line in status:
                    if line.startswith("VmRSS:"):
                        return int(line.split()[1]) * 1024
        except OSError:
            pass
        return 0

    def run(self, job: tuple[str, str, int], timeout: float, max_rss: int) -> tuple[str, str, float]:
        began = time.monotonic()
        self.connection.send(job)
        while True:
            if self.connection.poll(0.1):
                outcome, note = self.connection.recv()
                return outcome, note, time.monotonic() - began
            elapsed = time.monotonic() - began
            if elapsed > timeout:
                return "hang", "", elapsed
            if self.rss() > max_rss:
                return "memory", "", elapsed
            if not self.process.is_alive():
                return "memory", "worker died (killed by the kernel?)", elapsed

    def stop(self) -> None:
        self.process.kill()
        self.process.join()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=500, help="Cases in all, spread over the kinds.")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--kinds", default=",".join(KINDS), help="Comma-separated kinds: " + ", ".join(KINDS))
    parser.add_argument("--timeout", type=float, default=20.0, help="Seconds before a case is a hang.")
    parser.add_argument("--max-rss", type=float, default=2.0, help="Gigabytes before a case is over memory.")
    args = parser.parse_args(argv)
    kinds = tuple(kind.strip() for kind in args.kinds.split(","))
    unknown = set(kinds) - set(KINDS)
    if unknown:
        parser.error(f"unknown kinds: {', '.join(sorted(unknown))}")

    from click.testing import CliRunner

    from guardsim.cli import main as guardsim

    with tempfile.TemporaryDirectory() as folder:
        templates = make_templates(
            lambda line: CliRunner().invoke(guardsim, line, catch_exceptions=False), Path(folder)
        )
    counts: dict[tuple[str, str], Counter[str]] = defaultdict(Counter)
    examples: dict[tuple[str, str, str], str] = {}
    slowest = (0.0, "")
    began = time.monotonic()
    worker = Worker(templates)
    try:
        for kind, command, seed in cases(args.cases, args.seed, kinds):
            outcome, note, seconds = worker.run((kind, command, seed), args.timeout, int(args.max_rss * 2**30))
            if outcome in ("hang", "memory"):
                worker.stop()
                worker = Worker(templates)
                note = note or f"case seed {seed}"
            counts[(kind, command)][outcome] += 1
            if outcome != "ok":
                examples.setdefault((kind, command, outcome), f"{note} (case seed {seed})")
            slowest = max(slowest, (seconds, f"{kind} {command}: {note}"))
    finally:
        worker.connection.send(None)
        worker.process.join(timeout=5)
        if worker.process.is_alive():
            worker.stop()
    _report(counts, examples, args, time.monotonic() - began, slowest)
    failures = sum(count for counter in counts.values() for outcome, count in counter.items() if outcome != "ok")
    return 1 if failures else 0


def _report(
    counts: dict[tuple[str, str], Counter[str]],
    examples: dict[tuple[str, str, str], str],
    args: Any,
    seconds: float,
    slowest: tuple[float, str],
) -> None:
    shown = [outcome for outcome in OUTCOMES if any(counter[outcome] for counter in counts.values())]
    width = max(len(f"{kind} {command}") for kind, command in counts)
    print(f"{'kind command':<{width}}  " + "  ".join(f"{name:>{max(len(name), 5)}}" for name in shown))
    total: Counter[str] = Counter()
    for (kind, command), counter in counts.items():
        total.update(counter)
        cells = "  ".join(f"{counter[name]:>{max(len(name), 5)}}" for name in shown)
        print(f"{kind + ' ' + command:<{width}}  {cells}")
    print(f"{'total':<{width}}  " + "  ".join(f"{total[name]:>{max(len(name), 5)}}" for name in shown))
    print(
        f"\n{sum(total.values())} cases (seed {args.seed}) in {seconds:.0f} s; slowest {slowest[0]:.1f} s ({slowest[1]})"
    )
    found = sum(count for name, count in total.items() if name != "ok")
    print(
        f"findings: {found} ({total['traceback']} tracebacks, {total['hang']} hangs, "
        f"{total['accepted-bad']} wrong acceptances, {found - total['traceback'] - total['hang'] - total['accepted-bad']} "
        "other)"
    )
    for (kind, command, outcome), note in sorted(examples.items()):
        print(f"  {outcome}: {kind} {command}: {note}")


if __name__ == "__main__":
    sys.exit(main())
