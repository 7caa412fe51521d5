"""`validate --fix`: unambiguous repairs give a valid level with the same free area; the rest is left alone."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import shapely
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

from guardsim import load_level
from guardsim.cli import main
from guardsim.level import check_level_data
from guardsim.validate.repair import repair_level_data
from tests.bad_levels import changed
from tests.common import LEVELS, SQUARE_WITH_HOLE, TINY_LEVELS, shipped_levels, tiny_levels, write_level

OUTER = [[0, 0], [10, 0], [10, 10], [0, 10]]


def free_area(data: dict[str, Any]) -> shapely.Geometry:
    """The area a level file describes, read leniently (overlapping or self-touching holes allowed)."""
    walls = [shapely.make_valid(Polygon(hole)) for hole in data.get("holes", [])]
    outer = shapely.make_valid(Polygon(data["outer"]))
    return outer.difference(shapely.union_all(walls)) if walls else outer


def assert_same_area(before: dict[str, Any], after: dict[str, Any]) -> None:
    assert free_area(before).symmetric_difference(free_area(after)).area == pytest.approx(0, abs=1e-9)


def problems_of(data: Any) -> list[str]:
    return [str(problem) for problem in check_level_data(data, source="fixed.json")[1]]


REPAIRABLE: dict[str, tuple[dict[str, Any], list[str]]] = {
    "duplicate-and-closing-points": (
        {"outer": [[0, 0], [10, 0], [10, 0], [10, 10], [0, 10], [0, 0]]},
        ["outer: dropped 2 duplicate points"],
    ),
    "point-on-straight-edge": (
        {"outer": [[0, 0], [5, 0], [10, 0], [10, 10], [0, 10]]},
        ["outer: dropped 1 point on a straight edge"],
    ),
    "clockwise-outer": (
        {"outer": [[0, 0], [0, 10], [10, 10], [10, 0]]},
        ["outer: reversed to counter-clockwise (y up)"],
    ),
    "counter-clockwise-hole": (
        {"outer": OUTER, "holes": [[[2, 2], [4, 2], [4, 4], [2, 4]]]},
        ["holes[0]: reversed to clockwise (y up)"],
    ),
    "overlapping-holes": (
        {"outer": OUTER, "holes": [[[2, 2], [2, 5], [5, 5], [5, 2]], [[4, 4], [4, 7], [7, 7], [7, 4]]]},
        ["holes[0] and holes[1]: merged (they overlap or share an edge) into one hole"],
    ),
    "hole-inside-hole": (
        {"outer": OUTER, "holes": [[[2, 2], [2, 8], [8, 8], [8, 2]], [[3, 3], [3, 4], [4, 4], [4, 3]]]},
        ["holes[0] and holes[1]: merged (they overlap or share an edge) into one hole"],
    ),
    "holes-sharing-an-edge": (
        {"outer": OUTER, "holes": [[[2, 2], [2, 4], [4, 4], [4, 2]], [[4, 2], [4, 3], [6, 3], [6, 2]]]},
        ["holes[0] and holes[1]: merged (they overlap or share an edge) into one hole"],
    ),
    "wall-band-around-a-pocket": (
        {
            "outer": OUTER,
            "holes": [
                [[2, 2], [2, 3], [8, 3], [8, 2]],
                [[2, 7], [2, 8], [8, 8], [8, 7]],
                [[2, 3], [2, 7], [3, 7], [3, 3]],
                [[7, 3], [7, 7], [8, 7], [8, 3]],
            ],
        },
        ["holes[0] and holes[1] and holes[2] and holes[3]: merged (they overlap or share an edge) into 2 holes"],
    ),
    "self-touching-hole": (
        {"outer": OUTER, "holes": [[[2, 2], [2, 4], [4, 4], [4, 6], [6, 6], [6, 4], [4, 4], [4, 2]]]},
        ["holes[0]: split where it touches itself"],
    ),
    "self-touching-outer": (
        {"outer": [[0, 0], [0, 10], [10, 10], [10, 0], [5, 0], [7, 3], [3, 3], [5, 0]]},
        ["outer: split where it touches itself into the outer ring and 1 hole"],
    ),
}


@pytest.mark.parametrize("case", list(REPAIRABLE))
def test_repair_makes_the_level_valid_without_changing_its_area(case: str) -> None:
    """Each repairable fault is repaired as reported, the result loads, and the free area is the same."""
    data, expected = REPAIRABLE[case]
    fixed, repairs = repair_level_data(data)
    described = [str(repair) for repair in repairs]
    for line in expected:
        assert line in described
    assert problems_of(fixed) == []
    assert_same_area(data, fixed)
    assert repair_level_data(fixed)[1] == [], "a repaired level needs no more repairs"


NOT_REPAIRABLE = {
    "bow-tie-hole": ({"outer": OUTER, "holes": [[[2, 2], [4, 4], [4, 2], [2, 4]]]}, "crosses or touches itself"),
    "hole-outside": ({"outer": OUTER, "holes": [[[8, 8], [12, 8], [12, 12], [8, 12]]]}, "outside the outer ring"),
    "figure-eight-outer": (
        {"outer": [[0, 0], [4, 0], [4, 4], [8, 4], [8, 8], [4, 8], [4, 4], [0, 4]]},
        "crosses or touches itself",
    ),
    "unknown-key": ({"outer": OUTER, "hole": []}, "unknown key"),
    "string-coordinate": ({"outer": [[0, 0], [10, "0"], [10, 10], [0, 10]]}, "must be numbers"),
    # An integer no float holds was an OverflowError inside the repair (fuzz: holes.0.1.0 = 10**400).
    "integer-past-float-range": (
        {"outer": OUTER, "holes": [[[2, 2], [10**400, 2], [4, 4]]]},
        "coordinate must be a number of at most",
    ),
    "huge-outer-coordinate": ({"outer": [[0, 0], [10**400, 0], [10, 10], [0, 10]]}, "coordinate must be a number"),
}


@pytest.mark.parametrize("case", list(NOT_REPAIRABLE))
def test_ambiguous_faults_are_left_for_the_designer(case: str) -> None:
    """Crossing rings, holes outside, two rooms meeting at a point, typos and wrong types stay as they are."""
    data, problem = NOT_REPAIRABLE[case]
    fixed, _ = repair_level_data(data)
    assert any(problem in line for line in problems_of(fixed))


@tiny_levels
def test_valid_tiny_levels_keep_their_area(level_data: dict[str, Any]) -> None:
    """Repairing a valid level changes at most orientation and straight-edge points."""
    fixed, repairs = repair_level_data(level_data)
    assert problems_of(fixed) == []
    assert_same_area(level_data, fixed)
    assert all("reversed" in repair.what or "straight" in repair.what for repair in repairs)


@shipped_levels
def test_shipped_levels_keep_their_area(level_path: Path) -> None:
    """The shipped levels survive repair unchanged in area and still load."""
    data = json.loads(level_path.read_text(encoding="utf-8"))
    fixed, _ = repair_level_data(data)
    assert problems_of(fixed) == []
    assert_same_area(data, fixed)


rectangles = st.lists(
    st.tuples(st.integers(1, 8), st.integers(1, 8), st.integers(1, 4), st.integers(1, 4)), min_size=1, max_size=8
)


@settings(max_examples=60, deadline=None)
@given(rectangles)
def test_any_pile_of_wall_rectangles_repairs_to_a_valid_level(boxes: list[tuple[int, int, int, int]]) -> None:
    """Rectangles dropped anywhere inside the room, overlapping or not, repair to a level that loads with
    the same free area."""
    holes = [[[x, y], [min(x + w, 9), y], [min(x + w, 9), min(y + h, 9)], [x, min(y + h, 9)]] for x, y, w, h in boxes]
    data = {"outer": OUTER, "holes": holes}
    fixed, _ = repair_level_data(data)
    assert problems_of(fixed) == []
    assert_same_area(data, fixed)


def run(*args: str | Path) -> Any:
    return CliRunner().invoke(main, [str(arg) for arg in args])


def test_validate_fix_writes_the_repaired_level(tmp_path: Path) -> None:
    """`validate BAD --fix OUT` lists the repairs, ends with one line saying what it fixed and where it
    wrote (never 'ok' for a file that had problems), writes OUT atomically and exits 0."""
    data, _ = REPAIRABLE["overlapping-holes"]
    path = write_level(tmp_path, changed(data, guard={"start": [0.5, 0.5]}))
    out = tmp_path / "fixed.json"
    result = run("validate", path, "--fix", out, "--no-warnings")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].startswith(f"{path}: repaired holes[0] and holes[1]: merged")
    repairs = f"{len(lines) - 1} repair{'s' if len(lines) > 2 else ''}"
    assert lines[-1] == f"{path}: made {repairs} (above), the result is valid -> {out}"
    assert not any(line.endswith(": ok") for line in lines)
    level = load_level(out)
    assert len(level.holes) == 1
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_validate_fix_says_when_there_is_nothing_to_fix(tmp_path: Path) -> None:
    """A level that needs no repair is ok, and OUT is the same level, written."""
    path = write_level(tmp_path, repair_level_data(SQUARE_WITH_HOLE)[0])
    out = tmp_path / "fixed.json"
    result = run("validate", path, "--fix", out, "--no-warnings")
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines() == [f"{path}: ok, nothing to fix -> {out} (the same level)"]
    assert load_level(out).holes == load_level(path).holes


def test_validate_fix_does_not_write_an_invalid_level(tmp_path: Path) -> None:
    """When a fault is not repairable, OUT is not written and the exit status is 2."""
    data, _ = NOT_REPAIRABLE["bow-tie-hole"]
    path = write_level(tmp_path, data)
    out = tmp_path / "fixed.json"
    result = run("validate", path, "--fix", out)
    assert result.exit_code == 2
    assert "crosses or touches itself" in result.stdout
    assert "not written" in result.stdout
    assert not out.exists()


def test_validate_fix_says_a_level_no_guard_fits_is_not_written(tmp_path: Path) -> None:
    """Valid geometry the guard cannot stand in: the error, then that OUT is not written."""
    path = write_level(tmp_path, {"outer": [[0, 0], [1, 0], [1, 1], [0, 1]], "guard": {"radius": 2}})
    out = tmp_path / "fixed.json"
    result = run("validate", path, "--fix", out)
    assert result.exit_code == 2
    assert result.stdout.splitlines()[-1] == (
        f"{path}: not written to {out}: the problems above need a designer's decision"
    )
    assert not out.exists()


def test_validate_fix_takes_one_level(tmp_path: Path) -> None:
    """--fix with two levels is one error line and exit 2."""
    first = write_level(tmp_path, SQUARE_WITH_HOLE, "a.json")
    second = write_level(tmp_path, TINY_LEVELS["l-room"], "b.json")
    result = run("validate", first, second, "--fix", tmp_path / "out.json")
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"guardsim: error: --fix {tmp_path / 'out.json'} takes exactly one LEVEL, not 2"
    ]
    assert LEVELS
