"""Reference against fast path, side by side: per-tick time, episodes per second, peak memory.

Usage::

    python benchmarks/speed.py                      # the four shipped levels and two Moving AI maps
    python benchmarks/speed.py --episodes 20 --maps ../shared/maps/movingai/den520d.map

For each level, in a fresh process (so that peak memory is that level's alone):

- per-tick time (vision + field + decision), median and 99th percentile in microseconds, for the
  reference (a pymunk ray per cell in the cone every tick, a full-grid sweep every tick) and for the fast
  path (shared vision cache, compiled loop with incremental sweeps), the latter from a cold cache, so
  that first-visit vision fills are counted. On maps of 256 x 256 and more the reference is capped at
  ``--reference-ticks`` ticks;
- milliseconds per episode and episodes per second on one core, with the speed-up: reference episodes
  against the same episodes on the fast path, first from a cold cache and then warm (steady state, as in
  a long batch);
- peak resident memory of the process.

The per-tick timings of the fast path return to Python after every tick, which adds a few
microseconds to each; whole-episode times have no such overhead.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
LEVELS = sorted((REPO / "levels").glob("*.json"))
MAPS = [REPO.parent / "shared" / "maps" / "movingai" / name for name in ("Berlin_1_256.map", "AR0603SR.map")]


def load_scene(path: Path):
    """The scene of a level file or of a map imported at cell size 1."""
    from guardsim import load_level
    from guardsim.simulation import Scene

    if path.suffix == ".json":
        return Scene.from_level(load_level(path))
    from guardsim import load_level

    return Scene.from_level(load_level(path))


def measure(path: Path, episodes: int, reference_ticks: int) -> dict:
    """All figures for one level, in this process."""
    from guardsim.motion import run_episode
    from guardsim.planners import RippleFront
    from guardsim.simulation import Simulation, choose_start, episode_generator

    began = time.perf_counter()
    scene = load_scene(path)
    build_seconds = time.perf_counter() - began
    grid = scene.grid
    large = grid.size > 100_000
    starts = [choose_start(scene, rng=episode_generator(0, episode)) for episode in range(episodes)]

    # Reference per tick: time the vision call and the planner's decision of each tick.
    reference_ticks_us: list[float] = []
    reference_episode_ms: list[float] = []
    reference_vision = scene.reference_vision()
    reference_runs = 1 if large else min(episodes, 5)
    for cell, heading in starts[:reference_runs]:
        last_vision = [0.0]

        def timed_vision(col: int, row: int, facing: int, _last=last_vision) -> np.ndarray:
            t0 = time.perf_counter()
            seen = reference_vision(col, row, facing)
            _last[0] = time.perf_counter() - t0
            return seen

        class TimedRippleFront(RippleFront):
            def next_move(self, state, _last=last_vision):  # type: ignore[no-untyped-def]
                t0 = time.perf_counter()
                move = super().next_move(state)
                reference_ticks_us.append((_last[0] + time.perf_counter() - t0) * 1e6)
                return move

        t0 = time.perf_counter()
        limit = reference_ticks if large else None
        trace = run_episode(
            scene, TimedRippleFront(), starts=[cell], headings=[heading], vision=timed_vision, max_steps=limit
        )
        reference_episode_ms.append((time.perf_counter() - t0) * 1e3)
        reference_steps = trace.steps

    # Fast path, cold cache, tick by tick.
    fast_ticks_us: list[float] = []
    for cell, heading in starts[: 1 if large else 3]:
        # Stepped one tick at a time, so each call is one compiled tick (and its vision fills).
        simulation = Simulation(scene, [RippleFront()])
        simulation.reset(starts=[cell], headings=[heading])
        while not simulation.done:
            t0 = time.perf_counter()
            simulation.step()
            fast_ticks_us.append((time.perf_counter() - t0) * 1e6)

    # Whole episodes: the reference's own episodes on the fast path, cold then warm.
    fresh = load_scene(path)
    fast_cold_ms = []
    for cell, heading in starts[:reference_runs]:
        t0 = time.perf_counter()
        run_episode(
            fresh, RippleFront(), starts=[cell], headings=[heading], max_steps=reference_ticks if large else None
        )
        fast_cold_ms.append((time.perf_counter() - t0) * 1e3)
    fast_warm_ms = []
    for cell, heading in starts[:reference_runs]:
        t0 = time.perf_counter()
        run_episode(
            fresh, RippleFront(), starts=[cell], headings=[heading], max_steps=reference_ticks if large else None
        )
        fast_warm_ms.append((time.perf_counter() - t0) * 1e3)
    batch_began = time.perf_counter()
    steps = []
    for cell, heading in starts:
        steps.append(run_episode(fresh, RippleFront(), starts=[cell], headings=[heading]).steps)
    batch_seconds = time.perf_counter() - batch_began

    return {
        "level": path.stem,
        "grid": f"{grid.shape[0]}x{grid.shape[1]}",
        "traversable": int(grid.traversable.sum()),
        "build_s": build_seconds,
        "reference_tick_median_us": statistics.median(reference_ticks_us),
        "reference_tick_p99_us": float(np.percentile(reference_ticks_us, 99)),
        "fast_tick_median_us": statistics.median(fast_ticks_us),
        "fast_tick_p99_us": float(np.percentile(fast_ticks_us, 99)),
        "reference_episode_ms": statistics.mean(reference_episode_ms),
        "reference_episode_steps": reference_steps,
        "fast_cold_episode_ms": statistics.mean(fast_cold_ms),
        "fast_warm_episode_ms": statistics.mean(fast_warm_ms),
        "episodes": episodes,
        "median_steps": statistics.median(steps),
        "batch_episodes_per_s": episodes / batch_seconds,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", nargs="*", type=Path, default=LEVELS)
    parser.add_argument("--maps", nargs="*", type=Path, default=[path for path in MAPS if path.exists()])
    parser.add_argument("--episodes", type=int, default=20, help="episodes per level for episodes/s")
    parser.add_argument("--reference-ticks", type=int, default=2000, help="reference tick cap on large maps")
    parser.add_argument("--one", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(measure(args.one, args.episodes, args.reference_ticks)))
        return
    rows = []
    for path in [*args.levels, *args.maps]:
        command = [sys.executable, __file__, "--one", str(path), "--episodes", str(args.episodes)]
        command += ["--reference-ticks", str(args.reference_ticks)]
        result = subprocess.run(command, capture_output=True, text=True, check=True)
        rows.append(json.loads(result.stdout.strip().splitlines()[-1]))
        print(f"measured {path.name}", file=sys.stderr)
    print("Per tick (vision + field + decision), microseconds; fast path from a cold cache")
    print(f"{'level':<14} {'grid':>9} {'ref median':>10} {'ref p99':>9} {'fast median':>11} {'fast p99':>9}")
    for row in rows:
        print(
            f"{row['level']:<14} {row['grid']:>9} {row['reference_tick_median_us']:>10.1f} "
            f"{row['reference_tick_p99_us']:>9.1f} {row['fast_tick_median_us']:>11.1f} {row['fast_tick_p99_us']:>9.1f}"
        )
    print()
    print("Per episode on one core (the same episodes on both paths), milliseconds")
    print(
        f"{'level':<14} {'steps':>6} {'reference':>9} {'fast cold':>9} {'fast warm':>9} {'x cold':>7} {'x warm':>7} "
        f"{'batch ep/s':>10} {'peak MB':>8}"
    )
    for row in rows:
        print(
            f"{row['level']:<14} {row['reference_episode_steps']:>6} {row['reference_episode_ms']:>9.1f} "
            f"{row['fast_cold_episode_ms']:>9.1f} {row['fast_warm_episode_ms']:>9.2f} "
            f"{row['reference_episode_ms'] / row['fast_cold_episode_ms']:>7.1f} "
            f"{row['reference_episode_ms'] / row['fast_warm_episode_ms']:>7.1f} "
            f"{row['batch_episodes_per_s']:>10.1f} {row['peak_rss_mb']:>8.0f}"
        )


if __name__ == "__main__":
    main()
