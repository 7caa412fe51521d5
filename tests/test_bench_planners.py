"""``guardsim bench`` comparing planners: lower bounds beside every episode, teams, the Bresenham sight rule.

Every episode runs for real through the command (in this process, ``--workers 1``, so that the scene
cache of :mod:`guardsim.experiment.episodes` is shared between runs with different vision options), and
rows are checked against episodes and bounds computed directly.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from guardsim import load_level
from guardsim.bounds import lower_bounds
from guardsim.cli.common import build_scene
from guardsim.experiment import RUN_NAME
from guardsim.level import HEADINGS
from guardsim.motion import run_episode
from guardsim.planners import PLANNERS
from tests.common import (
    LEVELS,
    SQUARE,
    SQUARE_WITH_HOLE,
    assert_one_line_error,
    bench,
    rows,
    without_seconds,
    write_level,
)

ALL_PLANNERS = ",".join(PLANNERS)
BOUND_COLUMNS = ("best_bound", "eccentricity_bound", "cluster_bound")

#: The bench comparison of every planner on every shipped level: the slow tier (`pytest -m slow`).
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def shipped_comparison(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """Three episodes of every planner on every shipped level: the output folder and the printed table."""
    out = tmp_path_factory.mktemp("shipped")
    result = bench(*LEVELS, "--planner", ALL_PLANNERS, "--episodes", "3", "--seed", "4", "--workers", "1", "--out", out)
    assert result.exit_code == 0, result.output
    return out, result.stdout


def test_bounds_never_exceed_any_planners_steps(shipped_comparison: tuple[Path, str]) -> None:
    """On every shipped level, every covered episode of every planner took at least the best bound; only
    random-walk may stop at the step limit, and those episodes are not covered, so not checked."""
    out, _ = shipped_comparison
    table = rows(out)
    assert len(table) == len(LEVELS) * len(PLANNERS) * 3
    checked = 0
    for row in table:
        assert row["guards"] == "1"
        best, eccentricity, cluster = (int(row[name]) for name in BOUND_COLUMNS)
        assert best >= max(eccentricity, cluster) > 0  # best also counts the path bound (issue 15)
        if row["outcome"] != "covered":
            assert (row["planner"], row["outcome"]) == ("random-walk", "step_limit"), row
            continue
        assert int(row["steps"]) >= best, row
        assert int(row["total_moves"]) <= int(row["steps"])
        assert float(row["plan_us_per_step"]) > 0
        checked += 1
    assert checked >= len(LEVELS) * (len(PLANNERS) - 1) * 3  # every episode but random-walk's is checked


def test_bound_columns_are_the_bounds_of_the_rows_start(shipped_comparison: tuple[Path, str]) -> None:
    """The bounds in a row are lower_bounds of that row's start cell and heading, the same for every
    planner (the planners share their episodes' starts)."""
    out, _ = shipped_comparison
    table = rows(out)
    path = LEVELS[0]
    scene = build_scene(load_level(path))
    for episode in ("0", "1"):
        same_start = [row for row in table if row["level_file"] == os.path.normpath(path) and row["episode"] == episode]
        assert {row["planner"] for row in same_start} == set(PLANNERS)
        starts = {(row["start_col"], row["start_row"], row["start_heading"]) for row in same_start}
        bounds = {tuple(row[name] for name in BOUND_COLUMNS) for row in same_start}
        assert len(starts) == len(bounds) == 1
        ((col, row, heading),) = starts
        expected = lower_bounds(scene, (int(col), int(row)), HEADINGS[heading] // 90)
        assert bounds == {(str(expected.best), str(expected.eccentricity), str(expected.cluster))}


def test_every_planner_gets_a_group_and_a_table_line(shipped_comparison: tuple[Path, str]) -> None:
    """summary.json has one group per level and planner, with the median ratio to the bound; so does
    the printed table."""
    out, stdout = shipped_comparison
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    groups = summary["groups"]
    assert [(group["level_file"], group["planner"]) for group in groups] == [
        (os.path.normpath(path), planner) for path in LEVELS for planner in sorted(PLANNERS)
    ]
    table = rows(out)
    for group in groups:
        members = [
            row for row in table if (row["level_file"], row["planner"]) == (group["level_file"], group["planner"])
        ]
        ratios = sorted(int(row["steps"]) / int(row["best_bound"]) for row in members)
        assert group["bound_ratio"]["median"] == pytest.approx(ratios[1], abs=1e-3)
        assert group["bound_ratio"]["min"] == pytest.approx(ratios[0], abs=1e-3)
        assert group["bound_ratio"]["median"] >= 1
    lines = stdout.splitlines()
    assert "steps/bound med" in lines[0]
    assert "moves med" not in lines[0]
    assert len(lines) == 1 + len(groups)
    assert {line.split()[-1] for line in lines[1:]} == {f"{group['bound_ratio']['median']:.2f}" for group in groups}


def test_two_planners_write_both_groups(tmp_path: Path) -> None:
    """--planner ripplefront,tour: both planners' rows, groups and table lines, from the same starts."""
    out = tmp_path / "out"
    result = bench(SQUARE, "--planner", "ripplefront,tour", "--episodes", "3", "--workers", "1", "--out", out)
    assert result.exit_code == 0, result.output
    table = rows(out)
    assert [(row["planner"], row["episode"]) for row in table] == [
        (planner, str(episode)) for planner in ("ripplefront", "tour") for episode in range(3)
    ]
    starts = {planner: [(row["start_col"], row["start_row"], row["start_heading"]) for row in table if row["planner"] == planner]
              for planner in ("ripplefront", "tour")}  # fmt: skip
    assert starts["ripplefront"] == starts["tour"]
    groups = json.loads((out / "summary.json").read_text(encoding="utf-8"))["groups"]
    assert [group["planner"] for group in groups] == ["ripplefront", "tour"]
    assert [line.split()[1] for line in result.stdout.splitlines()[1:]] == ["ripplefront", "tour"]


def test_team_rows_have_makespan_and_moves_but_no_bounds(tmp_path: Path) -> None:
    """--guards 2: each row is run_episode(guards=2): steps are the makespan, total_moves the sum over
    both guards; bound columns are empty (they bound one guard, not a team); resume with another team
    size is refused."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    out = tmp_path / "out"
    options = ("--planner", "ripplefront,tour", "--episodes", "3", "--workers", "1", "--out", out)
    result = bench(level, "--guards", "2", *options)
    assert result.exit_code == 0, result.output
    scene = build_scene(load_level(level))
    for row in rows(out):
        trace = run_episode(scene, seed=0, episode=int(row["episode"]), planner=row["planner"], guards=2)
        assert trace.guards == 2
        assert row["guards"] == "2"
        assert (int(row["steps"]), int(row["total_moves"]), row["outcome"]) == (
            trace.steps,
            trace.total_moves,
            "covered",
        )
        assert (int(row["start_col"]), int(row["start_row"])) == trace.start
        assert [row[name] for name in BOUND_COLUMNS] == ["", "", ""]
        assert int(row["steps"]) <= int(row["total_moves"]) <= 2 * int(row["steps"])
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["run"]["guards"] == 2
    assert all(group["guards"] == 2 and group["bound_ratio"] is None for group in summary["groups"])
    assert all(group["total_moves"]["count"] == 3 for group in summary["groups"])
    header = result.stdout.splitlines()[0]
    assert header.split()[-2:] == ["moves", "med"]
    line = assert_one_line_error(bench(level, "--guards", "1", *options), out / RUN_NAME)
    assert "guards: 2 there, 1 here" in line


#: Vision options of the runs below, by output folder: the default, the same 360-degree guard with pymunk
#: rays and with Bresenham lines (the two rules differ on some states of this level), and the grid
#: solvers' rule with its unlimited range.
VISIONS = {
    "default": {},
    "pymunk-360": {"los": "pymunk", "fov": 360.0, "view_range": 8.0},
    "bresenham-360": {"los": "bresenham", "fov": 360.0, "view_range": 8.0},
    "bresenham-360-unlimited": {"los": "bresenham", "fov": 360.0},
}


def vision_arguments(vision: dict[str, object]) -> list[str]:
    """The command-line options of a vision dictionary: ``{"view_range": 8.0}`` -> ``--view-range 8``."""
    arguments = []
    for name, value in vision.items():
        arguments += [f"--{name.replace('_', '-')}", f"{value:g}" if isinstance(value, float) else str(value)]
    return arguments


def test_bresenham_360_rows_use_that_vision(tmp_path: Path) -> None:
    """Runs with different vision options on one level, one after the other in this process: each run's
    rows and bounds are those of its own vision (the scene cache keys on it, line of sight included),
    and run.json records it."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    common = ("--planner", "ripplefront,frontier", "--episodes", "4", "--workers", "1")
    for name, vision in VISIONS.items():
        result = bench(level, *common, *vision_arguments(vision), "--out", tmp_path / name)
        assert result.exit_code == 0, result.output
        scene = build_scene(load_level(level), **vision)  # type: ignore[arg-type]
        for row in rows(tmp_path / name):
            trace = run_episode(scene, seed=0, episode=int(row["episode"]), planner=row["planner"])
            bounds = lower_bounds(scene, trace.start, trace.headings[0])
            assert (int(row["steps"]), row["outcome"]) == (trace.steps, "covered"), (name, row)
            assert int(row["t90"]) == trace.steps_to_fraction(0.9)
            assert [int(row[column]) for column in BOUND_COLUMNS] == [bounds.best, bounds.eccentricity, bounds.cluster]
    steps = {name: [row["steps"] for row in rows(tmp_path / name)] for name in VISIONS}
    assert steps["pymunk-360"] != steps["bresenham-360"]  # so the check above tells the two rules apart
    run = json.loads((tmp_path / "bresenham-360-unlimited" / RUN_NAME).read_text(encoding="utf-8"))
    assert (run["los"], run["fov"], run["view_range"]) == ("bresenham", 360.0, None)
    grid = tmp_path / "bresenham-360-unlimited"
    line = assert_one_line_error(bench(level, *common, "--los", "bresenham", "--out", grid), grid / RUN_NAME)
    assert "fov: 360.0 there, null here" in line


def test_bresenham_rows_same_for_one_and_two_workers(tmp_path: Path) -> None:
    """With --los bresenham and a team, a process pool writes the rows of one process (wall time aside)."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    options = ("--planner", "random-walk,tour", "--episodes", "4", "--los", "bresenham", "--fov", "360")
    for guards in ("1", "2"):
        one = bench(level, *options, "--guards", guards, "--workers", "1", "--out", tmp_path / f"one{guards}")
        two = bench(level, *options, "--guards", guards, "--workers", "2", "--out", tmp_path / f"two{guards}")
        assert one.exit_code == two.exit_code == 0, one.output + two.output
        assert without_seconds(rows(tmp_path / f"one{guards}")) == without_seconds(rows(tmp_path / f"two{guards}"))
        assert one.stdout == two.stdout


def test_no_bounds_leaves_the_bound_columns_empty_and_is_part_of_the_run(tmp_path: Path) -> None:
    """--no-bounds: the same steps as with bounds, empty bound columns, and resuming with bounds is refused."""
    options = ("--episodes", "3", "--workers", "1")
    with_bounds = bench(SQUARE, *options, "--out", tmp_path / "with")
    without = bench(SQUARE, *options, "--no-bounds", "--out", tmp_path / "without")
    assert with_bounds.exit_code == 0 and without.exit_code == 0, with_bounds.output + without.output
    bound_columns = ("best_bound", "eccentricity_bound", "cluster_bound")
    assert all(row[column] for row in rows(tmp_path / "with") for column in bound_columns)
    assert all(row[column] == "" for row in rows(tmp_path / "without") for column in bound_columns)
    strip = [
        {k: v for k, v in row.items() if k not in bound_columns} for row in without_seconds(rows(tmp_path / "with"))
    ]
    assert strip == [
        {k: v for k, v in row.items() if k not in bound_columns} for row in without_seconds(rows(tmp_path / "without"))
    ]
    assert json.loads((tmp_path / "without" / RUN_NAME).read_text(encoding="utf-8"))["bounds"] is False
    resumed = bench(SQUARE, *options, "--out", tmp_path / "without")
    assert_one_line_error(resumed, tmp_path / "without")
