"""What drawing costs: whole-process wall time and peak memory of `guardsim play LEVEL` with and without
`--gif` (and `--html`), and the sizes of what they write, on every shipped level and a 512 x 512 Moving AI
map. Prints one Markdown table row per level.

Each command runs in its own process, ``--repeat`` times (the median is shown, after one warm-up run
that fills the compiled-code cache); peak memory is the process's maximum resident set size from
``os.wait4``. The target (issue 11): with ``--gif``, at most 1.5 x the time and 1.3 x the memory of the
same ``play`` without it.

    .venv/bin/python benchmarks/render_speed.py                      # this tree
    .venv/bin/python benchmarks/render_speed.py --tree /tmp/before   # another checkout, e.g. the old renderer
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
MOVING_AI = REPO.parent / "shared" / "maps" / "movingai" / "AR0603SR.map"


def run(tree: Path, arguments: list[str]) -> tuple[float, float, int]:
    """Wall seconds, CPU seconds (user + system) and peak resident kilobytes of one ``guardsim`` process
    run from ``tree``. CPU time is the steadier figure on a machine shared with other work."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    command = [sys.executable, "-c", "from guardsim.cli import main; main()", *arguments]
    began = time.perf_counter()
    process = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=tree)
    _, status, usage = os.wait4(process.pid, 0)
    seconds = time.perf_counter() - began
    stderr = process.stderr.read().decode() if process.stderr else ""
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(arguments)} failed: {stderr.strip()[-500:]}")
    return seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss


def measure(tree: Path, level: str, extra: list[str], repeat: int) -> tuple[float, float, int]:
    """Medians of :func:`run` over ``repeat`` runs of ``play LEVEL EXTRA``."""
    runs = [run(tree, ["play", level, *extra]) for _ in range(repeat)]
    wall, cpu, memory = (statistics.median(values) for values in zip(*runs))
    return wall, cpu, int(memory)


def level_arguments(tree: Path, work: Path) -> list[tuple[str, str]]:
    """``(name, path)`` of each level to measure; the Moving AI map imported once if ``play`` cannot read
    maps directly in ``tree``."""
    levels = [(path.stem, str(path)) for path in sorted((tree / "levels").glob("*.json"))]
    if MOVING_AI.is_file():
        imported = work / "AR0603SR.json"
        try:
            run(tree, ["import", str(MOVING_AI), "--out", str(imported)])
            levels.append((MOVING_AI.stem, str(imported)))
        except SystemExit as error:
            print(f"skipping {MOVING_AI.name}: {error}", file=sys.stderr)
    return levels


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tree", type=Path, default=REPO, help="checkout to measure (default: this one)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per command (median shown)")
    parser.add_argument("--html", action="store_true", help="also measure --gif --html together")
    parser.add_argument("--level", action="append", help="only levels with this name (repeatable)")
    options = parser.parse_args()
    tree = options.tree.resolve()
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        gif, page = work / "out.gif", work / "out.html"
        print(f"tree {tree}, median of {options.repeat}")
        print(
            "| level | play wall (s) | --gif wall (s) | wall ratio | play CPU (s) | --gif CPU (s) | CPU ratio "
            "| play (MB) | --gif (MB) | memory ratio | GIF (kB) |"
            + (" --gif --html CPU (s) | HTML (kB) |" if options.html else "")
        )
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|---:|" if options.html else ""))
        for name, level in level_arguments(tree, work):
            if options.level and name not in options.level:
                continue
            run(tree, ["play", level])  # warm-up: fills the compiled-code cache
            plain_wall, plain_cpu, plain_memory = measure(tree, level, [], options.repeat)
            gif_wall, gif_cpu, gif_memory = measure(tree, level, ["--gif", str(gif)], options.repeat)
            row = (
                f"| {name} | {plain_wall:.2f} | {gif_wall:.2f} | {gif_wall / plain_wall:.2f} | {plain_cpu:.2f} | "
                f"{gif_cpu:.2f} | {gif_cpu / plain_cpu:.2f} | {plain_memory / 1024:.0f} | {gif_memory / 1024:.0f} | "
                f"{gif_memory / plain_memory:.2f} | {gif.stat().st_size / 1000:.0f} |"
            )
            if options.html:
                _, both_cpu, _ = measure(tree, level, ["--gif", str(gif), "--html", str(page)], options.repeat)
                row += f" {both_cpu:.2f} | {page.stat().st_size / 1000:.0f} |"
            print(row, flush=True)


if __name__ == "__main__":
    main()
