"""Bad level files shared by the loader's, the command line's and the schema's tests: each case is a
file (or a stand-in for one) and the fragments its one-line error must hold."""

from __future__ import annotations

import copy
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from guardsim.level import DEFAULT_MAX_CELLS
from tests.common import EMPTY_SQUARE, SQUARE_WITH_HOLE, TINY_LEVELS, write_level

#: Stand-ins for files that cannot be written as text.
MISSING = object()
DIRECTORY = object()


@dataclass(frozen=True)
class BadLevel:
    """A bad level file and what its error must say."""

    content: Any
    """JSON-ready data, raw text (``str``), raw ``bytes``, :data:`MISSING` or :data:`DIRECTORY`."""
    fragments: tuple[str, ...]
    """Words the message must contain besides the file path: the location and a key phrase."""
    limits: dict[str, int] = field(default_factory=dict)
    """Keyword limits for :func:`load_level`, e.g. ``{"max_vertices": 3}``; the CLI gets the same options."""
    bug: str = ""
    """Why this case fails today (a known guardsim bug); the test is then a strict xfail."""
    cli_bug: str = ""
    """A bug only the command line has."""

    def write(self, folder: Path, name: str = "bad-level.json") -> Path:
        """Create the file (or directory, or nothing) in ``folder`` and return its path."""
        path = folder / name
        if self.content is MISSING:
            return path
        if self.content is DIRECTORY:
            path.mkdir()
        elif isinstance(self.content, bytes):
            path.write_bytes(self.content)
        else:
            write_level(folder, self.content, name)
        return path

    def cli_options(self) -> list[str]:
        """The limits as command-line options."""
        return [arg for key, value in self.limits.items() for arg in (f"--{key.replace('_', '-')}", str(value))]


def changed(data: dict[str, Any], **changes: Any) -> dict[str, Any]:
    """A deep copy of ``data`` with top-level keys replaced."""
    merged = copy.deepcopy(data)
    merged.update(changes)
    return merged


def guard_changed(data: dict[str, Any], **changes: Any) -> dict[str, Any]:
    """A deep copy of ``data`` with keys of its ``guard`` object replaced."""
    merged = copy.deepcopy(data)
    merged["guard"].update(changes)
    return merged


def raw(data: dict[str, Any], placeholder: str, literal: str) -> str:
    """JSON text of ``data`` with the string ``placeholder`` replaced by a bare literal such as ``NaN``."""
    return json.dumps(data).replace(json.dumps(placeholder), literal)


#: SQUARE_WITH_HOLE's pillar, and a small hole clear of it (both valid).
PILLAR = SQUARE_WITH_HOLE["holes"][0]
CORNER_HOLE = [[4.5, 0.5], [5.5, 0.5], [5.5, 1.5], [4.5, 1.5]]
UNIT_SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]

