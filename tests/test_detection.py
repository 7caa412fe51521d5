"""The detection model and the undetected sneak: the meter's rule, the level keys, and the graded search
checked against a brute force over absolute time and exact meter values (no dominance pruning), each
reported path replayed through the meters apart from the search."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.detection import (
    AwarenessMeter,
    DetectionModel,
    GuardDetection,
    intruder_state,
    patrol_gains,
    time_to_detection,
)
from guardsim.errors import LevelError
from guardsim.kernels.meter import DETECTED, meter_after
from guardsim.level import level_to_data, parse_level
from guardsim.patrol import Patrol, patrol_setup
from guardsim.scene import Scene
from guardsim.sneak import find_sneak, sneak_check
from guardsim.sneak.grade import grade_path
from guardsim.sneak.graded import undetected_search
from guardsim.vision.table import ViewTable
from tests.common import TINY_LEVELS, TWO_ROOMS, corridor_post, random_loop, scene_from, write_level

# --- The meter ---


def test_the_meter_rises_by_the_distance_rule_and_drains_by_forget() -> None:
    model = DetectionModel(detect_near=0.5, detect_far=2.5, forget=2.0, suspicious=0.35)
    meter = AwarenessMeter(model, view_range=10.0)
    # At 5 units, half the range: 0.5 + 2.0 * 0.5 = 1.5 s to detect; a 0.3 s tick adds 0.2.
    assert meter.update(0.3, True, 5.0) == pytest.approx(0.2)
    assert not meter.suspicious
    assert meter.update(0.3, True, 5.0) == pytest.approx(0.4)
    assert meter.suspicious and not meter.detected
    # Out of sight: 0.3 s of a 2 s forget takes 0.15 off.
    assert meter.update(0.3, False) == pytest.approx(0.25)
    # Past the view range counts as the range's edge: 2.5 s, 0.12 a tick.
    assert meter.update(0.3, True, 40.0) == pytest.approx(0.37)
    # At distance 0 a tick of 0.6 s is more than the 0.5 s needed: full, and it stays within [0, 1].
    assert meter.update(0.6, True, 0.0) == 1.0 and meter.detected
    for _ in range(20):
        meter.update(0.3, False)
    assert meter.level == 0.0 and meter.detected and meter.peak == 1.0


def test_three_thirds_detect_despite_rounding() -> None:
    level = 0.0
    for _ in range(3):
        level = meter_after(level, 0.5 / 1.5, 0.1)
    assert level == 1.0 >= DETECTED


def test_zero_detection_times_are_seen_is_caught() -> None:
    model = DetectionModel(detect_near=0, detect_far=0)
    assert model.instant and model.gain(0.5, 7.9, 8.0) == math.inf
    meter = AwarenessMeter(model, 8.0)
    assert meter.update(0.01, True, 7.9) == 1.0 and meter.detected


def test_intruder_states_go_from_calm_to_caught() -> None:
    assert intruder_state([0.0], False, 0.5, False) == "unseen"
    assert intruder_state([0.1, 0.0], True, 0.5, False) == "in view"
    assert intruder_state([0.1, 0.5], False, 0.5, False) == "suspicious"
    assert intruder_state([0.0], False, 0.5, True) == "detected"


def test_a_model_refuses_negative_or_odd_numbers() -> None:
    with pytest.raises(ValueError, match="forget"):
        DetectionModel(forget=-1)
    with pytest.raises(ValueError, match="suspicious"):
        DetectionModel(suspicious=1.5)


# --- The level keys ---


def test_detection_keys_are_read_written_and_checked() -> None:
    data = TINY_LEVELS["empty-square"] | {"guard": {"detect_near": 0.1, "detect_far": 3, "forget": 0, "suspicious": 1}}
    level = parse_level(data)
    assert DetectionModel.of_guard(level.guard) == DetectionModel(0.1, 3.0, 0.0, 1.0)
    written = level_to_data(level)["guard"]
    assert {key: written[key] for key in ("detect_near", "detect_far", "forget", "suspicious")} == data["guard"]
    # Defaults are not written, so existing level files round-trip unchanged.
    assert "detect_near" not in level_to_data(parse_level(TINY_LEVELS["empty-square"]))["guard"]
    with pytest.raises(LevelError, match=r"^test.json: guard.detect_far: must be at least 0, not -1"):
        parse_level(TINY_LEVELS["empty-square"] | {"guard": {"detect_far": -1}}, source="test.json")


# --- The graded search against brute force ---


def _brute_force(
    scene: Scene,
    table: ViewTable,
    patrol: Patrol,
    detection: GuardDetection,
    source: int,
    target: int,
    entry: int | None,
) -> int | None:
    """Fastest undetected ticks from ``source`` to ``target`` (entering at lap tick ``entry``, or any):
    breadth first over (lap tick, cell, exact meters), every state kept, none pruned; sight from the view
    table and distances from the guards' cells, as a game would compute them."""
    grid = scene.grid
    period, guards, cols = patrol.period or 1, patrol.guards, grid.shape[1]
    model, fall = detection.model, detection.model.fall(detection.dt)

    def meters_after(meters: tuple[float, ...], phase: int, cell: int) -> tuple[float, ...] | None:
        out = []
        for guard in range(guards):
            state = int(patrol.states[guard, phase])
            guard_cell = state // 4
            distance = grid.cell_size * math.hypot(cell // cols - guard_cell // cols, cell % cols - guard_cell % cols)
            sees = cell in table.sees(state).tolist()
            gain = model.gain(detection.dt, distance, detection.view_range) if sees else 0.0
            level = meter_after(meters[guard], gain, fall)
            if level >= DETECTED:
                return None
            out.append(level)
        return tuple(out)

    frontier = set()
    for phase in range(period) if entry is None else [entry]:
        meters = meters_after((0.0,) * guards, phase, source)
        if meters is not None:
            frontier.add((phase, source, meters))
    visited = set(frontier)
    ticks = 0
    while frontier:
        if any(cell == target for _, cell, _ in frontier):
            return ticks
        upcoming = set()
        for phase, cell, meters in frontier:
            after = (phase + 1) % period
            for other in [cell, *[int(o) for o in grid.neighbours[cell] if o >= 0]]:
                stepped = meters_after(meters, after, other)
                if stepped is not None and (after, other, stepped) not in visited:
                    visited.add((after, other, stepped))
                    upcoming.add((after, other, stepped))
        if len(visited) > BRUTE_FORCE_STATES:
            raise _TooMany
        frontier = upcoming
        ticks += 1
    return None


MODELS = [
    DetectionModel(),
    DetectionModel(detect_near=0.25, detect_far=1.0, forget=1.0),
    DetectionModel(detect_near=0.6, detect_far=2.0, forget=8.0),
]
#: Models for the brute force: two whose gains do not depend on distance (their meters stay on a small
#: lattice of values, so every state can be kept) and one that does.
LATTICE_MODELS = [
    DetectionModel(detect_near=1.0, detect_far=1.0, forget=2.0),
    DetectionModel(detect_near=0.75, detect_far=0.75, forget=1.0),
    DetectionModel(detect_near=0.5, detect_far=1.5, forget=1.0),
]
#: States the brute force keeps before it gives a case up (irrational distances make many meter values).
BRUTE_FORCE_STATES = 200_000


class _TooMany(Exception):
    pass


@pytest.mark.parametrize("name", ["square-with-hole", "l-room", "empty-square"])
def test_the_undetected_search_agrees_with_brute_force(name: str) -> None:
    """Both directions: every path it reports replays undetected and is as fast as brute force's; when it
    reports none, brute force finds none. The slack counts the entry ticks brute force gets through from."""
    guard = {"start": [0.5, 0.5], "heading": "right", "view_range": 3.5, "fov_degrees": 180}
    scene = scene_from(TINY_LEVELS[name] | {"guard": guard})
    setup = patrol_setup(scene)
    rng = np.random.default_rng(11)
    grid = scene.grid
    cells = np.flatnonzero(setup.goal)
    outcomes = set()
    compared = 0
    for trial in range(6):
        guards = 1 + trial % 2
        laps = [random_loop(scene, rng, int(rng.integers(1, 4))) for _ in range(guards)]
        period = int(np.lcm.reduce([lap.size for lap in laps]))
        patrol = Patrol(np.stack([np.tile(lap, period // lap.size) for lap in laps]), period, "test")
        detection = GuardDetection(LATTICE_MODELS[trial % len(LATTICE_MODELS)], 3.5, 0.5)
        for _ in range(3):
            source, target = (int(cells[rng.integers(cells.size)]) for _ in range(2))
            result = sneak_check(grid, setup.table, patrol, source, target, detection=detection, undetected=True)
            try:
                fastest = _brute_force(scene, setup.table, patrol, detection, source, target, None)
                through = sum(
                    _brute_force(scene, setup.table, patrol, detection, source, target, entry) is not None
                    for entry in range(period)
                )
            except _TooMany:
                continue
            compared += 1
            assert result.found == (fastest is not None)
            assert result.path is not None and result.grade is not None
            unseen = find_sneak(grid.neighbours, result.seen, source, target)
            outcomes.add((result.found, unseen is not None))
            if result.found:
                assert result.path.ticks == fastest
                replay = grade_path(
                    grid, setup.table, patrol.states, detection, result.path.start_tick, result.path.cells
                )
                assert not replay.detected and replay.peak < 1
            else:
                assert result.grade.detected
            path = result.path.cells.tolist()
            assert path[0] == source and path[-1] == target
            assert all(a == b or b in grid.neighbours[a].tolist() for a, b in itertools.pairwise(path))
            assert result.slack == through
    assert compared >= 12
    # Some cases need the graded rule (undetected, not unseen), and some have no way through at all.
    assert (True, False) in outcomes and (False, False) in outcomes and (True, True) in outcomes


def test_seen_is_caught_reproduces_the_unseen_answers() -> None:
    """With detect_near = detect_far = 0 the undetected search answers exactly as the unseen one."""
    scene = scene_from(TINY_LEVELS["square-with-hole"] | {"guard": {"view_range": 2.5}})
    setup = patrol_setup(scene)
    rng = np.random.default_rng(3)
    cells = np.flatnonzero(setup.goal)
    instant = GuardDetection(DetectionModel(detect_near=0, detect_far=0), 2.5, 0.5)
    for _ in range(8):
        lap = random_loop(scene, rng, int(rng.integers(1, 5)))
        patrol = Patrol(lap[None, :], lap.size, "test")
        source, target = (int(cells[rng.integers(cells.size)]) for _ in range(2))
        graded = sneak_check(scene.grid, setup.table, patrol, source, target, detection=instant, undetected=True)
        plain = sneak_check(scene.grid, setup.table, patrol, source, target, detection=instant)
        assert graded.found == plain.found and graded.slack == plain.slack
        assert graded.path is not None and plain.path is not None
        assert graded.path.ticks == plain.path.ticks and graded.path.ticks_in_view == plain.path.ticks_in_view


def test_acorridor_post_is_slipped_past_undetected_but_not_unseen() -> None:
    """A guard facing down the corridor's side sees the intruder pass at its side for a tick or two; its
    meter does not fill, so there is an undetected path but no unseen one."""
    scene = scene_from(TWO_ROOMS)
    setup = patrol_setup(scene)
    grid = scene.grid
    source, target = grid.flat(0, 0), grid.flat(10, 2)
    detection = GuardDetection(DetectionModel(detect_near=2.0, detect_far=3.0), scene.level.guard.view_range, 0.5)
    post = corridor_post(scene, 5, 1)
    plain = sneak_check(grid, setup.table, post, source, target, detection=detection)
    graded = sneak_check(grid, setup.table, post, source, target, detection=detection, undetected=True)
    assert not plain.found and plain.slack == 0
    assert graded.found and graded.slack == 1
    assert graded.grade is not None and 0 < graded.grade.peak < 1 and graded.grade.ticks_in_view >= 1
    assert graded.grade.closest_distance == 0.0  # it passes the guard's own cell


def test_a_label_budget_stops_the_search_with_a_named_error() -> None:
    neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    gain = np.zeros((1, 2, 3))
    from guardsim.errors import LimitError

    with pytest.raises(LimitError, match="passed 2 labels"):
        undetected_search(neighbours, gain, 0.1, 0, 2, max_labels=2)


# --- Time to detection ---


@pytest.mark.parametrize("model", MODELS, ids=["default", "quick", "slow"])
def test_time_to_detection_agrees_with_standing_there(model: DetectionModel) -> None:
    scene = scene_from(TINY_LEVELS["l-room"] | {"guard": {"view_range": 3.0}})
    setup = patrol_setup(scene)
    rng = np.random.default_rng(5)
    laps = [random_loop(scene, rng, 3), random_loop(scene, rng, 2)]
    period = int(np.lcm.reduce([lap.size for lap in laps]))
    states = np.stack([np.tile(lap, period // lap.size) for lap in laps])
    gains = patrol_gains(scene.grid, setup.table, states, model, view_range=3.0, dt=0.5)
    lasts = time_to_detection(gains, scene.grid.traversable)
    table_sets = {state: set(setup.table.sees(state).tolist()) for state in np.unique(states).tolist()}
    grid, cols = scene.grid, scene.grid.shape[1]
    fall = model.fall(0.5)
    for cell in np.flatnonzero(grid.traversable.ravel()).tolist():
        # Each tick's gain per guard from the view table and the guards' cells, apart from patrol_gains.
        tick_gains = []
        for phase in range(period):
            row = []
            for state in states[:, phase].tolist():
                own = state // 4
                distance = math.hypot(cell // cols - own // cols, cell % cols - own % cols)
                row.append(model.gain(0.5, distance, 3.0) if cell in table_sets[state] else 0.0)
            tick_gains.append(row)
        # Stand for 40 laps from every entry tick.
        outcomes = []
        for entry in range(period):
            levels, detected_after = [0.0] * len(laps), None
            for tick in range(40 * period):
                levels = [
                    meter_after(level, gain, fall) for level, gain in zip(levels, tick_gains[(entry + tick) % period])
                ]
                if max(levels) >= DETECTED:
                    detected_after = tick + 1
                    break
            outcomes.append(detected_after)
        expected = -1 if all(o is None for o in outcomes) else min(o for o in outcomes if o is not None)
        assert lasts[cell] == expected, cell


# --- The command ---


def test_sneak_undetected_command_prints_and_writes_the_grade(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    patrol = tmp_path / "post.json"
    patrol.write_text(json.dumps({"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [1]}]}))
    out = tmp_path / "out"
    base = ["sneak", str(level), "--patrol", str(patrol), "--from", "0.5,0.5", "--to", "10.5,2.5", "--out", str(out)]
    runner = CliRunner()
    plain = runner.invoke(main, [*base, "--detect-near", "2", "--detect-far", "3"])
    assert plain.exit_code == 0, plain.output
    assert "caught: no unseen path" in plain.output and "slack 0/1 entry ticks" in plain.output
    result = runner.invoke(main, [*base, "--undetected", "--detect-near", "2", "--detect-far", "3"])
    assert result.exit_code == 0, result.output
    assert "sneaks: undetected from tick 0" in result.output and "detected: no" in result.output
    data: dict[str, Any] = json.loads((out / "sneak.json").read_text())
    assert data["rule"] == "undetected" and data["found"] is True and data["detected"] is False
    assert 0 < data["peak_awareness"]["overall"] < 1 and data["peak_awareness"]["by_guard"] == [
        data["peak_awareness"]["overall"]
    ]
    assert data["slack"] == 1 and data["closest_distance"] == 0 and 0 < data["risk"] < 1
    assert len(data["awareness"]) == data["ticks"] + 1
    # The guard's own cell is always in view: exposure 1, and standing there is detected.
    assert data["exposure"][1][5] == 1.0 and data["time_to_detection"][1][5] is not None
    assert data["hiding_spots"] and data["hiding_spots"][0]["lasts"] is None
    # Instant detection from the command line: no undetected path.
    instant = runner.invoke(main, [*base, "--undetected", "--detect-near", "0", "--detect-far", "0"])
    assert instant.exit_code == 0 and "caught: no undetected path" in instant.output
    bad = runner.invoke(main, [*base, "--suspicious", "2"])
    assert bad.exit_code == 2 and "--suspicious" in bad.output and "Traceback" not in bad.output
