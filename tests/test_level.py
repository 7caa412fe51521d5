"""The level loader: every kind of bad level is a LevelError naming the file and the place at fault.

``BAD_LEVELS`` and ``GRID_TIME_LEVELS`` (tests/bad_levels.py) are shared with ``tests/test_cli.py``,
which checks that the same files give one clean error line on the command line.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import shapely

from guardsim import load_level
from guardsim.errors import LevelError
from guardsim.level import (
    GuardSpec,
    Level,
    Problem,
    check_level_data,
    free_area_of,
    level_to_data,
    parse_level,
)
from guardsim.simulation import Scene, choose_start
from tests.bad_levels import (
    BAD_LEVELS,
    GRID_TIME_LEVELS,
    PILLAR,
    BadLevel,
    bad_params,
    changed,
)
from tests.common import EMPTY_SQUARE, SQUARE_WITH_HOLE, shipped_levels, tiny_levels, write_level


def start_of(level: Level) -> tuple[tuple[int, int], int]:
    """Build the level's grid and place the guard at its start, as ``guardsim play`` does."""
    return choose_start(Scene.from_level(level), rng=np.random.default_rng(0), point=level.guard.start, heading="right")


@bad_params(BAD_LEVELS)
def test_bad_level_is_a_level_error_naming_file_and_place(tmp_path: Path, case: BadLevel) -> None:
    """Each kind of bad level raises LevelError with the file, the location and what is wrong."""
    path = case.write(tmp_path)
    with pytest.raises(LevelError) as caught:
        load_level(path, **case.limits)
    message = str(caught.value)
    assert message.startswith(f"{path}: ")
    assert "\n" not in message
    for fragment in case.fragments:
        assert fragment in message


@bad_params(GRID_TIME_LEVELS)
def test_start_where_guard_does_not_fit_fails_when_grid_is_built(tmp_path: Path, case: BadLevel) -> None:
    """A start cell too tight for the guard loads, then choose_start raises LevelError naming file and start."""
    path = case.write(tmp_path)
    level = load_level(path)
    with pytest.raises(LevelError) as caught:
        start_of(level)
    message = str(caught.value)
    assert message.startswith(f"{path}: ")
    for fragment in case.fragments:
        assert fragment in message


@pytest.mark.parametrize("key", ["max_cells", "max_vertices", "max_file_bytes"])
def test_limits_are_inclusive_and_can_be_raised(tmp_path: Path, key: str) -> None:
    """A level exactly at a limit loads; lowering the limit by one makes it a LevelError naming the keyword
    (the library's name for it; the command line adds its option)."""
    path = write_level(tmp_path, changed(SQUARE_WITH_HOLE, cell_size=0.1))
    size = {"max_cells": 60 * 60, "max_vertices": 8, "max_file_bytes": path.stat().st_size}[key]
    assert load_level(path, **{key: size}).grid_shape() == (60, 60)
    with pytest.raises(LevelError, match=f"{path}: .*over the limit of {size - 1}.*\\({key}\\)") as caught:
        load_level(path, **{key: size - 1})
    assert "--" not in str(caught.value)
    with pytest.raises(LevelError):
        load_level(path, **{key: size - 1})


def test_defaults_of_a_minimal_level(tmp_path: Path) -> None:
    """Only `outer` is required: cell_size 1.0, view_range 8, fov 90, radius 0.3, no holes, name from file."""
    path = write_level(tmp_path, {"outer": EMPTY_SQUARE["outer"]}, "minimal-room.json")
    level = load_level(path)
    assert level.name == "minimal-room"
    assert level.cell_size == 1.0
    assert level.holes == ()
    assert level.starts == ()
    assert level.guard == GuardSpec(view_range=8.0, fov_degrees=90.0, radius=0.3, start=None, heading=None)
    assert level.source == str(path)
    assert level.grid_shape() == (4, 4)


def test_given_values_override_defaults(tmp_path: Path) -> None:
    """Every field in the file reaches the Level, as floats."""
    data = {
        "name": "custom",
        "cell_size": 2,
        "outer": SQUARE_WITH_HOLE["outer"],
        "holes": SQUARE_WITH_HOLE["holes"],
        "guard": {"view_range": 5, "fov_degrees": 360, "radius": 0, "start": [1, 1], "heading": "up"},
        "starts": [[5, 5]],
    }
    level = load_level(write_level(tmp_path, data))
    assert level.name == "custom"
    assert level.cell_size == 2.0
    assert level.holes == (((2.0, 2.0), (4.0, 2.0), (4.0, 4.0), (2.0, 4.0)),)
    assert level.guard == GuardSpec(view_range=5.0, fov_degrees=360.0, radius=0.0, start=(1.0, 1.0), heading="up")
    assert level.starts == ((5.0, 5.0),)


