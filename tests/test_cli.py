"""The command line: bad input is one ``guardsim: error:`` line with status 2; good input does its job.

The bad level files are the ones of ``tests/test_level.py`` (``BAD_LEVELS`` and ``GRID_TIME_LEVELS``).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import imageio.v3 as iio
import pytest

from tests.bad_levels import BAD_LEVELS, GRID_TIME_LEVELS, PILLAR, BadLevel, bad_params, changed
from tests.common import (
    EMPTY_SQUARE,
    LEVELS,
    REPO,
    SQUARE_WITH_HOLE,
    TRACE_KEYS,
    assert_one_line_error,
    guardsim_command,
    run,
    shipped_levels,
    write_level,
)

SQUARE = REPO / "levels" / "square.json"
ALL_BAD_LEVELS = {**BAD_LEVELS, **GRID_TIME_LEVELS}


@bad_params(ALL_BAD_LEVELS, cli=True)
def test_play_bad_level_is_one_error_line(tmp_path: Path, case: BadLevel) -> None:
    """`guardsim play BAD.json` exits 2 with one `guardsim: error:` line naming the file and the fault."""
    path = case.write(tmp_path)
    result = run("play", path, "--gif", tmp_path / "out.gif", *case.cli_options())
    line = assert_one_line_error(result, path)
    for fragment in case.fragments:
        assert fragment in line
    assert result.stdout == ""
    assert not (tmp_path / "out.gif").exists()


@bad_params(ALL_BAD_LEVELS, cli=True)
def test_validate_bad_level_reports_it(tmp_path: Path, case: BadLevel) -> None:
    """`guardsim validate BAD.json` prints the fault on stdout, a count on stderr, and exits 2."""
    path = case.write(tmp_path)
    result = run("validate", path, *case.cli_options())
    assert "Traceback" not in result.output
    assert result.exit_code == 2
    problem_lines = result.stdout.splitlines()
    assert problem_lines
    assert all(str(path) in line for line in problem_lines)
    for fragment in case.fragments:
        assert fragment in result.stdout
    assert result.stderr == f"guardsim: error: 1 of 1 level(s) invalid: {path}\n"


def test_validate_prints_every_problem_of_every_file(tmp_path: Path) -> None:
    """Each file's problems are all listed, one line each; valid files say ok; any invalid file means exit 2."""
    two = write_level(
        tmp_path,
        changed(SQUARE_WITH_HOLE, cell_size="big", holes=[PILLAR, [[4.5, 4.5], [5.5, 4.5], [7, 7], [4.5, 5.5]]]),
        "two-problems.json",
    )
    one = write_level(tmp_path, changed(EMPTY_SQUARE, colour="red"), "one-problem.json")
    good = write_level(tmp_path, EMPTY_SQUARE, "good.json")
    result = run("validate", two, good, one)
    assert result.exit_code == 2
    assert result.stdout.splitlines() == [
        f"{two}: cell_size: must be a number, not a string",
        f"{two}: holes[1] point 2 (7, 7): hole point lies outside the outer ring (keep holes inside the outer ring)",
        f"{good}: ok",
        f"{one}: key 'colour': unknown key (known keys: ambient_light, cameras, cell_size, guard, holes, intruder, lights, name, outer, player_starts, starts, tile_pixels)",
    ]
    assert result.stderr == f"guardsim: error: 2 of 3 level(s) invalid: {two}, {one}\n"


def test_validate_goes_on_after_an_unreadable_file(tmp_path: Path) -> None:
    """A missing or non-JSON file is reported and the remaining files are still checked."""
    missing = tmp_path / "missing.json"
    broken = write_level(tmp_path, "{", "broken.json")
    result = run("validate", missing, broken, SQUARE)
    assert result.exit_code == 2
    lines = result.stdout.splitlines()
    assert lines[0] == f"{missing}: no such file"
    assert lines[1].startswith(f"{broken}: not valid JSON")
    assert lines[2] == f"{SQUARE}: ok"


def test_validate_shipped_levels_ok() -> None:
    """Every shipped level validates: one ok line each, exit 0, nothing on stderr."""
    result = run("validate", *LEVELS)
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines() == [f"{path}: ok" for path in LEVELS]
    assert result.stderr == ""


@pytest.mark.parametrize(
    ("option", "tight", "enough"),
    [("--max-cells", "35", "36"), ("--max-vertices", "7", "8"), ("--max-file-bytes", "10", "100000")],
    ids=["max-cells", "max-vertices", "max-file-bytes"],
)
def test_limit_options_raise_the_caps(tmp_path: Path, option: str, tight: str, enough: str) -> None:
    """Each size limit is an option: too low fails with a message naming it, high enough passes."""
    path = write_level(tmp_path, SQUARE_WITH_HOLE)
    too_low = run("validate", path, option, tight)
    assert too_low.exit_code == 2
    assert option in too_low.stdout
    high_enough = run("validate", path, option, enough)
    assert high_enough.exit_code == 0, high_enough.output


