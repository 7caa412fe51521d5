"""``sneak --unheard``: the exact search chooses a gait for every step and no guard hears one land.

Checked against a brute force that plays the gaits as the issue states them, tick by tick over absolute
time: (lap tick, cell, the sneaking step under way and its progress[, exact meters]), every state kept,
hearing from a breadth-first distance of its own. Both directions: what the search finds brute force
finds as fast, and what it does not find, brute force does not either. Each reported path is replayed.
"""

from __future__ import annotations

import itertools
import json
import math
from collections import deque
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.detection import DetectionModel, GuardDetection
from guardsim.kernels.meter import DETECTED, meter_after
from guardsim.level.model import IntruderSpec
from guardsim.patrol import Patrol, patrol_setup
from guardsim.scene import Scene
from guardsim.sneak import sneak_check, sneak_data
from guardsim.sneak.grade import grade_path
from tests.common import ALCOVE, ALCOVE_POST, TINY_LEVELS, random_loop, scene_from, write_level

# ALCOVE (tests/common.py): its guard, posted at (5, 2) facing the alcove's wall, sees no cell of the
# corridor, but every cell of the corridor is within 3 steps of it.


def _steps_between(neighbours: np.ndarray, source: int) -> dict[int, int]:
    """Steps along the grid from ``source`` to every cell it connects to (the brute force's own BFS)."""
    steps = {source: 0}
    queue = deque([source])
    while queue:
        cell = queue.popleft()
        for other in neighbours[cell].tolist():
            if other >= 0 and other not in steps:
                steps[other] = steps[cell] + 1
                queue.append(other)
    return steps


class _Ears:
    """Who hears a step land where, by the issue's words: the shortest 4-connected path between the
    player's cell and a guard's cell at that tick, times the cell size, at most the radius."""

    def __init__(self, scene: Scene, patrol: Patrol, intruder: IntruderSpec) -> None:
        self.grid, self.patrol, self.intruder = scene.grid, patrol, intruder
        self.distances = {cell: _steps_between(scene.grid.neighbours, cell) for cell in range(scene.grid.size)}

    def heard(self, phase: int, cell: int, gait: str) -> bool:
        radius = self.intruder.sneak_noise if gait == "sneak" else self.intruder.walk_noise
        if radius <= 0:
            return False
        for guard in range(self.patrol.guards):
            guard_cell = int(self.patrol.states[guard, phase]) // 4
            steps = self.distances[cell].get(guard_cell)
            if steps is not None and steps * self.grid.cell_size <= radius + 1e-9:
                return True
        return False


def _brute_force(
    scene: Scene,
    patrol: Patrol,
    ears: _Ears,
    source: int,
    target: int,
    entries: list[int],
    meters_after: Any,
) -> int | None:
    """Fastest ticks from ``source`` to ``target`` entering at a lap tick of ``entries``, neither heard nor
    (``meters_after`` None-returning) caught: breadth first over (lap tick, cell, step under way, meters).

    A state's step under way is ``None`` standing, else (the cell it sneaks to, ticks spent on it). Each
    tick a standing player waits (silent), walks a step (in the next cell the next tick, heard there and
    then by the walking radius) or starts a sneaking step; one sneaking to ``b`` spends ``sneak_ticks - 1``
    ticks where it is and lands in ``b`` at the last, heard there and then by the sneaking radius."""
    grid, period, ticks = scene.grid, patrol.period or 1, ears.intruder.sneak_ticks
    frontier = set()
    for phase in entries:
        meters = meters_after(None, phase, source)
        if meters is not None:
            frontier.add((phase, source, None, meters))
    visited = set(frontier)
    elapsed = 0
    while frontier:
        if any(cell == target for _, cell, _, _ in frontier):
            return elapsed
        upcoming = set()
        for phase, cell, under_way, meters in frontier:
            after = (phase + 1) % period
            moves: list[tuple[int, Any, str | None]] = []  # (cell then, step under way then, gait landing)
            if under_way is None:
                moves.append((cell, None, None))
                for other in (int(o) for o in grid.neighbours[cell] if o >= 0):
                    moves.append((other, None, "walk"))
                    moves.append((other, None, "sneak") if ticks == 1 else (cell, (other, 1), None))
            else:
                destination, spent = under_way
                if spent + 1 == ticks:
                    moves.append((destination, None, "sneak"))
                else:
                    moves.append((cell, (destination, spent + 1), None))
            for other, step, gait in moves:
                if gait is not None and ears.heard(after, other, gait):
                    continue
                stepped = meters_after(meters, after, other)
                if stepped is None:
                    continue
                state = (after, other, step, stepped)
                if state not in visited:
                    visited.add(state)
                    upcoming.add(state)
        if len(visited) > 300_000:
            raise _TooMany
        frontier = upcoming
        elapsed += 1
    return None