def test_closing_point_and_consecutive_duplicates_are_dropped() -> None:
    """A ring repeating its first point at the end, or a point twice in a row, keeps only distinct corners."""
    data = changed(
        SQUARE_WITH_HOLE,
        outer=[[0, 0], [6, 0], [6, 0], [6, 6], [0, 6], [0, 6], [0, 0]],
        holes=[[[2, 2], [2, 2], [4, 2], [4, 4], [2, 4], [2, 2]]],
    )
    level = parse_level(data, source="dupes.json")
    assert level.outer == ((0.0, 0.0), (6.0, 0.0), (6.0, 6.0), (0.0, 6.0))
    assert level.holes == (((2.0, 2.0), (4.0, 2.0), (4.0, 4.0), (2.0, 4.0)),)


def test_repeated_but_not_consecutive_points_are_kept() -> None:
    """Only consecutive duplicates go: a ring that revisits a corner later is reported, not silently fixed."""
    data = changed(EMPTY_SQUARE, outer=[[0, 0], [4, 0], [4, 4], [4, 0], [0, 4]])
    _, problems = check_level_data(data)
    assert [problem.where.split(" point")[0] for problem in problems] == ["outer"]


def test_check_level_data_reports_every_problem() -> None:
    """Two independent problems in one file are both returned, with their locations, and no level."""
    data = changed(
        SQUARE_WITH_HOLE,
        cell_size="big",
        holes=[PILLAR, [[4.5, 4.5], [5.5, 4.5], [7, 7], [4.5, 5.5]]],
        colour="red",
    )
    level, problems = check_level_data(data, source="two.json")
    assert level is None
    assert all(isinstance(problem, Problem) for problem in problems)
    wheres = [problem.where for problem in problems]
    assert "key 'colour'" in wheres
    assert "cell_size" in wheres
    assert "holes[1] point 2 (7, 7)" in wheres
    assert len(problems) == 3


def test_check_level_data_reports_problems_in_several_rings() -> None:
    """A bad outer point and a bad hole point are both reported (checking does not stop at the first ring)."""
    data = changed(
        SQUARE_WITH_HOLE,
        outer=[[0, 0], [6, "0"], [6, 6], [0, 6]],
        holes=[PILLAR, [[1, 1], [1.5, 1], "oops"]],
    )
    _, problems = check_level_data(data)
    assert [problem.where for problem in problems] == ["outer point 1", "holes[1] point 2"]


def test_parse_level_raises_the_first_problem_and_counts_the_rest() -> None:
    """parse_level's message is the first problem and says how many more `guardsim validate` would show."""
    data = changed(EMPTY_SQUARE, cell_size=0, guard={"radius": -1, "fov_degrees": 0})
    with pytest.raises(LevelError) as caught:
        parse_level(data, source="many.json")
    message = str(caught.value)
    assert message.startswith("many.json: cell_size: must be positive")
    assert message.endswith("(+2 more; run guardsim validate)")


def test_valid_level_reports_no_problems() -> None:
    """check_level_data returns the level and an empty list for a valid level."""
    level, problems = check_level_data(SQUARE_WITH_HOLE, source="ok.json")
    assert problems == []
    assert level is not None
    assert level.source == "ok.json"


TOUCHING_HOLES = {
    "hole-shares-edge-with-outer": ([[[0, 0], [2, 0], [2, 2], [0, 2]]], 32.0),
    "hole-fills-outer-corner-triangle": ([[[3, 0], [6, 0], [6, 3]]], 31.5),
    "hole-touches-outer-at-vertex": ([[[6, 3], [5, 2], [4, 3], [5, 4]]], 34.0),
    "holes-share-an-edge": ([[[2, 2], [3, 2], [3, 3], [2, 3]], [[3, 2], [4, 2], [4, 3], [3, 3]]], 34.0),
    "holes-share-part-of-an-edge": ([[[1, 1], [3, 1], [3, 2], [1, 2]], [[2, 2], [4, 2], [4, 3], [2, 3]]], 32.0),
    "holes-touch-at-a-corner": ([[[1, 1], [2, 1], [2, 2], [1, 2]], [[2, 2], [3, 2], [3, 3], [2, 3]]], 34.0),
}


