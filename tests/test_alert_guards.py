"""Guards that behave like game guards: the invariants of guardsim.alert.invariants hold over seeded
episodes (grid and continuous, every strategy), the checker catches each fault on hand-made traces, and
chases end (running, cutting off, giving up after losses; the radio only while the alarm is real).

The fast tier plays the tiny ROOM of tests/test_alert.py; the issue's own recipe (``guardsim patrol
--guards 2`` then ``guardsim alert --intruder evader --spotted --search all --episodes 6``) on real maps
is in the slow tier.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from guardsim.alert import SEARCHES, AlertRules, alert_episode, alert_trace_data, run_alerts
from guardsim.alert.invariants import check_alert_trace, corridor_cells
from guardsim.errors import LevelError
from guardsim.level import parse_level
from tests.test_alert import ROOM, ring_patrol, setup

REPO = Path(__file__).resolve().parent.parent
# ../shared beside the clone (CI), or beside the folder of worktrees.
MAPS = next(
    (base / "shared" / "maps" / "movingai" for base in (REPO.parent, REPO.parent.parent) if (base / "shared").is_dir()),
    REPO.parent / "shared" / "maps" / "movingai",
)


def _trace(paths: list[list[list[int]]], headings: list[list[int]], states: list[list[str]], **extra: Any) -> dict:
    ticks = len(paths[0])
    data: dict[str, Any] = {
        "paths": paths,
        "headings": headings,
        "guard_states": states,
        "events": [],
        "contaminated": [1] * ticks,
        "last_known": [None] * ticks,
        "intruder_path": [None] * ticks,
    }
    data.update(extra)
    return data


def kinds(data: dict, traversable: np.ndarray) -> list[str]:
    return [v.kind for v in check_alert_trace(data, traversable)]


# -- the checker can fail -------------------------------------------------------------------------


def test_checker_jitter_counts_walked_reversals_not_looks() -> None:
    free = np.ones((3, 4), dtype=bool)
    back_and_forth = [[0, 1], [1, 1]] * 3  # 5 reversals in a row
    headings = [0, 0, 2, 0, 2, 0]
    assert kinds(_trace([back_and_forth], [headings], [["search"] * 6]), free) == ["jitter"]
    three = [[0, 1], [1, 1], [0, 1], [1, 1], [0, 1]]  # 3 reversals: allowed
    assert kinds(_trace([three], [[0, 0, 2, 0, 2]], [["search"] * 5]), free) == []
    # Standing two ticks at each end (a look around) is not a walked reversal.
    looking = [[0, 1], [0, 1], [1, 1], [1, 1], [0, 1], [0, 1], [1, 1], [1, 1], [0, 1], [0, 1], [1, 1]]
    turning = [0, 2, 0, 2, 2, 0, 0, 2, 2, 0, 0]
    assert kinds(_trace([looking], [turning], [["search"] * 11]), free) == []


def test_checker_moonwalk_is_a_step_facing_another_way() -> None:
    free = np.ones((1, 4), dtype=bool)
    assert kinds(_trace([[[0, 0], [1, 0], [2, 0]]], [[0, 0, 0]], [["patrol"] * 3]), free) == []
    assert kinds(_trace([[[2, 0], [1, 0], [1, 0]]], [[2, 0, 0]], [["return"] * 3]), free) == ["moonwalk"]
    # A run (two cells straight in a tick) faces its way.
    assert kinds(_trace([[[0, 0], [2, 0]]], [[0, 0]], [["chase"] * 2]), free) == []


def test_checker_stacked_except_chasing_or_corridor() -> None:
    room = np.ones((5, 5), dtype=bool)
    first = [[1, 1]] * 12
    second = [[2, 1]] * 12
    headings = [[0] * 12, [0] * 12]
    assert kinds(_trace([first, second], headings, [["search"] * 12] * 2), room) == ["stacked"]
    assert kinds(_trace([first, second], headings, [["chase"] * 12] * 2), room) == []
    assert kinds(_trace([first[:10], second[:10]], [[0] * 10] * 2, [["search"] * 10] * 2), room) == []
    corridor = np.zeros((3, 5), dtype=bool)
    corridor[1, :] = True
    assert corridor_cells(corridor)[1].all()
    assert kinds(_trace([first, second], headings, [["search"] * 12] * 2), corridor) == []


def test_checker_radio_only_while_alarmed() -> None:
    free = np.ones((3, 3), dtype=bool)
    paths = [[[0, 0]] * 4, [[2, 2]] * 4]
    states = [["search", "search", "return", "return"], ["patrol", "patrol", "patrol", "search"]]
    late = _trace(paths, [[0] * 4] * 2, states, events=[{"tick": 3, "guard": 1, "event": "joined"}])
    assert kinds(late, free) == ["radio"]
    states[0][3] = "search"
    fine = _trace(paths, [[0] * 4] * 2, states, events=[{"tick": 3, "guard": 1, "event": "joined"}])
    assert kinds(fine, free) == []
    left = [{"tick": 2, "guard": -1, "event": "arrived"}, {"tick": 3, "guard": 1, "event": "joined"}]
    assert kinds(_trace(paths, [[0] * 4] * 2, states, events=left), free) == ["radio"]


def test_checker_wrong_way_is_walking_off_behind_the_last_seen_travel() -> None:
    free = np.ones((1, 12), dtype=bool)
    # The intruder ran right (last known 5 then 6); the guard at 6 walks left, away, for the whole window.
    known: list[Any] = [[4, 0], [5, 0], [6, 0]] + [[6, 0]] * 8
    walk_left = [[6, 0], [6, 0], [6, 0], [5, 0], [4, 0], [3, 0], [2, 0], [1, 0], [0, 0], [0, 0], [0, 0]]
    states = [["chase"] * 3 + ["search"] * 8]
    lost = [{"tick": 3, "guard": 0, "event": "lost"}]
    data = _trace([walk_left], [[2] * 11], states, events=lost, last_known=known)
    assert kinds(data, free) == ["wrong_way"]
    walk_right = [[6, 0], [6, 0], [6, 0], [7, 0], [8, 0], [9, 0], [10, 0], [11, 0], [11, 0], [11, 0], [11, 0]]
    assert kinds(_trace([walk_right], [[0] * 11], states, events=lost, last_known=known), free) == []


# -- the invariants hold --------------------------------------------------------------------------


def _check_runs(scene: Any, runs: dict[str, list[Any]]) -> int:
    checked = 0
    for search, episodes in runs.items():
        for index, episode in enumerate(episodes):
            data = json.loads(json.dumps(alert_trace_data(episode, scene, search=search, intruder="evader")))
            found = check_alert_trace(data, scene.grid.traversable)
            assert not found, (search, index, found[:3])
            checked += 1
    return checked


@pytest.mark.parametrize("guards", [2, 3])
def test_invariants_hold_on_seeded_episodes_on_the_grid(guards: int) -> None:
    """ROOM (a pillar; an open room where guards can crowd), every strategy, seeded spotted evaders."""
    scene, table = setup()
    patrol = ring_patrol(scene.grid, guards=min(guards, 2))
    if guards == 3:  # a third guard on the loop, a quarter lap on: more pairs to crowd
        states = np.vstack([patrol.states, np.roll(patrol.states[0], -5)[None, :]])
        patrol = type(patrol)(states, period=patrol.period, strategy="loop")
    runs = run_alerts(scene, patrol, searches=SEARCHES, episodes=8, seed=3, spotted=True, table=table, max_seconds=120)
    assert _check_runs(scene, runs) == 32
    outcomes = [e.result() for eps in runs.values() for e in eps]
    assert not any(o.outcome == "time_limit" and o.detections > 10 for o in outcomes)


def test_invariants_hold_in_continuous_motion() -> None:
    scene, table = setup()
    patrol = ring_patrol(scene.grid, guards=2)
    runs = run_alerts(
        scene, patrol, searches=("ripple", "team"), episodes=2, seed=5, spotted=True, table=table, max_seconds=60,
        motion="continuous",
    )  # fmt: skip
    assert _check_runs(scene, runs) == 4


@pytest.mark.slow
def test_invariants_hold_in_continuous_motion_on_square() -> None:
    """Square, a 2-guard loop patrol, continuous motion: where two searching bodies once walked side by
    side for 12 ticks (personal space counted on the decided cells, which the bodies lag)."""
    from guardsim import load_level
    from guardsim.patrol.plan import patrol_setup, plan_patrol
    from guardsim.scene import Scene

    scene = Scene.from_level(load_level(REPO / "levels" / "square.json"))
    patrol = plan_patrol(patrol_setup(scene, 2, seed=0), "loop").patrol
    runs = run_alerts(scene, patrol, searches=SEARCHES, episodes=4, seed=0, spotted=True, motion="continuous")
    assert _check_runs(scene, runs) == 16


@pytest.mark.slow
@pytest.mark.parametrize("name", ["arena", "maze-32-32-2", "passages"])
def test_the_issue_recipe_on_real_maps_is_clean(name: str, tmp_path: Path) -> None:
    """``guardsim patrol LEVEL --guards 2`` then ``guardsim alert ... --intruder evader --spotted --search
    all --episodes 6 --out RUN``: every trace clean (on the code before these rules: 9 jitter runs and 10
    moonwalks on arena, 28 jitter runs on maze-32-32-2, 5 jitter runs and 2 stacked pairs on passages)."""
    level = REPO / "levels" / f"{name}.json" if (REPO / "levels" / f"{name}.json").exists() else MAPS / f"{name}.map"
    if not level.exists():
        pytest.skip(f"{level} is not here")
    cli = [sys.executable, "-m", "guardsim.cli"]
    patrol = tmp_path / "P"
    subprocess.run([*cli, "patrol", str(level), "--guards", "2", "--out", str(patrol)], check=True, cwd=REPO)
    run = tmp_path / "RUN"
    subprocess.run(
        [*cli, "alert", str(level), "--patrol", str(patrol / "patrol.json"), "--intruder", "evader", "--spotted",
         "--search", "all", "--episodes", "6", "--workers", "1", "--out", str(run)],
        check=True, cwd=REPO,
    )  # fmt: skip
    from guardsim import load_level
    from guardsim.scene import Scene
    from tests.common import import_map

    scene = Scene.from_level(load_level(level) if level.suffix == ".json" else import_map(level).level)
    traces = sorted(run.glob("*-[0-9][0-9][0-9][0-9].json"))
    assert len(traces) == 24
    for path in traces:
        data = json.loads(path.read_text())
        assert check_alert_trace(data, scene.grid.traversable) == [], path.name
        assert not (data["outcome"]["outcome"] == "time_limit" and data["outcome"]["detections"] > 10)


# -- chases that end ------------------------------------------------------------------------------

CORRIDOR: dict[str, Any] = {
    "name": "long corridor",
    "outer": [[0, 0], [30, 0], [30, 1], [0, 1]],
    "guard": {"view_range": 40, "fov_degrees": 90, "detect_near": 0, "detect_far": 0},
}


def _corridor_chase(chase_speed: float) -> tuple[list[int], str]:
    """The guard's cells while it chases a route intruder down the corridor, and the outcome."""
    from guardsim.patrol.model import Patrol

    scene, table = setup(CORRIDOR, chase_speed=chase_speed)
    grid = scene.grid
    patrol = Patrol(np.array([[grid.flat(0, 0) * 4 + 0] * 2]), period=2, strategy="loop")
    episode = alert_episode(
        scene, patrol, intruder="route", source=grid.flat(6, 0), target=grid.flat(29, 0), table=table,
        spotted=True, rules=AlertRules.of_level(scene.level), max_seconds=60,
    )  # fmt: skip
    episode.run()
    record = episode.record
    chasing = [
        cells[0] for cells, states in zip(record["cells"], record["guard_states"], strict=True) if states[0] == "chase"
    ]
    return chasing, episode.outcome


