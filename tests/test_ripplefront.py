"""RippleFront's field against values worked out by hand, and its greedy choice."""

from __future__ import annotations

import numpy as np
import pytest

from guardsim.planners.ripplefront import FAR, greedy_move, ripple_sweep
from tests.common import EMPTY_SQUARE, scene_from


def open_grid_neighbours(rows: int, cols: int) -> np.ndarray:
    """Neighbour table of an open rows x cols grid (right, down, left, up)."""
    neighbours = np.full((rows * cols, 4), -1, dtype=np.int64)
    for row in range(rows):
        for col in range(cols):
            here = row * cols + col
            for direction, (dcol, drow) in enumerate(((1, 0), (0, 1), (-1, 0), (0, -1))):
                if 0 <= col + dcol < cols and 0 <= row + drow < rows:
                    neighbours[here, direction] = (row + drow) * cols + col + dcol
    return neighbours


def test_field_ripples_one_sweep_at_a_time() -> None:
    """3 x 3 grid, only the bottom-right cell unseen, from an all-zero field (worked by hand)."""
    neighbours = open_grid_neighbours(3, 3)
    seen = np.ones(9, dtype=bool)
    seen[8] = False
    field = np.zeros(9, dtype=np.int32)
    expected = [
        [[1, 1, 1], [1, 1, 1], [1, 1, 0]],
        [[2, 2, 2], [2, 2, 1], [2, 1, 0]],
        [[3, 3, 2], [3, 2, 1], [2, 1, 0]],
        [[4, 3, 2], [3, 2, 1], [2, 1, 0]],
        [[4, 3, 2], [3, 2, 1], [2, 1, 0]],
    ]
    for values in expected:
        field = ripple_sweep(field, seen, neighbours)
        assert field.reshape(3, 3).tolist() == values


def test_field_drops_when_a_cell_is_unseen_again_elsewhere() -> None:
    """Unseen cells are always 0, and their neighbours drop to 1 in one sweep."""
    neighbours = open_grid_neighbours(1, 5)
    seen = np.array([False, True, True, True, True])
    field = np.array([0, 7, 7, 7, 7], dtype=np.int32)
    field = ripple_sweep(field, seen, neighbours)
    assert field.tolist() == [0, 1, 8, 8, 8]


def test_isolated_seen_cell_is_far() -> None:
    """A seen cell with no connected neighbour gets FAR, never overflowing."""
    neighbours = np.full((1, 4), -1, dtype=np.int64)
    field = ripple_sweep(np.array([FAR], dtype=np.int32), np.array([True]), neighbours)
    assert field.tolist() == [FAR]


@pytest.mark.parametrize(
    ("distances", "heading", "expected"),
    [
        ([5, 3, 4, 3], 0, 1),  # smallest wins
        ([2, 2, 2, 2], 2, 2),  # all equal: keep heading
        ([3, 2, 9, 2], 0, 1),  # tie between 1 and 3, heading not among them: lowest number
        ([3, 2, 9, 2], 3, 3),  # tie including the heading: keep heading
    ],
    ids=["smallest", "all-equal-keeps-heading", "tie-lowest-number", "tie-keeps-heading"],
)
def test_greedy_tie_break(distances: list[int], heading: int, expected: int) -> None:
    """Ties go to the current heading, then to right, down, left, up in that order."""
    field = np.array(distances, dtype=np.int32)
    assert greedy_move(field, np.array([0, 1, 2, 3]), heading) == expected


def test_greedy_skips_walls() -> None:
    """A missing neighbour (-1) is never chosen; none at all gives None."""
    field = np.array([0, 9], dtype=np.int32)
    assert greedy_move(field, np.array([-1, 1, -1, -1]), 0) == 1
    assert greedy_move(field, np.array([-1, -1, -1, -1]), 0) is None


def test_real_grid_sweep_matches_bfs_after_convergence() -> None:
    """Enough sweeps turn the field into exact 4-connected distances to the unseen cells."""
    grid = scene_from(EMPTY_SQUARE).grid
    seen = np.ones(grid.size, dtype=bool)
    seen[grid.flat(3, 3)] = False
    field = np.zeros(grid.size, dtype=np.int32)
    for _ in range(grid.size):
        field = ripple_sweep(field, seen, grid.neighbours)
    expected = [[abs(3 - col) + abs(3 - row) for col in range(4)] for row in range(4)]
    assert field.reshape(4, 4).tolist() == expected
