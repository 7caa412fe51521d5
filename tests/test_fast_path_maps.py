"""The fast paths against the reference on every real map in ../shared/maps.

Vision: a seeded random sample of states on each map (all states on the shipped levels are checked in
test_fast_path.py). Traces: whole episodes on the maps small enough for the reference loop.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from guardsim.simulation import Scene
from guardsim.vision import visible_cells
from tests.common import fast_equals_reference, import_map

SHARED = Path(__file__).resolve().parents[2] / "shared" / "maps"
MAPS = sorted((SHARED / "movingai").glob("*.map")) + sorted((SHARED / "tiled").glob("*.tmx"))
SMALL_MAPS = [path for path in MAPS if path.suffix == ".map" and path.stat().st_size < 5_000]

needs_maps = pytest.mark.skipif(not MAPS, reason=f"the shared maps are not at {SHARED}")
#: Whole real maps, every state: the slow tier (`pytest -m slow`); tests/test_fast_path.py keeps Square fast.
pytestmark = pytest.mark.slow


@needs_maps
@pytest.mark.parametrize("map_path", MAPS, ids=[path.name for path in MAPS])
def test_vision_cache_equals_reference_on_sampled_states(map_path: Path) -> None:
    """300 random states per map see the same cells through the cache as through per-cell rays."""
    scene = Scene.from_level(import_map(map_path).level)
    grid = scene.grid
    cells = np.flatnonzero(grid.traversable.ravel())
    rng = np.random.default_rng(2026)
    for cell in rng.choice(cells, size=min(300, cells.size), replace=False):
        col, row = grid.unflat(int(cell))
        heading = int(rng.integers(4))
        expected = visible_cells(scene.world, grid, scene.cone, col, row, heading)
        assert np.array_equal(scene.vision_cache(col, row, heading), expected), (col, row, heading)


@needs_maps
@pytest.mark.parametrize("map_path", SMALL_MAPS, ids=[path.name for path in SMALL_MAPS])
def test_fast_trace_equals_reference_on_small_maps(map_path: Path) -> None:
    """A whole random episode gives the same trace on both paths."""
    scene = Scene.from_level(import_map(map_path).level)
    assert fast_equals_reference(scene, seed=3, episode=0).covered
