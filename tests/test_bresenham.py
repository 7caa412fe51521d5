"""The Bresenham line-of-sight rule: lines by hand, compiled against reference, the CLI options."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.cli.common import build_scene
from guardsim.vision.bresenham import bresenham_line
from tests.common import SQUARE_WITH_HOLE, import_map, level_from, write_level

SHARED = Path(__file__).resolve().parents[2] / "shared" / "maps" / "movingai"
OPTIMA_MAPS = [SHARED / name for name in ("maze-32-32-4.map", "arena.map", "den101d.map")]


@pytest.mark.parametrize(
    ("start", "end", "cells"),
    [
        ((0, 0), (3, 1), [(0, 0), (1, 0), (2, 1), (3, 1)]),
        ((0, 0), (1, 3), [(0, 0), (0, 1), (1, 2), (1, 3)]),
        ((0, 0), (2, 2), [(0, 0), (1, 1), (2, 2)]),
        ((3, 1), (0, 0), [(3, 1), (2, 1), (1, 0), (0, 0)]),
        ((2, 2), (2, 2), [(2, 2)]),
        ((0, 0), (-3, 0), [(0, 0), (-1, 0), (-2, 0), (-3, 0)]),
    ],
    ids=["shallow", "steep", "diagonal", "reversed", "same-cell", "leftward"],
)
def test_line_cells(start: tuple[int, int], end: tuple[int, int], cells: list[tuple[int, int]]) -> None:
    """The integer line visits the cells worked out by hand, traced from the viewer."""
    assert bresenham_line(*start, *end) == cells


def test_pillar_blocks_a_bresenham_line() -> None:
    """360 degrees, unlimited range: the pillar hides the cells straight behind it."""
    scene = build_scene(level_from(SQUARE_WITH_HOLE), "bresenham", 360.0)
    seen = {scene.grid.unflat(int(flat)) for flat in scene.vision_cache(0, 3, 0)}
    assert (1, 3) in seen and (5, 3) not in seen and (5, 0) not in seen and (5, 5) in seen
    assert len(scene.cone.offsets[0]) == 11 * 11


@pytest.mark.skipif(not all(path.exists() for path in OPTIMA_MAPS), reason="shared maps missing")
@pytest.mark.parametrize(
    "map_path",
    # den101d (4-5 s) runs in the slow tier only: the README's test command keeps its margin under 5 minutes.
    [
        pytest.param(path, id=path.stem, marks=[pytest.mark.slow] if path.stem == "den101d" else [])
        for path in OPTIMA_MAPS
    ],
)
def test_compiled_bresenham_equals_reference(map_path: Path) -> None:
    """80 random cells of each map with published optima see the same cells on both paths.

    (The plain-Python reference with an unlimited range takes ~40 ms a cell, hence a sample.)
    """
    scene = build_scene(import_map(map_path).level, "bresenham", 360.0)
    reference = scene.reference_vision()
    cells = np.flatnonzero(scene.grid.traversable.ravel())
    for flat in np.random.default_rng(7).choice(cells, size=min(80, cells.size), replace=False):
        col, row = scene.grid.unflat(int(flat))
        assert np.array_equal(scene.vision_cache(col, row, 0), reference(col, row, 0)), (col, row)


def test_bresenham_needs_no_range_limit_and_keeps_other_options(tmp_path: Path) -> None:
    """build_scene: Bresenham alone lifts the range to the grid's extent; --view-range still wins."""
    level = level_from(SQUARE_WITH_HOLE)
    assert build_scene(level, "bresenham").level.guard.view_range > 8.4
    assert build_scene(level, "bresenham", view_range=2.0).level.guard.view_range == 2.0
    assert build_scene(level).level.guard == level.guard
    assert dataclasses.asdict(build_scene(level, fov=120).level.guard)["fov_degrees"] == 120


def test_play_with_bresenham_options(tmp_path: Path) -> None:
    """`play --los bresenham --fov 360` covers and its trace equals the --reference run."""
    path = write_level(tmp_path, SQUARE_WITH_HOLE)
    runner = CliRunner()
    args = ["play", str(path), "--los", "bresenham", "--fov", "360"]
    fast = runner.invoke(main, [*args, "--trace", str(tmp_path / "fast.json")])
    reference = runner.invoke(main, [*args, "--trace", str(tmp_path / "ref.json"), "--reference"])
    assert fast.exit_code == 0 and reference.exit_code == 0, fast.output + reference.output
    assert "covered" in fast.output
    assert (tmp_path / "fast.json").read_bytes() == (tmp_path / "ref.json").read_bytes()
    bad = runner.invoke(main, ["play", str(path), "--fov", "400"])
    assert bad.exit_code == 2
