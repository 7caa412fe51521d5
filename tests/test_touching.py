"""Touching is touching: a door exactly as wide as the guard lets it through however the door's
coordinates are spelled, while a door one hair narrower does not (issue 12, item 7)."""

from __future__ import annotations

import json

import pytest

from guardsim.grid import build_grid
from guardsim.level import parse_level
from guardsim.world import World

#: The same door (y 5.2 to 5.8 in a wall at x 4 to 6, radius 0.3) written in different decimal spellings,
#: some of which round to different doubles, and the same door moved far from the origin.
SPELLINGS = {
    "plain": ("5.2", "5.8", 0.0),
    "trailing zeros": ("5.20", "5.800", 0.0),
    "long form": ("5.2000000000000002", "5.7999999999999998", 0.0),
    "one ulp low": ("5.199999999999999", "5.8", 0.0),
    "one ulp high": ("5.2", "5.800000000000001", 0.0),
    "exponent": ("52e-1", "0.58e1", 0.0),
    "shifted by 1000": ("1005.2", "1005.8", 1000.0),
}


def door_level(low: str, high: str, shift: float, radius: str = "0.3") -> dict:
    """A 10 x 11 room split by a wall at x 4-6 with a door from y ``low`` to ``high``."""
    text = f"""{{
      "cell_size": 1,
      "outer": [[0, {shift}], [10, {shift}], [10, {shift + 11}], [0, {shift + 11}]],
      "holes": [[[4, {shift}], [6, {shift}], [6, {low}], [4, {low}]],
                [[4, {high}], [6, {high}], [6, {shift + 11}], [4, {shift + 11}]]],
      "guard": {{"radius": {radius}}}
    }}"""
    return json.loads(text)


def door_open(data: dict) -> bool:
    """Whether the cells left and right of the wall are connected through the door's row."""
    level = parse_level(data)
    grid = build_grid(level, World(level))
    row = 5
    cells = [grid.traversable[row, col] for col in (3, 4, 5, 6)]
    return all(cells) and all(
        grid.neighbours[row * grid.shape[1] + col, 0] == row * grid.shape[1] + col + 1 for col in (3, 4, 5)
    )


@pytest.mark.parametrize("spelling", SPELLINGS.values(), ids=list(SPELLINGS))
def test_a_door_exactly_the_guards_width_is_open(spelling: tuple[str, str, float]) -> None:
    assert door_open(door_level(*spelling))


@pytest.mark.parametrize("spelling", SPELLINGS.values(), ids=list(SPELLINGS))
def test_a_door_narrower_than_the_guard_stays_shut(spelling: tuple[str, str, float]) -> None:
    # 0.301 is far past rounding: the guard would overlap the door posts by a thousandth of a unit.
    assert not door_open(door_level(*spelling, radius="0.301"))


def test_touching_tolerance_scales_with_the_level() -> None:
    small = World(parse_level(door_level("5.2", "5.8", 0.0)))
    large = World(parse_level({"cell_size": 1000, "outer": [[0, 0], [1e6, 0], [1e6, 1e6], [0, 1e6]]}))
    assert small.touch < 1e-7 < large.touch < 1e-2