@pytest.mark.parametrize(("holes", "free_area"), list(TOUCHING_HOLES.values()), ids=list(TOUCHING_HOLES))
def test_touching_holes_are_accepted(holes: list[Any], free_area: float) -> None:
    """Holes may touch the outer ring or each other without overlapping; the free area stays valid."""
    data = {"outer": [[0, 0], [6, 0], [6, 6], [0, 6]], "holes": holes, "guard": {"start": [5.5, 5.5]}}
    level, problems = check_level_data(data, source="touching.json")
    assert problems == []
    assert level is not None
    assert len(level.holes) == len(holes)
    area = level.free_area()
    assert shapely.is_valid(area)
    assert area.area == pytest.approx(free_area)
    assert start_of(level)[0] == (5, 5)


@tiny_levels
def test_level_to_data_round_trips(tmp_path: Path, level_data: dict[str, Any]) -> None:
    """level_to_data → JSON → parse_level gives back an equal Level."""
    level = parse_level(level_data, source="tiny.json")
    text = json.dumps(level_to_data(level))
    assert parse_level(json.loads(text), source="tiny.json") == level


def test_level_to_data_round_trips_every_field() -> None:
    """Non-default cell size, guard fields and marked starts survive the round trip too."""
    data = changed(
        SQUARE_WITH_HOLE,
        cell_size=0.5,
        guard={"view_range": 3, "fov_degrees": 120, "radius": 0.1, "start": [1, 5], "heading": "up"},
        starts=[[5, 1], [5, 5]],
    )
    level = parse_level(data, source="full.json")
    again = parse_level(level_to_data(level), source="full.json")
    assert again == level
    assert again.starts == ((5.0, 1.0), (5.0, 5.0))


@shipped_levels
def test_shipped_levels_load(level_path: Path) -> None:
    """Every level in levels/ loads under the default limits and its start fits the guard."""
    level = load_level(level_path)
    assert level.source == str(level_path)
    assert level.guard.start is not None
    start_of(level)


#: Holes whose polygon-with-holes is not valid (an enclosed pocket, a shared edge) and ones where it is.
FREE_AREA_HOLES = {
    **{name: holes for name, (holes, _) in TOUCHING_HOLES.items()},
    "disjoint-holes": [[[1, 1], [2, 1], [2, 2], [1, 2]], [[3, 3], [4, 3], [4, 4], [3, 4]]],
    "pocket-closed-by-corners": [
        [[1, 1], [2, 1], [2, 2], [1, 2]],
        [[2, 2], [3, 2], [3, 3], [2, 3]],
        [[1, 3], [2, 3], [2, 4], [1, 4]],
        [[0.5, 2], [1, 2], [1, 3], [0.5, 3]],
    ],
}


@pytest.mark.parametrize("holes", list(FREE_AREA_HOLES.values()), ids=list(FREE_AREA_HOLES))
def test_free_area_is_the_outer_ring_minus_the_union_of_the_holes(holes: list[Any]) -> None:
    """Whichever way it is built (the polygon with holes when that is valid), the free area is the
    difference, and valid."""
    outer = ((0, 0), (6, 0), (6, 6), (0, 6))
    rings = [tuple(map(tuple, hole)) for hole in holes]
    area = free_area_of(outer, rings)
    reference = shapely.Polygon(outer).difference(shapely.union_all([shapely.Polygon(ring) for ring in rings]))
    assert shapely.is_valid(area)
    assert area.equals(reference)


def test_many_disjoint_holes_are_checked_without_per_hole_geometry(monkeypatch: pytest.MonkeyPatch) -> None:
    """2,500 apart holes: no union of the holes and no per-ring check (validate of 24,000 such holes
    took 27 s, 16 of them in three unions; now 5.7 s)."""
    import guardsim.level.geometry as geometry
    import guardsim.level.model as model

    def no_union(*_: Any, **__: Any) -> Any:
        raise AssertionError("the holes were merged although they lie apart")

    checked: list[str] = []
    exact = geometry._ring_problem
    monkeypatch.setattr(model.shapely, "union_all", no_union)
    monkeypatch.setattr(geometry, "_ring_problem", lambda ring, where: checked.append(where) or exact(ring, where))
    holes = [[[x, y], [x + 1, y], [x + 1, y + 1], [x, y + 1]] for x in range(1, 100, 2) for y in range(1, 100, 2)]
    level, problems = check_level_data({"outer": [[0, 0], [101, 0], [101, 101], [0, 101]], "holes": holes})
    assert problems == []
    assert level is not None and len(level.holes) == 2500
    assert checked == ["outer"]
    assert level.free_area().area == pytest.approx(101 * 101 - 2500)
