"""The fuzz suite in CI: generated inputs of every kind each command reads, derandomised.

Each input kind gets a fixed number of mutation-based cases (``tests/fuzz_cases.py``) run through the
real command line in this process; every case must keep the rule (exit 0 with a correct result, or
exit 2 with one stderr line naming the file; no traceback; no half-written file). Property-based tests
(hypothesis, derandomised) drive the readers themselves with arbitrary JSON and text. The importer
kinds are counted by ``benchmarks/fuzz.py`` but not asserted here: guardsim/importers/ is fixed apart.

``python benchmarks/fuzz.py --cases N`` runs any number of cases, each in a watched child process.
"""

from __future__ import annotations

import json
import math
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from guardsim.cli import main
from guardsim.errors import GuardsimError, LevelError, RegressionError
from guardsim.files.reading import EXCERPT_CHARS, parse_json
from guardsim.level import check_level_data
from guardsim.regress.stored_trace import trace_from_stored
from tests import fuzz_cases
from tests.fuzz_cases import IMPORTER_KINDS, KINDS, ROUND4_KINDS, Templates, generate, make_templates, run_in_process

#: Cases per kind in CI, shared among its commands; regress and bench cases re-play episodes, so they
#: get fewer. A regression guard sized to the five-minute suite (level 600 -> 300 and manifest 120 -> 60
#: saved about 45 s of worker time); ``benchmarks/fuzz.py --cases 20000`` is the fuzz itself.
CASES = {
    "level": 300,
    "option": 300,
    "manifest": 60,
    "reference": 80,
    "trace": 120,
    "bench-folder": 100,
    "patrol": 90,
    "checks": 40,
    "intruder-route": 30,
    "checks-toml": 40,
    "round4-option": 40,
    "tiled-cases": 40,
    # The newer inputs (tests/fuzz_newer.py): the fast tier draws one case a command, the slow tier four.
    "cameras": 20,
    "lights": 16,
    "noise": 8,
    "noise-route": 4,
    "design-level": 16,
    "design-patrol": 16,
    "design-option": 12,
    # fortify runs a few exact searches on the tiny square per case: one case each in the fast tier.
    "fortify-option": 4,
    "fortify-patrol": 4,
}
#: The seed of the CI cases: derandomised, so a failure here fails the same way on every machine.
SEED = 16


def invoke(args: list[str]) -> Any:
    return CliRunner().invoke(main, args, catch_exceptions=False)


@pytest.fixture(scope="module")
def templates(tmp_path_factory: pytest.TempPathFactory) -> Templates:
    return make_templates(invoke, tmp_path_factory.mktemp("templates"))


PAIRS = [(kind, command) for kind in KINDS if kind not in IMPORTER_KINDS for command in KINDS[kind]]
#: The fourth round's kinds run in the slow tier only (their cases run whole commands: patrols of 64
#: guards, continuous alerts).
_PAIR_PARAMS = [
    pytest.param(kind, command, id=f"{kind}-{command}", marks=[pytest.mark.slow] if kind in ROUND4_KINDS else [])
    for kind, command in PAIRS
]


@pytest.mark.parametrize(("kind", "command"), _PAIR_PARAMS)
@pytest.mark.parametrize("share", [pytest.param(4, id="quarter"), pytest.param(1, id="all", marks=pytest.mark.slow)])
def test_generated_inputs_keep_the_rule(kind: str, command: str, share: int, templates: Templates) -> None:
    """Every generated input of this kind ends in exit 0 with a correct result or one named error line.

    The fast tier draws the first quarter of the cases; the slow tier (``pytest -m slow``) all of them.
    """
    failures: Counter[str] = Counter()
    examples: dict[str, str] = {}
    for index in range(max(1, CASES[kind] // len(KINDS[kind]) // share)):
        rng = np.random.default_rng([SEED, index, *map(ord, kind + command)])
        case = generate(kind, command, rng, templates)
        with tempfile.TemporaryDirectory() as folder:
            outcome = run_in_process(case, Path(folder))
        if outcome != "ok":
            failures[outcome] += 1
            examples.setdefault(outcome, case.note)
    assert not failures, f"{dict(failures)}; first of each: {examples}"


def test_generators_cover_every_kind_and_command() -> None:
    """Each kind has at least one command, and the case list spreads over every pair."""
    triples = fuzz_cases.cases(200, 0)
    assert {(kind, command) for kind, command, _ in triples} == {(k, c) for k in KINDS for c in KINDS[k]}


json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**30), max_value=10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=30),
    lambda children: st.lists(children, max_size=6) | st.dictionaries(st.text(max_size=12), children, max_size=6),
    max_leaves=40,
)
level_like = st.fixed_dictionaries(
    {},
    optional={
        "name": json_values,
        "cell_size": json_values | st.floats(min_value=1e-3, max_value=5),
        "outer": json_values | st.lists(st.lists(st.floats(-10, 10), min_size=2, max_size=2), max_size=8),
        "holes": json_values,
        "guard": json_values | st.fixed_dictionaries({}, optional={"heading": json_values, "start": json_values}),
        "starts": json_values,
    },
)