def test_default_max_cells_rejects_a_huge_grid(tmp_path: Path) -> None:
    """Without --max-cells, a 2000 x 2000 grid is refused before anything is built."""
    path = write_level(tmp_path, changed(EMPTY_SQUARE, cell_size=0.002))
    refused = run("validate", path)
    assert refused.exit_code == 2
    assert "2000 x 2000 = 4000000 cells is over the limit of 1000000" in refused.stdout
    assert "--max-cells" in refused.stdout


@shipped_levels
def test_play_shipped_level_over_max_cells(tmp_path: Path, level_path: Path) -> None:
    """`--max-cells 10` turns a shipped level into a one-line error that names the option."""
    result = run("play", level_path, "--max-cells", "10", "--gif", tmp_path / "out.gif")
    line = assert_one_line_error(result, level_path)
    assert "--max-cells" in line


def test_play_writes_gif_and_trace(tmp_path: Path) -> None:
    """`play --gif --trace` exits 0; the summary's step count is the trace's, and the trace is consistent."""
    gif = tmp_path / "square.gif"
    trace_path = tmp_path / "square.json"
    result = run("play", SQUARE, "--gif", gif, "--trace", trace_path, "--stride", "100")
    assert result.exit_code == 0, result.output
    assert result.stderr == ""
    summary = result.stdout.strip()
    assert "\n" not in summary
    assert "covered" in summary
    trace = json.loads(trace_path.read_text(encoding="utf-8"))
    assert set(trace) >= TRACE_KEYS
    match = re.search(r"after (\d+) steps", summary)
    assert match is not None, summary
    assert int(match.group(1)) == trace["steps"]
    assert trace["steps"] == len(trace["path"]) - 1 > 0
    assert len(trace["unseen_percent"]) == len(trace["path"])
    assert trace["unseen_percent"][-1] == 0
    assert trace["covered"] is True
    assert trace["level"] == "Square"
    assert trace["planner"] == "ripplefront"
    assert trace["seed"] == 0
    assert trace["cell_size"] == 1.0
    assert trace["shape"] == [60, 60]
    assert trace["start"] == trace["path"][0] == [2, 2]
    assert trace["reachable"] > 0
    assert trace["unreachable"] == 0
    assert gif.read_bytes()[:6] in (b"GIF87a", b"GIF89a")
    assert str(gif) in summary
    assert str(trace_path) in summary


@pytest.mark.parametrize("value", ["1", "a,b", "1,2,3", "nan,1", "1,inf", ""], ids=repr)
def test_play_malformed_start_is_one_usage_line(tmp_path: Path, value: str) -> None:
    """`--start` must be two finite numbers X,Y; anything else is one usage line with status 2."""
    result = run("play", SQUARE, "--start", value, "--gif", tmp_path / "out.gif")
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    [line] = result.stderr.splitlines()
    assert line.startswith("guardsim: error: Invalid value for '--start': ")
    assert line.endswith(" (see guardsim play --help)")
    assert not (tmp_path / "out.gif").exists()


@pytest.mark.parametrize(
    ("start", "fault"),
    [("25,25", "does not fit"), ("100,1", "lies outside the level"), ("-0.5,3", "lies outside the level")],
    ids=["in-pillar", "right-of-level", "left-of-level"],
)
def test_play_start_option_in_wall_or_outside(tmp_path: Path, start: str, fault: str) -> None:
    """A well-formed `--start` in a wall or off the level is a one-line error naming the start."""
    result = run("play", SQUARE, "--start", start, "--gif", tmp_path / "out.gif")
    line = assert_one_line_error(result, SQUARE)
    x, y = start.split(",")
    assert f"start ({float(x):g}, {float(y):g})" in line
    assert fault in line


def test_play_unwritable_output_is_one_error_line(tmp_path: Path) -> None:
    """A GIF path in a missing folder is an OutputError line with status 2, not a traceback."""
    level = write_level(tmp_path, EMPTY_SQUARE)
    target = tmp_path / "no-such-folder" / "out.gif"
    result = run("play", level, "--gif", target)
    line = assert_one_line_error(result, target)
    assert "does not exist" in line


def test_render_writes_png(tmp_path: Path) -> None:
    """`render --png` writes a PNG larger than 64 x 64 and reports the grid on one line."""
    png = tmp_path / "out.png"
    result = run("render", SQUARE, "--png", png)
    assert result.exit_code == 0, result.output
    image = iio.imread(png)
    assert image.shape[0] > 64
    assert image.shape[1] > 64
    assert image.shape[2] in (3, 4)
    assert result.stdout.startswith("Square: 60 x 60 cells")
    assert str(png) in result.stdout


def test_render_bad_level_is_one_error_line(tmp_path: Path) -> None:
    """`render` reports a bad level like `play` does and writes no image."""
    path = write_level(tmp_path, changed(EMPTY_SQUARE, cell_size=-1))
    png = tmp_path / "out.png"
    line = assert_one_line_error(run("render", path, "--png", png), path)
    assert "cell_size: must be positive" in line
    assert not png.exists()