BAD_LEVELS: dict[str, BadLevel] = {
    # Unreadable files.
    "missing-file": BadLevel(MISSING, ("no such file",)),
    "directory": BadLevel(DIRECTORY, ("is a directory",)),
    "not-utf8": BadLevel(b'{"name": "caf\xe9", "outer": []}', ("not UTF-8", "byte 13")),
    "not-json": BadLevel('{"outer": [[0, 0], [4, 0]', ("not valid JSON", "line 1")),
    "empty-file": BadLevel("", ("not valid JSON",)),
    "file-too-big": BadLevel(EMPTY_SQUARE, ("over the limit of 10", "max_file_bytes"), {"max_file_bytes": 10}),
    # Structure and types.
    "top-level-list": BadLevel([EMPTY_SQUARE], ("top level must be a JSON object", "not a list")),
    "top-level-number": BadLevel("42", ("top level must be a JSON object", "not a number")),
    "outer-missing": BadLevel({"guard": {}}, ("outer", "missing")),
    "outer-not-list": BadLevel(changed(EMPTY_SQUARE, outer="square"), ("outer", "must be a list", "not a string")),
    "point-three-numbers": BadLevel(
        changed(EMPTY_SQUARE, outer=[[0, 0], [4, 0, 1], [4, 4], [0, 4]]), ("outer point 1", "[x, y]")
    ),
    "point-not-list": BadLevel(changed(EMPTY_SQUARE, outer=[[0, 0], [4, 0], 4, [0, 4]]), ("outer point 2", "[x, y]")),
    "string-coordinate": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[4.5, 0.5], [5.5, 0.5], ["5.5", 1.5], [4.5, 1.5]]]),
        ("holes[1] point 2", "coordinates must be numbers"),
    ),
    "boolean-coordinate": BadLevel(
        changed(EMPTY_SQUARE, outer=[[0, 0], [4, False], [4, 4], [0, 4]]), ("outer point 1", "must be numbers")
    ),
    "holes-not-list": BadLevel(changed(EMPTY_SQUARE, holes={"a": 1}), ("holes", "must be a list", "not an object")),
    "cell-size-string": BadLevel(changed(EMPTY_SQUARE, cell_size="1"), ("cell_size", "must be a number", "a string")),
    "name-not-string": BadLevel(changed(EMPTY_SQUARE, name=7), ("name", "must be a string")),
    "guard-not-object": BadLevel(changed(EMPTY_SQUARE, guard=[0.5, 0.5]), ("guard", "must be an object", "a list")),
    "view-range-string": BadLevel(
        guard_changed(EMPTY_SQUARE, view_range="far"), ("guard.view_range", "must be a number", "a string")
    ),
    "view-range-null": BadLevel(guard_changed(EMPTY_SQUARE, view_range=None), ("guard.view_range", "not null")),
    "view-range-zero": BadLevel(guard_changed(EMPTY_SQUARE, view_range=0), ("guard.view_range", "must be positive")),
    "fov-over-360": BadLevel(guard_changed(EMPTY_SQUARE, fov_degrees=400), ("guard.fov_degrees", "at most 360")),
    "radius-negative": BadLevel(guard_changed(EMPTY_SQUARE, radius=-0.1), ("guard.radius", "at least 0")),
    "heading-unknown": BadLevel(guard_changed(EMPTY_SQUARE, heading="north"), ("guard.heading", "'north'")),
    "heading-list": BadLevel(guard_changed(EMPTY_SQUARE, heading=["up"]), ("guard.heading", "must be one of")),
    "start-not-point": BadLevel(guard_changed(EMPTY_SQUARE, start="corner"), ("guard.start", "[x, y]")),
    "unknown-key": BadLevel(changed(EMPTY_SQUARE, colour="red"), ("key 'colour'", "unknown key", "known keys")),
    "unknown-guard-key": BadLevel(guard_changed(EMPTY_SQUARE, speed=2), ("guard.speed", "unknown key")),
    # Too few points.
    "outer-two-points": BadLevel(
        changed(EMPTY_SQUARE, outer=[[0, 0], [4, 0], [4, 0], [0, 0]]), ("outer", "2 distinct points", "at least 3")
    ),
    "outer-empty": BadLevel(changed(EMPTY_SQUARE, outer=[]), ("outer", "0 distinct points")),
    "hole-two-points": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[5, 5], [5.5, 5.5], [5, 5]]]), ("holes[1]", "2 distinct points")
    ),
    # Non-finite numbers, which Python's json module accepts.
    "nan-coordinate": BadLevel(
        raw(changed(EMPTY_SQUARE, outer=[[0, 0], ["X", 0], [4, 4], [0, 4]]), "X", "NaN"),
        ("outer point 1", "finite"),
    ),
    "infinite-hole-coordinate": BadLevel(
        raw(changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[4.5, 0.5], [5.5, 0.5], [5.5, "X"]]]), "X", "Infinity"),
        ("holes[1] point 2", "finite"),
    ),
    "infinite-cell-size": BadLevel(raw(changed(EMPTY_SQUARE, cell_size="X"), "X", "Infinity"), ("cell_size", "finite")),
    "nan-view-range": BadLevel(raw(guard_changed(EMPTY_SQUARE, view_range="X"), "X", "NaN"), ("guard.view_range",)),
    "infinite-start": BadLevel(
        raw(guard_changed(EMPTY_SQUARE, start=[0.5, "X"]), "X", "-Infinity"), ("guard.start", "finite")
    ),
    # Rings that are not simple polygons.
    "bow-tie-outer": BadLevel(
        changed(EMPTY_SQUARE, outer=[[0, 0], [4, 4], [4, 0], [0, 4]]), ("outer point", "crosses or touches itself")
    ),
    "bow-tie-hole": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[4.5, 4.5], [5.5, 5.5], [5.5, 4.5], [4.5, 5]]]),
        ("holes[1] point 3 (4.5, 5)", "crosses or touches itself"),
    ),
    "collinear-outer": BadLevel(changed(EMPTY_SQUARE, outer=[[0, 0], [2, 0], [4, 0]]), ("outer", "encloses no area")),
    # Holes are screened all at once; these must still reach the exact per-ring check.
    "collinear-hole": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[4.5, 4.5], [5, 4.5], [5.5, 4.5]]]), ("holes[1]", "encloses no area")
    ),
    "nearly-collinear-hole": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[[[4.5, 4.5], [5, 4.5], [5.5, 4.5 + 1e-13]], PILLAR]),
        ("holes[0]", "encloses no area"),
    ),
    "hole-touching-itself": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[4.5, 4.5], [5.5, 4.5], [5, 5], [5.5, 5.5], [4.5, 5.5], [5, 5]]]),
        ("holes[1] point", "crosses or touches itself"),
    ),
    # Holes against the outer ring and each other.
    "hole-outside": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, [[4.5, 4.5], [5.5, 4.5], [7, 7], [4.5, 5.5]]]),
        ("holes[1] point 2 (7, 7)", "outside the outer ring"),
    ),
    "hole-crosses-concave-outer": BadLevel(
        changed(TINY_LEVELS["l-room"], holes=[[[1, 1], [3, 1], [3, 3], [1, 3]]]), ("holes[0]", "outside the outer ring")
    ),
    "holes-overlap": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[PILLAR, CORNER_HOLE, [[1, 1], [2.5, 1], [2.5, 2.5], [1, 2.5]]]),
        ("holes[0] and holes[2]", "holes overlap"),
    ),
    "hole-inside-hole": BadLevel(
        changed(SQUARE_WITH_HOLE, holes=[[[2.5, 2.5], [3.5, 2.5], [3.5, 3.5], [2.5, 3.5]], PILLAR]),
        ("holes[0] and holes[1]", "holes overlap"),
    ),
    # Starts.
    "start-in-wall": BadLevel(guard_changed(SQUARE_WITH_HOLE, start=[3, 3]), ("guard.start (3, 3)", "inside a wall")),
    "start-outside": BadLevel(guard_changed(EMPTY_SQUARE, start=[5, 1]), ("guard.start (5, 1)", "outside the level")),
    "marked-start-outside": BadLevel(
        changed(EMPTY_SQUARE, starts=[[1, 1], [-1, 2]]), ("starts point 1 (-1, 2)", "outside the level")
    ),
    # Sizes and limits.
    "cell-size-zero": BadLevel(changed(EMPTY_SQUARE, cell_size=0), ("cell_size", "must be positive")),
    "cell-size-negative": BadLevel(changed(EMPTY_SQUARE, cell_size=-1), ("cell_size", "must be positive", "-1")),
    "grid-too-large": BadLevel(
        changed(EMPTY_SQUARE, cell_size=0.001),
        ("cell_size", "4000 x 4000", f"limit of {DEFAULT_MAX_CELLS}", "max_cells"),
    ),
    "grid-over-max-cells": BadLevel(
        changed(EMPTY_SQUARE, cell_size=0.5), ("cell_size", "64 cells", "limit of 10", "max_cells"), {"max_cells": 10}
    ),
    "too-many-vertices": BadLevel(SQUARE_WITH_HOLE, ("8 vertices", "limit of 5", "max_vertices"), {"max_vertices": 5}),
    "cell-size-subnormal": BadLevel(changed(EMPTY_SQUARE, cell_size=1e-320), ("cell_size",)),
    "coordinates-span-overflows": BadLevel(
        changed(EMPTY_SQUARE, outer=[[-1e308, 0], [1e308, 0], [1e308, 1], [-1e308, 1]], guard={}), ()
    ),
    "integer-too-big-for-float": BadLevel(
        '{"outer": [[0, 0], [4, 0], [4, 4], [0, 4]], "cell_size": 1' + "0" * 400 + "}", ("cell_size",)
    ),
    "integer-too-many-digits": BadLevel(
        '{"outer": [[0, 0], [4, 0], [4, 4], [0, 4]], "cell_size": 1' + "0" * 5000 + "}", ()
    ),
}

