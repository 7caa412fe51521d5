"""The simulation loop: invariants on tiny levels, stored exact traces, shipped levels covered, determinism.

The exact traces live in ``tests/data/trace-<level>.json``. After an intended change of behaviour,
regenerate them with ``GUARDSIM_UPDATE_TRACES=1 python -m pytest tests/test_simulation.py`` and review
the diff.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from guardsim import load_level
from guardsim.motion import run_episode
from guardsim.planners import RippleFront
from guardsim.planners.base import GuardState
from guardsim.simulation import Scene, choose_start, default_max_steps
from guardsim.trace import Trace
from tests.common import SPLIT_ROOMS, TINY_LEVELS, TRACE_KEYS, level_from, scene_from, shipped_levels, tiny_levels

DATA = Path(__file__).parent / "data"


def play(scene: Scene, seed: int = 0, **options: object) -> Trace:
    """One RippleFront episode from the level's start (or a seeded draw)."""
    rng = np.random.default_rng(seed)
    level = scene.level
    cell, heading = choose_start(scene, rng=rng, point=level.guard.start, heading=level.guard.heading)
    return run_episode(scene, RippleFront(), starts=[cell], headings=[heading], seed=seed, **options)


@tiny_levels
def test_episode_invariants(level_data: dict) -> None:
    """Covered; every step is to a connected neighbour; every goal cell seen; unseen never grows."""
    scene = scene_from(level_data)
    trace = play(scene)
    assert trace.outcome == "covered"
    grid = scene.grid
    for (col, row), (next_col, next_row), heading in zip(trace.path, trace.path[1:], trace.headings[1:]):
        assert grid.neighbours[grid.flat(col, row), heading] == grid.flat(next_col, next_row)
    assert (trace.first_seen[trace.goal] >= 0).all()
    assert (trace.first_seen[trace.goal] <= trace.steps).all()
    assert all(a >= b for a, b in zip(trace.unseen_percent, trace.unseen_percent[1:]))
    assert trace.unseen_percent[-1] == 0.0
    assert len(trace.unseen_percent) == len(trace.path) == len(trace.headings)


@pytest.mark.parametrize("name", list(TINY_LEVELS))
def test_exact_trace_on_tiny_level(name: str) -> None:
    """The whole trace on each tiny level, with a short-sighted guard, equals the stored one byte for byte."""
    data = TINY_LEVELS[name]
    text = play(scene_from(data, guard={**data["guard"], "view_range": 2.0})).to_json()
    stored = DATA / f"trace-{name}.json"
    if os.environ.get("GUARDSIM_UPDATE_TRACES"):
        stored.write_text(text, encoding="utf-8")
    assert text == stored.read_text(encoding="utf-8")


def test_unreachable_cells_are_reported_not_chased() -> None:
    """The sealed room's 9 cells are unreachable, left out of the goal, and the episode still covers."""
    trace = play(scene_from(SPLIT_ROOMS))
    assert (trace.reachable, trace.unreachable) == (9, 9)
    assert trace.outcome == "covered"
    assert all(col < 3 for col, _ in trace.path)


@shipped_levels
def test_shipped_level_is_covered(level_path: Path) -> None:
    """A full episode on each shipped level, from its start, sees every reachable cell."""
    trace = play(Scene.from_level(load_level(level_path)))
    assert trace.covered
    assert trace.unreachable == 0
    assert trace.steps < default_max_steps(Scene.from_level(load_level(level_path)).grid)


@pytest.mark.parametrize("seed", [0, 7])
def test_same_seed_same_trace(seed: int) -> None:
    """Two copies from the same seed give the same trace JSON; a random start makes seeds matter."""
    level = level_from(TINY_LEVELS["square-with-hole"], guard={})
    first = play(Scene.from_level(level), seed=seed).to_json()
    second = play(Scene.from_level(level), seed=seed).to_json()
    assert first == second


def test_different_seeds_draw_different_starts() -> None:
    """With no start in the level, the seed picks the start and heading."""
    level = level_from(TINY_LEVELS["square-with-hole"], guard={})
    starts = {(play(Scene.from_level(level), seed=seed).start) for seed in range(10)}
    assert len(starts) > 3


def test_step_limit_stops_the_episode() -> None:
    """With max_steps=2 the episode ends after two steps with outcome step_limit."""
    trace = play(Scene.from_level(load_level(Path("levels/square.json"))), max_steps=2)
    assert (trace.outcome, trace.steps, trace.covered) == ("step_limit", 2, False)


class _StandStill:
    """A planner that never moves: the loop must end the episode as stuck."""

    name = "stand-still"

    def reset(self, setup: object) -> None:
        pass

    def next_move(self, state: GuardState) -> int | None:
        return None


def test_no_move_possible_ends_stuck() -> None:
    """A planner with no move gives outcome stuck after zero steps."""
    scene = scene_from(TINY_LEVELS["empty-square"])
    trace = run_episode(scene, _StandStill(), starts=[(0, 0)], headings=[0])
    assert (trace.outcome, trace.steps) == ("stuck", 0)


def test_trace_json_round_trip_and_keys() -> None:
    """The JSON has the documented keys and reads back to an equal trace."""
    trace = play(scene_from(TINY_LEVELS["l-room"]))
    data = json.loads(trace.to_json())
    assert set(data) >= TRACE_KEYS
    assert data["steps"] == len(data["path"]) - 1
    assert Trace.from_data(data).to_json() == trace.to_json()


def test_steps_to_fraction() -> None:
    """T50/T90/T100 read off first_seen: monotone, and T100 is the last step of a covered episode."""
    trace = play(Scene.from_level(load_level(Path("levels/passages.json"))))
    t50, t90, t100 = (trace.steps_to_fraction(f) for f in (0.5, 0.9, 1.0))
    assert t50 is not None and t90 is not None
    assert 0 < t50 <= t90 <= t100 == trace.steps


def test_more_sweeps_per_tick_changes_behaviour() -> None:
    """sweeps_per_tick is passed through: a converged field gives a different walk on the square."""
    scene = Scene.from_level(load_level(Path("levels/square.json")))
    cell, heading = choose_start(scene, rng=np.random.default_rng(0), point=scene.level.guard.start, heading="right")
    ripple = run_episode(scene, RippleFront(1), starts=[cell], headings=[heading])
    converged = run_episode(scene, RippleFront(50), starts=[cell], headings=[heading])
    assert converged.covered and ripple.covered
    assert converged.path != ripple.path
