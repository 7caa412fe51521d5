"""Every example of issue 16 ("Robustness, round two") outside the map importers, as a test.

Each bad input ends in exit 2 with one stderr line naming the file and the fault (quoting at most a
short excerpt), or is accepted with a correct result; inputs inside the default limits finish (the
figures are in docs/robustness.md, measured by benchmarks/fuzz.py, not asserted here).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import Result

from guardsim.files.reading import EXCERPT_CHARS
from tests.common import EMPTY_SQUARE, SQUARE_WITH_HOLE, guardsim_command, run, write_level

SQUARE_ROOM = {"outer": [[0, 0], [10, 0], [10, 10], [0, 10]]}


def one_error_line(result: Result | subprocess.CompletedProcess[str], named: Path | str) -> str:
    """The single stderr line of a refused command, which must name ``named``."""
    code = result.exit_code if isinstance(result, Result) else result.returncode
    assert code == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stdout + result.stderr
    [line] = result.stderr.splitlines()
    assert line.startswith("guardsim: error: ")
    assert str(named) in line
    return line


def nested(depth: int) -> str:
    return "[" * depth + "]" * depth


# ---------------------------------------------------------------- malformed numbers and nesting


@pytest.mark.parametrize("command", ["validate", "play", "render"])
def test_deeply_nested_level_is_one_line(tmp_path: Path, command: str) -> None:
    """A level nested 100,000 deep (RecursionError in validate --fix before) is refused before decoding."""
    path = write_level(tmp_path, '{"outer": ' + nested(100_000) + "}")
    extra = {"validate": ["--fix", str(tmp_path / "fixed.json")], "play": [], "render": ["--png", "x.png"]}[command]
    result = run(command, path, *extra)
    if command == "validate":
        assert result.exit_code == 2 and "nested 100001 deep" in result.stdout
        assert not (tmp_path / "fixed.json").exists()
    else:
        assert "nested 100001 deep, over the limit of" in one_error_line(result, path)


def test_view_range_and_fov_nan_are_refused_on_the_command_line(tmp_path: Path) -> None:
    """--fov nan played 107 steps instead of 13, and bench stored NaN in run.json: both are usage errors."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    for command, extra in (("play", []), ("bench", ["--out", str(tmp_path / "out")]), ("bounds", [])):
        for option in ("--fov", "--view-range"):
            for value in ("nan", "inf", "-inf"):
                result = run(command, level, *extra, option, value)
                assert result.exit_code == 2, (command, option, value)
                assert f"Invalid value for '{option}'" in result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("value", ["NaN", "Infinity", "1e400", "-1e999"])
def test_non_finite_level_numbers_are_located(tmp_path: Path, value: str) -> None:
    """Non-finite numbers in a level file are refused with the field that holds them."""
    path = write_level(tmp_path, '{"outer": [[0, 0], [4, 0], [4, 4], [0, 4]], "guard": {"view_range": ' + value + "}}")
    assert "guard.view_range" in one_error_line(run("play", path), path)


def test_huge_integer_is_located(tmp_path: Path) -> None:
    """A 5,001-digit integer (past Python's conversion limit) is one line with its line and column."""
    path = write_level(tmp_path, '{"outer": [[0, 0], [4, 0], [4, 4], [0, 4]], "cell_size": 1' + "0" * 5000 + "}")
    line = one_error_line(run("play", path), path)
    assert "5001 digits" in line and "line 1 column" in line


# ---------------------------------------------------------------- messages: one line, short, named


def test_enormous_offending_value_is_quoted_as_a_short_excerpt(tmp_path: Path) -> None:
    """A guard.heading that is a list of lists was echoed whole (206,674 characters)."""
    path = write_level(tmp_path, {**EMPTY_SQUARE, "guard": {"heading": [[[1, 2]] * 300] * 300}})
    line = one_error_line(run("play", path), path)
    assert len(line) < len(str(path)) + 3 * EXCERPT_CHARS
    assert "guard.heading" in line and " ... " in line


def test_file_name_with_a_newline_keeps_the_message_on_one_line(tmp_path: Path) -> None:
    """The name is shown with its newline escaped, so the error stays one line."""
    path = write_level(tmp_path, {"outer": [[0, 0], [1, 0]]}, "bad\nname.json")
    result = run("play", path)
    assert result.exit_code == 2
    [line] = result.stderr.splitlines()
    assert "bad\\nname.json" in line and "ring has 2 distinct points" in line


