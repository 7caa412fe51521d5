"""Big maps: seconds and peak memory of each command on Moving AI maps from 64 x 64 to 512 x 512.

Usage::

    python benchmarks/big_maps.py                                   # every map and command below
    python benchmarks/big_maps.py --maps room-64-64-8,maze-128-128-10 --commands patrol
    python benchmarks/big_maps.py --timeout 120                     # stop each command after 120 s
    python benchmarks/big_maps.py --max-memory-mb 6000              # stop each command past 6000 MB
    python benchmarks/big_maps.py --patrol-of patrol-4              # the others read the 4-guard patrol
    python benchmarks/big_maps.py --map-dir /work/shared/maps/movingai   # maps elsewhere

Each map is imported (``guardsim import``) into a temporary folder, then each command runs as its own
process, as a user runs it (``python -m guardsim.cli ...``), warm (its kernels compiled by an untimed
first patrol run). CPU seconds are the process's user and system time (``os.wait4``): on a shared
machine the CPU seconds are the steadier figure. Memory is given twice: the process's own peak resident
set (``os.wait4``, exact), and the peak of the resident sets of it and every process it started (worker
processes, the compile-ahead helper) summed, sampled every 50 ms. A command that runs past ``--timeout``
or whose processes together hold more than ``--max-memory-mb`` is stopped (its whole process group) and
shown as ``> T s`` or ``> M MB``; one that refuses the map shows its exit status and message. The other
commands read the patrol that ``--patrol-of`` writes (run first, untimed, when it is not in
``--commands``). Prints a Markdown table: one row per map and command, with the time, the memory and
the command's last line of output. Reads ``../shared/maps/movingai`` beside the repository; contacts
nothing.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
MAPS = REPO.parent / "shared" / "maps" / "movingai"

#: The maps, smallest first: a Moving AI room map, a maze, a city, a Dragon Age dungeon, two 512 x 512
#: game maps (StarCraft's AR0603SR, Warcraft III's duskwood).
DEFAULT_MAPS = ("room-64-64-8", "maze-128-128-10", "Berlin_1_256", "den520d", "AR0603SR", "duskwood")

#: Commands by name: the arguments after ``guardsim``, with ``{level}``, ``{out}``, ``{patrol}``,
#: ``{start}`` and ``{goal}`` filled in per map. ``patrol`` comes first: the others read its patrol.
COMMANDS = {
    "patrol": ["patrol", "{level}", "--out", "{out}/p1"],
    "patrol-2": ["patrol", "{level}", "--guards", "2", "--out", "{out}/p2"],
    "patrol-4": ["patrol", "{level}", "--guards", "4", "--out", "{out}/p4"],
    "sneak": ["sneak", "{level}", "--patrol", "{patrol}", "--from", "{start}", "--to", "{goal}", "--out", "{out}/s"],
    "sneak-undetected": [
        "sneak",
        "{level}",
        "--patrol",
        "{patrol}",
        "--from",
        "{start}",
        "--to",
        "{goal}",
        "--undetected",
        "--out",
        "{out}/su",
    ],
    "alert-100": [
        "alert",
        "{level}",
        "--patrol",
        "{patrol}",
        "--episodes",
        "100",
        "--workers",
        "2",
        "--out",
        "{out}/a",
    ],
    "bounds": ["bounds", "{level}"],
    "play": ["play", "{level}"],
    "check": [
        "check", "{level}", "--patrol", "{patrol}", "--sneak", "{start}", "{goal}", "--expect", "sneaks",
    ],
    "report": ["report", "{level}", "--patrol", "{patrol}", "--from", "{start}", "--to", "{goal}", "--json", "{out}/r.json"],
    "diff": [
        "diff", "{level}", "{level}", "--patrol-old", "{patrol}", "--patrol-new", "{patrol}", "--from", "{start}",
        "--to", "{goal}", "--json", "{out}/d.json",
    ],
    "fortify": [
        "fortify", "{level}", "--patrol", "{patrol}", "--from", "{start}", "--to", "{goal}", "--max-rounds", "8",
        "--out", "{out}/f",
    ],
}  # fmt: skip
DEFAULT_COMMANDS = ("patrol", "patrol-2", "patrol-4", "sneak", "sneak-undetected", "alert-100", "bounds")


#: Where each patrol command writes its patrol.
PATROL_FOLDERS = {"patrol": "p1", "patrol-2": "p2", "patrol-4": "p4"}


def _tree_rss(root: int) -> int:
    """Resident bytes of ``root`` and every process below it, from /proc (0 where it cannot be read)."""
    children: dict[int, list[int]] = {}
    resident: dict[int, int] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", encoding="ascii", errors="replace") as stat:
                fields = stat.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(entry))
        resident[int(entry)] = int(fields[21]) * os.sysconf("SC_PAGE_SIZE")
    total, stack = 0, [root]
    while stack:
        pid = stack.pop()
        total += resident.get(pid, 0)
        stack.extend(children.get(pid, []))
    return total


def _run(
    arguments: list[str], timeout: float, max_bytes: float = float("inf")
) -> tuple[float, float, int, int, int | None, str]:
    """Wall seconds, CPU seconds (user + system), the process's peak resident bytes, the peak of it and its
    processes together, exit status (None: stopped at ``timeout`` or ``max_bytes``) and last output line
    (``stopped at N MB`` when stopped for memory)."""
    environment = {**os.environ, "PYTHONPATH": str(REPO)}
    began = time.perf_counter()
    together = 0
    stopped = ""
    with tempfile.TemporaryFile() as output:
        process = subprocess.Popen(
            [sys.executable, "-m", "guardsim.cli", *arguments], stdout=output, stderr=subprocess.STDOUT,
            env=environment, start_new_session=True,
        )  # fmt: skip
        status: int | None = None
        while True:
            pid, code, usage = os.wait4(process.pid, os.WNOHANG)
            if pid:
                status = os.waitstatus_to_exitcode(code)
                break
            together = max(together, _tree_rss(process.pid))
            over_time = time.perf_counter() - began > timeout
            if over_time or together > max_bytes:
                stopped = "" if over_time else f"stopped at {together / 2**20:.0f} MB"
                # Its own session: the workers and helper it started go too.
                os.killpg(process.pid, signal.SIGKILL)
                _, _, usage = os.wait4(process.pid, 0)
                break
            time.sleep(0.05)
        # The compile-ahead helper a first run forks is a grandchild: counted only when it was waited for.
        peak, cpu = usage.ru_maxrss * 1024, usage.ru_utime + usage.ru_stime
        seconds = time.perf_counter() - began
        output.seek(0)
        lines = [line for line in output.read().decode(errors="replace").splitlines() if line.strip()]
    # The summary line: not a progress line, nor a note indented under the summary.
    said = [
        line
        for line in lines
        if not line.startswith(" ")
        and (not line.startswith("guardsim: ") or line.startswith(("guardsim: error", "guardsim: warning")))
    ]
    last = stopped or (said[-1] if said else "")
    return seconds, cpu, peak, max(peak, together), status, last


def _ends(level: Path) -> tuple[str, str]:
    """Two far-apart traversable points of an imported map (world units): its first and last free cells."""
    import json

    data = json.loads(level.read_text(encoding="utf-8"))
    from guardsim.level import parse_level
    from guardsim.scene import Scene

    scene = Scene.from_level(parse_level(data, source=str(level)))
    grid = scene.grid
    free = [int(cell) for cell in grid.traversable.ravel().nonzero()[0]]
    points = []
    for cell in (free[0], free[-1]):
        col, row = grid.unflat(cell)
        points.append(
            f"{grid.origin[0] + (col + 0.5) * grid.cell_size},{grid.origin[1] + (row + 0.5) * grid.cell_size}"
        )
    return points[0], points[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--maps", default=",".join(DEFAULT_MAPS))
    parser.add_argument("--commands", default=",".join(DEFAULT_COMMANDS))
    parser.add_argument("--timeout", type=float, default=300.0, help="Seconds before a command is stopped.")
    parser.add_argument("--map-dir", type=Path, default=MAPS, help=f"Where the .map files are [default: {MAPS}].")
    parser.add_argument(
        "--max-memory-mb",
        type=float,
        default=8000.0,
        help="Resident MB (all its processes) before a command is stopped.",
    )
    parser.add_argument(
        "--patrol-of",
        choices=sorted(PATROL_FOLDERS),
        default="patrol",
        help="The patrol command whose patrol the others read.",
    )
    args = parser.parse_args()
    commands = args.commands.split(",")
    unknown = set(commands) - set(COMMANDS)
    if unknown:
        parser.error(f"unknown commands {', '.join(sorted(unknown))}; known: {', '.join(COMMANDS)}")
    max_bytes = args.max_memory_mb * 2**20
    print("| map | grid | command | seconds | CPU seconds | peak memory | all processes | result |")
    print("|---|---|---|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name in args.maps.split(","):
            level = Path(folder) / f"{name}.json"
            source = args.map_dir / f"{name}.map"
            *_, status, last = _run(["import", str(source), "--out", str(level)], args.timeout)
            if status != 0:
                parser.error(f"{source}: cannot import: {last}")
            start, goal = _ends(level)
            out = Path(folder) / name
            fill = {"level": str(level), "out": str(out), "start": start, "goal": goal}
            fill["patrol"] = str(out / PATROL_FOLDERS[args.patrol_of] / "patrol.json")
            # Warm: the first run of a kernel version compiles it (untimed).
            _run(["patrol", str(level), "--out", str(out / "warm")], args.timeout * 4, max_bytes)
            if args.patrol_of not in commands:
                _run([part.format(**fill) for part in COMMANDS[args.patrol_of]], args.timeout * 4, max_bytes)
            for command in commands:
                seconds, cpu, peak, together, status, last = _run(
                    [part.format(**fill) for part in COMMANDS[command]], args.timeout, max_bytes
                )
                if status is None:
                    time_text = f"> {args.timeout:.0f}" if not last else f"{seconds:.1f}"
                    result = last or "stopped"
                else:
                    time_text = f"{seconds:.1f}"
                    result = last if status == 0 else f"exit {status}: {last}"
                result = result.replace(str(folder) + "/", "").replace("|", "/")[:140]
                print(
                    f"| {name} | {_grid(level)} | {command} | {time_text} | {cpu:.1f} | {peak / 2**20:.0f} MB "
                    f"| {together / 2**20:.0f} MB | {result} |"
                )
                sys.stdout.flush()


def _grid(level: Path) -> str:
    import json

    data = json.loads(level.read_text(encoding="utf-8"))
    xs = [point[0] for point in data["outer"]]
    ys = [point[1] for point in data["outer"]]
    size = float(data.get("cell_size", 1.0))
    return f"{round((max(xs) - min(xs)) / size)} x {round((max(ys) - min(ys)) / size)}"


if __name__ == "__main__":
    main()