def test_a_chasing_guard_runs_an_extra_step_on_alternate_ticks() -> None:
    """chase_speed 1.5: steps 1, 2, 1, 2, ... from the first chase tick, straight down a corridor, and it
    catches a walking intruder that walking (chase_speed 1) it only follows."""
    running, run_outcome = _corridor_chase(1.5)
    steps = np.diff(running).tolist()
    assert steps[:6] == [1, 2, 1, 2, 1, 2], steps
    walking, walk_outcome = _corridor_chase(1.0)
    assert set(np.diff(walking).tolist()) == {1}
    assert (run_outcome, walk_outcome) == ("captured", "escaped")


def test_a_guard_gives_up_after_losing_the_intruder_n_times() -> None:
    """give_up_losses 1: each guard's first loss ends its chasing for the episode (it is never in chase
    after it), and no detection by it follows."""
    scene, table = setup(give_up_losses=1)
    patrol = ring_patrol(scene.grid, guards=2)
    runs = run_alerts(scene, patrol, searches=("ripple",), episodes=12, seed=2, spotted=True, table=table)
    losers = 0
    for episode in runs["ripple"]:
        for guard in range(2):
            lost = [e.tick for e in episode.events if e.guard == guard and e.event == "lost"]
            if not lost:
                continue
            losers += 1
            assert len(lost) == 1
            assert all(states[guard] != "chase" for states in episode.record["guard_states"][lost[0] :])
    assert losers > 0