#: Levels the loader accepts but whose start cell the guard's circle does not fit; found when the grid is built.
GRID_TIME_LEVELS: dict[str, BadLevel] = {
    "radius-too-big-at-start": BadLevel(
        guard_changed(EMPTY_SQUARE, radius=0.6), ("start (0.5, 0.5)", "cell [0, 0]", "radius 0.6", "does not fit")
    ),
    "start-cell-centre-in-wall": BadLevel(
        changed(EMPTY_SQUARE, holes=[[[1.4, 1], [3, 1], [3, 3], [1.4, 3]]], guard={"start": [1.2, 1.5]}),
        ("start (1.2, 1.5)", "cell [1, 1]", "does not fit"),
    ),
}


def bad_params(cases: dict[str, BadLevel], *, cli: bool = False) -> Any:
    """``pytest.mark.parametrize`` over bad levels, with known bugs as strict xfails."""
    params = []
    for case in cases.values():
        reason = case.bug or (case.cli_bug if cli else "")
        # Overflowing coordinates also make shapely warn on the way to the bug.
        marks = [pytest.mark.xfail(reason=reason, strict=True), pytest.mark.filterwarnings("ignore::RuntimeWarning")]
        params.append(pytest.param(case, marks=marks if reason else []))
    return pytest.mark.parametrize("case", params, ids=list(cases))
