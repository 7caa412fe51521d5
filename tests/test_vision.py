"""Vision: the cone's range and edges, walls blocking sight, cells behind corners."""

from __future__ import annotations

import pytest

from guardsim.level import GuardSpec
from guardsim.vision import VisionCone, visible_cells
from tests.common import EMPTY_SQUARE, SPLIT_ROOMS, SQUARE_WITH_HOLE, scene_from

RIGHT, DOWN, LEFT, UP = range(4)


def seen_cells(data: dict, col: int, row: int, heading: int, **guard: float) -> set[tuple[int, int]]:
    """``(col, row)`` of every cell seen from a state."""
    scene = scene_from(data, guard=guard) if guard else scene_from(data)
    flat = visible_cells(scene.world, scene.grid, scene.cone, col, row, heading)
    return {scene.grid.unflat(int(index)) for index in flat}


def test_cone_edges_are_inclusive() -> None:
    """With a 90-degree cone facing right, exactly the cells with |drow| <= dcol are seen."""
    expected = {(dc, dr) for dc in range(4) for dr in range(4) if dr <= dc}
    assert seen_cells(EMPTY_SQUARE, 0, 0, RIGHT) == expected


def test_range_limits_sight() -> None:
    """A range of 2 cells keeps (2, 0) but drops (2, 1), whose centre is sqrt(5) away."""
    assert seen_cells(EMPTY_SQUARE, 0, 0, RIGHT, view_range=2.0) == {(0, 0), (1, 0), (2, 0), (1, 1)}


def test_cone_does_not_see_behind() -> None:
    """Facing left from the left wall, only the guard's own cell is seen."""
    assert seen_cells(EMPTY_SQUARE, 0, 1, LEFT) == {(0, 1)}


def test_own_cell_always_seen() -> None:
    """Even with a tiny range the guard's cell is seen."""
    assert seen_cells(EMPTY_SQUARE, 2, 2, UP, view_range=0.1) == {(2, 2)}


def test_wall_blocks_sight() -> None:
    """A thin wall between two rooms hides the far room entirely."""
    seen = seen_cells(SPLIT_ROOMS, 0, 0, RIGHT)
    assert seen == {(0, 0), (1, 0), (1, 1), (2, 0), (2, 1), (2, 2)}


def test_cell_behind_a_corner() -> None:
    """Looking down past the pillar: (3, 5) is hidden behind its corner, (1, 5) is in plain sight."""
    seen = seen_cells(SQUARE_WITH_HOLE, 0, 0, DOWN)
    assert (1, 5) in seen
    assert (3, 5) not in seen
    assert (3, 1) not in seen  # outside the cone: |dcol| > drow


@pytest.mark.parametrize("heading", range(4), ids=["right", "down", "left", "up"])
def test_cone_offsets_rotate_with_heading(heading: int) -> None:
    """The cone for each heading is the right-facing cone rotated by 90 degrees per heading."""
    cone = VisionCone.from_guard(GuardSpec(view_range=5.0, fov_degrees=70.0), 1.0)
    right = {tuple(offset) for offset in cone.offsets[0].tolist()}
    rotated = right
    for _ in range(heading):
        rotated = {(-drow, dcol) for dcol, drow in rotated}
    assert {tuple(offset) for offset in cone.offsets[heading].tolist()} == rotated


def test_full_circle_fov() -> None:
    """A 360-degree cone sees every cell in range whatever the heading."""
    cone = VisionCone.from_guard(GuardSpec(view_range=1.5, fov_degrees=360.0), 1.0)
    assert len(cone.offsets[0]) == 9
