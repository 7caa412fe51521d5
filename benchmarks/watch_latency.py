"""Save-to-page latency of ``guardsim watch``, measured in real headless Chromium.

Starts ``guardsim watch`` on a copy of a level (or map) in a temporary folder, opens its page in headless
Chromium (driven over DevTools on 127.0.0.1, tests/devtools.py), waits for the first analysis (the cold
one), then saves the file ``--saves`` times, alternating two edits:

- ``walls``: one wall moved by a cell and back (a level: the first hole shifted; a Moving AI map: one
  tile toggled), so the scene, view table and patrol are rebuilt;
- ``keys``: a detection key changed (a level's ``guard.detect_far``; a map: the same tile again, so this
  row is a wall edit too), so the scene and patrol are reused.

Latency is the time from the save (the rename onto the file, as editors save) until the page has drawn
the new analysis (the page stamps the time it drew it); the server's own analysis time is shown beside.
Prints a Markdown table and the median per edit. ``--cpu`` instead times the analysis itself in this
process (processor seconds of both cores, so a busy machine changes it less; and wall seconds): what a
save costs on an idle machine, before the page is sent it. ``--steps`` times each step of one re-analysis (scene, view table, patrol,
exposure, sneak check, report) per edit.

    python benchmarks/watch_latency.py                                   # levels/mgs_docks.json, 60 x 60
    python benchmarks/watch_latency.py ../shared/maps/movingai/Berlin_1_256.map --saves 3 --timeout 600
    python benchmarks/watch_latency.py --cpu
    python benchmarks/watch_latency.py ../shared/maps/movingai/Berlin_1_256.map --steps
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests.devtools import CHROMIUM, LivePage  # noqa: E402

STATUS = "document.getElementById('status').dataset"


def _port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _save(path: Path, text: str) -> float:
    temporary = path.with_name(path.name + ".tmp~")
    temporary.write_text(text, encoding="utf-8")
    began = time.time()
    os.replace(temporary, path)
    return began


def _edits(path: Path) -> list[tuple[str, str]]:
    """The texts saved in turn, with their kind, starting from the file as it is."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".json":
        data = json.loads(text)
        moved = json.loads(text)
        moved["holes"][0] = [[x + moved.get("cell_size", 1.0), y] for x, y in moved["holes"][0]]
        keyed = json.loads(text)
        keyed.setdefault("guard", {})["detect_far"] = 1.0
        return [
            ("walls", json.dumps(moved)),
            ("walls", json.dumps(data)),
            ("keys", json.dumps(keyed)),
            ("keys", json.dumps(data)),
        ]
    lines = text.splitlines()
    start = lines.index("map") + 1
    row = start + (len(lines) - start) // 2
    col = next(k for k, char in enumerate(lines[row]) if char == ".")
    toggled = list(lines)
    toggled[row] = lines[row][:col] + "@" + lines[row][col + 1 :]
    return [("walls", "\n".join(toggled) + "\n"), ("walls", text)]


def _level_edits(path: str) -> tuple[Any, list[tuple[str, Any]]]:
    """The level at ``path`` and its two edits: the first wall moved by a cell, ``guard.detect_far`` set."""
    import dataclasses

    from guardsim import load_level

    level = load_level(path)
    moved = dataclasses.replace(
        level, holes=(tuple((x + level.cell_size, y) for x, y in level.holes[0]), *level.holes[1:])
    )
    keyed = dataclasses.replace(level, guard=dataclasses.replace(level.guard, detect_far=1.0))
    return level, [("walls", moved), ("keys", keyed)]


def cpu(path: str, saves: int) -> None:
    """Processor seconds of one analysis (with its first report and the page's JSON) per edit of a level."""

    from guardsim.design import analyse, report_data, report_of
    from guardsim.viewer.serve import analysis_payload

    level, edits = _level_edits(path)
    base = analyse(level, planner="cover")
    for kind, edited in edits:
        spent, walls = [], []
        for _ in range(saves):
            began, clock = time.process_time(), time.perf_counter()
            analysis = analyse(edited, planner="cover", reuse=base)
            json.dumps(analysis_payload(analysis, report_data(report_of(analysis, ways=False))))
            spent.append(time.process_time() - began)
            walls.append(time.perf_counter() - clock)
        reused = " and ".join(analysis.reused) or "nothing"
        print(
            f"{level.name}, {kind}: median {statistics.median(spent):.2f} s, least {min(spent):.2f} s of processor time"
            f" (both cores counted), median {statistics.median(walls):.2f} s wall (reused {reused}; load average"
            f" {os.getloadavg()[0]:.1f})"
        )


