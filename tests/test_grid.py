"""Rasterisation: which cells are traversable, connected and reachable, on levels small enough to count."""

from __future__ import annotations

import numpy as np
import pytest

from guardsim.errors import LevelError
from guardsim.grid import start_cell
from tests.common import EMPTY_SQUARE, L_ROOM, SPLIT_ROOMS, SQUARE_WITH_HOLE, level_from, scene_from

CORRIDOR = {"outer": [[0, 0], [5, 0], [5, 1], [0, 1]]}


@pytest.mark.parametrize(
    ("data", "shape", "traversable", "reachable"),
    [
        (EMPTY_SQUARE, (4, 4), 16, 16),
        (SQUARE_WITH_HOLE, (6, 6), 32, 32),
        (L_ROOM, (6, 6), 20, 20),
        (SPLIT_ROOMS, (3, 6), 18, 9),
    ],
    ids=["empty-square", "square-with-hole", "l-room", "split-rooms"],
)
def test_cell_counts(data: dict, shape: tuple[int, int], traversable: int, reachable: int) -> None:
    """Exact counts of traversable cells and of cells reachable from the start."""
    scene = scene_from(data)
    assert scene.grid.shape == shape
    assert int(scene.grid.traversable.sum()) == traversable
    assert int(scene.grid.component(0, 0).sum()) == reachable


def test_hole_cells_are_not_traversable() -> None:
    """The pillar's four cells are walls; the cells around it are free."""
    grid = scene_from(SQUARE_WITH_HOLE).grid
    assert not grid.traversable[2:4, 2:4].any()
    assert grid.traversable[1, 1:5].all() and grid.traversable[4, 1:5].all()


def test_l_room_corner_is_outside() -> None:
    """The cut-out corner of the L lies outside the outer ring."""
    grid = scene_from(L_ROOM).grid
    assert not grid.traversable[2:, 2:].any()
    assert grid.traversable[:2, :].all() and grid.traversable[:, :2].all()


@pytest.mark.parametrize(("radius", "traversable"), [(0.45, 5), (0.5, 5), (0.51, 0), (0.6, 0)])
def test_guard_must_fit(radius: float, traversable: int) -> None:
    """In a one-cell corridor the guard fits while its radius is at most half a cell.

    A circle exactly touching both walls fits: only a wall closer than the radius blocks.
    """
    grid = scene_from(CORRIDOR, guard={"radius": radius}).grid
    assert int(grid.traversable.sum()) == traversable


def test_thin_wall_cuts_connection_but_not_cells() -> None:
    """Cells on both sides of a thin wall are traversable, yet not connected across it."""
    grid = scene_from(SPLIT_ROOMS).grid
    assert grid.traversable[:, 2].all() and grid.traversable[:, 3].all()
    for row in range(3):
        assert grid.neighbours[grid.flat(2, row), 0] == -1
        assert grid.neighbours[grid.flat(3, row), 2] == -1
    assert grid.neighbours[grid.flat(1, 0), 0] == grid.flat(2, 0)


def test_neighbours_are_symmetric() -> None:
    """If a connects to b in one direction, b connects back to a in the opposite one."""
    grid = scene_from(SQUARE_WITH_HOLE).grid
    for cell in range(grid.size):
        for direction in range(4):
            other = grid.neighbours[cell, direction]
            if other >= 0:
                assert grid.neighbours[other, (direction + 2) % 4] == cell


def test_largest_component_picks_the_bigger_room() -> None:
    """With rooms of 6 and 3 cells, the largest component is the 6-cell one."""
    data = {"outer": [[0, 0], [6, 0], [6, 1], [0, 1]], "holes": [[[3.9, 0], [4.1, 0], [4.1, 1], [3.9, 1]]]}
    component = scene_from(data).grid.largest_component()
    assert component[0, :4].all() and not component[0, 4:].any()


def test_world_is_a_real_pymunk_space() -> None:
    """Every ring edge is a static segment in the space; the guard is a body with a circle."""
    scene = scene_from(SQUARE_WITH_HOLE)
    assert len(scene.world.walls) == 8
    assert all(shape.body is scene.world.space.static_body for shape in scene.world.walls)
    assert scene.world.guard_shape in scene.world.space.shapes
    scene.world.place_guard((1.5, 1.5))
    assert tuple(scene.world.guard_body.position) == (1.5, 1.5)


def test_cell_centres_and_lookup() -> None:
    """The centre of [col, row] is origin + (col + 0.5, row + 0.5) * cell_size; cell_of inverts it."""
    data = {"cell_size": 2.0, "outer": [[10, 20], [18, 20], [18, 26], [10, 26]]}
    grid = scene_from(data).grid
    assert grid.origin == (10.0, 20.0)
    assert grid.shape == (3, 4)
    assert grid.centre(1, 2) == (13.0, 25.0)
    assert grid.cell_of((13.0, 25.0)) == (1, 2)
    assert grid.cell_of((9.0, 25.0)) is None


def test_start_in_a_cell_too_tight_for_the_guard() -> None:
    """A start whose cell cannot hold the guard's circle is a LevelError naming the cell."""
    level = level_from(CORRIDOR, guard={"radius": 0.6})
    grid = scene_from(CORRIDOR, guard={"radius": 0.6}).grid
    with pytest.raises(LevelError, match=r"test\.json: start \(0\.5, 0\.5\) is in cell \[0, 0\]"):
        start_cell(level, grid, (0.5, 0.5))


def test_traversable_is_boolean_grid() -> None:
    """The grid exposes numpy arrays of the documented dtypes and shapes."""
    grid = scene_from(EMPTY_SQUARE).grid
    assert grid.traversable.dtype == np.bool_
    assert grid.neighbours.shape == (16, 4)