def test_library_warnings_do_not_reach_stderr(tmp_path: Path) -> None:
    """Coordinates that overflow inside GEOS made shapely print RuntimeWarnings before the error line;
    in a real process the error is now the only line."""
    ring = [[-1e308, 0], [1e308, 0], [1e308, 1e308], [-1e308, 1e308]]
    path = write_level(tmp_path, {"outer": ring, "holes": [[[0, 0], [1e307, 0], [0, 1e307]]]})
    for command in (["validate", "--fix", str(tmp_path / "fixed.json")], ["play"]):
        result = subprocess.run(
            [*guardsim_command(), command[0], str(path), *command[1:]], capture_output=True, text=True, check=False
        )
        assert result.returncode == 2
        assert len(result.stderr.splitlines()) == 1, result.stderr


# ---------------------------------------------------------------- special files


@pytest.mark.parametrize("command", ["validate", "play", "render", "bounds", "regress"])
def test_fifo_and_device_inputs_are_refused_without_blocking(tmp_path: Path, command: str) -> None:
    """A FIFO blocked validate, play, import and regress forever; /dev/zero passed 3 GB in seconds
    (the byte cap looked only at st_size, which is 0 there). Both are one line now, at once."""
    fifo = tmp_path / "level.json"
    os.mkfifo(fifo)
    device = tmp_path / "zero.json"
    device.symlink_to("/dev/zero")
    extra = {"render": ["--png", str(tmp_path / "x.png")], "regress": ["--renders", str(tmp_path)]}.get(command, [])
    for path, what in ((fifo, "is a FIFO"), (device, "is a character device")):
        result = subprocess.run(
            [*guardsim_command(), command, str(path), *extra], capture_output=True, text=True, timeout=60, check=False
        )
        line = one_error_line(result, path)
        # validate lists each file's problems on stdout; the stderr line names the invalid files.
        assert what in (result.stdout if command == "validate" else line)


# ---------------------------------------------------------------- hangs and memory inside the limits


@pytest.mark.slow
def test_million_cell_level_validates(tmp_path: Path) -> None:
    """A 10 x 10 level at cell_size 0.01 (exactly the default 1,000,000 cells) did not finish in 900 s;
    the hidden-area check now stops at --max-rays and says so."""
    path = write_level(tmp_path, {**SQUARE_ROOM, "cell_size": 0.01})
    result = run("validate", path)
    assert result.exit_code == 0, result.output
    assert f"{path}: ok" in result.stdout
    assert "not checked for hidden areas" in result.stdout


@pytest.mark.slow
def test_long_outer_ring_validates_and_plays(tmp_path: Path) -> None:
    """An outer ring of 99,997 points (validate 96 s, bounds 102 s before) is a valid level."""
    angles = np.linspace(0, 2 * math.pi, 99_997, endpoint=False)
    ring = np.stack([50 + 40 * np.cos(angles), 50 + 40 * np.sin(angles)], axis=1).tolist()
    path = write_level(tmp_path, {"outer": ring, "cell_size": 2})
    validated = run("validate", path, "--no-warnings")
    assert validated.exit_code == 0 and f"{path}: ok" in validated.stdout
    assert run("play", path, "--max-steps", "5", "--trace", tmp_path / "t.json").exit_code == 0
    trace = json.loads((tmp_path / "t.json").read_text(encoding="utf-8"))
    # The grid is the ring's: 40 cells across; every cell walked lies inside the ring, each a step apart.
    assert trace["shape"] == [40, 40] and trace["steps"] == 5 and len(trace["path"]) == 6
    origin = trace["origin"]
    for col, row in trace["path"]:
        centre = (origin[0] + 2 * col + 1, origin[1] + 2 * row + 1)
        assert math.hypot(centre[0] - 50, centre[1] - 50) < 40
    for (c0, r0), (c1, r1) in zip(trace["path"], trace["path"][1:]):
        assert abs(c0 - c1) + abs(r0 - r1) <= 1


