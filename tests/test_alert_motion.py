"""Alert episodes in continuous motion (issue 26, ``alert --motion continuous``): determinism, invariants
checked by replaying every physics tick (a detection only once a meter filled, a body never inside a
wall, never faster than the guard walks or turns), a capture and an escape, the trace, and the CLI.

The level and patrol are test_alert's: a 12 x 8 room with a 2 x 2 pillar, one or two guards on a
20-tick loop round it.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner, Result

from guardsim.alert import alert_episode, alert_trace_data
from guardsim.alert.episode import AlertEpisode
from guardsim.alert.movement import ContinuousMovement
from guardsim.cli import main
from guardsim.kernels.meter import DETECTED
from guardsim.motion import GuardMotion, pose_visible_cells
from guardsim.motion.parameters import STEER_DEGREES
from tests.common import write_level
from tests.test_alert import ROOM, ring_patrol, setup, write_patrol

#: (intruder, entry (col, row), goal or None, guards, outcome): one episode that ends in a capture and
#: one in which the intruder is detected and gets away.
CASES = {
    "still-captured": ("still", (10, 6), None, 1, "captured"),
    "route-escaped": ("route", (0, 7), (11, 0), 2, "escaped"),
}


def continuous_episode(case: str, motion: str | GuardMotion = "continuous") -> AlertEpisode:
    kind, entry, goal, guards, _ = CASES[case]
    scene, table = setup()
    grid = scene.grid
    return alert_episode(
        scene, ring_patrol(grid, guards=guards), intruder=kind, source=grid.flat(*entry),
        target=-1 if goal is None else grid.flat(*goal), table=table, max_seconds=120, motion=motion,
    )  # fmt: skip


def movement_of(episode: AlertEpisode) -> ContinuousMovement:
    movement = episode.movement
    assert isinstance(movement, ContinuousMovement)
    return movement


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_outcome(case: str) -> None:
    """The capture happens within the capture radius of the body; the escape after a detection."""
    episode = continuous_episode(case)
    outcome = episode.run()
    assert outcome.outcome == CASES[case][4]
    assert outcome.detected_at is not None
    if outcome.outcome == "captured":
        catcher = next(e.guard for e in episode.events if e.event == "captured")
        assert episode.movement.distance(catcher, episode.intruder.cell) <= episode.rules.capture_radius + 1e-9
    else:
        assert outcome.back_on_route_at is not None and all(m == "patrol" for m in episode.modes)


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_same_seed_same_episode(case: str) -> None:
    """Two runs side by side agree at every grid tick, and on every physics tick's pose, to the bit."""
    first, second = continuous_episode(case), continuous_episode(case)
    while not first.done:
        first.step()
        second.step()
        assert first.modes == second.modes and first.record["poses"][-1] == second.record["poses"][-1]
    assert second.done and first.result() == second.result() and first.events == second.events
    assert np.array_equal(movement_of(first).poses, movement_of(second).poses)


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_invariants_by_replay(case: str) -> None:
    """Replayed: a guard detects (and chases) only in a tick its meter filled; every physics tick's body
    lies clear of the walls in the real pymunk space, moves and turns no faster than the guard can (running
    when it chases), and walks the way it faces."""
    episode = continuous_episode(case)
    scene, _ = setup()
    world, radius = scene.world, scene.level.guard.radius
    motion = movement_of(episode).motion
    episode.run()
    record = episode.record
    chased = [False] * len(episode.modes)
    for event in episode.events:
        if event.event == "detected":
            assert record["awareness_peak"][event.tick][event.guard] >= round(DETECTED, 4)
            chased[event.guard] = True
    for tick, states in enumerate(record["guard_states"]):
        for guard, state in enumerate(states):
            if state == "chase":
                assert max(peaks[guard] for peaks in record["awareness_peak"][: tick + 1]) >= round(DETECTED, 4)
    assert any(chased)
    poses = movement_of(episode).poses
    assert poses.shape[1] == math.floor(episode.tick * episode.rules.dt * motion.tick_hz + 1e-9) + 1
    for guard_poses in poses:
        for t, x, y, _ in guard_poses.tolist():
            assert world.fits((x, y), radius), (t, x, y)
        moves = np.diff(guard_poses[:, 1:3], axis=0)
        steps = np.hypot(*moves.T)
        # A chasing (or cutting-off) guard runs at chase_speed times walking.
        assert steps.max() <= motion.step_length * episode.rules.chase_speed + 1e-9
        turns = np.abs((np.diff(guard_poses[:, 3]) + 180.0) % 360.0 - 180.0)
        assert turns.max() <= motion.turn_step + 1e-9
        # A body walks the way it faces (within the steering slack): no walking backwards or sideways.
        moving = steps > 1e-9
        travel = np.degrees(np.arctan2(moves[moving, 1], moves[moving, 0]))
        facing = guard_poses[1:, 3][moving]
        off = np.abs((travel - facing + 180.0) % 360.0 - 180.0)
        assert off.size == 0 or off.max() <= STEER_DEGREES + motion.turn_step + 1e-6


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_bodies_keep_up_and_rejoin_by_their_route_clocks(case: str) -> None:
    """At every grid tick each body is at most two cells from its decided cell (it decides only with at
    most one cell left to reach); a patrolling guard stands where its patrol puts it at its route clock."""
    episode = continuous_episode(case)
    cell_size = episode.grid.cell_size
    while not episode.done:
        episode.step()
        for guard, mode in enumerate(episode.modes):
            assert episode.movement.distance(guard, episode.cells[guard]) <= 2 * cell_size + 1e-9
            if mode == "patrol":
                state = episode.patrol.state(guard, episode.route_clocks[guard] + episode.phase)
                assert (episode.cells[guard], episode.headings[guard]) == (state // 4, state % 4)
    assert all(clock <= episode.tick for clock in episode.route_clocks)


def test_sight_is_the_pose_reference_vision() -> None:
    """What the guards see in a grid tick (what the search clears) is, cell for cell, the reference
    vision (a pymunk ray per cell) from every physics tick's pose of the tick, not a table row."""
    episode = continuous_episode("route-escaped")
    scene, _ = setup()
    movement = movement_of(episode)
    ticks_of = [0]
    sights = [set(episode.seen_now.tolist())]
    while not episode.done:
        episode.step()
        ticks_of.append(movement.physics_tick)
        sights.append(set(episode.seen_now.tolist()))
    poses = movement.poses
    for tick, seen in enumerate(sights):
        first = ticks_of[tick - 1] + 1 if tick else 0
        expected: set[int] = set()
        for guard_poses in poses:
            for _, x, y, heading in guard_poses[first : ticks_of[tick] + 1].tolist():
                expected.update(pose_visible_cells(scene.world, scene.grid, scene.cone, x, y, heading).tolist())
        assert seen == expected, tick


def test_bodies_leave_the_space_and_the_trace_has_poses() -> None:
    """A team's bodies are in the scene's space while the episode runs and gone after; the trace JSON
    carries the motion and each tick's poses and meter peaks."""
    scene, _ = setup()
    before = len(scene.world.space.bodies)
    episode = continuous_episode("route-escaped", GuardMotion(move_speed=2.0, turn_speed=90.0, tick_hz=20.0))
    assert len(scene.world.space.bodies) == before + 2
    episode.run()
    assert len(scene.world.space.bodies) == before
    unfinished = continuous_episode("still-captured")
    unfinished.step()
    unfinished.close()
    assert len(scene.world.space.bodies) == before
    data = json.loads(json.dumps(alert_trace_data(episode, scene, search="ripple", intruder="route")))
    assert (data["motion"], data["tick_hz"], data["turn_speed"]) == ("continuous", 20.0, 90.0)
    ticks = episode.tick + 1
    assert [len(p) for p in data["poses"]] == [ticks, ticks] == [len(p) for p in data["awareness_peak"]]
    t, x, y, _ = data["poses"][1][-1]
    assert t == round(episode.tick * episode.rules.dt, 6)
    assert data["paths"][1][-1] == list(scene.grid.unflat(scene.grid.flat(*scene.grid.cell_of((x, y)))))


# -- the CLI ------------------------------------------------------------------------------------


@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    scene, _ = setup()
    return write_level(tmp_path, ROOM), write_patrol(tmp_path, scene.grid)


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(main, [str(arg) for arg in args])


def test_cli_continuous_one_episode_and_trace(files: tuple[Path, Path], tmp_path: Path) -> None:
    level, patrol = files
    trace = tmp_path / "alert.json"
    result = run("alert", level, "--patrol", patrol, "--intruder", "still", "--from", "10.5,6.5", "--motion",
                 "continuous", "--tick-hz", "20", "--trace", trace, "--gif", tmp_path / "a.gif",
                 "--html", tmp_path / "a.html")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (tmp_path / "a.gif").stat().st_size > 0 and "guard_poses" in (tmp_path / "a.html").read_text()
    assert result.stdout.splitlines()[0].startswith("alert room: captured, detected at ")
    data = json.loads(trace.read_text())
    assert data["motion"] == "continuous" and data["tick_hz"] == 20.0 and data["outcome"]["outcome"] == "captured"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--move-speed", "3"], "grid episodes have no game time"),
    ],
    ids=["speed-on-grid"],
)
def test_cli_refusals_are_one_line(files: tuple[Path, Path], args: list[str], message: str) -> None:
    level, patrol = files
    result = run("alert", level, "--patrol", patrol, "--intruder", "still", "--from", "10.5,6.5", *args)
    assert result.exit_code == 2
    assert message in result.output and "Traceback" not in result.output


