"""First use: the wall time of each command's first run with an empty compiled cache, and of the next run.

Each command runs in a fresh process on a copy of this checkout without bytecode or compiled caches
(``GUARDSIM_CACHE_DIR`` and ``NUMBA_CACHE_DIR`` pointed at a new empty folder), as a new install runs
it, then once more on the cache the first run left. Each figure is the whole process, from start to
exit, as a user waits for it. ``--rev REV`` measures another commit the same way (a ``git worktree``),
for before/after tables; ``--fresh-venv`` installs the copy into a new virtual environment first.

``--after-compile`` runs the install step first (``guardsim compile``, timed once, into a folder each
command's cache starts as a copy of): the first run a user who followed the README meets.

    python benchmarks/cold_start.py [--commands play,tour,patrol,sneak,bounds,optimum,bench] [--runs 1]
    python benchmarks/cold_start.py --rev d763654
    python benchmarks/cold_start.py --after-compile
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

#: The commands measured, in table order (``--commands`` picks among them).
NAMES = (
    "play",
    "tour",
    "patrol",
    "sneak",
    "bounds",
    "optimum",
    "bench",
    "optimum-team",
    "patrol-team",
    "sneak-undetected",
    "alert",
    "check",
    "report",
    "diff",
    "render",
    "validate",
)
#: The commands that read the patrol made beforehand (in a cache of its own, so that theirs is cold).
NEEDS_PATROL = frozenset({"sneak", "sneak-undetected", "alert", "check"})

#: A 12 x 9 room with one pillar, for ``optimum``.
ROOM = {
    "name": "room with a pillar",
    "outer": [[0, 0], [12, 0], [12, 9], [0, 9]],
    "holes": [[[5, 4], [7, 4], [7, 5], [5, 5]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}


def command_lines(scratch: Path, checkout: Path, run: str) -> dict[str, list[str]]:
    """Each measured command's arguments (after ``guardsim``); ``run`` keeps output folders apart."""
    square = str(checkout / "levels" / "square.json")
    patrol = str(scratch / "setup" / "patrol.json")
    return {
        "play": ["play", square],
        "tour": ["play", square, "--planner", "tour"],
        "patrol": ["patrol", square, "--out", str(scratch / f"patrol-{run}")],
        "sneak": ["sneak", square, "--patrol", patrol,
                  "--from", "2.5,2.5", "--to", "57.5,57.5"],
        "bounds": ["bounds", square],
        "optimum": ["optimum", str(scratch / "room.json")],
        "bench": ["bench", square, "--episodes", "4", "--workers", "1", "--out", str(scratch / f"bench-{run}")],
        "optimum-team": ["optimum", str(scratch / "room.json"), "--start", "0.5,0.5", "--start", "11.5,8.5", "--guards", "2"],
        "patrol-team": ["patrol", square, "--guards", "2", "--out", str(scratch / f"patrol-team-{run}")],
        "sneak-undetected": ["sneak", square, "--patrol", patrol, "--from", "2.5,2.5", "--to", "57.5,57.5",
                             "--undetected"],
        "alert": ["alert", square, "--patrol", patrol, "--from", "2.5,2.5", "--to", "57.5,57.5",
                  "--trace", str(scratch / f"alert-{run}.json")],
        "check": ["check", square, "--patrol", patrol, "--max-idleness", "1000", "--sneak", "2.5,2.5", "57.5,57.5",
                  "--expect", "sneaks"],
        "report": ["report", square],
        "diff": ["diff", square, str(checkout / "levels" / "passages.json")],
        "render": ["render", square, "--png", str(scratch / f"render-{run}.png")],
        "validate": ["validate", square],
    }  # fmt: skip


def fresh_copy(source: Path, target: Path) -> Path:
    """A copy of a checkout without bytecode, compiled caches or its virtual environment."""
    ignore = shutil.ignore_patterns(
        ".venv", ".git", "__pycache__", "*.nbi", "*.nbc", "*.egg-info", ".mypy_cache", ".ruff_cache", ".pytest_cache",
        ".hypothesis",
    )  # fmt: skip
    shutil.copytree(source, target, ignore=ignore)
    return target


def timed(command: list[str], env: dict[str, str], cwd: Path) -> tuple[float, int, str]:
    """Wall seconds, exit status and standard error of one run."""
    began = time.perf_counter()
    done = subprocess.run(
        command, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, errors="replace"
    )
    return time.perf_counter() - began, done.returncode, done.stderr


