"""Alert episodes: the frame budget, and the search strategies compared (docs/alert.md, docs/results.md).

Usage::

    python benchmarks/alert.py --frame                      # per-tick times, 3 guards on Square (60 x 60)
    python benchmarks/alert.py --episodes 100               # the experiment: every map, 1, 2, 4 guards
    python benchmarks/alert.py --episodes 10 --maps square,arena --guards 1,2

The experiment: on each map, a loop patrol for K guards (``guardsim patrol``'s planner), then N seeded
episodes (patrol phase, entry and goal drawn from seed 0, the same for every strategy) of an ``evader``
intruder that starts in some guard's view, detected (``spotted``: that guard's meter starts full), mid-level
on its way from its entry to its goal; it then runs for the cell it reaches first that is farthest from every guard and waits there while any guard
searches. One row per map, team size and strategy: detections, capture rate among detected episodes,
seconds from detection to capture, seconds searching, seconds to re-acquire after losing sight, seconds
from detection until every guard is back on its route. Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
MAPS = REPO.parent / "shared" / "maps" / "movingai"
SHIPPED = {p.stem: p for p in sorted((REPO / "levels").glob("*.json"))}
REAL = ("arena", "den020d", "maze-32-32-2", "room-32-32-4")


def _scene(name: str):  # type: ignore[no-untyped-def]
    from guardsim import load_level
    from guardsim.scene import Scene

    level = load_level(SHIPPED[name] if name in SHIPPED else MAPS / f"{name}.map")
    return Scene.from_level(level)


def _patrol(scene, guards: int):  # type: ignore[no-untyped-def]
    from guardsim.patrol.plan import patrol_setup, plan_patrol

    return plan_patrol(patrol_setup(scene, guards, seed=0), "loop").patrol


def frame_budget(ticks: int = 600, episodes: int = 20) -> None:
    """Per-tick wall time of 3-guard alert episodes on Square (evader, ripple)."""
    import numpy as np

    from guardsim.alert import alert_episode
    from guardsim.alert.run import _seeded_points
    from guardsim.vision.table import view_table

    scene = _scene("square")
    patrol = _patrol(scene, 3)
    table = view_table(scene.grid, scene.vision())
    generator = np.random.default_rng(0)
    times: list[float] = []
    episode_seconds: list[tuple[float, float]] = []
    for search in ("ripple", "diffuse", "team", "last-known"):
        for _ in range(episodes // 4):
            entry, goal = _seeded_points(scene, patrol, generator)
            phase = int(generator.integers(patrol.ticks))
            episode = alert_episode(
                scene, patrol, intruder="evader", source=entry, target=goal, search=search, phase=phase, table=table
            )
            began = time.perf_counter()
            while not episode.done:
                before = time.perf_counter()
                episode.step()
                times.append(time.perf_counter() - before)
            episode_seconds.append((time.perf_counter() - began, episode.tick * episode.rules.dt))
    times.sort()
    wall = sum(w for w, _ in episode_seconds)
    game = sum(g for _, g in episode_seconds)
    print(f"Square 60 x 60, 3 guards, evader, all four strategies, {len(episode_seconds)} episodes, {len(times)} ticks")
    print(
        f"per tick: median {1000 * statistics.median(times):.3f} ms, 99th percentile "
        f"{1000 * times[int(0.99 * (len(times) - 1))]:.3f} ms, worst {1000 * times[-1]:.3f} ms"
    )
    print(f"game seconds per wall second: {game / wall:.0f} x real time")


def experiment(maps: list[str], guards: list[int], episodes: int) -> None:
    from guardsim.alert import SEARCHES, run_alerts, summarise

    print(
        "| map | guards | search | detected | capture rate | to capture (s) | searching (s) | re-acquire (s) | back on route (s) |"
    )
    print("|" + " --- |" * 9)

    def fmt(value: float | None) -> str:
        return "-" if value is None else f"{value:.1f}"

    for name in maps:
        scene = _scene(name)
        for count in guards:
            patrol = _patrol(scene, count)
            runs = run_alerts(
                scene, patrol, intruder="evader", searches=SEARCHES, episodes=episodes, seed=0, spotted=True
            )
            for search, eps in runs.items():
                row = summarise(search, [e.result() for e in eps])
                print(
                    f"| {name} | {count} | {search} | {row.detected}/{row.episodes} | {row.capture_rate:.2f} | "
                    f"{fmt(row.time_to_capture)} | {fmt(row.searching)} | {fmt(row.reacquire)} | {fmt(row.back_on_route)} |",
                    flush=True,
                )


def figure(table: Path, out: Path) -> None:
    """Capture rate per strategy and team size, averaged over the maps of a saved experiment table."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from guardsim.alert import SEARCHES

    rates: dict[tuple[str, int], list[float]] = {}
    for line in table.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 9 and cells[1].isdigit():
            rates.setdefault((cells[2], int(cells[1])), []).append(float(cells[4]))
    teams = sorted({k for _, k in rates})
    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=100)
    width = 0.8 / len(SEARCHES)
    for index, search in enumerate(SEARCHES):
        means = [statistics.mean(rates.get((search, k), [0.0])) for k in teams]
        ax.bar([t + (index - 1.5) * width for t in range(len(teams))], means, width, label=search)
    ax.set_xticks(range(len(teams)), [f"{k} guard{'s' if k > 1 else ''}" for k in teams])
    ax.set_ylabel("capture rate (mean over maps)")
    ax.set_ylim(0, 1)
    ax.legend(ncol=4, fontsize=8, loc="upper left")
    ax.set_title("Evader spotted mid-level: captures by search strategy")
    fig.tight_layout()
    fig.savefig(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frame", action="store_true", help="Only the frame budget.")
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--maps", default=",".join([*SHIPPED, *REAL]))
    parser.add_argument("--guards", default="1,2,4")
    parser.add_argument("--figure", nargs=2, metavar=("TABLE", "PNG"), help="Draw the figure of a saved table.")
    args = parser.parse_args()
    if args.figure:
        figure(Path(args.figure[0]), Path(args.figure[1]))
        return
    frame_budget()
    if not args.frame:
        experiment(args.maps.split(","), [int(g) for g in args.guards.split(",")], args.episodes)


if __name__ == "__main__":
    main()
