"""``guardsim bench``: rows that do not depend on the workers, resume, errors per episode, outputs.

Everything runs for real: episodes on tiny levels (``tests/common.py``) or shipped levels with few
episodes, a real process pool, a real subprocess interrupted with SIGINT and one whose worker is killed.
The Dask path is in ``tests/test_bench_cluster.py``.
"""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import time
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import psutil
import pytest
from click.testing import CliRunner

from guardsim import load_level
from guardsim.cli import main
from guardsim.cli.bench import ProgressLine
from guardsim.experiment import CSV_COLUMNS, RUN_NAME, EpisodeRecord, read_results
from guardsim.experiment.executors import LocalPool
from guardsim.motion import run_episode
from guardsim.render.plots import StepsBox, plot_steps
from guardsim.simulation import Scene
from guardsim.trace import Trace
from tests.common import (
    EMPTY_SQUARE,
    L_ROOM,
    SQUARE,
    SQUARE_WITH_HOLE,
    assert_one_line_error,
    bench,
    guardsim_command,
    rows,
    without_seconds,
    write_level,
)

#: A valid level in which the guard fits nowhere: every episode raises when it draws its start.
NO_ROOM = {**EMPTY_SQUARE, "name": "no room", "guard": {"radius": 2.5}}


@pytest.fixture
def tiny_levels(tmp_path: Path) -> list[Path]:
    """Two tiny level files."""
    return [write_level(tmp_path, SQUARE_WITH_HOLE, "hole.json"), write_level(tmp_path, L_ROOM, "l.json")]


def test_rows_identical_for_one_and_two_workers(tmp_path: Path, tiny_levels: list[Path]) -> None:
    """--workers 1 (in this process) and --workers 2 (process pool) write the same rows in the same order,
    for a deterministic planner and for one that draws from the episode's generator (random-walk)."""
    options = ("--episodes", "6", "--seed", "3", "--planner", "ripplefront,random-walk")
    one = bench(*tiny_levels, *options, "--workers", "1", "--out", tmp_path / "one")
    two = bench(*tiny_levels, *options, "--workers", "2", "--out", tmp_path / "two")
    assert one.exit_code == 0, one.output
    assert two.exit_code == 0, two.output
    assert "on 2 local processes" in two.stderr
    assert len(rows(tmp_path / "one")) == 24
    assert without_seconds(rows(tmp_path / "one")) == without_seconds(rows(tmp_path / "two"))
    assert (tmp_path / "one" / "summary.json").read_bytes() == (tmp_path / "two" / "summary.json").read_bytes()
    assert one.stdout == two.stdout


def test_results_csv_and_summary_json(tmp_path: Path, tiny_levels: list[Path]) -> None:
    """Each row is its episode (start, heading, steps, T50 <= T90 <= T99); the summary is their statistics."""
    out = tmp_path / "out"
    result = bench(*tiny_levels, "--episodes", "5", "--seed", "7", "--workers", "1", "--out", out)
    assert result.exit_code == 0, result.output
    assert (out / "results.csv").read_text(encoding="utf-8").splitlines()[0] == ",".join(CSV_COLUMNS)
    table = rows(out)
    assert [(row["level_file"], row["episode"]) for row in table] == [
        (os.path.normpath(path), str(episode)) for path in sorted(map(str, tiny_levels)) for episode in range(5)
    ]
    scenes = {os.path.normpath(path): Scene.from_level(load_level(path)) for path in tiny_levels}
    for row in table:
        trace = run_episode(scenes[row["level_file"]], seed=7, episode=int(row["episode"]))
        assert row["planner"] == "ripplefront"
        assert row["seed"] == "7"
        assert row["level"] == trace.level
        assert (int(row["start_col"]), int(row["start_row"])) == trace.start
        assert row["start_heading"] == ("right", "down", "left", "up")[trace.headings[0]]
        assert int(row["steps"]) == trace.steps
        assert row["outcome"] == trace.outcome == "covered"
        assert int(row["reachable"]) == trace.reachable
        assert row["error"] == ""
        assert float(row["seconds"]) >= 0
        t50, t90, t99 = (int(row[name]) for name in ("t50", "t90", "t99"))
        assert (t50, t90, t99) == tuple(trace.steps_to_fraction(f) for f in (0.5, 0.9, 0.99))
        assert 0 <= t50 <= t90 <= t99 <= trace.steps
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["run"] == json.loads((out / RUN_NAME).read_text(encoding="utf-8"))
    assert summary["run"]["seed"] == 7
    assert len(summary["groups"]) == 2
    for group in summary["groups"]:
        members = [row for row in table if row["level_file"] == group["level_file"]]
        steps = np.array([int(row["steps"]) for row in members])
        t90 = np.array([int(row["t90"]) for row in members])
        assert group["planner"] == "ripplefront"
        assert group["episodes"] == 5
        assert group["outcomes"] == {"covered": 5, "step_limit": 0, "stuck": 0, "error": 0}
        for name, values in (("steps", steps), ("t90", t90)):
            assert group[name]["count"] == 5
            assert group[name]["min"] == values.min()
            assert group[name]["max"] == values.max()
            assert group[name]["median"] == pytest.approx(np.median(values), abs=1e-3)
            assert group[name]["mean"] == pytest.approx(values.mean(), abs=1e-3)
            assert [group[name]["q1"], group[name]["q3"]] == pytest.approx(np.percentile(values, [25, 75]), abs=1e-3)
    lines = result.stdout.splitlines()
    assert lines[0].split()[:4] == ["level", "planner", "episodes", "covered"]
    assert {line.split("  ")[0] for line in lines[1:]} == {"square with hole", "L room"}
    assert "\r" not in result.stderr  # no progress bar when stderr is not a terminal


