"""Chases that end: capture rate, time to capture, detections per episode and time to give up, per map,
team size and search strategy (docs/results.md, "Alert: chases that end").

Usage::

    python benchmarks/alert_chases.py --episodes 100                     # every map, 1, 2, 4 guards
    python benchmarks/alert_chases.py --episodes 20 --maps square,arena --guards 1,2
    PYTHONPATH=OLD_CHECKOUT python benchmarks/alert_chases.py ...         # the same table on other code

The experiment is benchmarks/alert.py's: on each map a loop patrol for K guards (``guardsim patrol``'s
planner), then N seeded episodes (patrol phase, entry and goal drawn from seed 0, the same for every
strategy) of an ``evader`` that starts in some guard's view, detected (``--spotted``), on its way to a
goal at least a third of the level away; chased, it runs for the cell it reaches first that is farthest
from every guard and waits there while any guard is alarmed. Episodes stop at 300 s. The guards import
from whatever ``guardsim`` is first on the path, so the same command measures the code before a change
(a checkout of it on ``PYTHONPATH``) and after.

Columns: capture rate (captures per episode), mean seconds from the first detection to the capture,
mean detections per episode, mean seconds from the first detection to the first guard giving up (over
the episodes where one did), and the episodes that ran to the time limit with more than 10 detections.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
# ../shared beside the clone (CI), or beside the folder of worktrees.
MAPS = next(
    (base / "shared" / "maps" / "movingai" for base in (REPO.parent, REPO.parent.parent) if (base / "shared").is_dir()),
    REPO.parent / "shared" / "maps" / "movingai",
)
SHIPPED = {p.stem: p for p in sorted((REPO / "levels").glob("*.json"))}
REAL = ("arena", "den020d", "maze-32-32-2", "room-32-32-4")


def _scene(name: str):  # type: ignore[no-untyped-def,unused-ignore]
    from guardsim import load_level
    from guardsim.scene import Scene

    level = load_level(SHIPPED[name] if name in SHIPPED else MAPS / f"{name}.map")
    return Scene.from_level(level)


def _mean(values: list[float]) -> str:
    return "-" if not values else f"{statistics.mean(values):.1f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--maps", default=",".join([*SHIPPED, *REAL]))
    parser.add_argument("--guards", default="1,2,4")
    args = parser.parse_args()
    import guardsim
    from guardsim.alert import SEARCHES, run_alerts
    from guardsim.patrol.plan import patrol_setup, plan_patrol

    print(f"guardsim from {Path(guardsim.__file__).parent}", file=sys.stderr)
    print("| map | guards | search | capture rate | to capture (s) | detections | to give up (s) | endless |")
    print("|" + " --- |" * 8)
    began = time.perf_counter()
    for name in args.maps.split(","):
        scene = _scene(name)
        for count in (int(g) for g in args.guards.split(",")):
            patrol = plan_patrol(patrol_setup(scene, count, seed=0), "loop").patrol
            runs = run_alerts(
                scene, patrol, intruder="evader", searches=SEARCHES, episodes=args.episodes, seed=0, spotted=True
            )
            for search, episodes in runs.items():
                outcomes = [e.result() for e in episodes]
                captured = [o for o in outcomes if o.captured_at is not None and o.detected_at is not None]
                gave_up = [o for o in outcomes if o.gave_up_at is not None and o.detected_at is not None]
                endless = sum(o.outcome == "time_limit" and o.detections > 10 for o in outcomes)
                print(
                    f"| {name} | {count} | {search} | {len(captured) / len(outcomes):.2f} | "
                    f"{_mean([o.captured_at - o.detected_at for o in captured])} | "  # type: ignore[operator]
                    f"{statistics.mean(o.detections for o in outcomes):.1f} | "
                    f"{_mean([o.gave_up_at - o.detected_at for o in gave_up])} | {endless} |",  # type: ignore[operator]
                    flush=True,
                )
            print(f"{name}, {count} guards: {time.perf_counter() - began:.0f} s so far", file=sys.stderr, flush=True)


if __name__ == "__main__":
    main()