def failure(status: int, stderr: str) -> str:
    """A failed run for a table cell: its exit status and the last line of its standard error."""
    last = (stderr.strip().splitlines() or ["(no stderr)"])[-1].strip()[:120]
    return f"exit {status}: {last}".replace("|", "\\|")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--commands", default=",".join(NAMES), help=f"comma-separated, of: {','.join(NAMES)}")
    parser.add_argument("--runs", type=int, default=1, help="cold runs per command (each with a new empty cache)")
    parser.add_argument("--rev", help="measure this commit instead of the working tree")
    parser.add_argument("--fresh-venv", action="store_true", help="install into a new virtual environment first")
    parser.add_argument("--after-compile", action="store_true",
                        help="run `guardsim compile` first: each cache starts compiled, as after the install step")
    args = parser.parse_args()
    args.commands = [name.strip() for name in args.commands.split(",") if name.strip()]
    unknown = [name for name in args.commands if name not in NAMES]
    if unknown or not args.commands:
        parser.error(f"--commands: unknown {','.join(unknown) or '(none given)'}; known: {','.join(NAMES)}")
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    with tempfile.TemporaryDirectory() as folder:
        scratch = Path(folder)
        (scratch / "room.json").write_text(json.dumps(ROOM))
        if args.rev:
            checkout = scratch / "checkout"
            subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", str(checkout), args.rev],
                           check=True, capture_output=True)  # fmt: skip
        else:
            checkout = REPO
        try:
            rows = measure(args, scratch, checkout)
        finally:
            if args.rev:
                subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(checkout)], check=False)
    label = args.rev or "working tree"
    # Other work on the two cores changes these figures more than most code changes: say how busy it was.
    load = ", ".join(f"{value:.1f}" for value in os.getloadavg())
    caches = "caches after `guardsim compile`" if args.after_compile else "empty caches"
    print(f"first use on {label} ({'fresh venv' if args.fresh_venv else 'this venv'}, {caches}), seconds;"
          f" load average at the end {load}")  # fmt: skip
    print("| command | first run s | second run s | said compiling |")
    print("| --- | --- | --- | --- |")
    for row in rows:
        print(row)


def measure(args: argparse.Namespace, scratch: Path, checkout: Path) -> list[str]:
    if args.fresh_venv:
        source = fresh_copy(checkout, scratch / "source")
        subprocess.run([sys.executable, "-m", "venv", str(scratch / "venv")], check=True)
        subprocess.run([str(scratch / "venv" / "bin" / "python"), "-m", "pip", "install", "--quiet", str(source)],
                       check=True)  # fmt: skip
        python, base_env = str(scratch / "venv" / "bin" / "python"), dict(os.environ)
    else:
        python, base_env = sys.executable, dict(os.environ)
    base_env.pop("GUARDSIM_COMPILE_NOTICE", None)

    def environment(cache: Path, copy: Path | None) -> dict[str, str]:
        env = dict(base_env, GUARDSIM_CACHE_DIR=str(cache), NUMBA_CACHE_DIR=str(cache))
        if copy is not None:
            env["PYTHONPATH"] = str(copy)
        return env

    def run_line(name: str, run: str) -> list[str]:
        return [python, "-m", "guardsim.cli", *command_lines(scratch, checkout, run)[name]]

    # sneak, alert and check read a patrol, made beforehand in a cache of its own, so that theirs is cold.
    setup_failed = ""
    if NEEDS_PATROL & set(args.commands):
        setup_copy = None if args.fresh_venv else fresh_copy(checkout, scratch / "copy-setup")
        setup = [*run_line("patrol", "setup")[:5], "--out", str(scratch / "setup")]
        _, status, stderr = timed(setup, environment(scratch / "cache-setup", setup_copy), scratch)
        if status:
            setup_failed = "making patrol.json: " + failure(status, stderr)
    rows: list[str] = []
    compiled = scratch / "cache-compiled"
    installed: Path | None = None
    if args.after_compile:
        # numba finds a cached function under its source file's path: the commands run on this same copy
        # (its bytecode compiled by the step, as an install's is).
        installed = None if args.fresh_venv else fresh_copy(checkout, scratch / "copy-compile")
        seconds, status, stderr = timed([python, "-m", "guardsim.cli", "compile"], environment(compiled, installed),
                                        scratch)  # fmt: skip
        rows.append(f"| `guardsim compile` | {failure(status, stderr) if status else f'{seconds:.1f}'} | | |")
        print(rows[-1], file=sys.stderr, flush=True)
    for name in args.commands:
        shown = " ".join(command_lines(scratch, checkout, "0")[name])
        shown = shown.replace(f"{checkout}/", "").replace(str(scratch), "…")
        cold: list[float] = []
        warm: list[float] = []
        said: list[bool] = []
        failed = setup_failed if name in NEEDS_PATROL else ""
        for run in range(args.runs):
            if failed:
                break
            if args.after_compile:
                copy = installed
            else:
                copy = None if args.fresh_venv else fresh_copy(checkout, scratch / f"copy-{name}-{run}")
            cache = scratch / f"cache-{name}-{run}"
            if args.after_compile:
                shutil.copytree(compiled, cache)
            env = environment(cache, copy)
            # Run from the scratch folder: from the checkout, Python would import its package, not the copy.
            seconds, status, stderr = timed(run_line(name, f"{run}a"), env, scratch)
            said.append("compiling" in stderr)
            if status:
                failed = "first run " + failure(status, stderr)
                break
            cold.append(seconds)
            # A new output folder: bench resumes from a results.csv it finds, and would run nothing.
            seconds, status, stderr = timed(run_line(name, f"{run}b"), env, scratch)
            if status:
                failed = "second run " + failure(status, stderr)
                break
            warm.append(seconds)
        compiling = ("yes" if all(said) else "no" if not any(said) else "some runs") if said else ""
        if failed:
            rows.append(f"| `guardsim {shown}` | {failed} | | {compiling} |")
        else:
            rows.append(f"| `guardsim {shown}` | {median(cold):.1f} | {median(warm):.1f} | {compiling} |")
        print(rows[-1], file=sys.stderr, flush=True)
    return rows


def median(values: list[float]) -> float:
    ordered = sorted(values)
    return ordered[len(ordered) // 2]


if __name__ == "__main__":
    main()
