"""Alert episodes: invariants checked by replaying each tick, a still intruder against a brute force,
the return to the route at its phase, the radio, determinism, the CLI and the level keys."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from guardsim.alert import SEARCHES, AlertRules, alert_episode, alert_trace_data, run_alerts
from guardsim.alert.episode import AlertEpisode
from guardsim.cli import main
from guardsim.errors import LevelError
from guardsim.kernels.meter import DETECTED
from guardsim.level import parse_level
from guardsim.patrol.model import Patrol
from guardsim.scene import Scene
from guardsim.vision.table import view_table
from tests.common import write_level

#: A 14 x 8 room with a pillar; one guard walks a loop round the pillar.
ROOM: dict[str, Any] = {
    "name": "alert room",
    "outer": [[0, 0], [14, 0], [14, 8], [0, 8]],
    "holes": [[[6, 3], [8, 3], [8, 5], [6, 5]]],
    "guard": {"view_range": 5, "fov_degrees": 90},
}


def loop_patrol(scene: Scene, guards: int = 1) -> Patrol:
    """A loop round the pillar, cells (3..10, 1) and (3..10, 6); guard g a quarter lap behind g - 1."""
    grid = scene.grid
    cells: list[tuple[int, int]] = [(c, 1) for c in range(3, 11)]
    cells += [(10, r) for r in range(2, 7)]
    cells += [(c, 6) for c in range(9, 2, -1)]
    cells += [(3, r) for r in range(5, 1, -1)]
    states = []
    for index, cell in enumerate(cells):
        after = cells[(index + 1) % len(cells)]
        dx, dy = after[0] - cell[0], after[1] - cell[1]
        heading = {(1, 0): 0, (0, 1): 1, (-1, 0): 2, (0, -1): 3}[(dx, dy)]
        states.append(grid.flat(*cell) * 4 + heading)
    lap = np.array(states, dtype=np.int64)
    shift = len(states) // max(guards, 1) // 2
    return Patrol(np.stack([np.roll(lap, -g * shift) for g in range(guards)]), period=len(states), strategy="loop")


@pytest.fixture(scope="module")
def room() -> Scene:
    return Scene.from_level(parse_level(ROOM))


def stepped(episode: AlertEpisode) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Step to the end; the contaminated set and every guard's view (reference vision) at each tick."""
    scene_sets = [episode.contamination.cells.copy()]
    views = [_views(episode)]
    while not episode.done:
        episode.step()
        scene_sets.append(episode.contamination.cells.copy())
        views.append(_views(episode))
    return scene_sets, views


def _views(episode: AlertEpisode) -> np.ndarray:
    seen = np.zeros(episode.grid.size, dtype=bool)
    for cell, heading in zip(episode.cells, episode.headings, strict=True):
        seen[episode.table.sees(cell * 4 + heading)] = True
    return seen