class _TooMany(Exception):
    pass


def _unseen_meters(seen: np.ndarray) -> Any:
    def meters_after(meters: Any, phase: int, cell: int) -> Any:
        return None if seen[phase, cell] else ()

    return meters_after


def _graded_meters(scene: Scene, table: Any, patrol: Patrol, detection: GuardDetection) -> Any:
    grid, cols, model = scene.grid, scene.grid.shape[1], detection.model
    fall = model.fall(detection.dt)

    def meters_after(meters: Any, phase: int, cell: int) -> Any:
        meters = (0.0,) * patrol.guards if meters is None else meters
        out = []
        for guard in range(patrol.guards):
            state = int(patrol.states[guard, phase])
            guard_cell = state // 4
            distance = grid.cell_size * math.hypot(cell // cols - guard_cell // cols, cell % cols - guard_cell % cols)
            sees = cell in table.sees(state).tolist()
            level = meter_after(
                meters[guard], model.gain(detection.dt, distance, detection.view_range) if sees else 0.0, fall
            )
            if level >= DETECTED:
                return None
            out.append(level)
        return tuple(out)

    return meters_after


def _replay(scene: Scene, patrol: Patrol, ears: _Ears, result: Any) -> None:
    """The path's gaits are the issue's: a sneaking step is ``sneak_ticks`` ticks, in its first cell for
    all but the last; waits stay; no landing is heard."""
    path = result.path
    cells, gaits = path.cells.tolist(), list(path.gaits)
    period, ticks = result.period, ears.intruder.sneak_ticks
    assert len(gaits) == len(cells) - 1
    tick = 1
    while tick < len(cells):
        gait = gaits[tick - 1]
        if gait == "sneak":
            landing = tick + ticks - 1
            assert gaits[tick - 1 : landing] == ["sneak"] * ticks
            assert cells[tick - 1 : landing] == [cells[tick - 1]] * ticks
            assert cells[landing] in scene.grid.neighbours[cells[landing - 1]].tolist()
            assert not ears.heard((path.start_tick + landing) % period, cells[landing], "sneak")
            tick = landing + 1
            continue
        if gait == "wait":
            assert cells[tick] == cells[tick - 1]
        else:
            assert gait == "walk" and cells[tick] in scene.grid.neighbours[cells[tick - 1]].tolist()
            assert not ears.heard((path.start_tick + tick) % period, cells[tick], "walk")
        tick += 1


#: Noise keys tried: walking heard 1 to 3 cells away, sneaking silent or heard next door, 1 to 3 ticks.
EARS = [
    IntruderSpec(walk_noise=2, sneak_ticks=2, sneak_noise=0),
    IntruderSpec(walk_noise=3, sneak_ticks=3, sneak_noise=1),
    IntruderSpec(walk_noise=1.5, sneak_ticks=1, sneak_noise=0),
    IntruderSpec(walk_noise=2.5, sneak_ticks=2, sneak_noise=1.2),
]


def _cases(name: str, seed: int, view_range: float) -> Any:
    scene = scene_from(
        TINY_LEVELS[name] | {"guard": {"start": [0.5, 0.5], "heading": "right", "view_range": view_range}}
    )
    setup = patrol_setup(scene)
    rng = np.random.default_rng(seed)
    cells = np.flatnonzero(setup.goal)
    for trial in range(4):
        guards = 1 + trial % 2
        laps = [random_loop(scene, rng, int(rng.integers(1, 4))) for _ in range(guards)]
        period = int(np.lcm.reduce([lap.size for lap in laps]))
        patrol = Patrol(np.stack([np.tile(lap, period // lap.size) for lap in laps]), period, "test")
        for index in range(3):
            source, target = (int(cells[rng.integers(cells.size)]) for _ in range(2))
            yield scene, setup.table, patrol, source, target, EARS[(trial + index) % len(EARS)]


@pytest.mark.parametrize("name", ["square-with-hole", "l-room"])
def test_the_unheard_search_agrees_with_brute_force(name: str) -> None:
    """Unseen and unheard: found exactly when brute force finds a way, as fast; the slack is brute force's
    count of entry ticks; the path replays unseen and unheard with the gaits it gives."""
    outcomes = set()
    for scene, table, patrol, source, target, intruder in _cases(name, 5, 2.5):
        detection = GuardDetection.of_level(scene.level)
        result = sneak_check(
            scene.grid, table, patrol, source, target, detection=detection, unheard=True, intruder=intruder
        )
        ears = _Ears(scene, patrol, intruder)
        meters = _unseen_meters(result.seen)
        period = result.period
        fastest = _brute_force(scene, patrol, ears, source, target, list(range(period)), meters)
        silent = _brute_force(
            scene, patrol, _Ears(scene, patrol, IntruderSpec()), source, target, list(range(period)), meters
        )
        through = sum(_brute_force(scene, patrol, ears, source, target, [e], meters) is not None for e in range(period))
        assert result.found == (fastest is not None), (source, target, intruder)
        assert result.path is not None and result.path.gaits is not None
        outcomes.add((result.found, silent is not None))
        if result.found:
            assert result.path.ticks == fastest
            assert not result.seen[
                (result.path.start_tick + np.arange(result.path.cells.size)) % period, result.path.cells
            ].any()
            _replay(scene, patrol, ears, result)
        else:
            assert result.path.ticks_in_view + result.path.steps_heard > 0
        assert result.slack == through
    # Some cases are stopped by the ears alone, some get through, some are stopped by the eyes.
    assert {(True, True), (False, True), (False, False)} <= outcomes


@pytest.mark.parametrize("name", ["square-with-hole", "l-room"])
def test_the_undetected_unheard_search_agrees_with_brute_force(name: str) -> None:
    """Undetected and unheard, over exact meters (lattice models), in both directions."""
    models = [
        DetectionModel(detect_near=1.0, detect_far=1.0, forget=2.0),
        DetectionModel(detect_near=0.75, detect_far=0.75, forget=1.0),
    ]
    outcomes = set()
    compared = 0
    for index, (scene, table, patrol, source, target, intruder) in enumerate(_cases(name, 12, 3.5)):
        detection = GuardDetection(models[index % 2], 3.5, 0.5)
        result = sneak_check(
            scene.grid, table, patrol, source, target, detection=detection, undetected=True, unheard=True,
            intruder=intruder,
        )  # fmt: skip
        ears = _Ears(scene, patrol, intruder)
        meters = _graded_meters(scene, table, patrol, detection)
        try:
            fastest = _brute_force(scene, patrol, ears, source, target, list(range(result.period)), meters)
            through = sum(
                _brute_force(scene, patrol, ears, source, target, [e], meters) is not None for e in range(result.period)
            )
        except _TooMany:
            continue
        compared += 1
        assert result.found == (fastest is not None)
        assert result.path is not None and result.path.gaits is not None
        unseen = (
            result.found
            and not result.seen[
                (result.path.start_tick + np.arange(result.path.cells.size)) % result.period, result.path.cells
            ].any()
        )
        outcomes.add((result.found, bool(unseen)))
        if result.found:
            assert result.path.ticks == fastest
            replay = grade_path(scene.grid, table, patrol.states, detection, result.path.start_tick, result.path.cells)
            assert not replay.detected
            _replay(scene, patrol, ears, result)
        assert result.slack == through
    assert compared >= 8
    assert {(True, False), (False, False)} <= outcomes


def _alcove(walk_noise: float, sneak_noise: float) -> tuple[Scene, Any, Patrol, IntruderSpec]:
    scene = scene_from(ALCOVE)
    setup = patrol_setup(scene)
    # Facing down into the alcove's wall (heading 1): it sees its own cell only.
    post = Patrol(np.array([[scene.grid.flat(5, 2) * 4 + 1]]), 1, "post")
    return scene, setup.table, post, IntruderSpec(walk_noise=walk_noise, sneak_ticks=2, sneak_noise=sneak_noise)


def test_a_guard_beside_the_only_corridor_hears_walking_not_sneaking() -> None:
    """Walking steps heard 3 cells away: no way through the corridor unheard; sneaking steps heard 0.5
    away (not the next cell): a way, sneaking the corridor's cells within 3 steps of the guard."""
    scene, table, post, loud = _alcove(3, 0.5)
    grid = scene.grid
    source, target = grid.flat(0, 1), grid.flat(10, 1)
    detection = GuardDetection.of_level(scene.level)
    plain = sneak_check(grid, table, post, source, target, detection=detection)
    assert plain.found and plain.path is not None and plain.path.ticks == 10
    walking = sneak_check(grid, table, post, source, target, detection=detection, unheard=True,
                          intruder=IntruderSpec(walk_noise=3, sneak_ticks=2, sneak_noise=3))  # fmt: skip
    assert not walking.found and walking.slack == 0
    assert walking.path is not None and walking.path.steps_heard == 5 and walking.path.ticks_in_view == 0
    sneaking = sneak_check(grid, table, post, source, target, detection=detection, unheard=True, intruder=loud)
    assert sneaking.found and sneaking.path is not None and sneaking.slack == 1
    gaits = sneaking.path.gaits
    assert gaits is not None
    # Columns 3 to 7 of the corridor are within 3 steps of (5, 2): their five steps sneak (2 ticks each).
    assert sneaking.path.ticks == 15 and gaits.count("sneak") == 10 and gaits.count("walk") == 5
    data = json.loads(json.dumps(sneak_data(sneaking, grid)))
    assert data["unheard"] is True and data["gaits"] == list(gaits) and data["steps_heard"] == 0
    assert "gaits" not in sneak_data(plain, grid)


def test_silent_steps_answer_as_without_ears() -> None:
    """With the default keys (silent steps) --unheard answers exactly as the search without it, every
    step a walk or a wait."""
    for scene, table, patrol, source, target, _ in itertools.islice(_cases("l-room", 3, 2.5), 6):
        detection = GuardDetection.of_level(scene.level)
        for undetected in (False, True):
            plain = sneak_check(scene.grid, table, patrol, source, target, detection=detection, undetected=undetected)
            eared = sneak_check(
                scene.grid, table, patrol, source, target, detection=detection, undetected=undetected, unheard=True
            )
            assert plain.path is not None and eared.path is not None and eared.path.gaits is not None
            assert eared.path.cells.tolist() == plain.path.cells.tolist() and eared.slack == plain.slack
            assert set(eared.path.gaits) <= {"walk", "wait"} and plain.path.gaits is None


def test_sneak_unheard_command_prints_the_gaits(tmp_path: Path) -> None:
    level = write_level(tmp_path, ALCOVE | {"intruder": {"walk_noise": 3, "sneak_noise": 0.5, "sneak_ticks": 2}})
    patrol = tmp_path / "post.json"
    patrol.write_text(json.dumps(ALCOVE_POST))
    runner = CliRunner()
    out = tmp_path / "run"
    args = ["sneak", str(level), "--patrol", str(patrol), "--from", "0.5,1.5", "--to", "10.5,1.5", "--unheard"]
    result = runner.invoke(main, [*args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "sneaks: unseen, unheard from tick 0 of the lap, 15 ticks" in result.output
    assert "gaits: walk x2, sneak x5 (2 ticks each), walk x3" in result.output
    data = json.loads((out / "sneak.json").read_text())
    assert data["gaits"].count("sneak") == 10
    # The path as an alert route: the route intruder takes its gaits from sneak.json and is not heard.
    trace = tmp_path / "trace.json"
    route = ["alert", str(level), "--patrol", str(patrol), "--intruder", "route", "--route", str(out / "sneak.json")]
    walked = runner.invoke(main, [*route, "--to", "10.5,1.5", "--trace", str(trace)])
    assert walked.exit_code == 0, walked.output
    events = json.loads(trace.read_text())["events"]
    assert not [e for e in events if e["event"] == "heard"] and [e for e in events if e["event"] == "arrived"]
    loud = runner.invoke(main, [*args, "--sneak-noise", "3"])
    assert loud.exit_code == 0 and "caught: no unseen, unheard path" in loud.output and "heard 5 times" in loud.output
    bad = runner.invoke(main, [*args, "--sneak-noise", "-1"])
    assert bad.exit_code == 2 and "--sneak-noise" in bad.output


# -- alert: the sneak intruder plans its gaits; the evader runs when chased -----------------------------


def test_the_alert_sneak_intruder_sneaks_past_the_alcove_unheard() -> None:
    """With walk_noise 3 and sneak_noise 0.5 the ``sneak`` intruder of ``alert`` plans with gaits (the
    search above): it crosses the corridor unheard, its five steps beside the alcove two ticks each, as
    planned tick for tick. A ``route`` intruder walking the same corridor is heard."""
    from guardsim.alert import AlertRules, alert_episode
    from guardsim.level import parse_level

    scene, table, post, _ = _alcove(3, 0.5)
    grid = scene.grid
    rules = AlertRules.of_level(parse_level(ALCOVE | {"intruder": {"walk_noise": 3, "sneak_noise": 0.5}}))
    source, target = grid.flat(0, 1), grid.flat(10, 1)
    runs = {}
    for kind in ("sneak", "route"):
        episode = alert_episode(
            scene, post, intruder=kind, source=source, target=target, table=table, rules=rules, max_seconds=30
        )
        episode.run()
        runs[kind] = episode
    sneaker, walker = runs["sneak"], runs["route"]
    assert sneaker.outcome == "undetected_arrival" and not [e for e in sneaker.events if e.event == "heard"]
    planned = sneak_check(grid, table, post, source, target, detection=GuardDetection.of_level(scene.level),
                          unheard=True, intruder=IntruderSpec(walk_noise=3, sneak_noise=0.5))  # fmt: skip
    assert planned.path is not None
    cells = [cell for cell in sneaker.record["intruder"] if cell is not None]
    assert cells == planned.path.cells.tolist()[: len(cells)] and len(cells) == planned.path.ticks
    assert [e.tick for e in walker.events if e.event == "heard"][:1] == [3]


def test_a_chased_evader_runs() -> None:
    """An evader with a run speed of 2 cells a tick moves two cells in some tick while chased, never more,
    and at most one a tick unchased; without a run speed it never moves two. The guards' contaminated
    set grows by the run (their reach): the episode's invariants still hold."""
    from guardsim.alert import AlertRules, alert_episode, alert_trace_data, check_alert_trace
    from tests.test_alert import ring_patrol, seen_entry, setup

    scene, table = setup()
    grid = scene.grid
    patrol = ring_patrol(grid, guards=1)
    moves: dict[bool, set[int]] = {True: set(), False: set()}
    for run in (None, 2.0):
        rules = AlertRules.of_level(
            scene.level, run_speed=None if run is None else run / AlertRules.of_level(scene.level).dt
        )
        assert rules.run_speed == run
        episode = alert_episode(
            scene, patrol, intruder="evader", source=seen_entry(grid, table, patrol, 3), target=grid.flat(11, 7),
            phase=3, max_seconds=60, table=table, rules=rules, spotted=True,
        )  # fmt: skip
        episode.run()
        cells, states = episode.record["intruder"], episode.record["guard_states"]
        for tick in range(1, len(cells)):
            if cells[tick] is None or cells[tick - 1] is None:
                continue
            (r0, c0), (r1, c1) = divmod(cells[tick - 1], grid.shape[1]), divmod(cells[tick], grid.shape[1])
            step = abs(r1 - r0) + abs(c1 - c0)
            chased = "chase" in states[tick - 1]
            moves[run is not None].add(step)
            assert step <= (2 if run is not None and chased else 1), (run, tick, step)
        data = json.loads(json.dumps(alert_trace_data(episode, scene, search="ripple", intruder="evader")))
        assert not check_alert_trace(data, grid.traversable)
    assert 2 in moves[True] and 2 not in moves[False]


# -- bad input ------------------------------------------------------------------------------------------


def test_bad_ears_are_one_line_errors(tmp_path: Path) -> None:
    """A noise key below 0 in the level or as an option, a sneak.json whose gaits are not walk, sneak or
    wait, and one whose sneaking steps take other than the level's sneak_ticks (a gait this level does
    not allow): one line naming the file or the option, exit status 2."""
    runner = CliRunner()
    patrol = tmp_path / "post.json"
    patrol.write_text(json.dumps(ALCOVE_POST))
    noisy = write_level(tmp_path, ALCOVE | {"intruder": {"walk_noise": 3, "sneak_noise": 0.5}}, "noisy.json")
    quiet = write_level(tmp_path, ALCOVE | {"intruder": {"walk_noise": -3}}, "bad.json")
    sneak = ["sneak", "--patrol", str(patrol), "--from", "0.5,1.5", "--to", "10.5,1.5", "--unheard"]
    cases: list[tuple[list[str], str]] = [
        ([sneak[0], str(quiet), *sneak[1:]], f"{quiet}: intruder.walk_noise"),
        ([sneak[0], str(noisy), *sneak[1:], "--walk-noise", "-2"], "--walk-noise"),
    ]
    out = tmp_path / "run"
    made = runner.invoke(main, [sneak[0], str(noisy), *sneak[1:], "--out", str(out)])
    assert made.exit_code == 0, made.output
    data = json.loads((out / "sneak.json").read_text())
    for name, gaits in (("run", ["run", *data["gaits"][1:]]), ("three", None)):
        route = tmp_path / f"{name}.json"
        if gaits is None:
            # The same path with a sneaking step stretched to 3 ticks: the level's sneak_ticks is 2.
            first = data["gaits"].index("sneak")
            path = [*data["path"][: first + 1], data["path"][first], *data["path"][first + 1 :]]
            route.write_text(
                json.dumps(data | {"path": path, "gaits": [*data["gaits"][:first], "sneak", *data["gaits"][first:]]})
            )
            needle = "gaits: the sneaking step landing at tick 5 takes 3 ticks; the level's sneak_ticks is 2"
        else:
            route.write_text(json.dumps(data | {"gaits": gaits}))
            needle = "gaits: not one of walk, sneak, wait"
        alert = ["alert", str(noisy), "--patrol", str(patrol), "--intruder", "route", "--route", str(route)]
        cases.append((alert, f"{route}: {needle}"))
    for args, needle in cases:
        result = runner.invoke(main, args)
        assert result.exit_code == 2, (args, result.output)
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and needle in lines[0], (needle, result.stderr)