@settings(derandomize=True, max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=level_like | json_values)
def test_level_check_never_raises_and_speaks_in_short_lines(data: Any) -> None:
    """Any decoded JSON gives a level or problems, never an exception; each problem is one short line."""
    level, problems = check_level_data(data, source="fuzz.json", max_cells=10_000)
    assert (level is None) == bool(problems)
    for problem in problems:
        text = str(problem)
        assert "\n" not in text and len(text) < 6 * EXCERPT_CHARS


@settings(derandomize=True, max_examples=500, deadline=None)
@given(text=st.text(max_size=200) | st.binary(max_size=200).map(lambda b: b.decode("latin-1")))
def test_json_reader_fails_only_with_one_located_line(text: str) -> None:
    """Any text is a value or one LevelError line naming the source; NaN and Infinity never get through."""
    try:
        value = parse_json(text, source="fuzz.json")
    except LevelError as error:
        assert str(error).startswith("fuzz.json: ") and "\n" not in str(error)
        return
    assert _finite(value)


def _finite(value: Any) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, list):
        return all(_finite(item) for item in value)
    if isinstance(value, dict):
        return all(_finite(item) for item in value.values())
    return True


@settings(derandomize=True, max_examples=400, deadline=None)
@given(data=st.dictionaries(st.sampled_from(["path", "headings", "shape", "cell_size", "guard_paths", "guards"]),
                            json_values, max_size=4))  # fmt: skip
def test_stored_trace_check_never_raises_anything_else(data: dict[str, Any]) -> None:
    """A stored trace with any of its fields replaced by arbitrary JSON is a Trace or one RegressionError."""
    stored = json.loads((Path(__file__).parent / "data" / "trace-l-room.json").read_text(encoding="utf-8"))
    stored.update(data)
    try:
        trace_from_stored(stored, source="t.trace.json", max_cells=10_000)
    except RegressionError as error:
        assert str(error).startswith("t.trace.json: ") and "\n" not in str(error)
    except GuardsimError:  # pragma: no cover - any other library error is a bug here
        raise


@pytest.mark.parametrize("field", ["cell_size", "origin", "unseen_percent"])
def test_stored_trace_integers_past_float_range_are_one_line(field: str) -> None:
    """An integer too large for a float in a number field is the field's one-line error, not an
    OverflowError (found by an outside fuzzer)."""
    stored = json.loads((Path(__file__).parent / "data" / "trace-l-room.json").read_text(encoding="utf-8"))
    huge = 10**400
    stored[field] = {"cell_size": huge, "origin": [huge, 0], "unseen_percent": [huge]}[field]
    with pytest.raises(RegressionError, match=rf"^t\.trace\.json: not a guardsim trace: {field}: must be"):
        trace_from_stored(stored, source="t.trace.json", max_cells=10_000)


def test_long_or_multiline_level_names_are_refused() -> None:
    """A level name starts every summary line: a huge one was echoed whole, a newline split the line."""
    from guardsim.level import parse_level

    square = {"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]}
    with pytest.raises(LevelError, match=r"name: is 1000000 characters long; at most 200"):
        parse_level({**square, "name": "x" * 1_000_000})
    with pytest.raises(LevelError, match=r"name: must not contain control characters"):
        parse_level({**square, "name": "two\nlines"})
    assert parse_level({**square, "name": "x" * 200}).name == "x" * 200


def test_many_layers_make_short_lines(tmp_path: Path) -> None:
    """A Tiled map with 2,000 wall layers: every change and warning line stays short."""
    from tests.common import import_map

    layers = "".join(
        f'<objectgroup name="walls {"n" * 80} {index}"><object id="{index + 1}" x="{8 * (index % 40)}" '
        f'y="0" width="8" height="8"/></objectgroup>'
        for index in range(2000)
    )
    path = tmp_path / "many.tmx"
    floor = ",".join(["1"] * 2000)
    path.write_text(
        '<map orientation="orthogonal" width="40" height="50" tilewidth="8" tileheight="8">'
        '<tileset firstgid="1" name="t" tilewidth="8" tileheight="8" tilecount="1" columns="1"/>'
        f'<layer id="1" name="Ground" width="40" height="50"><data encoding="csv">{floor}</data></layer>{layers}</map>'
    )
    imported = import_map(path)
    lines = [*imported.changes, *imported.warnings]
    assert lines and max(len(line) for line in lines) < 1000, max(len(line) for line in lines)
