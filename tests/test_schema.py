"""The shipped JSON Schemas: valid draft 2020-12 schemas that agree with the readers.

The level's: structure (types, required keys, unknown keys and number ranges) as the hand-written loader
checks it; geometry (simple rings, holes inside the outer ring, overlaps, starts on the free area) is the
loader's alone, so those cases are not compared here. The patrol, checks, manifest and trace schemas:
every file guardsim writes passes, every key a writer writes is in the schema, the enumerations are the
code's, and a bad document gets the reader's verdict, in the same one line.
"""

from __future__ import annotations

import gzip
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.errors import GuardsimError
from guardsim.files.schema import SCHEMAS, level_schema, problem, schema
from guardsim.level import check_level_data
from guardsim.motion.parameters import MOTIONS
from guardsim.patrol import parse_patrol, read_patrol
from guardsim.planners import PLANNERS
from guardsim.regress.references import FORMAT as MANIFEST_FORMAT
from guardsim.regress.references import REFERENCE_FRAME_SIZE, read_manifest
from guardsim.regress.stored_trace import trace_from_stored
from guardsim.trace import OUTCOMES
from guardsim.validate.checks import EXPECTATIONS, parse_checks
from guardsim.vision.rules import LineOfSight
from tests.bad_levels import BAD_LEVELS, changed, guard_changed
from tests.common import (
    EMPTY_SQUARE,
    LEVELS,
    REPO,
    SQUARE_WITH_HOLE,
    TINY_LEVELS,
    TWO_ROOMS,
    run,
    scene_from,
    shipped_levels,
    tiny_levels,
    write_level,
)

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
    "tile-pixels": changed(EMPTY_SQUARE, tile_pixels=[64, 32]),
    "tile-pixels-whole-float": changed(EMPTY_SQUARE, tile_pixels=[64.0, 64]),
    "tile-pixels-fraction": changed(EMPTY_SQUARE, tile_pixels=[64.5, 64]),
    "tile-pixels-zero": changed(EMPTY_SQUARE, tile_pixels=[0, 64]),
    "tile-pixels-too-large": changed(EMPTY_SQUARE, tile_pixels=[4097, 64]),
    "tile-pixels-one-side": changed(EMPTY_SQUARE, tile_pixels=[64]),
    "tile-pixels-bool": changed(EMPTY_SQUARE, tile_pixels=[True, 64]),
    "tile-pixels-number": changed(EMPTY_SQUARE, tile_pixels=64),
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
    """The schema lists exactly the loader's keys, at the top level, in `guard` and in `intruder`."""
    schema = level_schema()
    full = changed(
        TINY_LEVELS["square-with-hole"],
        cell_size=1,
        starts=[[0.5, 0.5]],
        player_starts=[[5.5, 5.5]],
        tile_pixels=[64, 64],
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
            "dark_sight": 1.5,
            "chase_speed": 2,
            "give_up_losses": 4,
        },
        cameras=[{"position": [0.5, 0.5], "heading": 90, "sweep": 45}],
        ambient_light=0.5,
        lights=[{"position": [0.5, 0.5], "radius": 3}],
        intruder={"walk_noise": 3, "sneak_ticks": 2, "sneak_noise": 1},
    )
    assert set(schema["properties"]) == set(full)
    assert set(schema["properties"]["guard"]["properties"]) == set(full["guard"])
    assert set(schema["properties"]["intruder"]["properties"]) == set(full["intruder"])
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


# ---------------------------------------------------------------- the documents guardsim writes and reads


def test_every_schema_is_valid_and_described() -> None:
    """Each shipped schema is valid draft 2020-12 and says what each of its top-level keys means."""
    for name in SCHEMAS:
        document = schema(name)
        jsonschema.Draft202012Validator.check_schema(document)
        assert document["$schema"] == "https://json-schema.org/draft/2020-12/schema"
        assert document["title"].startswith("guardsim ") and document["description"]
        undescribed = [key for key, node in document["properties"].items() if "description" not in node]
        assert not undescribed, (name, undescribed)


def _nodes(node: Any, where: str = "") -> list[tuple[str, dict[str, Any]]]:
    """Every schema object inside ``node``, with where it is."""
    found = []
    if isinstance(node, dict):
        found.append((where, node))
        for key, value in node.items():
            if key not in ("x-message", "enum", "const", "default", "required"):
                found += _nodes(value, f"{where}/{key}")
    elif isinstance(node, list):
        for index, value in enumerate(node):
            found += _nodes(value, f"{where}/{index}")
    return found


