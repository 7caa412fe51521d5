"""Count the game-guard violations (guardsim.alert.invariants) in alert runs: traces already written by
``guardsim alert --out RUN``, or episodes run here.

Usage::

    python benchmarks/alert_invariants.py --level LEVEL RUN [RUN ...]     # traces of guardsim alert --out
    python benchmarks/alert_invariants.py --run --maps square,arena --guards 2 --episodes 6 [--motion continuous]

``--run`` plays the issue's recipe through the library: a 2-guard loop patrol (``guardsim patrol``'s), then
``--episodes`` seeded episodes per search strategy of a spotted evader (``guardsim alert --intruder evader
--spotted --search all``). Prints one line per map and a total: episodes, clean episodes, violations by kind,
and episodes ending at the time limit with more than 10 detections.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
# ../shared beside the clone (CI), or beside the folder of worktrees.
MAPS = next(
    (base / "shared" / "maps" / "movingai" for base in (REPO.parent, REPO.parent.parent) if (base / "shared").is_dir()),
    REPO.parent / "shared" / "maps" / "movingai",
)
SHIPPED = {p.stem: p for p in sorted((REPO / "levels").glob("*.json"))}


def _level(name_or_path: str):  # type: ignore[no-untyped-def,unused-ignore]
    from guardsim import load_level

    if name_or_path in SHIPPED:
        return load_level(SHIPPED[name_or_path])
    path = Path(name_or_path)
    if not path.exists():
        path = MAPS / f"{name_or_path}.map"
    return load_level(path)


def _count(traces: list[dict], traversable) -> tuple[Counter[str], int, int]:  # type: ignore[no-untyped-def,unused-ignore]
    from guardsim.alert.invariants import check_alert_trace

    kinds: Counter[str] = Counter()
    clean = endless = 0
    for data in traces:
        found = check_alert_trace(data, traversable)
        kinds.update(v.kind for v in found)
        clean += not found
        outcome = data["outcome"]
        endless += outcome["outcome"] == "time_limit" and outcome["detections"] > 10
    return kinds, clean, endless


def _line(label: str, episodes: int, kinds: Counter[str], clean: int, endless: int) -> str:
    from guardsim.alert.invariants import VIOLATIONS

    parts = ", ".join(f"{kind} {kinds[kind]}" for kind in VIOLATIONS)
    return f"{label}: {episodes} episodes, {clean} clean; {parts}; time limit with >10 detections {endless}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="*", help="Folders of guardsim alert --out (with --level).")
    parser.add_argument("--level", help="The level the runs played (a shipped level's name, a path or a map name).")
    parser.add_argument("--run", action="store_true", help="Play the episodes here.")
    parser.add_argument("--maps", default="square,passages,arena,den020d")
    parser.add_argument("--guards", type=int, default=2)
    parser.add_argument("--episodes", type=int, default=6)
    parser.add_argument("--motion", default="grid", choices=("grid", "continuous"))
    args = parser.parse_args()
    total: Counter[str] = Counter()
    episodes = clean = endless = 0
    if not args.run:
        from guardsim.scene import Scene

        traversable = Scene.from_level(_level(args.level)).grid.traversable
        for run in args.runs:
            traces = [json.loads(p.read_text()) for p in sorted(Path(run).glob("*-[0-9][0-9][0-9][0-9].json"))]
            kinds, ok, bad = _count(traces, traversable)
            print(_line(run, len(traces), kinds, ok, bad), flush=True)
            total += kinds
            episodes, clean, endless = episodes + len(traces), clean + ok, endless + bad
    else:
        from guardsim.alert import SEARCHES, alert_trace_data, run_alerts
        from guardsim.patrol.plan import patrol_setup, plan_patrol
        from guardsim.scene import Scene

        for name in args.maps.split(","):
            scene = Scene.from_level(_level(name))
            patrol = plan_patrol(patrol_setup(scene, args.guards, seed=0), "loop").patrol
            runs = run_alerts(
                scene, patrol, intruder="evader", searches=SEARCHES, episodes=args.episodes, seed=0, spotted=True,
                motion=args.motion,
            )  # fmt: skip
            traces = [
                json.loads(json.dumps(alert_trace_data(e, scene, search=s, intruder="evader")))
                for s, eps in runs.items()
                for e in eps
            ]
            kinds, ok, bad = _count(traces, scene.grid.traversable)
            print(_line(name, len(traces), kinds, ok, bad), flush=True)
            total += kinds
            episodes, clean, endless = episodes + len(traces), clean + ok, endless + bad
    print(_line("total", episodes, total, clean, endless))


if __name__ == "__main__":
    main()
