"""The fast paths give exactly the reference's answers: vision state by state, traces tick by tick."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from guardsim import load_level
from guardsim.motion import run_episode
from guardsim.planners import RippleFront
from guardsim.simulation import Scene, choose_start, episode_generator
from guardsim.vision import visible_cells
from tests.common import (
    TINY_LEVELS,
    fast_equals_reference,
    scene_from,
    shipped_levels,
    shipped_levels_square_fast,
    tiny_levels,
)


def assert_every_state_matches(scene: Scene) -> int:
    """Compare the cache with the per-cell rays on every state; return how many states were checked."""
    grid = scene.grid
    checked = 0
    for cell in np.flatnonzero(grid.traversable.ravel()):
        col, row = grid.unflat(int(cell))
        for heading in range(4):
            expected = visible_cells(scene.world, grid, scene.cone, col, row, heading)
            assert np.array_equal(scene.vision_cache(col, row, heading), expected), (col, row, heading)
            checked += 1
    return checked


@shipped_levels_square_fast
def test_vision_cache_equals_reference_on_every_state(level_path: Path) -> None:
    """All (cell, heading) states of each shipped level see the same cells on both paths."""
    scene = Scene.from_level(load_level(level_path))
    assert assert_every_state_matches(scene) == 4 * int(scene.grid.traversable.sum())


@tiny_levels
def test_vision_cache_equals_reference_on_tiny_levels(level_data: dict) -> None:
    """Same on the tiny levels, with a short range so that walls and open space both occur."""
    assert_every_state_matches(scene_from(level_data, guard={"view_range": 2.5, "fov_degrees": 120}))


@shipped_levels
@pytest.mark.parametrize("sweeps", [1, 3])
def test_fast_trace_equals_reference_trace(level_path: Path, sweeps: int) -> None:
    """Random episodes give byte-identical traces on the compiled path and the reference loop."""
    scene = Scene.from_level(load_level(level_path))
    for episode in range(2):
        fast_equals_reference(scene, seed=11, episode=episode, sweeps_per_tick=sweeps)


@pytest.mark.parametrize("max_steps", [0, 1, 37])
def test_fast_path_honours_the_step_limit(max_steps: int) -> None:
    """The compiled loop stops at the same tick with the same outcome as the reference."""
    scene = Scene.from_level(load_level(Path("levels/passages.json")))
    cell, heading = choose_start(scene, rng=episode_generator(0, 0))
    fast = fast_equals_reference(scene, RippleFront(), starts=[cell], headings=[heading], max_steps=max_steps)
    assert fast.outcome == "step_limit" and fast.steps == max_steps


def test_unreachable_cells_on_the_fast_path() -> None:
    """A sealed room stays out of the goal on the fast path too."""
    scene = scene_from(TINY_LEVELS["split-rooms"], guard={"view_range": 2.0})
    fast = fast_equals_reference(scene, RippleFront(), starts=[(0, 0)], headings=[0])
    assert fast.unreachable == 9


def test_cache_is_shared_between_episodes() -> None:
    """A second episode from the same start computes no new vision state."""
    scene = Scene.from_level(load_level(Path("levels/square.json")))
    run_episode(scene, seed=0, episode=0)
    computed = scene.vision_cache.computed
    assert computed > 0
    run_episode(scene, seed=0, episode=0)
    assert scene.vision_cache.computed == computed