@pytest.mark.parametrize("count", [2000, pytest.param(33_000, marks=pytest.mark.slow)])
def test_identical_holes_are_refused_in_bounded_output(tmp_path: Path, count: int) -> None:
    """33,000 identical holes passed 8 GB in validate and render; 2,000 took 25 s. The overlap check
    catches repeats first and lists at most 20 pairs."""
    path = write_level(tmp_path, {**SQUARE_ROOM, "holes": [[[2, 2], [3, 2], [3, 3]]] * count})
    result = run("validate", path)
    assert result.exit_code == 2
    lines = result.stdout.splitlines()
    assert 1 < len(lines) <= 22
    assert "holes[0] and holes[1]: holes are the same ring" in lines[0]
    assert "more holes repeat an earlier ring" in lines[-1]
    assert "holes are the same ring" in one_error_line(run("play", path), path)
    fixed = tmp_path / "fixed.json"
    repaired = run("validate", path, "--fix", fixed)
    assert repaired.exit_code == 0, repaired.output
    assert len(json.loads(fixed.read_text(encoding="utf-8"))["holes"]) == 1


def test_frame_size_over_the_limit_is_refused_before_drawing(tmp_path: Path) -> None:
    """A manifest asking for 4096-pixel frames took a minute and 5 GB; it is refused by --max-frame-size."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE, "room.json")
    renders = tmp_path / "renders"
    assert run("regress", level, "--renders", renders, "--update").exit_code == 0
    manifest_path = renders / "room" / "manifest.json"
    manifest = json.loads(manifest_path.read_text(encoding="utf-8"))
    manifest["frame_size"] = 4096
    manifest_path.write_text(json.dumps(manifest), encoding="utf-8")
    line = one_error_line(run("regress", level, "--renders", renders), manifest_path)
    assert "over the limit of 1024 pixels (max_frame_size: raise it with --max-frame-size)" in line


# ---------------------------------------------------------------- regress with bad references


def damaged_references(tmp_path: Path, damage: Any) -> tuple[Path, Path, Path]:
    """References of a small level written by ``regress --update``, then damaged by ``damage(folder)``."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE, "room.json")
    renders = tmp_path / "renders"
    assert run("regress", level, "--renders", renders, "--update").exit_code == 0
    folder = renders / "room"
    damaged = damage(folder)
    return level, renders, damaged


def edit_trace(change: Any) -> Any:
    def damage(folder: Path) -> Path:
        path = next(folder.glob("*.trace.json"))
        data = json.loads(path.read_text(encoding="utf-8"))
        change(data)
        path.write_text(json.dumps(data), encoding="utf-8")
        return path

    return damage


def write_png_bytes(content: bytes) -> Any:
    def damage(folder: Path) -> Path:
        path = next(folder.glob("*-050.png"))
        path.write_bytes(content)
        return path

    return damage


def _declared_png(width: int, height: int) -> bytes:
    from tests.fuzz_cases import _png_declaring

    return _png_declaring(width, height)


@pytest.mark.parametrize(
    ("damage", "fragment"),
    [
        (edit_trace(lambda d: d.update(path=[])), "path: must be a non-empty list"),
        (edit_trace(lambda d: d.update(cell_size="1")), "cell_size: must be a positive number"),
        (
            edit_trace(lambda d: d.update(guard_paths=[d["path"], d["path"]], guard_headings=[d["headings"]] * 2)),
            None,
        ),
        (edit_trace(lambda d: d.update(shape=[100_000, 100_000])), "over the limit of 1000000 (max_cells"),
        (write_png_bytes(_declared_png(20_000, 20_000)), "a key frame of 20000 x 20000 pixels"),
        (write_png_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 40), "not a PNG image"),
        (lambda folder: _write(folder / "manifest.json", nested(50_000)), "over the limit of 64"),
        (lambda folder: _write(next(folder.glob("*.trace.json")), nested(50_000)), "over the limit of 64"),
    ],
    ids=["empty-path", "string-cell-size", "guard-paths-without-guards", "huge-shape", "png-bomb", "broken-png",
         "nested-manifest", "nested-trace"],
)  # fmt: skip
def test_bad_references_are_one_line(tmp_path: Path, damage: Any, fragment: str | None) -> None:
    """Each stored reference that raised inside regress (IndexError, ValueError, KeyError,
    DecompressionBombError, SyntaxError, RecursionError) is one error line naming the file, or, for a
    trace that still parses (a team trace against a one-guard run), a difference (exit 1)."""
    level, renders, damaged = damaged_references(tmp_path, damage)
    result = run("regress", level, "--renders", renders)
    if fragment is None:
        assert result.exit_code == 1 and "DIFFERS" in result.stdout and not result.stderr, result.output
    else:
        assert fragment in one_error_line(result, damaged)


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


