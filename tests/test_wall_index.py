"""The sight screen's wall index: each wall in the buckets its segment crosses, counted before it is built.

The index once entered every wall in every bucket of its bounding box: 99,997 spikes from the middle of
a level to its rim made 120 million entries and 3 GB of Python lists (6 GB at a shorter view range)
before the view table's estimate was asked. The invariant that matters is the screen's: a wall that
touches a ray is always tested against it.
"""

from __future__ import annotations

import math
import tracemalloc
from typing import Any

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.errors import LimitError
from guardsim.kernels import screen as screen_module
from guardsim.kernels.screen import BLOCKED, CLEAR, WallIndex, index_walls, screen
from tests.common import write_level


def bounding_box_index(
    segments: np.ndarray, origin: tuple[float, float], extent: tuple[float, float], reach: float
) -> WallIndex:
    """The former index, every wall in every bucket of its box: the reference the new one must agree with."""
    new = index_walls(segments, origin, extent, reach)
    bucket, columns, rows = new.bucket, new.columns, new.rows
    members: list[list[int]] = [[] for _ in range(columns * rows)]
    for index, (ax, ay, bx, by) in enumerate(segments.tolist()):
        first_row = min(rows - 1, max(0, int((min(ay, by) - origin[1]) // bucket)))
        last_row = min(rows - 1, max(0, int((max(ay, by) - origin[1]) // bucket)))
        first_col = min(columns - 1, max(0, int((min(ax, bx) - origin[0]) // bucket)))
        last_col = min(columns - 1, max(0, int((max(ax, bx) - origin[0]) // bucket)))
        for row in range(first_row, last_row + 1):
            for col in range(first_col, last_col + 1):
                members[row * columns + col].append(index)
    start = np.zeros(len(members) + 1, dtype=np.int64)
    start[1:] = np.cumsum([len(walls) for walls in members])
    walls = np.array([wall for walls in members for wall in walls], dtype=np.int64)
    return new._replace(start=start, walls=walls)


def verdicts(index: WallIndex, eye: tuple[float, float], targets: np.ndarray) -> np.ndarray:
    out = np.zeros(len(targets), dtype=np.int8)
    screen(eye[0], eye[1], targets, index, np.zeros(index.segments.shape[0] + 1, dtype=np.int64), out)
    return out


def random_segments(rng: np.random.Generator, count: int, size: float, bucket: float) -> np.ndarray:
    """Long and short, slanted, level and upright segments, many of them on bucket sides or corners."""
    ends = rng.uniform(0, size, (count, 4))
    snapped = rng.random((count, 4)) < 0.4
    ends[snapped] = np.round(ends[snapped] / bucket) * bucket
    upright = rng.random(count) < 0.15
    ends[upright, 2] = ends[upright, 0]
    level = rng.random(count) < 0.15
    ends[level, 3] = ends[level, 1]
    return ends


@pytest.mark.parametrize("seed", range(6))
def test_every_wall_touching_a_ray_is_screened(seed: int) -> None:
    """Against random walls, the new index blocks exactly the rays the bounding-box index blocked, and
    leaves no ray that touches a wall (as shapely sees it) clear."""
    rng = np.random.default_rng(seed)
    size, reach = 40.0, 5.0
    segments = random_segments(rng, 60, size, reach)
    origin, extent = (0.0, 0.0), (size, size)
    new = index_walls(segments, origin, extent, reach)
    old = bounding_box_index(segments, origin, extent, reach)
    assert new.walls.size < old.walls.size
    lines = shapely.linestrings(segments.reshape(-1, 2, 2))
    for _ in range(150):
        eye = tuple(rng.uniform(0, size, 2).round(rng.integers(0, 3)))
        angles = rng.uniform(0, 2 * math.pi, 40)
        lengths = rng.uniform(0, reach, 40)
        targets = np.stack([eye[0] + lengths * np.cos(angles), eye[1] + lengths * np.sin(angles)], axis=1)
        got, reference = verdicts(new, eye, targets), verdicts(old, eye, targets)
        assert np.array_equal(got == BLOCKED, reference == BLOCKED)
        rays = shapely.linestrings(np.stack([np.broadcast_to(eye, targets.shape), targets], axis=1))
        touching = np.array([shapely.intersects(ray, lines).any() for ray in rays])
        assert not np.any(touching & (got == CLEAR)), eye


def fan(count: int, centre: float = 500.0, inner: float = 20.0, outer: float = 495.0) -> np.ndarray:
    """A star ring of ``count`` points alternating between two radii: long thin spikes."""
    angles = np.linspace(0, 2 * math.pi, count, endpoint=False)
    radii = np.where(np.arange(count) % 2 == 1, outer, inner)
    return np.stack([centre + radii * np.cos(angles), centre + radii * np.sin(angles)], axis=1)


def ring_segments(ring: np.ndarray) -> np.ndarray:
    return np.hstack([ring, np.roll(ring, -1, axis=0)])


def test_long_spikes_enter_only_the_buckets_they_cross() -> None:
    """2,000 spikes on a 1000-unit level at a reach of 8: each enters about the buckets along it, a
    tenth of its bounding box."""
    segments = ring_segments(fan(2000))
    new = index_walls(segments, (5.0, 5.0), (990.0, 990.0), 8.0)
    old = bounding_box_index(segments, (5.0, 5.0), (990.0, 990.0), 8.0)
    assert new.walls.size * 10 < old.walls.size
    spans = (np.abs(segments[:, 2] - segments[:, 0]) + np.abs(segments[:, 3] - segments[:, 1])) / new.bucket
    assert new.walls.size <= int((spans + 4).sum())


def test_wall_index_over_the_limit_is_refused_before_it_is_listed() -> None:
    """The 99,997-point star at a reach of 4 (15 million entries, past 5.7 GB before) is one LimitError,
    counted in entries: no more memory than the count's temporary arrays."""
    segments = ring_segments(fan(99_997))
    tracemalloc.start()
    try:
        with pytest.raises(LimitError) as raised:
            index_walls(segments, (5.0, 5.0), (990.0, 990.0), 4.0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    message = str(raised.value)
    assert "\n" not in message
    assert "99997 wall segments would hold more than 8000000 entries (max_wall_entries)" in message
    assert peak < 400 * 2**20, peak
    # Just under the limit is built, and holds what it counted.
    assert index_walls(segments, (5.0, 5.0), (990.0, 990.0), 8.0).walls.size <= screen_module.MAX_WALL_ENTRIES


def test_bounds_refuses_a_level_past_the_wall_index_limit_in_one_line(tmp_path: Any, monkeypatch: Any) -> None:
    """The command line names the file and the limit, exit status 2 (limit lowered to keep the level small)."""
    monkeypatch.setattr(screen_module, "MAX_WALL_ENTRIES", 500)
    ring = fan(400, centre=50.0, inner=4.0, outer=48.0).round(6).tolist()
    path = write_level(tmp_path, {"outer": ring, "cell_size": 2, "guard": {"start": [50, 50]}}, "spikes.json")
    result = CliRunner().invoke(main, ["bounds", str(path)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("guardsim: error: ") and "spikes.json: " in lines[0]
    assert "(max_wall_entries: use fewer long walls" in lines[0]
