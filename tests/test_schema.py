"""The shipped JSON Schema: a valid draft 2020-12 schema that agrees with the loader on structure.

Structure means types, required keys, unknown keys and number ranges. Geometry (simple rings, holes
inside the outer ring, overlaps, starts on the free area) is the loader's alone, so those cases are
not compared here.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.level import check_level_data
from guardsim.schema import level_schema
from tests.bad_levels import BAD_LEVELS, changed, guard_changed
from tests.common import EMPTY_SQUARE, LEVELS, TINY_LEVELS, shipped_levels, tiny_levels

jsonschema = pytest.importorskip("jsonschema", reason="pip install -e '.[test]' brings jsonschema")

#: The cases of tests/test_level.py whose fault is structural, so the schema must reject them too.
STRUCTURAL_BAD_CASES = [
    "top-level-list",
    "outer-missing",
    "outer-not-list",
    "point-three-numbers",
    "point-not-list",
    "string-coordinate",
    "boolean-coordinate",
    "holes-not-list",
    "cell-size-string",
    "name-not-string",
    "guard-not-object",
    "view-range-string",
    "view-range-null",
    "view-range-zero",
    "fov-over-360",
    "radius-negative",
    "heading-unknown",
    "heading-list",
    "start-not-point",
    "unknown-key",
    "unknown-guard-key",
    "outer-empty",
]

#: More structural cases, valid and invalid, at the edges of each rule.
EDGE_CASES: dict[str, dict[str, Any]] = {
    "only-outer": {"outer": EMPTY_SQUARE["outer"]},
    "closing-point-repeated": changed(EMPTY_SQUARE, outer=[[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]]),
    "integer-and-float-numbers": changed(EMPTY_SQUARE, cell_size=0.5, outer=[[0, 0], [4.0, 0], [4, 4.5], [0, 4]]),
    "cell-size-zero": changed(EMPTY_SQUARE, cell_size=0),
    "cell-size-negative": changed(EMPTY_SQUARE, cell_size=-1),
    "cell-size-null": changed(EMPTY_SQUARE, cell_size=None),
    "fov-exactly-360": guard_changed(EMPTY_SQUARE, fov_degrees=360),
    "fov-zero": guard_changed(EMPTY_SQUARE, fov_degrees=0),
    "radius-zero": guard_changed(EMPTY_SQUARE, radius=0),
    "start-null": guard_changed(EMPTY_SQUARE, start=None),
    "start-three-numbers": guard_changed(EMPTY_SQUARE, start=[1, 1, 1]),
    "start-one-number": guard_changed(EMPTY_SQUARE, start=[1]),
    "heading-null": guard_changed(EMPTY_SQUARE, heading=None),
    "heading-each": guard_changed(EMPTY_SQUARE, heading="up"),
    "guard-empty": changed(EMPTY_SQUARE, guard={}),
    "guard-null": changed(EMPTY_SQUARE, guard=None),
    "holes-empty": changed(EMPTY_SQUARE, holes=[]),
    "hole-not-list": changed(EMPTY_SQUARE, holes=[7]),
    "hole-with-two-points": changed(EMPTY_SQUARE, holes=[[[1, 1], [2, 2]]]),
    "starts-given": changed(EMPTY_SQUARE, starts=[[1.5, 1.5], [2.5, 0.5]]),
    "starts-not-list": changed(EMPTY_SQUARE, starts={"x": 1}),
    "starts-point-string": changed(EMPTY_SQUARE, starts=[["1", 2]]),
    "starts-empty": changed(EMPTY_SQUARE, starts=[]),
    "name-null": changed(EMPTY_SQUARE, name=None),
    "top-level-string": "level",  # type: ignore[dict-item]
}


@pytest.fixture(scope="module")
def validator() -> Any:
    """A draft 2020-12 validator of the shipped schema."""
    schema = level_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def loader_accepts(data: Any) -> bool:
    """Whether the loader finds no problem in decoded level JSON."""
    return not check_level_data(data, source="case.json")[1]


def test_schema_is_valid_draft_2020_12(validator: Any) -> None:
    """The shipped file is a valid draft 2020-12 schema (check_schema raises otherwise) that requires `outer`."""
    assert validator.schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert validator.schema["required"] == ["outer"]


@shipped_levels
def test_every_shipped_level_is_valid(validator: Any, level_path: Path) -> None:
    """Each level in levels/ passes the schema."""
    errors = list(validator.iter_errors(json.loads(level_path.read_text(encoding="utf-8"))))
    assert not errors, [error.message for error in errors]


@tiny_levels
def test_tiny_levels_are_valid(validator: Any, level_data: dict[str, Any]) -> None:
    """The canonical tiny levels pass the schema."""
    assert validator.is_valid(level_data)


@pytest.mark.parametrize("name", STRUCTURAL_BAD_CASES)
def test_structural_bad_levels_are_rejected_by_both(validator: Any, name: str) -> None:
    """Every structurally bad level the loader rejects, the schema rejects too."""
    data = BAD_LEVELS[name].content
    data = json.loads(data) if isinstance(data, str) else data
    assert not loader_accepts(data)
    assert not validator.is_valid(data)


@pytest.mark.parametrize("name", list(EDGE_CASES))
def test_schema_and_loader_agree_at_the_edges(validator: Any, name: str) -> None:
    """On each edge case the schema and the loader give the same verdict."""
    data = EDGE_CASES[name]
    assert validator.is_valid(data) == loader_accepts(data), (validator.is_valid(data), loader_accepts(data))


def test_every_known_key_is_in_the_schema() -> None:
    """The schema lists exactly the loader's keys, at the top level and in `guard`."""
    schema = level_schema()
    full = changed(
        TINY_LEVELS["square-with-hole"],
        cell_size=1,
        starts=[[0.5, 0.5]],
        player_starts=[[5.5, 5.5]],
        guard={
            "view_range": 5,
            "fov_degrees": 90,
            "radius": 0.3,
            "start": [0.5, 0.5],
            "heading": "up",
            "move_speed": 2,
            "turn_speed": 180,
            "tick_hz": 30,
            "detect_near": 0.5,
            "detect_far": 2,
            "forget": 3,
            "suspicious": 0.4,
            "capture_radius": 1.5,
            "search_seconds": 20,
            "radio_delay": 1,
        },
    )
    assert set(schema["properties"]) == set(full)
    assert set(schema["properties"]["guard"]["properties"]) == set(full["guard"])
    assert loader_accepts(full)
    # One unknown key anywhere makes both reject.
    assert not loader_accepts(changed(full, extra=1))
    assert not loader_accepts(guard_changed(full, extra=1))


def test_schema_command_prints_the_schema() -> None:
    """`guardsim schema` prints the shipped schema as JSON."""
    result = CliRunner().invoke(main, ["schema"])
    assert result.exit_code == 0
    assert json.loads(result.stdout) == level_schema()


def test_schema_command_in_a_subprocess() -> None:
    """The installed `guardsim` entry point prints the same schema (it is package data, not a repo file)."""
    completed = subprocess.run(
        [sys.executable, "-c", "from guardsim.cli import main; main()", "schema"],
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    )
    assert json.loads(completed.stdout) == level_schema()
    assert LEVELS, "the shipped levels are there to validate"