def test_max_steps_ends_episodes_at_the_limit(tmp_path: Path) -> None:
    """--max-steps 2 on a shipped level: every episode stops at 2 steps, T99 never reached."""
    out = tmp_path / "out"
    result = bench(SQUARE, "--episodes", "3", "--max-steps", "2", "--workers", "1", "--out", out)
    assert result.exit_code == 0, result.output
    table = rows(out)
    assert [(row["outcome"], row["steps"], row["t99"]) for row in table] == [("step_limit", "2", "")] * 3
    assert "3 step_limit" in result.stdout


def test_episode_that_raises_is_recorded_and_the_rest_continue(tmp_path: Path) -> None:
    """A level where the guard fits nowhere makes each of its episodes raise: recorded as "error", with its
    full traceback in errors.log, the others run, and the command exits with status 3 (EPISODE_ERRORS)."""
    no_room = write_level(tmp_path, NO_ROOM, "no-room.json")
    hole = write_level(tmp_path, SQUARE_WITH_HOLE, "hole.json")
    out = tmp_path / "out"
    result = bench(no_room, hole, "--episodes", "3", "--workers", "2", "--out", out)
    assert result.exit_code == 3, result.output
    log = (out / "errors.log").read_text(encoding="utf-8")
    assert log.count("Traceback (most recent call last):") == 3
    assert log.count(f"=== {no_room} planner ripplefront seed 0 episode ") == 3
    assert "LevelError: " in log
    table = rows(out)
    errors = [row for row in table if row["level_file"] == str(no_room)]
    assert [row["outcome"] for row in errors] == ["error"] * 3
    for row in errors:
        assert row["error"] == f"LevelError: {no_room}: no cell where the guard fits; nothing to cover"
        assert row["steps"] == row["t90"] == row["start_col"] == ""
    assert [row["outcome"] for row in table if row["level_file"] == str(hole)] == ["covered"] * 3
    assert f"guardsim: error: 3 episodes raised an error; tracebacks in {out / 'errors.log'}" in result.stderr
    groups = json.loads((out / "summary.json").read_text(encoding="utf-8"))["groups"]
    (failed,) = (group for group in groups if group["level_file"] == str(no_room))
    assert failed["outcomes"]["error"] == 3
    assert failed["steps"] is None