@pytest.mark.parametrize("name", SCHEMAS)
def test_messages_word_keywords_of_their_node(name: str) -> None:
    """An ``x-message`` is a string, or an object naming validation keywords its node holds."""
    for where, node in _nodes(schema(name)):
        wording = node.get("x-message")
        if isinstance(wording, dict):
            assert set(wording) <= set(node), (where, set(wording) - set(node))
        else:
            assert wording is None or isinstance(wording, str), where


def test_enumerations_are_the_codes() -> None:
    """Names listed in the schemas are the ones the code knows."""
    assert schema("checks")["properties"]["planner"]["enum"] == list(PLANNERS)
    assert schema("checks")["$defs"]["sneak"]["properties"]["expect"]["enum"] == list(EXPECTATIONS)
    for name in ("patrol", "trace"):
        assert schema(name)["properties"]["motion"]["enum"] == list(MOTIONS)
    assert schema("manifest")["$defs"]["episode"]["properties"]["motion"]["enum"] == list(MOTIONS)
    assert schema("trace")["properties"]["outcome"]["enum"] == list(OUTCOMES)
    assert schema("manifest")["$defs"]["episode"]["properties"]["outcome"]["enum"] == list(OUTCOMES)
    assert schema("trace")["properties"]["line_of_sight"]["enum"] == [rule.value for rule in LineOfSight] + [None]
    assert schema("manifest")["properties"]["format"]["const"] == MANIFEST_FORMAT
    assert schema("manifest")["properties"]["frame_size"]["default"] == REFERENCE_FRAME_SIZE


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[Path]]:
    """The documents guardsim writes, by schema: patrols (loop, team, walked with --compare, continuous,
    evaluated), traces (one guard, a team with its recorded field, continuous) and a regress manifest."""
    folder = tmp_path_factory.mktemp("written")
    level = write_level(folder, SQUARE_WITH_HOLE, "pillar.json")
    patrols = {
        "loop": [],
        "team": ["--guards", "2"],
        "walked": ["--strategy", "random", "--compare"],
        "continuous": ["--motion", "continuous"],
    }
    for name, options in patrols.items():
        assert run("patrol", level, "--out", folder / name, *options).exit_code == 0, name
    assert (
        run("patrol", level, "--out", folder / "evaluated", "--evaluate", folder / "loop" / "patrol.json").exit_code
        == 0
    )
    traces = {"one": [], "team": ["--guards", "2", "--record-field"], "continuous": ["--motion", "continuous"]}
    for name, options in traces.items():
        assert run("play", level, "--trace", folder / f"{name}.trace.json", *options).exit_code == 0, name
    renders = folder / "renders"
    assert (
        run("regress", level, "--renders", renders, "--update", "--motion", "continuous", "--tick-hz", "10").exit_code
        == 0
    )
    return {
        "patrol": [folder / name / "patrol.json" for name in [*patrols, "evaluated"]],
        "trace": [folder / f"{name}.trace.json" for name in traces] + sorted((renders / "pillar").glob("*.trace.json")),
        "manifest": [renders / "pillar" / "manifest.json"],
    }


@pytest.mark.parametrize("name", ["patrol", "trace", "manifest"])
def test_what_guardsim_writes_is_valid_and_every_key_is_in_the_schema(
    written: dict[str, list[Path]], name: str
) -> None:
    """Each document a command writes passes its schema and its reader; the schema names every key written."""
    grid = scene_from(SQUARE_WITH_HOLE).grid
    known = set(schema(name)["properties"])
    for path in written[name]:
        data = json.loads(path.read_text(encoding="utf-8"))
        assert problem(data, name) is None, (path, problem(data, name))
        assert set(data) <= known, (path, set(data) - known)
        if name == "patrol":
            read_patrol(str(path), grid)
            for guard in data["guards"]:
                assert set(guard) <= set(schema(name)["$defs"]["guard"]["properties"])
        elif name == "trace":
            trace_from_stored(data, source=str(path), max_cells=10**6)
        else:
            assert read_manifest(path) is not None
            episode_keys = set(schema(name)["$defs"]["episode"]["properties"])
            assert all(set(episode) <= episode_keys for episode in data["episodes"])
            assert set(data["tolerance"]) == set(schema(name)["properties"]["tolerance"]["properties"])


STORED_TRACES = [
    *sorted((REPO / "renders").glob("*/*.trace.json")),
    *sorted((REPO / "tests" / "data").glob("trace-*.json")),
    *sorted((REPO / "tests" / "data" / "before_core").glob("*.json.gz")),
]


