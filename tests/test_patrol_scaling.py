"""Patrols on big maps: the quick leg, prune and idleness kernels give exactly what the plain definitions
give; a team never gets an empty loop; large levels take the scalable path and still see the goal each
lap; long commands say where they are (plain lines off a terminal, one redrawn line on one)."""

from __future__ import annotations

import io
import itertools
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from guardsim.grid import cell_of_state, heading_of_state, state_of
from guardsim.kernels.distances import FAR, distances_from
from guardsim.patrol import patrol_setup, plan_loop, score_patrol
from guardsim.patrol.loops import LoopBuilder
from guardsim.patrol.plan import LARGE_CELLS, auto_sources, is_large
from guardsim.patrol.scoring import NEVER, score_timeline, seen_timeline
from tests.common import TINY_LEVELS, run, scene_from, tiny_levels, write_level


def _full_field_path(builder: LoopBuilder, start: int, target: int) -> list[int]:
    """The leg by the definition: a whole breadth-first field from the target's entry cell, walked down."""
    entry = int(builder.table.entry[target])
    field = distances_from(builder.neighbours, np.array([entry], dtype=np.int64))
    cell, heading = int(cell_of_state(start)), int(heading_of_state(start))
    assert field[cell] < FAR
    states = []
    while cell != entry:
        for direction in (heading, 0, 1, 2, 3):
            other = int(builder.neighbours[cell, direction])
            if other >= 0 and field[other] == field[cell] - 1:
                cell, heading = other, direction
                break
        states.append(int(state_of(cell, heading)))
    return [*states, target]


def _walked_prune(builder: LoopBuilder, order: np.ndarray) -> np.ndarray:
    """Pruning by the definition: walk the whole lap without each viewpoint (latest first) and look."""
    keep = list(order.tolist())
    for state in reversed(order.tolist()):
        if len(keep) <= 1:
            break
        trial = [other for other in keep if other != state]
        if builder.lap_sees_goal(builder.walk(np.asarray(trial, dtype=np.int64))):
            keep = trial
    return np.asarray(keep, dtype=np.int64)


@tiny_levels
def test_a_leg_is_the_walk_down_the_whole_field(level_data: dict[str, Any]) -> None:
    scene = scene_from(level_data)
    setup = patrol_setup(scene)
    builder = LoopBuilder(scene.grid, setup.table, setup.goal)
    # States of the goal's component (split-rooms has two), arrivable from inside it.
    arrivable = np.flatnonzero((setup.table.entry >= 0) & np.repeat(setup.goal, 4))
    picks = arrivable[np.random.default_rng(0).choice(arrivable.size, size=min(12, arrivable.size), replace=False)]
    for start, target in itertools.product(picks.tolist(), repeat=2):
        assert builder.path(start, target) == _full_field_path(builder, start, target)


@tiny_levels
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_counted_pruning_drops_what_walking_the_lap_drops(level_data: dict[str, Any], seed: int) -> None:
    scene = scene_from(level_data)
    setup = patrol_setup(scene)
    builder = LoopBuilder(scene.grid, setup.table, setup.goal)
    viewpoints = builder.cover_viewpoints()
    # Extra viewpoints in a shuffled order, so that many of them can be dropped, some only thanks to legs.
    arrivable = np.flatnonzero((setup.table.entry >= 0) & np.repeat(setup.goal, 4))
    rng = np.random.default_rng(seed)
    extra = rng.choice(arrivable, size=min(20, arrivable.size), replace=False)
    order = np.unique(np.concatenate([viewpoints, extra]))
    order = order[rng.permutation(order.size)]
    assert np.array_equal(builder._prune(order), _walked_prune(builder, order))


def _timeline_score(timeline: np.ndarray, goal: np.ndarray, *, periodic: bool, warmup: int) -> tuple[Any, ...]:
    """Idleness by the definition: walk every tick of every cell."""
    ticks, cells = timeline.shape
    total = 2 * ticks if periodic else ticks
    start = ticks if periodic else warmup
    last = np.zeros(cells, dtype=np.int64)
    worst = np.zeros(cells, dtype=np.int64)
    summed = 0
    for tick in range(total):
        last[timeline[tick % ticks]] = tick
        idle = tick - last
        if tick >= start:
            summed += int(idle[goal].sum())
            worst = np.maximum(worst, idle)
    if periodic:
        worst[goal & ~timeline.any(axis=0)] = NEVER
    worst[~goal] = -2
    return worst.tolist(), summed


@pytest.mark.parametrize("periodic", [True, False], ids=["lap", "walked"])
@pytest.mark.parametrize("seed", range(4))
def test_settled_idleness_is_the_tick_by_tick_idleness(periodic: bool, seed: int) -> None:
    rng = np.random.default_rng(seed)
    timeline = rng.random((int(rng.integers(3, 40)), 30)) < rng.uniform(0.02, 0.4)
    timeline[:, 3] = False  # a cell never seen
    goal = rng.random(30) < 0.8
    if periodic:
        goal[3] = bool(seed % 2)
    warmup = 0 if periodic else int(rng.integers(0, timeline.shape[0]))
    score = score_timeline(timeline, goal, periodic=periodic, warmup=warmup)
    worst, summed = _timeline_score(timeline, goal, periodic=periodic, warmup=warmup)
    assert score.worst_gap.tolist() == worst
    if score.mean_idleness is not None:
        scored = timeline.shape[0] - warmup
        assert score.mean_idleness == summed / (int(goal.sum()) * scored)