def test_resume_retries_the_episodes_that_raised(tmp_path: Path) -> None:
    """Run again, the episodes that raised run again (and only they): their old rows are replaced, not
    duplicated, and once the level is fixed the resumed run exits 0."""
    level = write_level(tmp_path, NO_ROOM, "room.json")
    hole = write_level(tmp_path, SQUARE_WITH_HOLE, "hole.json")
    out = tmp_path / "out"
    assert bench(level, hole, "--episodes", "2", "--workers", "1", "--out", out).exit_code == 3
    again = bench(level, hole, "--episodes", "2", "--workers", "1", "--out", out)
    assert again.exit_code == 3
    assert "running 2 of 4 episodes" in again.stderr
    assert len(rows(out)) == 4
    assert (out / "errors.log").read_text(encoding="utf-8").count("Traceback") == 4
    # A fixed level is another file digest, so another run: the retry proper is within one batch's options.
    table = rows(out)
    assert sorted(row["outcome"] for row in table) == ["covered", "covered", "error", "error"]


def test_resume_after_a_half_written_line(tmp_path: Path, tiny_levels: list[Path]) -> None:
    """A results file cut mid-row (a killed run): the cut row goes, only the missing episodes run again."""
    out = tmp_path / "out"
    command = (*tiny_levels, "--episodes", "4", "--workers", "1", "--out", out)
    assert bench(*command).exit_code == 0
    full = rows(out)
    lines = (out / "results.csv").read_text(encoding="utf-8").splitlines(keepends=True)
    (out / "results.csv").write_text("".join(lines[:4]) + lines[4][:10], encoding="utf-8")
    resumed = bench(*command)
    assert resumed.exit_code == 0, resumed.output
    assert "running 5 of 8 episodes" in resumed.stderr
    assert "(3 already done)" in resumed.stderr
    after = rows(out)
    assert without_seconds(after) == without_seconds(full)
    assert after[:3] == full[:3]  # kept as written, wall time included: those episodes did not run again
    again = bench(*command)
    assert again.exit_code == 0
    assert "all 8 episodes already done" in again.stderr
    assert rows(out) == after


@pytest.mark.parametrize(
    ("changed_option", "fragment"),
    [(("--seed", "1"), "seed: 0 there, 1 here"), (("--max-steps", "5"), "max_steps: null there, 5 here")],
    ids=["seed", "max-steps"],
)
def test_resume_refuses_a_folder_of_other_options(
    tmp_path: Path, tiny_levels: list[Path], changed_option: tuple[str, str], fragment: str
) -> None:
    """The same --out with other options is a one-line error naming run.json and the first difference."""
    out = tmp_path / "out"
    assert bench(tiny_levels[0], "--episodes", "2", "--workers", "1", "--out", out).exit_code == 0
    before = (out / "results.csv").read_bytes()
    result = bench(tiny_levels[0], "--episodes", "2", "--workers", "1", "--out", out, *changed_option)
    line = assert_one_line_error(result, out / RUN_NAME)
    assert fragment in line
    assert (out / "results.csv").read_bytes() == before


def test_resume_refuses_a_changed_level_file(tmp_path: Path) -> None:
    """Editing a level between runs changes its digest in run.json: refused rather than mixed."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    out = tmp_path / "out"
    assert bench(level, "--episodes", "2", "--workers", "1", "--out", out).exit_code == 0
    write_level(tmp_path, {**SQUARE_WITH_HOLE, "name": "renamed"})
    line = assert_one_line_error(bench(level, "--episodes", "2", "--workers", "1", "--out", out), out / RUN_NAME)
    assert "levels:" in line


def test_bad_inputs_are_one_line_errors(tmp_path: Path) -> None:
    """Unknown planner, bad level, --workers with --scheduler, --out a file, a corrupt results file."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    out = tmp_path / "out"
    assert "'nope'; known: ripplefront" in assert_one_line_error(
        bench(level, "--planner", "ripplefront,nope", "--out", out), "--planner"
    )
    bad = write_level(tmp_path, {**SQUARE_WITH_HOLE, "cell_size": -1}, "bad.json")
    assert "cell_size: must be positive" in assert_one_line_error(bench(level, bad, "--out", out), bad)
    assert_one_line_error(
        bench(level, "--workers", "2", "--scheduler", "tcp://127.0.0.1:8786", "--out", out), "--scheduler"
    )
    a_file = tmp_path / "a-file"
    a_file.write_text("", encoding="utf-8")
    assert "is not a folder" in assert_one_line_error(bench(level, "--out", a_file), a_file)
    assert not out.exists()  # nothing was written by the refused commands
    assert bench(level, "--episodes", "2", "--workers", "1", "--out", out).exit_code == 0
    results = out / "results.csv"
    results.write_text(results.read_text(encoding="utf-8").replace(",covered,", ",covered,x", 1), encoding="utf-8")
    line = assert_one_line_error(bench(level, "--episodes", "2", "--workers", "1", "--out", out), results)
    assert "line 2: t50 is not a number" in line
    usage = bench(level, "--episodes", "0")
    assert usage.exit_code == 2
    assert usage.stderr.splitlines() == [
        "guardsim: error: Invalid value for '--episodes': 0 is not in the range 1<=x<=1000000. (see guardsim bench --help)"
    ]