# ---------------------------------------------------------------- bench run folders


def bench_folder(tmp_path: Path) -> tuple[list[str | Path], Path]:
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    out = tmp_path / "out"
    command: list[str | Path] = [level, "--episodes", "3", "--workers", "1", "--no-bounds", "--out", out]
    assert run("bench", *command).exit_code == 0
    return command, out


def test_bench_refuses_a_duplicated_row_and_a_row_outside_the_batch(tmp_path: Path) -> None:
    """A results.csv with a finished row twice, or a row for episode 99 of a 3-episode batch, counted
    4 episodes for --episodes 3; both are one line naming the file and the line."""
    command, out = bench_folder(tmp_path)
    results = out / "results.csv"
    lines = results.read_text(encoding="utf-8").splitlines(keepends=True)
    results.write_text("".join([*lines, lines[1]]), encoding="utf-8")
    assert "line 5: repeats the episode of line 2" in one_error_line(run("bench", *command), results)
    row = lines[1].split(",")
    row[5] = "99"
    results.write_text("".join([*lines, ",".join(row)]), encoding="utf-8")
    assert "line 5: episode 99 of ripplefront" in one_error_line(run("bench", *command), results)
    results.write_text("".join(lines), encoding="utf-8")
    assert run("bench", *command).exit_code == 0


def test_deeply_nested_run_json_is_one_line(tmp_path: Path) -> None:
    """A run.json nested deeply (RecursionError in experiment/results.py before)."""
    command, out = bench_folder(tmp_path)
    (out / "run.json").write_text(nested(100_000), encoding="utf-8")
    assert "over the limit of 64" in one_error_line(run("bench", *command), out / "run.json")


def test_level_without_free_area_is_not_ok(tmp_path: Path) -> None:
    """Walls covering the whole floor (a TMX imported with exit 0) made a level validate called ok; a level
    whose holes cover the outer ring, or where the guard fits in no cell, is invalid."""
    covered = write_level(
        tmp_path,
        {**SQUARE_ROOM, "holes": [[[0, 0], [5, 0], [5, 10], [0, 10]], [[5, 0], [10, 0], [10, 10], [5, 10]]]},
        "covered.json",
    )
    result = run("validate", covered)
    assert result.exit_code == 2
    assert f"{covered}: holes: the holes cover the whole outer ring: the level has no free area" in result.stdout
    tight = write_level(tmp_path, {**SQUARE_ROOM, "guard": {"radius": 6}}, "tight.json")
    result = run("validate", tight)
    assert result.exit_code == 2
    assert "no cell where the guard (radius 6) fits" in result.stdout


def test_fix_leaves_a_ring_with_an_absurd_coordinate_to_the_loader(tmp_path: Path) -> None:
    """A hole reaching to x = 1e40 was "repaired" by --fix into another hole (GEOS loses the level's
    digits next to 1e40) and written with exit 0; it is now reported, and nothing is written."""
    level = {**SQUARE_WITH_HOLE, "holes": [[[2, 2], [4, 2], [4, 4], [10**40, 4]]]}
    path = write_level(tmp_path, level)
    fixed = tmp_path / "fixed.json"
    result = run("validate", path, "--fix", fixed)
    assert result.exit_code == 2
    assert "holes[0] point 3: coordinate must be a number of at most 1e+15 in size" in result.stdout
    assert not fixed.exists()


def test_optimum_memory_beyond_reach_is_one_line(tmp_path: Path) -> None:
    """Fuzz case seed 243: ``--memory-mb 10000000000000000000`` was numpy's traceback ("Maximum allowed
    dimension exceeded"); a size past the machine is now one line naming the level and the option."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    huge = run("optimum", level, "--memory-mb", "10000000000000000000")
    assert huge.exit_code == 2 and "'--memory-mb'" in huge.stderr.splitlines()[-1]
    result = run("optimum", level, "--memory-mb", str(2**20), "--max-expansions", "10")
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert result.stderr.splitlines() == [
        f"guardsim: error: {level}: cannot reserve 1048576 MB for the search nodes (memory_bytes: lower --memory-mb)"
    ]