def test_gif_draws_guards_at_their_bodies(tmp_path: Path) -> None:
    """Each frame's guard discs stand where the bodies were at that tick, not at their cells' centres."""
    import imageio.v3 as iio

    from guardsim.alert.trace import guard_trace
    from guardsim.render.alert import write_alert_gif
    from guardsim.render.palette import PALETTE, guard_index
    from guardsim.render.sneak import SneakFrames

    episode = continuous_episode("route-escaped")
    episode.run()
    scene, table = setup()
    path = tmp_path / "a.gif"
    count = write_alert_gif(path, scene, table, episode, suspicious=0.5)
    poses = np.asarray(episode.record["poses"], dtype=np.float64)
    frames = iio.imread(path, index=None)
    assert count == frames.shape[0] == poses.shape[0]
    drawer = SneakFrames(scene.level, guard_trace(scene, table, episode), size=None)
    grid = scene.grid
    scale = drawer.layout.scale
    checked = 0
    for tick in range(count):
        for guard in range(poses.shape[1]):
            x, y, _ = poses[tick, guard]
            cell = grid.cell_of((x, y))
            assert cell is not None
            centre = (
                grid.origin[0] + (cell[0] + 0.5) * grid.cell_size,
                grid.origin[1] + (cell[1] + 0.5) * grid.cell_size,
            )
            body, middle = np.asarray(drawer.to_pixels((x, y))), np.asarray(drawer.to_pixels(centre))
            if np.hypot(*(body - middle)) < 0.3 * scale:
                continue
            # The disc: pixels of exactly the guard's colour within a cell of the body.
            left, top = drawer.layout.left, drawer.layout.top
            x0, y0 = int(body[0] + left - scale), int(body[1] + top - scale)
            window = frames[tick, y0 : y0 + 2 * scale + 1, x0 : x0 + 2 * scale + 1].astype(int)
            rows, cols = np.nonzero((window == np.asarray(PALETTE[guard_index(guard)])).all(axis=2))
            assert rows.size, (tick, guard)
            disc = np.array([cols.mean() + x0 - left, rows.mean() + y0 - top])
            assert np.hypot(*(disc - body)) < np.hypot(*(disc - middle)), (tick, guard, disc, body, middle)
            checked += 1
    assert checked >= 5  # enough frames catch a body well away from its cell's centre