def test_play_episode_reproduces_a_bench_row(tmp_path: Path) -> None:
    """`play --seed S --episode K` gives the trace of bench's episode K: same start, steps and T-values."""
    out = tmp_path / "out"
    assert bench(SQUARE, "--episodes", "3", "--seed", "11", "--workers", "1", "--out", out).exit_code == 0
    row = rows(out)[2]
    trace_path = tmp_path / "episode.json"
    played = CliRunner().invoke(
        main, ["play", str(SQUARE), "--seed", "11", "--episode", "2", "--trace", str(trace_path)]
    )
    assert played.exit_code == 0, played.output
    text = trace_path.read_text(encoding="utf-8")
    assert text == run_episode(Scene.from_level(load_level(SQUARE)), seed=11, episode=2).to_json()
    trace = Trace.from_data(json.loads(text))
    assert (str(trace.start[0]), str(trace.start[1])) == (row["start_col"], row["start_row"])
    assert (str(trace.steps), trace.outcome, str(trace.reachable)) == (row["steps"], row["outcome"], row["reachable"])
    assert [str(trace.steps_to_fraction(f)) for f in (0.5, 0.9, 0.99)] == [row["t50"], row["t90"], row["t99"]]


def test_plot_files_decode(tmp_path: Path, tiny_levels: list[Path]) -> None:
    """--plot writes a PNG that decodes and an SVG that parses, with each box's median written on it."""
    out = tmp_path / "out"
    result = bench(*tiny_levels, "--episodes", "4", "--workers", "1", "--plot", "--out", out)
    assert result.exit_code == 0, result.output
    image = iio.imread(out / "steps.png")
    assert image.ndim == 3
    assert image.shape[0] > 200
    assert image.shape[1] > 200
    texts = svg_texts(out / "steps.svg")
    for group in json.loads((out / "summary.json").read_text(encoding="utf-8"))["groups"]:
        assert f"{group['steps']['median']:g}" in texts
        assert group["level"] in texts


def svg_texts(path: Path) -> list[str]:
    """Every text of an SVG (which must parse as XML)."""
    return [text.strip() for text in ElementTree.parse(path).getroot().itertext() if text.strip()]


def test_plot_one_box_per_planner_with_a_legend(tmp_path: Path) -> None:
    """With two planners each level gets two boxes and two medians, and a legend names the planners."""
    boxes = [
        StepsBox("A", "first", [10, 12, 14]),
        StepsBox("A", "second", [20, 21, 22, 23]),
        StepsBox("B", "first", [5, 7]),
        StepsBox("B", "second", [30]),
    ]
    targets = [tmp_path / "boxes.svg", tmp_path / "boxes.png"]
    figure = plot_steps(boxes, targets)
    (axes,) = figure.axes
    labels = sorted((round(float(text.xy[0]), 3), float(text.xy[1]), text.get_text()) for text in axes.texts)
    # Level A at x = 0 and B at x = 1; within a level the first planner's box left of the second's; each
    # median written at its box's median.
    assert labels == [(-0.2, 12, "12"), (0.2, 21.5, "21.5"), (0.8, 6, "6"), (1.2, 30, "30")]
    assert axes.get_xlim()[0] < -0.2 < 1.2 < axes.get_xlim()[1]
    assert axes.get_yscale() == "linear"  # medians at most 5x apart
    far_apart = plot_steps([StepsBox("A", "fast", [10, 11]), StepsBox("A", "slow", [3000, 3100])], [])
    assert far_apart.axes[0].get_yscale() == "log"
    texts = svg_texts(targets[0])
    for expected in ("12", "21.5", "6", "30", "first", "second", "A", "B"):
        assert expected in texts
    first = [target.read_bytes() for target in targets]
    plot_steps(boxes, targets)
    assert [target.read_bytes() for target in targets] == first  # no timestamps: same data, same bytes


