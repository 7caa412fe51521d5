"""Every planner on every shipped level, for teams of 1, 2 and 4 guards: steps, T90, planning time.

Usage::

    python benchmarks/planners.py                          # 20 episodes, all planners, 1/2/4 guards
    python benchmarks/planners.py --episodes 50 --planners ripplefront,tour --guards 1,4 levels/square.json
    python benchmarks/planners.py --planners tour --tour-parts --guards 1   # what each part of tour buys

Episode k of a level draws its starts and headings as ``guardsim bench`` and ``guardsim play --episode
k --guards K`` do (``run_episode``), so any row can be re-played. Prints one Markdown table per
team size, with per level and planner:

- ``covered``: episodes that saw every reachable cell within the loop's step limit (10 per cell);
- ``median``: median steps (a team's makespan: ticks until covered), over all episodes;
- ``T90``: median first tick with 90 % of the reachable cells seen;
- ``moves``: median moves summed over the guards (teams only; a guard that stays makes none);
- ``plan us/step``: wall time inside the planners (``reset`` and every ``next_move``) per guard
  decision, in microseconds, the planners' level tables already built (their cost is printed per level
  first, as "level setup"); tour's whole plan is made at its first decision and counted here;
- ``first ms``: the median over episodes of the first decision's time (the slowest guard's), in
  milliseconds: where tour makes its whole plan, the spike a game would see in one frame. (The longest
  call of an episode is not shown: on a shared machine it mostly measures the scheduler's time slice.)

With ``--tour-parts`` seven more rows per level show parts of ``tour`` alone: ``tour/cover`` walks the
set-cover tour as it is (no refinement, no frontier seed), ``tour/cover+refine`` refines it,
``tour/frontier+refine`` refines the frontier walk only, ``tour/lawnmower+refine`` the lawnmower routes
only, ``tour/spiral+refine`` the spirals only, ``tour/no-lawnmower`` is ``tour`` with every seed but
the lawnmower, and ``tour/no-polish`` is ``tour`` without polishing its shortest walk (the parts
alone are not polished either).

Timing wraps each planner in a proxy, so the single RippleFront guard runs the Python planner (numpy
sweeps over the whole grid) rather than the compiled fast path of ``guardsim play``; its steps are
identical either way (tests/test_fast_path.py). Timings are one core of a shared machine: compare them
within a table, not across runs.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

from guardsim import load_level
from guardsim.motion import run_episode
from guardsim.planners import PLANNERS, EpisodeSetup, GuardState, Planner, Tour
from guardsim.planners.tour import SEEDS
from guardsim.planners.viewpoint_cover import greedy_cover
from guardsim.simulation import Scene, choose_start, episode_generator, team_starts
from guardsim.trace import Trace
from guardsim.vision.table import view_table

LEVELS = sorted(Path(__file__).resolve().parent.parent.joinpath("levels").glob("*.json"))


class TimedPlanner:
    """A planner that adds up the wall time its calls take."""

    def __init__(self, planner: Planner) -> None:
        self.planner = planner
        self.name = planner.name
        self.seconds = 0.0
        self.first = 0.0
        self.calls = 0

    def reset(self, setup: EpisodeSetup) -> None:
        began = time.perf_counter()
        self.planner.reset(setup)
        self._add(time.perf_counter() - began, decision=False)

    def next_move(self, state: GuardState) -> int | None:
        began = time.perf_counter()
        move = self.planner.next_move(state)
        self._add(time.perf_counter() - began, decision=True)
        return move

    def _add(self, seconds: float, *, decision: bool) -> None:
        self.seconds += seconds
        if decision and self.calls == 0:
            self.first = seconds
        self.calls += decision


#: The parts of ``tour`` shown by ``--tour-parts``.
TOUR_PARTS: dict[str, Callable[[], Planner]] = {
    "tour/cover": partial(Tour, seeds=("cover",), refine_rounds=0, polish_trials=0),
    "tour/cover+refine": partial(Tour, seeds=("cover",), polish_trials=0),
    "tour/frontier+refine": partial(Tour, seeds=("frontier",), polish_trials=0),
    "tour/lawnmower+refine": partial(Tour, seeds=("lawnmower",), polish_trials=0),
    "tour/spiral+refine": partial(Tour, seeds=("spiral",), polish_trials=0),
    "tour/no-lawnmower": partial(Tour, seeds=tuple(seed for seed in SEEDS if seed != "lawnmower")),
    "tour/no-polish": partial(Tour, polish_trials=0),
}


def timed_episode(
    scene: Scene, planner: Callable[[], Planner], guards: int, seed: int, episode: int
) -> tuple[Trace, float, float]:
    """Episode ``episode`` as ``run_episode`` plays it; also seconds per decision and the first one's."""
    rng = episode_generator(seed, episode)
    cells, headings = team_starts(scene, choose_start(scene, rng=rng), guards, rng=rng)
    planners = [TimedPlanner(planner()) for _ in range(guards)]
    trace = run_episode(scene, planners, starts=cells, headings=headings, rng=rng, seed=seed)
    calls = max(1, sum(timed.calls for timed in planners))
    return trace, sum(timed.seconds for timed in planners) / calls, max(timed.first for timed in planners)