def steps(path: str) -> None:
    """Where the seconds of one re-analysis go, step by step (processor and wall seconds), for each edit."""

    import guardsim.design.analysis as analysis_module
    from guardsim.design import analyse, report_data, report_of
    from guardsim.viewer.serve import analysis_payload

    spent: dict[str, list[float]] = {}

    def timed(name: str, function: object) -> object:
        # The exposure of a long lap is counted in a thread beside the sneak check: its own processor
        # time is its thread's, and the sneak check's row (the whole process's) includes it.
        processor = time.thread_time if name == "exposure" else time.process_time

        def run(*args: object, **kwargs: object) -> object:
            began, clock = processor(), time.perf_counter()
            try:
                return function(*args, **kwargs)  # type: ignore[operator]
            finally:
                totals = spent.setdefault(name, [0.0, 0.0])
                totals[0] += processor() - began
                totals[1] += time.perf_counter() - clock

        return run

    scene_class = analysis_module.Scene
    patched = {
        "reused_view_table": "view table (sight away from the edit)",
        "view_table": "view table (whole)",
        "plan_loop": "patrol planned",
        "score_patrol": "idleness",
        "patrol_gains": "exposure",
        "_exposure": "exposure",
        "_pair": "sneak check",
    }
    for name, label in patched.items():
        setattr(analysis_module, name, timed(label, getattr(analysis_module, name)))

    class TimedScene(scene_class):  # type: ignore[misc, valid-type]
        from_level = staticmethod(timed("scene", scene_class.from_level))

    analysis_module.Scene = TimedScene
    level, edits = _level_edits(path)
    base = analyse(level, planner="cover")
    for kind, edited in edits:
        spent.clear()
        began, clock = time.process_time(), time.perf_counter()
        analysis = analyse(edited, planner="cover", reuse=base)
        page_data = timed(
            "report and page data", lambda found: analysis_payload(found, report_data(report_of(found, ways=False)))
        )
        json.dumps(page_data(analysis))  # type: ignore[operator]
        total = time.process_time() - began, time.perf_counter() - clock
        print(
            f"\n{level.name}, {kind} (reused {' and '.join(analysis.reused) or 'nothing'}; load average {os.getloadavg()[0]:.1f})"
        )
        print("| step | processor s | wall s |\n| --- | --- | --- |")
        for name, (cpu_seconds, wall_seconds) in spent.items():
            print(f"| {name} | {cpu_seconds:.2f} | {wall_seconds:.2f} |")
        print(f"| all | {total[0]:.2f} | {total[1]:.2f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("level", nargs="?", default=str(REPO / "levels/mgs_docks.json"))
    parser.add_argument("--saves", type=int, default=8)
    parser.add_argument("--guards", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=120.0, help="Seconds to wait for one analysis.")
    parser.add_argument("--cpu", action="store_true", help="Time the analysis alone, in this process.")
    parser.add_argument("--steps", action="store_true", help="Time each step of one re-analysis per edit.")
    args = parser.parse_args()
    if args.cpu:
        cpu(args.level, args.saves)
        return
    if args.steps:
        steps(args.level)
        return
    if CHROMIUM is None:
        sys.exit("no chromium on PATH: apt-get install -y chromium")
    folder = Path(tempfile.mkdtemp(prefix="watch-latency-"))
    level = folder / Path(args.level).name
    shutil.copy(args.level, level)
    port = _port()
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    log = (folder / "watch.out").open("w")
    server = subprocess.Popen(
        [sys.executable, "-m", "guardsim.cli", "watch", level.name, "--guards", str(args.guards), "--port", str(port)],
        cwd=folder,
        stdout=log,
        stderr=subprocess.STDOUT,
        env=env,
    )
    page = None
    try:
        deadline = time.monotonic() + 60
        while "serving" not in (folder / "watch.out").read_text():
            if server.poll() is not None or time.monotonic() > deadline:
                sys.exit((folder / "watch.out").read_text())
            time.sleep(0.05)
        page = LivePage(f"http://127.0.0.1:{port}/", folder / "profile")
        began = time.monotonic()
        page.wait_for(f"{STATUS}.number == '1'", timeout=args.timeout)
        print(f"{level.name}: first analysis shown {time.monotonic() - began:.2f} s after the page opened (cold)")
        edits = _edits(level)
        rows = []
        print("\n| save | edit | save to page (s) | analysis (s) | reused |\n| --- | --- | --- | --- | --- |")
        for k in range(args.saves):
            kind, text = edits[k % len(edits)]
            number = k + 2
            saved = _save(level, text)
            page.wait_for(f"{STATUS}.number == '{number}'", timeout=args.timeout, every=0.02)
            shown = float(page.evaluate(f"{STATUS}.shownAt")) / 1000
            status = page.evaluate("document.getElementById('status').textContent")
            seconds = status.split("took ")[1].split(" s")[0]
            reused = status.split("reused ")[1] if "reused " in status else "-"
            rows.append((kind, shown - saved))
            print(f"| {k + 1} | {kind} | {shown - saved:.2f} | {seconds} | {reused} |", flush=True)
        for kind in sorted({kind for kind, _ in rows}):
            values = [latency for name, latency in rows if name == kind]
            print(
                f"\n{kind}: median {statistics.median(values):.2f} s, worst {max(values):.2f} s over {len(values)} saves"
            )
    finally:
        if page is not None:
            page.close()
        server.terminate()
        server.wait(timeout=30)
        log.close()
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