@pytest.mark.parametrize("path", STORED_TRACES, ids=[f"{path.parent.name}/{path.name}" for path in STORED_TRACES])
def test_stored_traces_are_valid(path: Path) -> None:
    """The traces stored in the repository (references, test data, traces from before the core) pass."""
    raw = path.read_bytes()
    data = json.loads(gzip.decompress(raw) if path.suffix == ".gz" else raw)
    assert problem(data, "trace") is None


@pytest.mark.parametrize("path", sorted((REPO / "renders").glob("*/manifest.json")), ids=lambda path: path.parent.name)
def test_stored_manifests_are_valid(path: Path) -> None:
    assert problem(json.loads(path.read_text(encoding="utf-8")), "manifest") is None
    assert read_manifest(path) is not None


def test_the_documented_checks_file_is_valid() -> None:
    """The checks file of docs/patrols.md passes (TOML needs Python 3.11)."""
    tomllib = pytest.importorskip("tomllib")
    text = (REPO / "docs" / "patrols.md").read_text(encoding="utf-8")
    example = text.split("```toml\n", 1)[1].split("```", 1)[0]
    assert problem(tomllib.loads(example), "checks") is None


# ---------------------------------------------------------------- same verdict, same line

_POST = {"shape": [3, 11], "guards": [{"loop": [[5, 1], [5, 1]], "headings": [0, 0]}]}
_L_ROOM_TRACE = json.loads((REPO / "tests" / "data" / "trace-l-room.json").read_text(encoding="utf-8"))
_MANIFEST = {"format": 1, "episodes": [{"name": "level-start", "seed": 0, "episode": None}]}

#: (schema, document, a fragment of the line, or None when the document is valid).
DOCUMENTS: dict[str, tuple[str, Any, str | None]] = {
    "patrol-post": ("patrol", _POST, None),
    "patrol-walked-extra-keys": ("patrol", {**_POST, "period": None, "comment": "kept"}, None),
    "patrol-list": ("patrol", [_POST], "expected a JSON object, got a list"),
    "patrol-no-guards": ("patrol", {"shape": [3, 11]}, 'missing "guards"'),
    "patrol-shape-floats": ("patrol", {**_POST, "shape": [3.0, 11]}, "shape: expected [rows, cols]"),
    "patrol-cell-float": (
        "patrol",
        {**_POST, "guards": [{"loop": [[5, 1.0]], "headings": [0]}]},
        "guards[0].loop[0]: expected [col, row], two whole numbers, got [5,1.0]",
    ),
    "patrol-heading-bool": (
        "patrol",
        {**_POST, "guards": [{"loop": [[5, 1]], "headings": [True]}]},
        "guards[0].headings[0]: expected 0, 1, 2 or 3 (right, down, left, up), got True",
    ),
    "patrol-guard-without-headings": (
        "patrol",
        {**_POST, "guards": [{"loop": [[5, 1]]}]},
        'guards[0]: missing "headings"',
    ),
    "patrol-negative-period": (
        "patrol",
        {**_POST, "period": -1},
        "period: expected a whole number of ticks or null, got -1",
    ),
    "patrol-cell-size-string": ("patrol", {**_POST, "cell_size": "1"}, "cell_size: expected the level's cell size"),
    "checks-full": (
        "checks",
        {
            "max_cover_steps": 9,
            "max_idleness": None,
            "no_unreachable": True,
            "guards": 2,
            "planner": "tour",
            "safe": [[1.5, 0.5]],
            "undetected": False,
            "sneak": [{"from": [0, 0], "to": [1, 1], "expect": "caught"}],
            "min_slack": 0,
            "max_slack": 3,
        },
        None,
    ),
    "checks-table-list": ("checks", [], "expected a table of rules, got a list"),
    "checks-planner": ("checks", {"planner": "astar"}, "planner: 'astar' is not one of ripplefront,"),
    "checks-guards-zero": (
        "checks",
        {"guards": 0},
        "guards: expected a whole number from 1 to 64 (as --guards), got 0",
    ),
    "checks-sneak-extra": (
        "checks",
        {"sneak": [{"from": [0, 0], "to": [1, 1], "expect": "caught", "via": [2, 2]}]},
        "sneak[0]: expected a table with exactly from, to and expect",
    ),
    "checks-safe-nan": ("checks", {"safe": [[float("nan"), 0.5]]}, "safe[0]: expected [x, y], two finite numbers"),
    "checks-patrol-number": ("checks", {"patrol": 3}, "patrol: expected a file name, got a number"),
    "manifest-minimal": ("manifest", _MANIFEST, None),
    "manifest-continuous": (
        "manifest",
        {**_MANIFEST, "episodes": [{"name": "c", "motion": "continuous", "tick_hz": 10, "move_speed": None}]},
        None,
    ),
    "manifest-format": ("manifest", {**_MANIFEST, "format": 2}, "format: expected 1"),
    "manifest-list": ("manifest", [], "not a guardsim regress manifest of format 1"),
    "manifest-frame-size": (
        "manifest",
        {**_MANIFEST, "frame_size": 8},
        "frame_size: must be a whole number of pixels from 16, not 8",
    ),
    "manifest-tolerance": (
        "manifest",
        {**_MANIFEST, "tolerance": {"channel": 300}},
        'tolerance: must be {"channel": 0 to 255',
    ),
    "manifest-no-episodes": ("manifest", {**_MANIFEST, "episodes": []}, "episodes: must be a non-empty list"),
    "manifest-name-newline": (
        "manifest",
        {**_MANIFEST, "episodes": [{"name": "a\n"}]},
        "episodes[0].name: must be letters",
    ),
    "manifest-seed-huge": (
        "manifest",
        {**_MANIFEST, "episodes": [{"name": "a", "seed": 2**63}]},
        "episodes[0].seed: must be",
    ),
    "manifest-speed": (
        "manifest",
        {**_MANIFEST, "episodes": [{"name": "a", "motion": "continuous", "turn_speed": 0}]},
        "episodes[0].turn_speed: must be a positive number up to 1e+06, not 0",
    ),
    "trace-l-room": ("trace", _L_ROOM_TRACE, None),
    "trace-string": ("trace", "trace", "not a guardsim trace: the top level is a string, not an object"),
    "trace-no-goal": (
        "trace",
        {k: v for k, v in _L_ROOM_TRACE.items() if k != "goal"},
        'not a guardsim trace: missing "goal"',
    ),
    "trace-outcome": (
        "trace",
        {**_L_ROOM_TRACE, "outcome": "won"},
        'outcome: must be one of covered, step_limit, stuck, not "won"',
    ),
    "trace-heading": (
        "trace",
        {**_L_ROOM_TRACE, "headings": [4] * len(_L_ROOM_TRACE["path"])},
        "headings: must be a list of heading numbers 0 to 3",
    ),
    "trace-goal-two": ("trace", {**_L_ROOM_TRACE, "goal": [[2] * 6] * 6}, "goal: must be rows of 0s and 1s"),
    "trace-fov": ("trace", {**_L_ROOM_TRACE, "fov_degrees": 400}, "fov_degrees: must be a number of degrees"),
    "trace-continuous-without-poses": (
        "trace",
        {**_L_ROOM_TRACE, "motion": "continuous"},
        "a continuous trace needs poses",
    ),
}