def level_setup(scene: Scene) -> str:
    """Build the shared tables once, untimed by the episodes, and say what they cost."""
    began = time.perf_counter()
    table = view_table(scene.grid, scene.vision())
    views = time.perf_counter() - began
    began = time.perf_counter()
    cover = greedy_cover(table, scene.grid.largest_component().ravel())
    return f"views of {table.entry.size} states {views:.2f} s, set cover {time.perf_counter() - began:.3f} s ({cover.size} viewpoints)"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="*", type=Path, default=LEVELS)
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--planners", default=",".join(PLANNERS), help="Comma-separated planner names.")
    parser.add_argument("--guards", default="1,2,4", help="Comma-separated team sizes.")
    parser.add_argument("--tour-parts", action="store_true", help="Also run parts of tour alone.")
    args = parser.parse_args()
    planners: dict[str, Callable[[], Planner]] = {name: PLANNERS[name] for name in args.planners.split(",")}
    if args.tour_parts:
        planners.update(TOUR_PARTS)
    teams = [int(size) for size in args.guards.split(",")]
    rows: dict[int, list[str]] = {size: [] for size in teams}
    for path in args.levels:
        scene = Scene.from_level(load_level(path))
        print(f"{path.stem}: level setup: {level_setup(scene)}", flush=True)
        for planner, factory in planners.items():
            # One untimed episode builds whatever the planner keeps per level (e.g. tour's cover).
            timed_episode(scene, factory, 1, args.seed, args.episodes)
            for size in teams:
                results = [timed_episode(scene, factory, size, args.seed, k) for k in range(args.episodes)]
                traces = [trace for trace, _, _ in results]
                t90 = [t for t in (trace.steps_to_fraction(0.9) for trace in traces) if t is not None]
                moves = f"{statistics.median(trace.total_moves for trace in traces):g}" if size > 1 else "-"
                t90_median = f"{statistics.median(t90):g}" if t90 else "-"
                rows[size].append(
                    f"| {path.stem} | {planner} | {sum(trace.covered for trace in traces)}/{len(traces)} "
                    f"| {statistics.median(trace.steps for trace in traces):g} "
                    f"| {t90_median} | {moves} "
                    f"| {1e6 * statistics.mean(seconds for _, seconds, _ in results):.0f} "
                    f"| {1e3 * statistics.median(first for _, _, first in results):.1f} |"
                )
                print(rows[size][-1], flush=True)
    for size in teams:
        print(
            f"\n{size} guard{'s' if size > 1 else ''}, {args.episodes} episodes per level and planner, seed {args.seed}:\n"
        )
        print("| level | planner | covered | median | T90 | moves | plan us/step | first ms |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        print("\n".join(rows[size]))


if __name__ == "__main__":
    main()
