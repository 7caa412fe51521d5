"""guardsim check: exit 0 when every rule holds, 1 with exactly one line per broken rule, 2 on bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from guardsim.checks import CheckRules, SneakRule, run_checks
from guardsim.cli import main
from tests.common import SPLIT_ROOMS, scene_from, write_level
from tests.test_patrol import CORRIDOR

POST = {"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}


@pytest.fixture
def corridor(tmp_path: Path) -> tuple[Path, Path]:
    level = write_level(tmp_path, CORRIDOR)
    post = tmp_path / "post.json"
    post.write_text(json.dumps(POST))
    return level, post


def _run(*args: str) -> tuple[int, list[str]]:
    result = CliRunner().invoke(main, ["check", *args])
    return result.exit_code, result.output.strip().splitlines()


def _measured() -> tuple[int, int]:
    """The corridor's cover steps (ripplefront) and its loop's worst idleness, to set limits around."""
    scene = scene_from(CORRIDOR)
    results = run_checks(scene, CheckRules(max_cover_steps=0, max_idleness=0))
    steps = int(results[0].message.split(" in ")[1].split()[0])
    idleness = int(results[1].message.split(" is ")[1].split()[0])
    return steps, idleness


@pytest.mark.parametrize(
    "broken", [set(), {"max-cover-steps"}, {"max-idleness", "sneak"}, {"max-cover-steps", "max-idleness", "sneak"}]
)
def test_check_fails_exactly_on_the_rules_broken(corridor: tuple[Path, Path], broken: set[str]) -> None:
    level, _ = corridor
    steps, idleness = _measured()
    args = [str(level)]
    args += ["--max-cover-steps", str(steps - 1 if "max-cover-steps" in broken else steps)]
    args += ["--max-idleness", str(idleness - 1 if "max-idleness" in broken else idleness)]
    # Under the loop patrol a player gets through the corridor unseen.
    args += ["--sneak", "0.5,0.5", "10.5,2.5", "--expect", "caught" if "sneak" in broken else "sneaks"]
    code, lines = _run(*args)
    assert code == (1 if broken else 0), lines
    if broken:
        named = {line.split(": broken: ")[1].split(":")[0].split(" ")[0] for line in lines}
        assert named == broken and len(lines) == len(broken)
    else:
        assert lines == [f"{level}: all 3 rules hold"]


def test_a_post_in_the_corridor_passes_the_caught_rule(corridor: tuple[Path, Path]) -> None:
    level, post = corridor
    code, lines = _run(str(level), "--patrol", str(post), "--sneak", "0.5,0.5", "10.5,2.5", "--expect", "caught")
    assert code == 0, lines
    code, lines = _run(str(level), "--patrol", str(post), "--max-idleness", "1000")
    assert code == 1 and "unbounded" in lines[0] and len(lines) == 1


def test_no_unreachable() -> None:
    # The split rooms: the wall leaves the right room out of the guard's reach.
    results = run_checks(scene_from(SPLIT_ROOMS), CheckRules(no_unreachable=True))
    assert [result.holds for result in results] == [False]
    assert run_checks(scene_from(CORRIDOR), CheckRules(no_unreachable=True))[0].holds


def test_rules_from_a_checks_file(corridor: tuple[Path, Path], tmp_path: Path) -> None:
    level, _post = corridor
    checks = tmp_path / "checks.toml"
    checks.write_text(
        'no_unreachable = true\nmax_idleness = 5\npatrol = "post.json"\n'
        '[[sneak]]\nfrom = [0.5, 0.5]\nto = [10.5, 2.5]\nexpect = "sneaks"\n'
    )
    code, lines = _run(str(level), "--checks", str(checks))
    assert code == 1
    assert [line.split(": broken: ")[1].split(":")[0] for line in lines] == [
        "max-idleness",
        "sneak 0.5,0.5 -> 10.5,2.5",
    ]
    as_json = tmp_path / "checks.json"
    as_json.write_text(json.dumps({"no_unreachable": True}))
    assert _run(str(level), "--checks", str(as_json)) == (0, [f"{level}: all 1 rule holds"])


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "no rule to check"),
        (["--sneak", "0.5,0.5", "10.5,2.5"], "each --sneak needs its --expect"),
        (["--sneak", "4.5,0.5", "10.5,2.5", "--expect", "caught"], "--sneak: from 4.5,0.5 is not a cell"),
        (["--patrol", "missing.json", "--max-idleness", "3"], "missing.json"),
    ],
    ids=["no-rule", "no-expect", "wall-point", "missing-patrol"],
)
def test_bad_input_is_exit_2(corridor: tuple[Path, Path], args: list[str], message: str) -> None:
    level, _ = corridor
    code, lines = _run(str(level), *args)
    assert code == 2 and len(lines) == 1 and message in lines[0], lines


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("max_idle = 3\n", "unknown rule 'max_idle'"),
        ("max_idleness = -1\n", "max_idleness: expected a whole number of at least 0"),
        ('[[sneak]]\nfrom = [0, 0]\nto = [1, 1]\nexpect = "maybe"\n', "sneak[0]: expect: 'maybe'"),
        ("max_idleness = [\n", "not valid TOML"),
    ],
    ids=["unknown", "negative", "expect", "syntax"],
)
def test_bad_checks_files(corridor: tuple[Path, Path], tmp_path: Path, text: str, message: str) -> None:
    level, _ = corridor
    checks = tmp_path / "bad.toml"
    checks.write_text(text)
    code, lines = _run(str(level), "--checks", str(checks))
    assert code == 2 and len(lines) == 1 and message in lines[0], lines


def test_sneak_rule_library_call() -> None:
    scene = scene_from(CORRIDOR)
    [result] = run_checks(scene, CheckRules(sneaks=(SneakRule((0.5, 0.5), (10.5, 2.5), "sneaks"),)))
    assert result.holds and "unseen path" in result.message


def test_a_bad_sneak_point_in_a_checks_file_names_the_file_and_the_rule(
    corridor: tuple[Path, Path], tmp_path: Path
) -> None:
    """Fuzz case seed 1000146: a point far outside the level, in a checks file, named no file."""
    level, _ = corridor
    checks = tmp_path / "rules.json"
    checks.write_text(json.dumps({"sneak": [{"from": [2**63, 0.5], "to": [10.5, 2.5], "expect": "caught"}]}))
    code, lines = _run(str(level), "--checks", str(checks))
    assert code == 2 and lines == [
        f"guardsim: error: {checks}: sneak[0]: from 9.22337e+18,0.5 is not a cell a guard-sized player can stand in"
    ]


def test_a_missing_patrol_in_a_checks_file_names_the_checks_file(corridor: tuple[Path, Path], tmp_path: Path) -> None:
    """Fuzz case seed 1131: the line named only the joined path of a patrol that does not exist."""
    level, _ = corridor
    checks = tmp_path / "rules.json"
    checks.write_text(json.dumps({"max_idleness": 10, "patrol": "1"}))
    code, lines = _run(str(level), "--checks", str(checks))
    assert code == 2 and lines == [f"guardsim: error: {checks}: patrol: {tmp_path / '1'}: no such file"]