class Terminal(io.StringIO):
    """A text stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def test_progress_line_only_on_a_terminal() -> None:
    """The progress line shows done/total, rate and time left on a terminal, and nothing elsewhere."""
    terminal, pipe = Terminal(), io.StringIO()
    for stream in (terminal, pipe):
        progress = ProgressLine(3, stream)
        for _ in range(3):
            time.sleep(0.01)
            progress.advance(None)  # type: ignore[arg-type]
        progress.close()
    assert pipe.getvalue() == ""
    last = terminal.getvalue().rstrip("\n").split("\r")[-1]
    assert last.startswith("3/3 episodes ")
    assert "/s" in last
    assert "0s left" in last
    assert terminal.getvalue().endswith("\n")


def kill_own_process(item: int) -> int:
    """Work that kills its own worker process on item 3 (module-level, so workers can import it)."""
    if item == 3:
        os.kill(os.getpid(), signal.SIGKILL)
    return item * 10


def test_local_pool_reports_a_killed_worker_as_failures() -> None:
    """A worker killed mid-item breaks the pool: each unfinished item comes back as a failure, none hangs."""
    with LocalPool(2) as pool:
        completions = list(pool.run_unordered(kill_own_process, range(12)))
    assert sorted(completion.item for completion in completions) == list(range(12))
    failed = [completion for completion in completions if completion.failure is not None]
    assert 3 in {completion.item for completion in failed}
    assert all(completion.result == completion.item * 10 for completion in completions if completion not in failed)


def start_bench(out: Path, *args: str) -> subprocess.Popen[str]:
    """Start the real `guardsim bench` on the shipped square with two workers, in its own process group."""
    return subprocess.Popen(
        [*guardsim_command(), "bench", str(SQUARE), "--out", str(out), "--workers", "2", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        # As from a terminal: a test run started in the background of a shell without job control (as
        # `(bash .ci/run &)`) ignores SIGINT, and a child would inherit that and never see the Ctrl-C.
        preexec_fn=_default_sigint,
    )


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def wait_for_rows(process: subprocess.Popen[str], results: Path, count: int) -> None:
    """Wait until ``results`` holds ``count`` rows (the run is under way)."""
    deadline = time.monotonic() + 60
    while not results.exists() or results.read_text(encoding="utf-8").count("\n") <= count:
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.01)


@pytest.mark.slow  # 7-12 s: the README command stays under 5 minutes; CI runs the slow tier
def test_interrupted_run_resumes(tmp_path: Path) -> None:
    """Ctrl-C mid-run (SIGINT to the whole process group, as a terminal sends it): status 130, one line,
    complete rows kept; the same command then runs only the rest."""
    out = tmp_path / "out"
    process = start_bench(out, "--episodes", "1000")
    wait_for_rows(process, out / "results.csv", 5)
    os.killpg(process.pid, signal.SIGINT)
    stdout, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    last = stderr.splitlines()[-1]
    assert last.startswith("guardsim: interrupted; ")
    assert "run the same command again to resume" in last
    assert "Traceback" not in stderr
    assert stdout == ""
    kept = read_results(out / "results.csv")
    assert 5 <= len(kept) < 1000
    assert f"{len(kept)} of 1000 episodes are in" in last
    resumed = bench(SQUARE, "--out", out, "--workers", "1", "--episodes", "1000")
    assert resumed.exit_code == 0, resumed.output
    assert f"({len(kept)} already done)" in resumed.stderr
    final = read_results(out / "results.csv")
    assert [record.episode for record in final] == list(range(1000))
    assert set(kept) <= set(final)  # the interrupted run's rows, wall time included, were not redone


@pytest.mark.slow
def test_killed_worker_run_resumes(tmp_path: Path) -> None:
    """SIGKILL to one pool worker: status 1, a line saying how many did not run; the same command finishes."""
    out = tmp_path / "out"
    process = start_bench(out, "--episodes", "1000")
    wait_for_rows(process, out / "results.csv", 3)
    children = psutil.Process(process.pid).children(recursive=True)
    # Forked by the fork server, or (start method fork) the command's own children.
    workers = [child for child in children if child.ppid() != process.pid] or children
    assert workers, children
    workers[0].kill()
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 1, stderr
    last = stderr.splitlines()[-1]
    assert "episodes did not run (BrokenProcessPool" in last
    assert last.endswith("run the same command again to resume")
    kept = read_results(out / "results.csv")
    resumed = bench(SQUARE, "--out", out, "--workers", "1", "--episodes", "1000")
    assert resumed.exit_code == 0, resumed.output
    assert f"({len(kept)} already done)" in resumed.stderr
    assert [record.episode for record in read_results(out / "results.csv")] == list(range(1000))


def test_records_round_trip_through_csv_fields() -> None:
    """A record with empty fields survives to_row/from_row."""
    record = EpisodeRecord("L", "l.json", "ripplefront", 1, 0, 4, None, None, None, None, None, "error", None, None,
                           None, None, None, None, None, 0.25, None, "ValueError: boom")  # fmt: skip
    assert EpisodeRecord.from_row(record.to_row()) == record


def test_reference_gives_the_fast_path_rows(tmp_path: Path, tiny_levels: list[Path]) -> None:
    """--reference (per-cell rays, the planner's own loop) and the default fast path record the same episodes."""
    fast = bench(*tiny_levels, "--episodes", "3", "--workers", "1", "--out", tmp_path / "fast")
    slow = bench(*tiny_levels, "--episodes", "3", "--workers", "1", "--reference", "--out", tmp_path / "slow")
    assert fast.exit_code == slow.exit_code == 0, fast.output + slow.output
    assert without_seconds(rows(tmp_path / "fast")) == without_seconds(rows(tmp_path / "slow"))
    assert json.loads((tmp_path / "slow" / RUN_NAME).read_text(encoding="utf-8"))["reference"] is True


def test_second_run_on_a_busy_folder_is_refused(tmp_path: Path) -> None:
    """While one bench appends to a folder, a second one on the same folder is a one-line error."""
    out = tmp_path / "out"
    process = start_bench(out, "--episodes", "1000")
    try:
        wait_for_rows(process, out / "results.csv", 1)
        second = bench(SQUARE, "--episodes", "1000", "--workers", "1", "--out", out)
        assert "another guardsim bench is writing to this folder" in assert_one_line_error(second, out / "results.csv")
    finally:
        os.killpg(process.pid, signal.SIGINT)
        process.communicate(timeout=60)


def test_several_planners_are_grouped_per_level_and_planner(tmp_path: Path, tiny_levels: list[Path]) -> None:
    """--planner a,b: rows, summary groups and table lines per (level, planner); the plot has both."""
    out = tmp_path / "out"
    result = bench(*tiny_levels, "--episodes", "3", "--planner", "tour,ripplefront", "--workers", "1", "--plot",
                   "--out", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    table = rows(out)
    keys = [(row["level_file"], row["planner"], row["episode"]) for row in table]
    assert keys == sorted(keys)
    assert {row["planner"] for row in table} == {"ripplefront", "tour"}
    groups = json.loads((out / "summary.json").read_text(encoding="utf-8"))["groups"]
    # In level file order (hole.json, l.json), then planner name order.
    assert [(group["level"], group["planner"]) for group in groups] == [
        ("square with hole", "ripplefront"), ("square with hole", "tour"), ("L room", "ripplefront"), ("L room", "tour")
    ]  # fmt: skip
    assert json.loads((out / RUN_NAME).read_text(encoding="utf-8"))["planners"] == ["ripplefront", "tour"]
    assert len(result.stdout.splitlines()) == 5
    texts = svg_texts(out / "steps.svg")
    assert "ripplefront" in texts
    assert "tour" in texts


def test_a_run_folder_with_an_option_set_only_one_side_says_both_values() -> None:
    """Reusing a continuous run's folder for a grid run names the option and both sides' values."""
    from guardsim.experiment.results import _difference

    assert _difference({"motion": "continuous", "seed": 0}, {"seed": 0}) == '"continuous" there, not set here'.join(
        ["motion: ", ""]
    )
    assert _difference({"seed": 0}, {"seed": 0, "tick_hz": 30}) == "tick_hz: not set there, 30 here"
