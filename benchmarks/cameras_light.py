"""Cameras and light: what they cost the undetected sneak search, and how fast the light map is.

1. Square (60 x 60) with a loop patrol of 2 guards: ``sneak_check(undetected=True)`` from corner to
   corner, once as shipped and once with 3 sweeping cameras, 5 lamps and a dark ambient (0.2). The
   cameras' swings are picked so that their periods divide the patrol's lap (as a designer tuning a level
   would: the joint lap stays the patrol's), and the seconds of both are printed with their ratio
   (warm: each is run once before it is timed). The seconds include building the cameras' sight and the
   light map (``level_watch``).
2. A 256 x 256 open level with 50 lamps of radius 12 at seeded random places and a few pillars:
   the seconds of ``light_map``, cold and warm (best of 3).

    python benchmarks/cameras_light.py
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from guardsim import load_level
from guardsim.detection import GuardDetection
from guardsim.detection.light import light_map
from guardsim.detection.watch import level_watch
from guardsim.level import Camera, Light, parse_level
from guardsim.patrol import patrol_setup, plan_loop
from guardsim.scene import Scene
from guardsim.sneak import sneak_check

REPO = Path(__file__).resolve().parent.parent


def _divisor_swings(period: int, dt: float) -> list[tuple[float, float]]:
    """``(sweep, pause)`` pairs at 90 degrees/s whose swings last a whole even number of ticks dividing
    ``period``, longest first."""
    swings = []
    for ticks in range(min(period, 40), 5, -1):
        if period % ticks or ticks % 2:
            continue
        # 90 degrees of turning each way takes 1 s; the pauses fill the rest.
        pause = ticks * dt / 2 - 1.0
        if pause >= 0:
            swings.append((90.0, pause))
    return swings or [(0.0, 1.0)]


def sneak_figures(guards: int) -> None:
    level = load_level(REPO / "levels" / "square.json")
    scene = Scene.from_level(level)
    setup = patrol_setup(scene, guards)
    patrol = plan_loop(setup, guards)[0].patrol
    detection = GuardDetection.of_level(level)
    assert patrol.period is not None
    swings = _divisor_swings(patrol.period, detection.dt)
    spots = [((30.0, 0.0), 90.0), ((0.0, 30.0), 0.0), ((60.0, 45.0), 180.0)]
    cameras = tuple(
        Camera(position, heading=heading, fov_degrees=60, sweep=swings[i % len(swings)][0], turn_speed=90,
               pause=swings[i % len(swings)][1])
        for i, (position, heading) in enumerate(spots)
    )  # fmt: skip
    lamps = tuple(Light((x, y), 8.0, 0.8) for x, y in ((10, 10), (50, 10), (30, 30), (10, 50), (50, 50)))
    watched = dataclasses.replace(level, cameras=cameras, lights=lamps, ambient_light=0.2)
    watched_scene = Scene(watched, scene.world, scene.grid, scene.cone, scene.rule)
    grid = scene.grid
    cells = np.flatnonzero(setup.goal)
    col, row = cells % grid.shape[1], cells // grid.shape[1]
    source, target = int(cells[np.argmin(col + row)]), int(cells[np.argmax(col + row)])

    def plain() -> object:
        return sneak_check(grid, setup.table, patrol, source, target, detection=detection, undetected=True)

    def with_watch() -> object:
        watch = level_watch(watched_scene, detection.dt)
        return sneak_check(grid, setup.table, patrol, source, target, detection=detection, undetected=True, watch=watch)

    rows = []
    for name, run in (("without", plain), ("with", with_watch)):
        run()
        began = time.perf_counter()
        result = run()
        rows.append((name, time.perf_counter() - began, result))
    (_, base, _), (_, seconds, _) = rows
    print(f"square, {guards} guards, lap {patrol.period} ticks; camera periods "
          f"{level_watch(watched_scene, detection.dt).periods}")  # fmt: skip
    for name, spent, result in rows:
        path = result.path  # type: ignore[attr-defined]
        print(
            f"  {name:7} cameras and light: found {result.found}, ticks {path.ticks}, "  # type: ignore[attr-defined]
            f"lap {result.period}, {spent:.2f} s"  # type: ignore[attr-defined]
        )
    print(f"  ratio with / without: {seconds / base:.2f} (at most 3 wanted)")


def light_figures(lamps: int, size: int) -> None:
    rng = np.random.default_rng(40)
    pillars = []
    for _ in range(40):
        x, y = (float(v) for v in rng.integers(4, size - 8, 2))
        pillars.append([[x, y], [x + 3, y], [x + 3, y + 3], [x, y + 3]])
    level = parse_level({"name": "lamps", "outer": [[0, 0], [size, 0], [size, size], [0, size]], "holes": pillars})
    lights = []
    scene = Scene.from_level(level)
    free = np.flatnonzero(scene.grid.traversable.ravel())
    for cell in rng.choice(free, lamps, replace=False).tolist():
        lights.append(Light((cell % size + 0.5, cell // size + 0.5), 12.0, 0.7))
    lit = dataclasses.replace(level, lights=tuple(lights), ambient_light=0.1)
    lit_scene = Scene(lit, scene.world, scene.grid, scene.cone, scene.rule)
    began = time.perf_counter()
    light_map(lit_scene)
    cold = time.perf_counter() - began
    warm = []
    for _ in range(3):
        began = time.perf_counter()
        values = light_map(lit_scene)
        warm.append(time.perf_counter() - began)
    print(
        f"light map {size} x {size}, {lamps} lamps of radius 12: cold {cold:.3f} s, warm {min(warm):.3f} s "
        f"(at most 1 s wanted); mean light {float(values.mean()):.3f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--guards", type=int, default=2)
    parser.add_argument("--lamps", type=int, default=50)
    parser.add_argument("--size", type=int, default=256)
    args = parser.parse_args()
    light_figures(args.lamps, args.size)
    sneak_figures(args.guards)


if __name__ == "__main__":
    main()