def test_page_draws_guards_at_their_bodies(tmp_path: Path) -> None:
    """The page carries every guard's poses, and in real Chromium each guard's disc is centred on its
    body, not on its cell, at a tick where the body is between cells."""
    from guardsim.viewer.alerts import write_alert_page
    from tests.pages import page_json
    from tests.test_alert_html import decoded, screenshot
    from tests.test_browser import CHROMIUM

    episode = continuous_episode("route-escaped")
    episode.run()
    scene, table = setup()
    page = tmp_path / "a.html"
    write_alert_page(page, scene, table, episode)
    data = page_json(page.read_text())
    poses = np.asarray(episode.record["poses"], dtype=np.float64)
    for guard, text in enumerate(data["guard_poses"]):
        assert np.allclose(decoded(text, "f4").reshape(-1, 3), poses[:, guard], atol=1e-3)
    if CHROMIUM is None:
        pytest.skip("no chromium on PATH: install Debian's chromium (apt-get install -y chromium), as .ci/run does")
    grid = scene.grid

    def offset(tick: int, guard: int) -> float:
        x, y, _ = poses[tick, guard]
        col, row = (x - grid.origin[0]) / grid.cell_size, (y - grid.origin[1]) / grid.cell_size
        return float(np.hypot(col % 1 - 0.5, row % 1 - 0.5))

    tick, guard = max(((t, g) for t in range(poses.shape[0]) for g in range(poses.shape[1])), key=lambda p: offset(*p))
    assert offset(tick, guard) > 0.3
    (left, top, scale), image = screenshot(page, f"tick={tick}&scale=24", tmp_path / "profile")
    x, y, _ = poses[tick, guard]
    body = np.array(
        [left + (x - grid.origin[0]) / grid.cell_size * scale, top + (y - grid.origin[1]) / grid.cell_size * scale]
    )
    cell = np.floor((body - (left, top)) / scale)
    middle = np.array([left, top]) + (cell + 0.5) * scale
    colour = np.array([int(data["guard_colours"][guard][k : k + 2], 16) for k in (1, 3, 5)])
    x0, y0 = int(body[0] - scale), int(body[1] - scale)
    window = image[y0 : y0 + 2 * scale + 1, x0 : x0 + 2 * scale + 1]
    rows, cols = np.nonzero(np.abs(window - colour).sum(axis=2) <= 6)
    assert rows.size
    disc = np.array([cols.mean() + x0, rows.mean() + y0])
    assert np.hypot(*(disc - body)) < np.hypot(*(disc - middle)), (disc, body, middle)


def test_cli_subprocess_continuous_episodes(files: tuple[Path, Path]) -> None:
    """A real process: many continuous episodes, one worker, a table per strategy."""
    level, patrol = files
    done = subprocess.run(
        [sys.executable, "-m", "guardsim.cli", "alert", str(level), "--patrol", str(patrol), "--intruder", "evader",
         "--spotted", "--episodes", "2", "--workers", "1", "--max-seconds", "30", "--motion", "continuous"],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "| ripple | 2/2 |" in done.stdout


def test_grid_route_clocks_are_the_tick() -> None:
    """On the grid every guard decides every tick: the route clock is the tick (the grid's behaviour)."""
    episode = continuous_episode("route-escaped", motion="grid")
    episode.run()
    assert episode.route_clocks == [episode.tick, episode.tick]
