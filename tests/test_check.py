"""guardsim check: exit 0 when every rule holds, 1 with exactly one line per broken rule, 2 on bad input."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.validate.checks import CheckRules, SafeRule, SneakRule, run_checks
from tests.common import ALCOVE, ALCOVE_POST, SPLIT_ROOMS, TWO_ROOMS, scene_from, write_level

POST = {"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}
#: A guard pacing the corridor, [3, 1] to [7, 1] and back: an 8-tick lap. Facing right from [7, 1] (lap
#: tick 4) it glimpses the right room's [9, 0] and [9, 2] (once a lap, never detected under the default
#: model) and [10, 0], [10, 2] at ticks 3 and 4 (detected after 2 ticks); it never sees [8, 0] or [8, 2].
PACER_GUARD = {
    "loop": [[3, 1], [4, 1], [5, 1], [6, 1], [7, 1], [6, 1], [5, 1], [4, 1], [3, 1]],
    "headings": [2, 0, 0, 0, 0, 2, 2, 2, 2],
}
PACER = {"shape": [3, 11], "guards": [PACER_GUARD]}


@pytest.fixture
def corridor(tmp_path: Path) -> tuple[Path, Path]:
    level = write_level(tmp_path, TWO_ROOMS)
    post = tmp_path / "post.json"
    post.write_text(json.dumps(POST))
    return level, post


def _run(*args: str) -> tuple[int, list[str]]:
    result = CliRunner().invoke(main, ["check", *args])
    return result.exit_code, result.output.strip().splitlines()


def _measured() -> tuple[int, int]:
    """The corridor's cover steps (ripplefront) and its loop's worst idleness, to set limits around."""
    scene = scene_from(TWO_ROOMS)
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
    assert run_checks(scene_from(TWO_ROOMS), CheckRules(no_unreachable=True))[0].holds


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
    assert _run(str(level), "--checks", str(as_json)) == (0, [f"{level}: its one rule holds"])


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
        ('[[sneak]]\nfrom = [0, 0]\nto = [1, 1]\nexpect = "maybe"\n', "sneak[0].expect: 'maybe'"),
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


@pytest.mark.parametrize("rules", [{"safe": [[10**400, 0.5]]}, {"sneak": [{"from": [0.5, -(10**400)], "to": [1, 1],
                                   "expect": "sneaks"}]}], ids=["safe", "sneak-from"])  # fmt: skip
def test_integers_past_float_range_in_a_checks_file_are_one_line(
    corridor: tuple[Path, Path], tmp_path: Path, rules: dict[str, Any]
) -> None:
    """A JSON checks file may hold integers no float holds: one line naming the file and the rule
    (was an OverflowError traceback, found by the fuzz)."""
    level, _ = corridor
    checks = tmp_path / "huge.json"
    checks.write_text(json.dumps(rules))
    code, lines = _run(str(level), "--checks", str(checks))
    assert code == 2 and len(lines) == 1, lines
    assert "huge.json: " in lines[0] and "expected [x, y], two finite numbers, got [" in lines[0]
    assert len(lines[0]) - len(str(checks)) < 160


def test_sneak_rule_library_call() -> None:
    scene = scene_from(TWO_ROOMS)
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


#: A sneak table, last in a TOML file (the keys after it would be its own).
_SNEAK = '[[sneak]]\nfrom = [0.5, 0.5]\nto = [2.5, 2.5]\nexpect = "sneaks"\n'


def _patrol_file(folder: Path, data: dict[str, object], name: str = "patrol.json") -> str:
    path = folder / name
    path.write_text(json.dumps(data))
    return str(path)


def _broken(lines: list[str]) -> list[str]:
    """``rule: message`` of each broken-rule line."""
    return [line.split(": broken: ", 1)[1] for line in lines]


def test_a_safe_spot_a_guard_sees_breaks_the_build_until_it_is_fixed(corridor: tuple[Path, Path]) -> None:
    level, _ = corridor
    pacer = _patrol_file(level.parent, PACER)
    code, lines = _run(str(level), "--patrol", pacer, "--safe", "9.5,0.5")
    assert code == 1 and _broken(lines) == [
        "safe 9.5,0.5: cell [9, 0] is in view of guard 0 for 1 of 8 lap ticks, first at lap tick 4"
    ]
    # Fixed by moving the spot to a cell the guard never sees ...
    assert _run(str(level), "--patrol", pacer, "--safe", "8.5,0.5") == (0, [f"{level}: its one rule holds"])
    # ... or by changing the patrol: a post facing left never looks into the right room.
    left = _patrol_file(level.parent, {"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [2]}]}, "left.json")
    assert _run(str(level), "--patrol", left, "--safe", "9.5,0.5") == (0, [f"{level}: its one rule holds"])


def test_a_safe_spot_seen_by_two_guards_names_both(corridor: tuple[Path, Path]) -> None:
    level, _ = corridor
    both = {"shape": [3, 11], "guards": [PACER_GUARD, {"loop": [[5, 1]], "headings": [0]}]}
    code, lines = _run(
        str(level), "--patrol", _patrol_file(level.parent, both), "--safe", "9.5,1.5", "--safe", "8.5,0.5"
    )
    assert code == 1 and _broken(lines) == [
        "safe 9.5,1.5: cell [9, 1] is in view of guards 0 and 1 for 8 of 8 lap ticks, first at lap tick 0"
    ]


def test_an_undetected_safe_spot_may_be_seen_briefly(corridor: tuple[Path, Path]) -> None:
    level, _ = corridor
    pacer = _patrol_file(level.parent, PACER)
    # Seen once a lap from four cells away: the plain rule breaks, the undetected one holds.
    assert _run(str(level), "--patrol", pacer, "--safe", "9.5,0.5")[0] == 1
    assert _run(str(level), "--patrol", pacer, "--safe", "9.5,0.5", "--undetected") == (
        0,
        [f"{level}: its one rule holds"],
    )
    [result] = run_checks(scene_from(TWO_ROOMS), CheckRules(patrol=pacer, safe=(SafeRule((9.5, 0.5)),), undetected=True))
    assert result == (
        "safe 9.5,0.5",
        True,
        "cell [9, 0]: a player standing there is never detected "
        "(in view of guard 0 for 1 of 8 lap ticks, first at lap tick 4)",
    )
    # Seen two ticks running: detected.
    code, lines = _run(str(level), "--patrol", pacer, "--safe", "10.5,0.5", "--undetected")
    assert code == 1 and _broken(lines) == [
        "safe 10.5,0.5: cell [10, 0]: a player standing there is detected after 2 ticks "
        "(in view of guard 0 for 2 of 8 lap ticks, first at lap tick 3)"
    ]
    # A slower model lets the same spot pass.
    slow = ["--detect-near", "1", "--detect-far", "2"]
    assert _run(str(level), "--patrol", pacer, "--safe", "10.5,0.5", "--undetected", *slow)[0] == 0


#: The pacer stops every unseen crossing; under the default model every crossing is detected too, but with
#: slower detection (--detect-near 1 --detect-far 2) a player can slip past undetected from any lap tick.
SLOW = ("--detect-near", "1", "--detect-far", "2")


@pytest.mark.parametrize(
    ("model", "expect", "broken"),
    [
        ((), "detected", None),
        ((), "caught", None),
        ((), "undetected", "expected undetected, detected: no undetected path (closest call: 1 ticks in view)"),
        (SLOW, "undetected", None),
        (SLOW, "caught", None),
        (SLOW, "detected", "expected detected, undetected: an undetected path of 12 ticks from lap tick"),
    ],
    ids=["default-detected", "default-caught", "default-undetected", "slow-undetected", "slow-caught", "slow-detected"],
)
def test_expect_undetected_or_detected(
    corridor: tuple[Path, Path], model: tuple[str, ...], expect: str, broken: str | None
) -> None:
    level, _ = corridor
    pacer = _patrol_file(level.parent, PACER)
    code, lines = _run(str(level), "--patrol", pacer, "--sneak", "0.5,0.5", "10.5,2.5", "--expect", expect, *model)
    if broken is None:
        assert (code, lines) == (0, [f"{level}: its one rule holds"])
    else:
        assert code == 1 and len(lines) == 1
        assert _broken(lines)[0].startswith(f"sneak 0.5,0.5 -> 10.5,2.5: {broken}"), lines


@pytest.mark.parametrize(
    ("expect", "limits", "broken"),
    [
        # Left room, [0, 0] to [2, 2]: an unseen path from 6 of the 8 lap ticks, an undetected one from 7.
        ("sneaks", ["--min-slack", "6", "--max-slack", "6"], []),
        (
            "sneaks",
            ["--min-slack", "7"],
            ["min-slack: {sneak}: an unseen path exists from 6 of 8 lap ticks, limit at least 7"],
        ),
        (
            "sneaks",
            ["--max-slack", "5"],
            ["max-slack: {sneak}: an unseen path exists from 6 of 8 lap ticks, limit at most 5"],
        ),
        ("undetected", ["--min-slack", "7", "--max-slack", "7"], []),
        (
            "undetected",
            ["--max-slack", "6"],
            ["max-slack: {sneak}: an undetected path exists from 7 of 8 lap ticks, limit at most 6"],
        ),
        (
            "undetected",
            ["--min-slack", "8"],
            ["min-slack: {sneak}: an undetected path exists from 7 of 8 lap ticks, limit at least 8"],
        ),
    ],
    ids=[
        "unseen-holds",
        "unseen-too-tight",
        "unseen-too-loose",
        "undetected-holds",
        "undetected-too-loose",
        "undetected-too-tight",
    ],
)
def test_slack_limits(corridor: tuple[Path, Path], expect: str, limits: list[str], broken: list[str]) -> None:
    level, _ = corridor
    pacer = _patrol_file(level.parent, PACER)
    code, lines = _run(str(level), "--patrol", pacer, "--sneak", "0.5,0.5", "2.5,2.5", "--expect", expect, *limits)
    if not broken:
        assert (code, lines) == (0, [f"{level}: all 3 rules hold"])
    else:
        assert code == 1 and _broken(lines) == [line.format(sneak="sneak 0.5,0.5 -> 2.5,2.5") for line in broken]


def test_safe_and_slack_rules_from_a_checks_file(corridor: tuple[Path, Path], tmp_path: Path) -> None:
    level, _ = corridor
    _patrol_file(tmp_path, PACER)
    checks = tmp_path / "checks.toml"
    checks.write_text(
        'patrol = "patrol.json"\nsafe = [[8.5, 0.5], [9.5, 0.5]]\nundetected = true\nmin_slack = 7\n'
        '[[sneak]]\nfrom = [0.5, 0.5]\nto = [2.5, 2.5]\nexpect = "undetected"\n'
    )
    assert _run(str(level), "--checks", str(checks)) == (0, [f"{level}: all 4 rules hold"])
    # An option adds to the file: a third safe spot, one a player standing in is detected in.
    code, lines = _run(str(level), "--checks", str(checks), "--safe", "10.5,2.5")
    assert code == 1 and _broken(lines) == [
        "safe 10.5,2.5: cell [10, 2]: a player standing there is detected after 2 ticks "
        "(in view of guard 0 for 2 of 8 lap ticks, first at lap tick 3)"
    ]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("safe = [3.5, 0.5]\n", "bad.toml: safe[0]: expected [x, y], two finite numbers, got 3.5"),
        ("safe = [[3.5]]\n", "bad.toml: safe[0]: expected [x, y], two finite numbers, got [3.5]"),
        ('safe = "3.5,0.5"\n', "bad.toml: safe: expected a list of [x, y] points, got a string"),
        ("safe = [[4.5, 0.5]]\n", "bad.toml: safe[0]: point 4.5,0.5 is not a cell a guard-sized player can stand in"),
        ("safe = [[8.5, 0.5]]\nundetected = 1\n", "bad.toml: undetected: expected true or false, got 1"),
        ("undetected = true\nmax_idleness = 9\n", "bad.toml: undetected: there is no safe rule in the file"),
        ("min_slack = 2\nmax_idleness = 9\n", "bad.toml: min_slack: there is no sneak rule in the file"),
        (f"max_slack = -1\n{_SNEAK}", "bad.toml: max_slack: expected a whole number of at least 0, got -1"),
        (f"min_slack = 1.5\n{_SNEAK}", "bad.toml: min_slack: expected a whole number of at least 0, got 1.5"),
        (f"min_slack = 5\nmax_slack = 4\n{_SNEAK}", "bad.toml: min_slack: 5 is over max_slack 4: no slack meets both"),
        (
            '[[sneak]]\nfrom = [0, 0]\nto = [1, 1]\nexpect = "unseen"\n',
            "bad.toml: sneak[0].expect: 'unseen' is not one of caught, sneaks, detected, undetected",
        ),
    ],
    ids=[
        "point-not-list",
        "short-point",
        "safe-string",
        "safe-in-wall",
        "undetected-number",
        "undetected-alone",
        "slack-alone",
        "negative-slack",
        "fractional-slack",
        "slack-crossed",
        "expect-unseen",
    ],
)
def test_bad_safe_and_slack_keys(corridor: tuple[Path, Path], tmp_path: Path, text: str, message: str) -> None:
    level, _ = corridor
    checks = tmp_path / "bad.toml"
    checks.write_text(text)
    code, lines = _run(str(level), "--checks", str(checks))
    assert code == 2 and len(lines) == 1 and lines[0].startswith(f"guardsim: error: {tmp_path / message}"), lines


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--min-slack", "3", "--max-idleness", "9"], "slack limits apply to the sneak rules' slack"),
        (["--undetected", "--max-idleness", "9"], "undetected applies to the safe rules"),
        (["--safe", "4.5,0.5"], "--safe: point 4.5,0.5 is not a cell"),
        (["--safe", "9.5"], "expected X,Y"),
        (
            ["--sneak", "0.5,0.5", "2.5,2.5", "--expect", "caught", "--min-slack", "3", "--max-slack", "2"],
            "min slack 3 is over max slack 2",
        ),
    ],
    ids=["slack-alone", "undetected-alone", "safe-in-wall", "safe-not-a-point", "slack-crossed"],
)
def test_bad_safe_and_slack_options_are_exit_2(corridor: tuple[Path, Path], args: list[str], message: str) -> None:
    level, _ = corridor
    code, lines = _run(str(level), *args)
    assert code == 2 and message in "\n".join(lines), lines
    assert code == 2 and sum(line.startswith(("guardsim: error", "Error")) for line in lines) == 1, lines


def test_check_unheard_asks_that_the_sneak_goes_unheard_too(tmp_path: Path) -> None:
    level = write_level(tmp_path, ALCOVE | {"intruder": {"walk_noise": 3, "sneak_noise": 3, "sneak_ticks": 2}})
    post = tmp_path / "post.json"
    post.write_text(json.dumps(ALCOVE_POST))
    sneak = ["--patrol", str(post), "--sneak", "0.5,1.5", "10.5,1.5"]
    # Unseen, the corridor is open; every step in it is heard, walking or sneaking.
    code, lines = _run(str(level), *sneak, "--expect", "caught")
    assert code == 1 and lines == [
        f"{level}: broken: sneak 0.5,1.5 -> 10.5,1.5: expected caught, sneaks: an unseen path of 10 ticks from lap tick 0"
    ]
    assert _run(str(level), *sneak, "--expect", "caught", "--unheard") == (0, [f"{level}: its one rule holds"])
    code, lines = _run(str(level), *sneak, "--expect", "sneaks", "--unheard")
    assert code == 1 and lines == [
        f"{level}: broken: sneak 0.5,1.5 -> 10.5,1.5: expected sneaks, caught: no unseen, unheard path (closest call: "
        "0 ticks in view, heard 5 times)"
    ]
    # A quieter sneak (0.5 units: not the next cell) gets through, sneaking past the alcove: 15 ticks.
    quiet = ["--sneak-noise", "0.5", "--min-slack", "2"]
    code, lines = _run(str(level), *sneak, "--expect", "sneaks", "--unheard", *quiet)
    assert code == 1 and lines == [
        f"{level}: broken: min-slack: sneak 0.5,1.5 -> 10.5,1.5: an unseen, unheard path exists from 1 of 1 lap "
        "ticks, limit at least 2"
    ]
    # The same from a checks file; and unheard needs a sneak rule to apply to.
    checks = tmp_path / "checks.json"
    checks.write_text(json.dumps({"unheard": True, "sneak": [{"from": [0.5, 1.5], "to": [10.5, 1.5], "expect": "caught"}]}))
    assert _run(str(level), "--patrol", str(post), "--checks", str(checks)) == (0, [f"{level}: its one rule holds"])
    checks.write_text(json.dumps({"unheard": True, "max_idleness": 10}))
    code, lines = _run(str(level), "--patrol", str(post), "--checks", str(checks))
    assert code == 2 and lines == [
        f"guardsim: error: {checks}: unheard: there is no sneak rule in the file for it to apply to"
    ]
    code, lines = _run(str(level), "--patrol", str(post), "--max-idleness", "10", "--unheard")
    assert code == 2 and lines[0].startswith("guardsim: error: ") and "unheard applies to the sneak rules" in lines[0]
