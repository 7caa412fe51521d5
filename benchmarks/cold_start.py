"""Cold start: the wall time of the first ``guardsim play`` on a fresh install, and of the next one.

"Fresh" means a new virtual environment with guardsim installed from this checkout (``--fresh-venv``),
or, by default, this checkout's ``.venv`` with an empty numba cache and no compiled bytecode of
guardsim's own (which is what a new install has: pip compiles the dependencies' bytecode at install).
Each figure is the whole process, from start to exit, as a user waits for it.

    python benchmarks/cold_start.py [--level levels/square.json] [--runs 3] [--fresh-venv]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def timed(command: list[str], env: dict[str, str], cwd: Path) -> float:
    began = time.perf_counter()
    subprocess.run(command, env=env, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - began


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", default="levels/square.json")
    parser.add_argument("--runs", type=int, default=3, help="cold runs (each with a new empty cache)")
    parser.add_argument("--fresh-venv", action="store_true", help="install into a new virtual environment first")
    parser.add_argument("--extra", action="append", default=[], help="more play options, e.g. --extra=--planner=tour")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)

        def fresh_copy(name: str) -> Path:
            # A copy of the checkout without bytecode or numba caches.
            copy = root / name
            shutil.copytree(REPO, copy, ignore=shutil.ignore_patterns(".venv", ".git", "__pycache__", "*.nbi", "*.nbc"))
            return copy

        source = fresh_copy("guardsim-src")
        if args.fresh_venv:
            subprocess.run([sys.executable, "-m", "venv", str(root / "venv")], check=True)
            pip = [str(root / "venv" / "bin" / "python"), "-m", "pip", "install", "--quiet"]
            subprocess.run([*pip, str(source)], check=True)
            python = str(root / "venv" / "bin" / "python")
            env = dict(os.environ)
        else:
            python = str(REPO / ".venv" / "bin" / "python")
            env = dict(os.environ, PYTHONPATH=str(source))
        command = [python, "-m", "guardsim.cli", "play", str(REPO / args.level), *args.extra]
        cold, warm = [], []
        for run in range(args.runs):
            env["NUMBA_CACHE_DIR"] = str(root / f"numba-cache-{run}")
            if not args.fresh_venv and run:
                env["PYTHONPATH"] = str(fresh_copy(f"guardsim-src-{run}"))
            cold.append(timed(command, env, root))
            warm.append(timed(command, env, root))
    print(
        f"level {args.level} {' '.join(args.extra)} ({'fresh venv' if args.fresh_venv else 'this venv, empty caches'})"
    )
    print(f"first play (cold): {' '.join(f'{s:.2f}' for s in cold)} s; median {sorted(cold)[len(cold) // 2]:.2f} s")
    print(f"second play (warm): {' '.join(f'{s:.2f}' for s in warm)} s; median {sorted(warm)[len(warm) // 2]:.2f} s")


if __name__ == "__main__":
    main()