def test_the_second_guard_cuts_off_instead_of_following() -> None:
    """Round ROOM's pillar, two chasing or alarmed guards: while one sees the intruder the other is never
    on the cell the lead stood on the tick before (it does not follow in single file)."""
    scene, table = setup()
    patrol = ring_patrol(scene.grid, guards=2)
    runs = run_alerts(scene, patrol, searches=("ripple",), episodes=10, seed=7, spotted=True, table=table)
    both = 0
    for episode in runs["ripple"]:
        record = episode.record
        for tick in range(1, len(record["cells"])):
            states = record["guard_states"][tick]
            if states.count("chase") + states.count("search") < 2 or "chase" not in states:
                continue
            both += 1
            lead = states.index("chase")
            other = 1 - lead
            assert record["cells"][tick][other] != record["cells"][tick - 1][lead] or states[other] == "chase"
    assert both > 0


def test_no_radio_after_the_intruder_left() -> None:
    """A route intruder spotted two cells from its exit leaves at tick 2, the guard gives up at 4, and the
    radio (due at tick 8) brings nobody to search an empty room."""
    scene, table = setup(radio_delay=4.0)
    grid = scene.grid
    patrol = ring_patrol(grid, guards=2)
    episode = alert_episode(
        scene, patrol, intruder="route", source=grid.flat(2, 0), target=grid.flat(0, 0), table=table, spotted=True
    )
    episode.run()
    ticks = {e.event: e.tick for e in episode.events}
    assert ticks["detected"] == 0 and ticks["arrived"] == 2 and ticks["gave_up"] < episode.rules.radio_ticks
    assert "joined" not in ticks


@pytest.mark.parametrize(
    ("key", "value", "needle"),
    [("chase_speed", 0, "guard.chase_speed"), ("give_up_losses", 0, "guard.give_up_losses"),
     ("give_up_losses", 1.5, "whole number")],
)  # fmt: skip
def test_bad_chase_keys_are_one_line_errors(key: str, value: float, needle: str) -> None:
    with pytest.raises(LevelError) as error:
        parse_level({**ROOM, "guard": {**ROOM["guard"], key: value}})
    assert needle in str(error.value) and "\n" not in str(error.value)


def test_chase_keys_are_read() -> None:
    level = parse_level({**ROOM, "guard": {**ROOM["guard"], "chase_speed": 2, "give_up_losses": 5}})
    rules = AlertRules.of_level(level)
    assert (rules.chase_speed, rules.give_up_losses) == (2.0, 5)
    assert (
        AlertRules.of_level(parse_level(ROOM)).chase_speed,
        AlertRules.of_level(parse_level(ROOM)).give_up_losses,
    ) == (
        1.5,
        3,
    )