def test_console_script_bad_level(tmp_path: Path) -> None:
    """The real `guardsim play` process on a bad level: status 2, one stderr line, no traceback."""
    path = write_level(tmp_path, changed(SQUARE_WITH_HOLE, holes=[[[1, 1], [3, 3], [3, 1], [1, 3]]]))
    completed = subprocess.run(
        [*guardsim_command(), "play", str(path), "--gif", str(tmp_path / "out.gif")],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert completed.returncode == 2
    assert "Traceback" not in completed.stderr + completed.stdout
    lines = completed.stderr.splitlines()
    assert len(lines) == 1, completed.stderr
    assert lines[0].startswith(f"guardsim: error: {path}: holes[0] point ")
    assert "crosses or touches itself" in lines[0]
    assert completed.stdout == ""


@pytest.mark.parametrize("option", ["--move-speed", "--turn-speed", "--tick-hz", "--max-seconds"])
@pytest.mark.parametrize("command", ["play", "bench"])
def test_game_speeds_without_continuous_motion_are_refused(tmp_path: Path, command: str, option: str) -> None:
    """A speed given to a grid episode was ignored without a word: the run looked like it used it."""
    extra = ["--out", str(tmp_path / "out")] if command == "bench" else []
    result = run(command, SQUARE, *extra, option, "3")
    assert result.exit_code == 2 and not (tmp_path / "out").exists()
    assert result.stderr.splitlines() == [
        f"guardsim: error: Invalid value for {option}: grid episodes have no game time; it needs --motion "
        f"continuous (see guardsim {command} --help)"
    ]


def test_unknown_commands_and_missing_arguments_are_one_line() -> None:
    assert run("plya").stderr.splitlines() == ["guardsim: error: No such command 'plya'. (see guardsim --help)"]
    assert run("play").stderr.splitlines() == ["guardsim: error: Missing argument 'LEVEL'. (see guardsim play --help)"]


def test_a_gif_named_as_another_format_is_refused(tmp_path: Path) -> None:
    """``--gif x.png`` wrote GIF data into a .png with exit 0; a name without a suffix is still fine."""
    result = run("play", SQUARE, "--gif", tmp_path / "x.png")
    assert result.exit_code == 2 and not (tmp_path / "x.png").exists()
    assert result.stderr.splitlines() == [
        f"guardsim: error: Invalid value for '--gif': '{tmp_path / 'x.png'}' ends in '.png', but a GIF is written: "
        "name it .gif (see guardsim play --help)"
    ]
    assert run("play", SQUARE, "--gif", tmp_path / "plain", "--max-steps", "2").exit_code == 0
    assert (tmp_path / "plain").read_bytes()[:6] == b"GIF89a"


def test_no_command_prints_the_help() -> None:
    """`guardsim` alone prints the usage and the commands, on several lines, and exits 0."""
    result = run()
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert lines[0].startswith("Usage: ") and any(line.strip().startswith("play") for line in lines)
    assert "error" not in result.stderr


def test_view_of_an_alert_trace_needs_its_level_and_fits_it(tmp_path: Path) -> None:
    """An alert trace is drawn on the level it was played on: without --level, and on another level, one
    line each."""
    trace = tmp_path / "al.json"
    trace.write_text('{"level": "x", "shape": [2, 2], "guard_states": [["patrol"]], "events": []}')
    result = run("view", trace, "--html", tmp_path / "x.html")
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"guardsim: error: {trace}: an alert episode's trace: give --level LEVEL, the level it was played on"
    ]
    other = run("view", trace, "--level", SQUARE, "--html", tmp_path / "x.html")
    assert other.exit_code == 2
    assert other.stderr.splitlines() == [
        f"guardsim: error: {trace}: not an alert trace of this level (ValueError: its grid is 2 x 2, the level's "
        "60 x 60)"
    ]
    assert not (tmp_path / "x.html").exists()


def test_patrol_refuses_an_unwritable_export_before_its_work(tmp_path: Path) -> None:
    """`--export` naming a folder: one line, exit 2, and no patrol.json written first."""
    out = tmp_path / "out"
    result = run("patrol", SQUARE, "--out", out, "--export", tmp_path)
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [f"guardsim: error: {tmp_path}: cannot write: Is a directory"]
    assert not (out / "patrol.json").exists()


@pytest.mark.parametrize(
    ("arguments", "status", "stdout", "stderr"),
    [
        (["--version"], 0, "guardsim, version", ""),
        (["play", "missing.json"], 2, "", "guardsim: error: missing.json: no such file"),
    ],
)
def test_the_program_exits_at_once_after_the_exit_handlers(
    arguments: list[str], status: int, stdout: str, stderr: str, tmp_path: Path
) -> None:
    # run() skips the interpreter's teardown with os._exit: the exit handlers must still run, after
    # the command's output, and the status must be the command's.
    program = (
        "import atexit, sys\n"
        "atexit.register(lambda: print('handler ran', flush=True))\n"
        f"sys.argv = ['guardsim', *{arguments!r}]\n"
        "from guardsim.cli import run\n"
        "run()\n"
        "print('not reached')\n"
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert done.returncode == status
    assert done.stdout.startswith(stdout)
    assert done.stdout.endswith("handler ran\n")
    assert "not reached" not in done.stdout
    assert done.stderr.strip() == stderr
