"""Record guardsim/kernels/plan.json: what each command compiles, with what argument types, in what order.

Runs each command once on a shipped level, in a fresh process with an empty cache and without compiling
ahead, and notes every compiled function it compiles (those it calls from Python, and the guardsim
kernels they call whose argument types can be written down), its argument types, its own compile time
and the entry it was compiled under. ``guardsim.kernels.ahead`` replays the plan on two
processes the first time a command runs. Re-run after changing a kernel's arguments or adding one to a
command; ``tests/test_kernels.py`` says when the plan is stale.

    python benchmarks/compile_plan.py [--commands tour,patrol,...]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PLAN = REPO / "guardsim" / "kernels" / "plan.json"

#: A 12 x 9 room with one pillar: small enough for ``optimum`` to prove in a moment.
ROOM = {
    "name": "room with a pillar",
    "outer": [[0, 0], [12, 0], [12, 9], [0, 9]],
    "holes": [[[5, 4], [7, 4], [7, 5], [5, 5]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}


def commands(scratch: Path) -> dict[str, list[str]]:
    """Each plan entry's command line (``guardsim`` left out)."""
    square = str(REPO / "levels" / "square.json")
    return {
        "play:tour": ["play", square, "--planner", "tour"],
        "patrol": ["patrol", square, "--out", str(scratch / "patrol")],
        "sneak": ["sneak", square, "--patrol", str(scratch / "patrol" / "patrol.json"),
                  "--from", "2.5,2.5", "--to", "57.5,57.5", "--undetected", "--out", str(scratch / "sneak")],
        # With audible steps the searches choose gaits (dense, with the noise rule): sneak --unheard, check --unheard.
        "sneak:unheard": ["sneak", square, "--patrol", str(scratch / "patrol" / "patrol.json"), "--from", "2.5,2.5",
                          "--to", "57.5,57.5", "--unheard", "--walk-noise", "3", "--sneak-noise", "1"],
        "alert": ["alert", square, "--patrol", str(scratch / "patrol" / "patrol.json"),
                  "--from", "10.5,10.5", "--to", "50.5,50.5"],
        "bounds": ["bounds", square],
        "optimum": ["optimum", str(scratch / "room.json")],
        "bench": ["bench", square, "--episodes", "4", "--workers", "1", "--out", str(scratch / "bench")],
        "optimum:team": ["optimum", str(scratch / "room.json"), "--start", "0.5,0.5", "--start", "11.5,8.5",
                         "--guards", "2"],
        "patrol:team": ["patrol", square, "--guards", "2", "--out", str(scratch / "patrol-team")],
        "check": ["check", square, "--patrol", str(scratch / "patrol" / "patrol.json"), "--max-idleness", "1000",
                  "--no-unreachable", "--safe", "30.5,30.5", "--sneak", "2.5,2.5", "57.5,57.5", "--expect", "sneaks",
                  "--undetected"],
        "fortify": ["fortify", square, "--patrol", str(scratch / "patrol" / "patrol.json"), "--from", "2.5,2.5",
                    "--to", "57.5,57.5", "--cameras", "1", "--posts", "0"],
        # report, diff, check --baseline and watch: one analysis (loop patrol, sneak checks, ways, risk).
        "report": ["report", square],
    }  # fmt: skip


RECORDER = """
import json, sys, time
from numba.core import event
from guardsim.kernels.ahead import encode_type
# Each compile a frame: [began, seconds of planned callees, frame number, caller's frame number].
records, stack, count, skipped = [], [], [0], {}
class Recorder(event.Listener):
    def on_start(self, e):
        stack.append([time.perf_counter(), 0.0, count[0], stack[-1][2] if stack else -1])
        count[0] += 1
    def on_end(self, e):
        began, below, frame, caller = stack.pop()
        spent = time.perf_counter() - began
        function = e.data["dispatcher"].py_func
        try:
            arguments = [encode_type(a) for a in e.data["args"]]
        except TypeError:
            arguments = None
        # numba's own helpers, callees whose argument types cannot be written down and functions that are
        # not dispatchers (register_jitable ones, compiled only inside callers) compile with their
        # caller: their time stays in it.
        own = getattr(sys.modules.get(function.__module__), function.__name__, None)
        if caller >= 0 and (arguments is None or not function.__module__.startswith("guardsim.")
                            or not hasattr(own, "compile")):
            skipped[frame] = caller
            stack[-1][1] += below
            return
        if stack:
            stack[-1][1] += spent
        records.append([function.__module__, function.__name__, arguments, round(spent - below, 2), frame, caller])
event.register("numba:compile", Recorder())
from guardsim.cli import main
try:
    main(sys.argv[2:])
except SystemExit:
    pass
index = {record[4]: number for number, record in enumerate(records)}
def planned(caller):
    # A caller left out passes its callees to the nearest planned one above it (-1: Python).
    while caller in skipped:
        caller = skipped[caller]
    return index.get(caller, -1)
plan = [[m, f, a, s, planned(caller)] for m, f, a, s, _, caller in records]
with open(sys.argv[1], "w") as out:
    json.dump(plan, out)
"""


def record(name: str, line: list[str], scratch: Path) -> list[list[object]]:
    env = dict(os.environ, GUARDSIM_CACHE_DIR=str(scratch / f"cache-{name}"), GUARDSIM_COMPILE_AHEAD="0",
               GUARDSIM_COMPILE_NOTICE="0")  # fmt: skip
    out = scratch / f"{name}.json"
    subprocess.run([sys.executable, "-c", RECORDER, str(out), *line], env=env, cwd=REPO, check=True,
                   stdout=subprocess.DEVNULL)  # fmt: skip
    entries: list[list[object]] = json.loads(out.read_text())
    return entries


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--commands", help="comma-separated plan entries to record again (default: all)")
    args = parser.parse_args()
    plan = json.loads(PLAN.read_text()) if PLAN.exists() else {}
    with tempfile.TemporaryDirectory() as folder:
        scratch = Path(folder)
        (scratch / "room.json").write_text(json.dumps(ROOM))
        lines = commands(scratch)
        # sneak reads a patrol: make it first, in a cache of its own.
        env = dict(os.environ, GUARDSIM_CACHE_DIR=str(scratch / "cache-setup"), GUARDSIM_COMPILE_NOTICE="0")
        subprocess.run([sys.executable, "-m", "guardsim.cli", *lines["patrol"]], env=env, cwd=REPO, check=True,
                       stdout=subprocess.DEVNULL)  # fmt: skip
        chosen = args.commands.split(",") if args.commands else list(lines)
        for name in chosen:
            plan[name] = record(name, lines[name], scratch)
            seconds = sum(float(entry[3]) for entry in plan[name])  # type: ignore[arg-type]
            print(f"{name}: {len(plan[name])} compiled functions, {seconds:.1f} s of compiling")
    PLAN.write_text(json.dumps(plan, indent=1) + "\n")
    print(f"wrote {PLAN.relative_to(REPO)}")


if __name__ == "__main__":
    main()