def _reader_line(name: str, data: Any, folder: Path) -> str | None:
    """What the reader of ``name`` says of ``data`` (its one error line), or ``None`` when it accepts it."""
    try:
        if name == "patrol":
            parse_patrol(data, scene_from(TWO_ROOMS).grid, source="p.json")
        elif name == "checks":
            parse_checks(data, source="c.json")
        elif name == "manifest":
            path = folder / "manifest.json"
            path.write_text(json.dumps(data), encoding="utf-8")
            read_manifest(path)
        else:
            trace_from_stored(data, source="t.json", max_cells=10**6)
    except GuardsimError as error:
        return str(error)
    return None


@pytest.mark.parametrize("case", list(DOCUMENTS))
def test_schema_and_reader_give_the_same_verdict_in_the_same_line(case: str, tmp_path: Path) -> None:
    """A document the schema rejects, the reader rejects with the schema's first fault as its one line."""
    name, data, fragment = DOCUMENTS[case]
    found = problem(data, name)
    line = _reader_line(name, data, tmp_path)
    if fragment is None:
        assert found is None and line is None, (found, line)
        return
    source = {"patrol": "p.json", "checks": "c.json", "manifest": str(tmp_path / "manifest.json"), "trace": "t.json"}
    prefix = "not a guardsim trace: " if name == "trace" else ""
    assert found is not None and line == f"{source[name]}: {prefix}{found}", (found, line)
    assert fragment in line and "\n" not in line, line


def test_schema_command_prints_each_schema() -> None:
    """`guardsim schema NAME` prints each shipped schema; without NAME, the level's."""
    for name in SCHEMAS:
        result = CliRunner().invoke(main, ["schema", name])
        assert result.exit_code == 0, result.output
        assert json.loads(result.stdout) == schema(name)
    assert CliRunner().invoke(main, ["schema", "route"]).exit_code == 2