@tiny_levels
def test_a_patrol_scores_as_its_seen_timeline(level_data: dict[str, Any]) -> None:
    scene = scene_from(level_data)
    setup = patrol_setup(scene, 2)
    patrol = plan_loop(setup, 2, planner="cover")[0].patrol
    timeline = seen_timeline(setup.table, patrol.states, setup.goal.size)
    direct, replayed = (
        score_patrol(setup.table, patrol, setup.goal),
        score_timeline(timeline, setup.goal, periodic=True),
    )
    assert direct.worst_gap.tolist() == replayed.worst_gap.tolist()
    assert (direct.worst_idleness, direct.mean_idleness) == (replayed.worst_idleness, replayed.mean_idleness)


def test_more_guards_than_ticks_never_leaves_a_guard_without_a_loop() -> None:
    scene = scene_from(TINY_LEVELS["empty-square"])
    setup = patrol_setup(scene, 32)
    plan, scores = plan_loop(setup, 32, planner="cover")
    assert plan.patrol.guards == 32 and set(scores) == {"shared", "split"}
    assert plan.score.worst_idleness is not None


#: An open 61 x 61 room with a pillar: just over the large-level threshold.
BIG_ROOM = {
    "name": "big-room",
    "outer": [[0, 0], [61, 0], [61, 61], [0, 61]],
    "holes": [[[20, 20], [40, 20], [40, 24], [20, 24]]],
    "cell_size": 1.0,
    "guard": {"fov_degrees": 90, "view_range": 8},
}


def test_a_large_level_takes_the_scalable_path_and_each_lap_sees_the_goal() -> None:
    scene = scene_from(BIG_ROOM)
    assert scene.grid.size > LARGE_CELLS
    setup = patrol_setup(scene)
    assert is_large(setup) and auto_sources(setup) == ("cover", "frontier")
    plan = plan_loop(setup, 1)[0]
    assert plan.patrol.planner in ("cover", "frontier")
    seen = np.zeros(setup.goal.size, dtype=bool)
    for state in plan.patrol.states[0].tolist():
        seen[setup.table.sees(state)] = True
    assert seen[setup.goal].all() and plan.score.worst_idleness is not None
    assert plan.patrol.period is not None and plan.score.worst_idleness < plan.patrol.period


def test_patrol_says_where_it_is_off_a_terminal(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from guardsim.cli import progress

    monkeypatch.setattr(progress, "QUIET_SECONDS", 0.0)
    monkeypatch.setenv("GUARDSIM_PROGRESS", "1")
    level = write_level(tmp_path, TINY_LEVELS["square-with-hole"])
    result = run("patrol", level, "--out", tmp_path / "o")
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    assert lines and all(line.startswith("guardsim: patrol: ") for line in lines)
    assert any("view table" in line for line in lines) and "\r" not in result.stderr
    assert "loop patrol" in result.stdout.splitlines()[-1]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_stage_line_redraws_in_place_on_a_terminal_and_ends_its_line(monkeypatch: pytest.MonkeyPatch) -> None:
    from guardsim.cli import progress

    monkeypatch.setattr(progress, "QUIET_SECONDS", 0.0)
    monkeypatch.setattr(progress, "REDRAW_SECONDS", 0.0)
    monkeypatch.setenv("GUARDSIM_PROGRESS", "1")
    stream = _Terminal()
    with progress.StageLine(stream, "patrol") as tell:
        tell("view table", 0, 0)
        tell("loop from cover viewpoints", 1, 2)
    text = stream.getvalue()
    assert text.startswith("\rguardsim: patrol: ") and text.endswith("\n") and text.count("\n") == 1
    assert "loop from cover viewpoints 1/2" in text


def test_a_quick_job_prints_no_progress(monkeypatch: pytest.MonkeyPatch) -> None:
    from guardsim.cli.progress import StageLine

    monkeypatch.setenv("GUARDSIM_PROGRESS", "1")
    stream = io.StringIO()
    with StageLine(stream, "patrol") as tell:
        tell("view table", 0, 0)
    assert stream.getvalue() == ""


def test_a_patrol_over_its_memory_budget_is_refused_up_front(tmp_path: Path) -> None:
    level = write_level(tmp_path, TINY_LEVELS["square-with-hole"])
    result = run("patrol", level, "--out", tmp_path / "o", "--memory-mb", "64")
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and "over the budget of 64 MB" in lines[0] and "raise it with --memory-mb" in lines[0]
    assert not (tmp_path / "o" / "patrol.json").exists()


@tiny_levels
def test_distances_between_stopping_early_are_the_whole_fields(
    level_data: dict[str, Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Also with the sources searched in two halves at once (as on a big map)."""
    import guardsim.kernels.distances as distances_module
    from guardsim.kernels.distances import distance_fields, distances_between

    neighbours = scene_from(level_data).grid.neighbours
    rng = np.random.default_rng(3)
    cells = np.arange(neighbours.shape[0])
    for split in (False, True):
        monkeypatch.setattr(distances_module, "SPLIT_BETWEEN_WORK", 0 if split else 20_000_000)
        for size in (1, 3, 12):
            sources, targets = rng.choice(cells, size=size), rng.choice(cells, size=size + 2)
            whole = distance_fields(neighbours, sources)[:, targets]
            assert np.array_equal(distances_between(neighbours, sources, targets), whole)