def _distance(episode: AlertEpisode, a: int, b: int) -> float:
    cols = episode.grid.shape[1]
    return math.hypot(a % cols - b % cols, a // cols - b // cols) * episode.grid.cell_size


@pytest.mark.parametrize("search", SEARCHES)
@pytest.mark.parametrize("intruder", ["route", "evader", "still", "sneak"])
def test_invariants_hold_on_every_tick(room: Scene, search: str, intruder: str) -> None:
    """Chase only from a full meter; capture only within the radius; a cleared cell was in some guard's
    view that tick (the view table checked against the reference vision at those states)."""
    grid = room.grid
    patrol = loop_patrol(room, 2)
    reference = room.reference_vision()
    table = view_table(grid, room.vision())
    from guardsim.alert.run import _seeded_points

    entry, goal = _seeded_points(room, patrol, np.random.default_rng(3), table=table, phase=4)
    cases = [((1, 1), (12, 6), 0, False), ((12, 1), (1, 6), 9, False), ((5, 7), (12, 4), 17, False)]
    cases.append((grid.unflat(entry), grid.unflat(goal), 4, True))
    runs = losses = 0
    for source, target, phase, spotted in cases:
        episode = alert_episode(
            room,
            patrol,
            intruder=intruder,
            source=grid.flat(*source),
            target=-1 if intruder == "still" else grid.flat(*target),
            search=search,
            phase=phase,
            max_seconds=120,
            table=table,
            spotted=spotted,
        )
        sets, views = stepped(episode)
        record = episode.record
        for tick in range(1, len(sets)):
            for guard, state in enumerate(record["guard_states"][tick]):
                if state == "chase" and record["guard_states"][tick - 1][guard] != "chase":
                    assert record["awareness"][tick][guard] >= DETECTED - 1e-4, (tick, guard)
            grown = sets[tick - 1].copy()
            for cell in np.flatnonzero(sets[tick - 1]):
                grown[[n for n in grid.neighbours[cell] if n >= 0]] = True
            cleared = np.flatnonzero(grown & ~sets[tick])
            if record["last_known"][tick] >= 0 and sets[tick].sum() > 1:
                assert views[tick][cleared].all(), (tick, cleared[~views[tick][cleared]])
            for guard, cell in enumerate(record["cells"][tick]):
                col, row = grid.unflat(cell)
                heading = record["headings"][tick][guard]
                assert set(reference(col, row, heading).tolist()) == set(table.sees(cell * 4 + heading).tolist())
        for event in episode.events:
            if event.event == "captured":
                intruder_cell = record["intruder"][event.tick]
                guard_cell = record["cells"][event.tick][event.guard]
                assert _distance(episode, guard_cell, intruder_cell) <= episode.rules.capture_radius + 1e-9
            if event.event == "detected":
                assert record["awareness"][event.tick][event.guard] >= DETECTED - 1e-4
        runs += 1
        losses += sum(e.event == "lost" for e in episode.events)
    assert runs == 4
    assert losses > 0 or intruder == "route"  # the search, hence the clearing rule, was exercised


def test_back_on_route_means_on_the_route_at_its_phase(room: Scene) -> None:
    """From each back_on_route on, the guard is where its patrol puts it at that tick plus the phase."""
    grid = room.grid
    patrol = loop_patrol(room, 2)
    checked = 0
    for search in SEARCHES:
        for phase in (0, 7):
            episode = alert_episode(
                room,
                patrol,
                intruder="evader",
                source=grid.flat(3, 3),
                target=grid.flat(12, 6),
                search=search,
                phase=phase,
                max_seconds=200,
            )
            episode.run()
            record = episode.record
            for event in episode.events:
                if event.event != "back_on_route":
                    continue
                later = [e.tick for e in episode.events if e.guard == event.guard and e.tick > event.tick]
                end = min([*later, len(record["cells"]) - 1])
                for tick in range(event.tick, end + 1):
                    if record["guard_states"][tick][event.guard] != "patrol":
                        break
                    state = patrol.state(event.guard, tick + phase)
                    assert record["cells"][tick][event.guard] * 4 + record["headings"][tick][event.guard] == state
                    checked += 1
    assert checked > 0


def test_radio_brings_the_teammate_after_the_delay(room: Scene) -> None:
    grid = room.grid
    patrol = loop_patrol(room, 2)
    episode = alert_episode(room, patrol, intruder="still", source=grid.flat(6, 1), search="ripple", max_seconds=60)
    episode.run()
    detected = next(e for e in episode.events if e.event == "detected")
    joined = [e for e in episode.events if e.event == "joined"]
    if not joined:  # the teammate was already chasing or captured first
        assert episode.outcome == "captured" and episode.tick < detected.tick + episode.rules.radio_ticks
    else:
        assert joined[0].tick == detected.tick + episode.rules.radio_ticks
        assert joined[0].guard != detected.guard


def brute_force_capturable(room: Scene, start_state: int, intruder: int) -> bool:
    """Whether some walk of one guard from ``start_state`` ever sees the cell ``intruder`` (breadth-first
    over its states)."""
    grid = room.grid
    table = view_table(grid, room.vision())
    seen = {start_state}
    layer = [start_state]
    while layer:
        following = []
        for state in layer:
            cell = state // 4
            if intruder in table.sees(state).tolist():
                return True
            for direction in range(4):
                there = int(grid.neighbours[cell, direction])
                if there >= 0 and there * 4 + direction not in seen:
                    seen.add(there * 4 + direction)
                    following.append(there * 4 + direction)
        layer = following
    return False


def test_ripple_finds_a_still_intruder_whenever_one_guard_can(room: Scene) -> None:
    """A still intruder on a drawn cell, the patrol from a drawn phase, the guards alerted if a guard sees
    it at the start (spotted): whenever that happens, a brute force over the one guard's states agrees a
    guard can see the cell, and ripple's chase and search end in a capture within the 300 s."""
    grid = room.grid
    patrol = loop_patrol(room, 1)
    table = view_table(grid, room.vision())
    generator = np.random.default_rng(26)
    free = np.flatnonzero(grid.traversable.ravel())
    found = 0
    for cell in generator.choice(free, size=12, replace=False).tolist():
        phase = int(generator.integers(patrol.period or 1))
        episode = alert_episode(
            room,
            patrol,
            intruder="still",
            source=cell,
            search="ripple",
            phase=phase,
            max_seconds=300,
            table=table,
            spotted=True,
        )
        episode.run()
        can = brute_force_capturable(room, patrol.state(0, phase), cell)
        if episode.result().detected_at is not None:
            assert can
            assert episode.outcome == "captured", (cell, phase, episode.result())
            found += 1
    assert found >= 6


def test_same_seed_same_traces(room: Scene) -> None:
    patrol = loop_patrol(room, 2)
    first = run_alerts(room, patrol, intruder="evader", searches=("team", "diffuse"), episodes=4, seed=5, spotted=True)
    again = run_alerts(room, patrol, intruder="evader", searches=("team", "diffuse"), episodes=4, seed=5, spotted=True)
    for name in first:
        for a, b in zip(first[name], again[name], strict=True):
            left = json.dumps(alert_trace_data(a, room, search=name, intruder="evader"))
            right = json.dumps(alert_trace_data(b, room, search=name, intruder="evader"))
            assert left == right


def test_level_keys(room: Scene) -> None:
    level = parse_level(
        {**ROOM, "guard": {**ROOM["guard"], "capture_radius": 2, "search_seconds": 10, "radio_delay": 1}}
    )
    rules = AlertRules.of_level(level)
    assert (rules.capture_radius, rules.search_ticks, rules.radio_ticks) == (2.0, 20, 2)
    assert AlertRules.of_level(parse_level(ROOM)).capture_radius == 1.0
    with pytest.raises(LevelError, match=r"guard\.search_seconds"):
        parse_level({**ROOM, "guard": {"search_seconds": -1}})


def test_cli(tmp_path: Path, room: Scene) -> None:
    level = write_level(tmp_path, ROOM)
    runner = CliRunner()
    patrol = tmp_path / "p"
    made = runner.invoke(main, ["patrol", str(level), "--guards", "2", "--out", str(patrol)])
    assert made.exit_code == 0, made.output
    base = ["alert", str(level), "--patrol", str(patrol / "patrol.json")]
    trace = tmp_path / "t.json"
    gif = tmp_path / "a.gif"
    one = runner.invoke(
        main, [*base, "--intruder", "still", "--from", "1.5,1.5", "--trace", str(trace), "--gif", str(gif)]
    )
    assert one.exit_code == 0, one.output
    assert one.output.splitlines()[0].startswith("alert room: ")
    data = json.loads(trace.read_text())
    ticks = data["outcome"]["ticks"] + 1
    for key in ("guard_states", "awareness", "paths", "headings"):
        assert len(data[key]) == 2 and all(len(per_guard) == ticks for per_guard in data[key])
    for key in ("intruder_path", "intruder_positions", "contaminated"):
        assert len(data[key]) == ticks
    assert all(set(event) == {"tick", "guard", "event"} for event in data["events"])
    with Image.open(gif) as image:
        assert image.n_frames > 1
    many = runner.invoke(main, [*base, "--episodes", "3", "--search", "all", "--spotted", "--out", str(tmp_path / "o")])
    assert many.exit_code == 0, many.output
    summary = json.loads((tmp_path / "o" / "alert.json").read_text())
    assert [row["search"] for row in summary["summary"]] == list(SEARCHES)
    assert len(list((tmp_path / "o").glob("*.json"))) == 13
    for options, message in [
        (["--from", "50,50", "--intruder", "still"], "--from 50,50 lies outside the level"),
        (["--from", "1.5,1.5"], "a evader intruder needs --to"),
        (["--intruder", "evader", "--route", str(trace)], "--route is the path of a route intruder"),
    ]:
        bad = runner.invoke(main, [*base, *options])
        assert bad.exit_code == 2, (options, bad.output)
        assert message in bad.output and "Traceback" not in bad.output
        assert len(bad.output.strip().splitlines()) == 1
    route = tmp_path / "route.json"
    route.write_text(json.dumps([[1.5, 1.5], [3.5, 1.5]]))
    jump = runner.invoke(main, [*base, "--intruder", "route", "--route", str(route)])
    assert jump.exit_code == 2 and "point 1 is not a 4-neighbour of point 0" in jump.output
    missing = runner.invoke(main, ["alert", str(level), "--patrol", str(tmp_path / "none.json"), "--from", "1.5,1.5"])
    assert missing.exit_code == 2 and "none.json" in missing.output
