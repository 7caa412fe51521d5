"""Cameras, light and shadow: the level keys and their checks, the light map, the cameras' swing, and the
sneak searches with cameras as watchers of the lap and light scaling the meters, checked against a brute
force over (lap tick, cell, meters) that computes sight, light and meters itself."""

from __future__ import annotations

import base64
import json
import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.detection import GuardDetection
from guardsim.detection.cameras import camera_ticks
from guardsim.detection.light import light_map
from guardsim.detection.sight import patrol_gains
from guardsim.detection.watch import joint_lap, lap_gains, level_watch
from guardsim.errors import LevelError, LimitError
from guardsim.importers.ldtk import import_ldtk
from guardsim.importers.tiled import import_tiled
from guardsim.level import Camera, Level, Light, check_level_data
from guardsim.patrol import Patrol, patrol_setup
from guardsim.scene import Scene
from guardsim.sneak import sneak_check
from guardsim.vision.table import ViewTable
from tests.common import REPO, TINY_LEVELS, level_from, random_loop, scene_from, write_level

DOORWAY = REPO / "examples" / "levels" / "camera-doorway.json"

# --- The level keys ---


@pytest.mark.parametrize(
    ("changes", "where", "words"),
    [
        ({"cameras": [{"position": [3, 3]}]}, "cameras[0].position", "inside a wall (holes[0])"),
        ({"cameras": [{"position": [1, 1]}, {"position": [9, 1]}]}, "cameras[1].position", "off the level"),
        ({"cameras": [{"position": [1, 1], "sweep": 400}]}, "cameras[0].sweep", "at most 360"),
        ({"lights": [{"position": [1, 1], "radius": 2, "intensity": 1.5}]}, "lights[0].intensity", "at most 1"),
        ({"lights": [{"position": [1, 1], "radius": 2, "intensity": 0}]}, "lights[0].intensity", "must be positive"),
        ({"lights": [{"position": [-1, 1], "radius": 2}]}, "lights[0].position", "off the level"),
        ({"lights": [{"position": [1, 1]}]}, "lights[0].radius", "missing"),
        ({"ambient_light": 1.5}, "ambient_light", "at most 1"),
        ({"cameras": [{"position": [1, 1], "zoom": 2}]}, "cameras[0].zoom", "unknown key"),
        ({"guard": {"dark_sight": -1}}, "guard.dark_sight", "at least 0"),
    ],
)
def test_bad_cameras_and_lights_name_the_key_path(changes: dict[str, object], where: str, words: str) -> None:
    """Each problem is one line naming the key path, e.g. ``cameras[2].position``."""
    _, problems = check_level_data(TINY_LEVELS["square-with-hole"] | changes)
    assert problems, changes
    assert problems[0].where == where and words in str(problems[0]), problems[0]


def test_a_camera_on_a_wall_edge_is_accepted_and_the_keys_round_trip() -> None:
    """A camera on a wall's boundary is valid; the keys write back as they were read."""
    from guardsim.level import level_to_data, parse_level

    data = TINY_LEVELS["square-with-hole"] | {
        "cameras": [{"position": [2, 3], "heading": 180, "sweep": 90, "view_range": 4}],
        "ambient_light": 0.25,
        "lights": [{"position": [6, 0], "radius": 3, "intensity": 0.5}],
    }
    level = parse_level(data)
    assert level.cameras[0] == Camera((2.0, 3.0), heading=180, sweep=90, view_range=4)
    assert parse_level(level_to_data(level)) == level
    assert "cameras" not in level_to_data(parse_level(TINY_LEVELS["square-with-hole"]))


def test_validate_prints_the_key_path_and_exits_2(tmp_path: Path) -> None:
    path = write_level(tmp_path, TINY_LEVELS["square-with-hole"] | {"cameras": [{"position": [3, 3]}]})
    result = CliRunner().invoke(main, ["validate", str(path)])
    assert result.exit_code != 0
    assert "cameras[0].position" in result.output and "inside a wall" in result.output


# --- Light and the cameras' swing ---


def test_the_light_map_follows_the_rule_and_walls_cast_shadows() -> None:
    """Lamps add ``intensity * (1 - d / radius)`` to the ambient light where they see the cell centre."""
    scene = scene_from(
        TINY_LEVELS["square-with-hole"], ambient_light=0.1, lights=[{"position": [0.5, 3.0], "radius": 5}]
    )
    light = light_map(scene)
    assert light.shape == scene.grid.shape
    # Beside the lamp, and behind the pillar from it (the pillar spans x 2..4, y 2..4).
    assert light[3, 0] == pytest.approx(0.1 + (1 - math.hypot(0, 0.5) / 5))
    assert light[3, 5] == pytest.approx(0.1)
    assert light[0, 5] == pytest.approx(min(1.0, 0.1 + max(0.0, 1 - math.hypot(5, 2.5) / 5)))
    assert light.max() <= 1.0


def test_a_camera_swings_by_the_rule_and_rounds_its_period_with_a_note() -> None:
    whole = Camera((0.0, 0.0), heading=90, sweep=90, turn_speed=90, pause=0.5)
    assert camera_ticks(whole, 0.5) == (6, None)
    odd = Camera((0.0, 0.0), heading=90, sweep=100, turn_speed=30, pause=1.0)
    ticks, note = camera_ticks(odd, 0.5)
    assert ticks == 17 and note is not None and "rounded to 17 ticks" in note
    assert camera_ticks(Camera((0.0, 0.0)), 0.5) == (1, None)


def test_the_joint_lap_is_the_lcm_and_has_a_raisable_limit() -> None:
    scene = scene_from(
        TINY_LEVELS["empty-square"],
        cameras=[
            {"position": [0, 0], "heading": 45, "sweep": 90, "turn_speed": 90, "pause": 0.5},
            {"position": [4, 4], "heading": 225, "sweep": 60, "turn_speed": 60, "pause": 0},
        ],
    )
    watch = level_watch(scene, 0.5)
    assert watch.periods == (6, 4)
    assert joint_lap(5, watch) == 60
    with pytest.raises(LimitError, match=r"joint lap .* is 60 ticks, over the limit of 50 \(raise it with --max-lap\)"):
        joint_lap(5, watch, max_lap=50)


def test_full_light_and_no_camera_give_the_gains_unchanged() -> None:
    """Ambient 1 makes every lamp irrelevant: the gains are the bytes they were without light."""
    plain = scene_from(TINY_LEVELS["square-with-hole"])
    lamps = scene_from(TINY_LEVELS["square-with-hole"], lights=[{"position": [1, 1], "radius": 3, "intensity": 0.5}])
    setup = patrol_setup(plain)
    patrol = Patrol(random_loop(plain, np.random.default_rng(3), 3)[None, :], 6, "test")
    detection = GuardDetection.of_level(plain.level)
    before = patrol_gains(
        plain.grid, setup.table, patrol.states, detection.model, view_range=detection.view_range, dt=detection.dt
    )
    after, states = lap_gains(lamps.grid, setup.table, patrol.states, detection, level_watch(lamps, detection.dt))
    assert after.gain.tobytes() == before.gain.tobytes() and after.cameras == 0
    assert np.array_equal(states, patrol.states)


# --- The sneak searches against brute force ---


def _heading(camera: Camera, tick: int, dt: float) -> float:
    """The swing's rule, written again: faces heading - sweep/2 at 0, turns, pauses, turns back, pauses."""
    if camera.sweep == 0:
        return camera.heading
    turn, pause = camera.sweep / camera.turn_speed, camera.pause
    period = 2 * (turn + pause)
    t = (tick * dt) % period
    low = camera.heading - camera.sweep / 2
    if t < turn:
        return low + camera.turn_speed * t
    if t < turn + pause:
        return low + camera.sweep
    if t < 2 * turn + pause:
        return low + camera.sweep - camera.turn_speed * (t - turn - pause)
    return low


def _clear(scene: Scene, eye: tuple[float, float], target: tuple[float, float]) -> bool:
    length = math.hypot(target[0] - eye[0], target[1] - eye[1])
    if length < 1e-9:
        return True
    hair = 1e-6 / length
    start = (eye[0] + (target[0] - eye[0]) * hair, eye[1] + (target[1] - eye[1]) * hair)
    return scene.world.line_of_sight(start, target)


class _World:
    """Sight, light and meters of a tiny level, computed from the rules directly (pymunk rays per cell)."""

    def __init__(self, scene: Scene, table: ViewTable, patrol: Patrol, detection: GuardDetection) -> None:
        level, grid = scene.level, scene.grid
        self.grid, self.table, self.detection = grid, table, detection
        dt = detection.dt
        cols = grid.shape[1]
        free = np.flatnonzero(grid.traversable.ravel())
        centre = {int(c): grid.centre(int(c) % cols, int(c) // cols) for c in free}
        self.light = np.zeros(grid.size)
        for cell, point in centre.items():
            total = level.ambient_light
            for lamp in level.lights:
                d = math.hypot(point[0] - lamp.position[0], point[1] - lamp.position[1])
                if d <= lamp.radius and _clear(scene, lamp.position, point):
                    total += lamp.intensity * max(0.0, 1 - d / lamp.radius)
            self.light[cell] = min(1.0, total)
        periods = [round(c.period_seconds / dt) if c.sweep else 1 for c in level.cameras]
        self.period = math.lcm(patrol.period or 1, *periods)
        self.guard_states = patrol.states[:, np.arange(self.period) % patrol.states.shape[1]]
        # (watcher, tick) -> {cell: distance} for the cameras.
        self.cameras = []
        for camera in level.cameras:
            reach = camera.view_range or level.guard.view_range
            sights = []
            for tick in range(self.period):
                angle = math.radians(_heading(camera, tick, dt))
                seen = {}
                for cell, point in centre.items():
                    dx, dy = point[0] - camera.position[0], point[1] - camera.position[1]
                    d = math.hypot(dx, dy)
                    if d > reach + 1e-9:
                        continue
                    cone = (
                        d == 0
                        or (dx * math.cos(angle) + dy * math.sin(angle)) / d
                        >= math.cos(math.radians(camera.fov_degrees) / 2) - 1e-9
                    )
                    if cone and _clear(scene, camera.position, point):
                        seen[cell] = d
                sights.append(seen)
            near = level.guard.detect_near if camera.detect_near is None else camera.detect_near
            far = level.guard.detect_far if camera.detect_far is None else camera.detect_far
            self.cameras.append((sights, reach, near, far))
        self.watchers = patrol.guards + len(self.cameras)

    def _gain(self, v: float, d: float, reach: float, near: float, far: float) -> float:
        if v <= 0:
            return 0.0
        seconds = near + (far - near) * min(d / reach, 1.0)
        return v * self.detection.dt / seconds if seconds > 0 else math.inf

    def gains(self, tick: int, cell: int) -> list[float]:
        """What a tick at lap tick ``tick`` in ``cell`` adds to each watcher's meter (0: unseen)."""
        model, grid, cols = self.detection.model, self.grid, self.grid.shape[1]
        out = []
        for guard in range(self.guard_states.shape[0]):
            state = int(self.guard_states[guard, tick % self.period])
            own = state // 4
            d = grid.cell_size * math.hypot(cell // cols - own // cols, cell % cols - own % cols)
            if cell not in self.table.sees(state).tolist():
                out.append(0.0)
                continue
            v = 1.0 if model.dark_sight > 0 and d <= model.dark_sight else float(self.light[cell])
            out.append(self._gain(v, d, self.detection.view_range, model.detect_near, model.detect_far))
        for sights, reach, near, far in self.cameras:
            seen = sights[tick % self.period]
            out.append(self._gain(float(self.light[cell]), seen[cell], reach, near, far) if cell in seen else 0.0)
        return out

    def step(self, meters: tuple[float, ...], tick: int, cell: int) -> tuple[float, ...] | None:
        fall = self.detection.dt / self.detection.model.forget
        out = []
        for level, gain in zip(meters, self.gains(tick, cell)):
            after = level + gain if gain > 0 else level - fall
            after = 1.0 if after >= 1.0 - 1e-9 else min(1.0, max(0.0, after))
            if after >= 1.0 - 1e-9:
                return None
            out.append(after)
        return tuple(out)

    def fastest(self, source: int, target: int, entry: int | None, *, unseen: bool) -> int | None:
        """Breadth first over (lap tick, cell, exact meters), nothing pruned (``unseen``: no watcher's
        gain may be above 0)."""
        starts = range(self.period) if entry is None else [entry]
        frontier = set()
        for tick in starts:
            meters = self.step((0.0,) * self.watchers, tick, source)
            if meters is not None and not (unseen and any(self.gains(tick, source))):
                frontier.add((tick, source, meters))
        visited = set(frontier)
        ticks = 0
        while frontier:
            if any(cell == target for _, cell, _ in frontier):
                return ticks
            upcoming = set()
            for tick, cell, meters in frontier:
                after = (tick + 1) % self.period
                for other in [cell, *[int(o) for o in self.grid.neighbours[cell] if o >= 0]]:
                    if unseen and any(self.gains(after, other)):
                        continue
                    stepped = self.step(meters, after, other)
                    if stepped is not None and (after, other, stepped) not in visited:
                        visited.add((after, other, stepped))
                        upcoming.add((after, other, stepped))
            if len(visited) > 60_000:
                raise _TooMany
            frontier = upcoming
            ticks += 1
        return None

    def replay(self, start: int, cells: list[int]) -> np.ndarray:
        fall = self.detection.dt / self.detection.model.forget
        meters = np.zeros(self.watchers)
        rows = []
        for offset, cell in enumerate(cells):
            for index, gain in enumerate(self.gains(start + offset, cell)):
                after = meters[index] + gain if gain > 0 else meters[index] - fall
                meters[index] = 1.0 if after >= 1.0 - 1e-9 else min(1.0, max(0.0, after))
            rows.append(meters.copy())
        return np.asarray(rows)


class _TooMany(Exception):
    pass


def _random_watch(level: dict[str, object], scene: Scene, rng: np.random.Generator) -> dict[str, object]:
    """One or two sweeping cameras at cell centres of the floor, a lamp or two and a dark ambient."""
    cols = scene.grid.shape[1]
    free = np.flatnonzero(scene.grid.traversable.ravel())
    swings = [(90, 90, 0.5), (60, 60, 0.0), (180, 180, 1.0)]  # whole-tick periods at 0.5 s: 6, 4, 8
    cameras = []
    for _ in range(1 + int(rng.integers(2))):
        cell = int(free[rng.integers(free.size)])
        sweep, turn, pause = swings[int(rng.integers(len(swings)))]
        cameras.append(
            {
                "position": [cell % cols + 0.5, cell // cols + 0.5],
                "heading": float(rng.integers(8)) * 45,
                "fov_degrees": 60,
                "view_range": 3,
                "sweep": sweep,
                "turn_speed": turn,
                "pause": pause,
                "detect_near": 0.5,
                "detect_far": 1.0,
            }
        )
    lights = []
    for _ in range(1 + int(rng.integers(2))):
        cell = int(free[rng.integers(free.size)])
        lights.append({"position": [cell % cols + 0.5, cell // cols + 0.5], "radius": 2.5, "intensity": 0.75})
    return level | {"cameras": cameras, "lights": lights, "ambient_light": float(rng.choice([0.0, 0.25]))}


@pytest.mark.parametrize("name", [pytest.param("square-with-hole", marks=pytest.mark.slow), "l-room"])
def test_sneak_with_cameras_and_light_agrees_with_brute_force(name: str) -> None:
    """Both rules, both directions: found, fastest ticks and slack equal the brute force's; the reported
    meters replay through the rule."""
    guard = {"start": [0.5, 0.5], "heading": "right", "view_range": 3.5, "fov_degrees": 180, "dark_sight": 1.0}
    base = TINY_LEVELS[name] | {"guard": guard}
    plain = scene_from(base)
    rng = np.random.default_rng(40)
    compared = 0
    outcomes = set()
    watched = dimmed = False
    for trial in range(4):
        scene = Scene.from_level(level_from(_random_watch(base, plain, rng)))
        setup = patrol_setup(scene)
        lap = random_loop(scene, rng, int(rng.integers(1, 3)))
        patrol = Patrol(lap[None, :], lap.size, "test")
        detection = GuardDetection.of_level(scene.level)
        watch = level_watch(scene, detection.dt)
        world = _World(scene, setup.table, patrol, detection)
        free = np.flatnonzero(setup.goal)
        for _ in range(2):
            source, target = (int(free[rng.integers(free.size)]) for _ in range(2))
            for undetected in (False, True):
                result = sneak_check(
                    scene.grid, setup.table, patrol, source, target, detection=detection, undetected=undetected,
                    watch=watch,
                )  # fmt: skip
                assert result.period == world.period
                try:
                    fastest = world.fastest(source, target, None, unseen=not undetected)
                    through = sum(
                        world.fastest(source, target, entry, unseen=not undetected) is not None
                        for entry in range(world.period)
                    )
                except _TooMany:
                    continue
                compared += 1
                outcomes.add((undetected, result.found))
                watched |= bool(result.gains.gain[result.gains.guards :].any())
                dimmed |= bool(((result.gains.gain[: result.gains.guards] > 0) & (watch.light < 1)).any())
                assert result.found == (fastest is not None), (trial, source, target, undetected)
                assert result.slack == through
                assert result.path is not None and result.grade is not None
                if result.found:
                    assert result.path.ticks == fastest
                replay = world.replay(result.path.start_tick, result.path.cells.tolist())
                assert np.allclose(result.grade.meters, replay, atol=1e-12)
    assert compared >= 10
    assert (True, True) in outcomes and (False, True) in outcomes
    # The cameras saw floor and the guards looked into the dim in the cases compared.
    assert watched and dimmed


# --- The doorway camera and the dark side passage ---


def _post(tmp_path: Path) -> Path:
    """The guard of camera-doorway.json standing at the side passage's end, looking back down it."""
    return REPO / "examples" / "levels" / "camera-doorway-post.json"


def test_the_dark_side_passage_gets_past_the_doorway_camera(tmp_path: Path) -> None:
    """In the dark the side passage is the way through; in full light it is closed; a spot the camera
    sweeps over fails check --safe with the lap ticks it is watched."""
    post = _post(tmp_path)
    runner = CliRunner()
    out = tmp_path / "dark"
    dark = runner.invoke(
        main, ["sneak", str(DOORWAY), "--patrol", str(post), "--to", "14.5,6.5", "--undetected", "--out", str(out)]
    )
    assert dark.exit_code == 0, dark.output
    assert "sneaks: undetected" in dark.output and "by camera: 0.00" in dark.output
    data = json.loads((out / "sneak.json").read_text())
    assert data["found"] and data["period"] == 10
    # Through the passage (row 3), never the doorway (row 0).
    assert [5, 3] in data["path"] and all(row != 0 for _, row in data["path"])
    lit = tmp_path / "lit.json"
    lit.write_text(DOORWAY.read_text().replace('"ambient_light": 0.0', '"ambient_light": 1.0'))
    closed = runner.invoke(main, ["sneak", str(lit), "--patrol", str(post), "--to", "14.5,6.5", "--undetected"])
    assert closed.exit_code == 0 and "caught: no undetected path" in closed.output
    check = runner.invoke(
        main, ["check", str(DOORWAY), "--patrol", str(post), "--safe", "9.5,0.5", "--safe", "2.5,3.5"]
    )
    assert check.exit_code == 1
    assert "safe 9.5,0.5: cell [9, 0] is in view of camera 0 for 2 of 10 lap ticks" in check.output
    assert "camera 0 watches it at lap ticks 0, 9" in check.output and "2.5,3.5" not in check.output


def test_a_joint_lap_past_the_limit_is_one_line_and_exit_2(tmp_path: Path) -> None:
    """A 3-tick patrol (the guard waits, steps out and back) and the 10-tick swing: a joint lap of 30."""
    patrol = json.loads(_post(tmp_path).read_text())
    patrol["period"] = 3
    patrol["guards"] = [{"loop": [[12, 3], [12, 3], [13, 3], [12, 3]], "headings": [2, 2, 0, 2]}]
    path = tmp_path / "three.json"
    path.write_text(json.dumps(patrol))
    base = ["sneak", str(DOORWAY), "--patrol", str(path), "--to", "14.5,6.5"]
    result = CliRunner().invoke(main, [*base, "--max-lap", "20"])
    assert result.exit_code == 2
    assert (
        "the joint lap of the patrol's 3 ticks and the cameras' swings (10 ticks) is 30 ticks, over the limit of 20 "
        "(raise it with --max-lap)" in result.output
    )
    assert len(result.output.strip().splitlines()) == 2  # the player start's line, then the error
    raised = CliRunner().invoke(main, [*base, "--max-lap", "30"])
    assert raised.exit_code == 0 and "slack" in raised.output
    checked = CliRunner().invoke(
        main, ["check", str(DOORWAY), "--patrol", str(path), "--safe", "9.5,0.5", "--max-lap", "20"]
    )
    assert checked.exit_code == 2 and "is 30 ticks, over the limit of 20" in checked.output


# --- Alert: camera alarms and dark cells ---


def test_a_camera_alarm_tells_every_guard_where_the_intruder_is() -> None:
    """An intruder walking toward the doorway fills the camera's meter at the first lit cell in its cone
    ((3, 0): (2, 0) is dark): the alarm event, and the guard, far off and blind to it, searches from the
    intruder's cell of that tick."""
    from guardsim.alert import alert_episode

    scene = Scene.from_level(level_from(json.loads(DOORWAY.read_text())))
    grid = scene.grid
    post = Patrol(np.array([[grid.flat(12, 3) * 4 + 2]]), 1, "post")
    route = [grid.flat(col, 0) for col in range(0, 15)]
    episode = alert_episode(scene, post, source=route[0], route=route, max_seconds=20)
    while not episode.done and not any(event.event == "alarm" for event in episode.events):
        episode.step()
    alarm = next(event for event in episode.events if event.event == "alarm")
    assert alarm.guard == 1  # the first camera, after the one guard
    assert episode.last_known == grid.flat(3, 0) and episode.modes == ["search"]
    assert episode.cameras.levels() == [1.0] and episode.meters[0].level == 0.0


def test_a_dark_cell_hides_an_intruder_a_guard_looks_at() -> None:
    """Down the dark side passage, in the guard's cone, the guard's meter never moves; in full light it fills."""
    from guardsim.alert import alert_episode

    data = json.loads(DOORWAY.read_text())
    outcomes = []
    for ambient in (0.0, 1.0):
        scene = Scene.from_level(level_from(data, ambient_light=ambient, cameras=[]))
        grid = scene.grid
        post = Patrol(np.array([[grid.flat(12, 3) * 4 + 2]]), 1, "post")
        route = [grid.flat(col, 3) for col in range(0, 11)]
        episode = alert_episode(scene, post, source=route[0], route=route, max_seconds=8)
        peak = 0.0
        while not episode.done:
            episode.step()
            peak = max(peak, episode.meters[0].level)
        outcomes.append(peak)
    assert outcomes[0] == 0.0 and outcomes[1] == 1.0


# --- Importers: Tiled objects and LDtk entities ---

CAMERAS_TMX = REPO / "tests" / "data" / "watchers" / "cameras.tmx"
TILED = shutil.which("tiled")


def _watchers_of(level: Level) -> tuple[object, ...]:
    return level.cameras, level.lights, level.ambient_light


def test_tiled_camera_and_light_objects_become_level_keys() -> None:
    """Classes camera/light in any case; heading from the rotation without a heading property; an ellipse
    lamp's radius from its width; the map property ambient_light."""
    imported = import_tiled(CAMERAS_TMX)
    level = imported.level
    assert level.cameras == (
        Camera((1.0, 1.0), heading=45, sweep=90, turn_speed=45, pause=1),
        Camera((9.0, 3.0), heading=180, fov_degrees=45),
    )
    assert level.lights == (Light((3.0, 3.0), 2.0), Light((7.0, 2.0), 3.0, 0.5))
    assert level.ambient_light == 0.2
    assert "2 camera(s), 2 light(s), ambient light 0.2" in " ".join(imported.changes)
    # Cameras and lamps are never walls: the level is the room and its pillar only.
    assert len(level.holes) == 1


@pytest.mark.skipif(TILED is None, reason="Debian's tiled is not installed (.ci/run installs it)")
def test_real_tiled_opens_the_map_and_its_json_imports_the_same(tmp_path: Path) -> None:
    """Real Tiled opens the hand-written TMX and saves it as JSON; both import to the same watchers."""
    again = tmp_path / "cameras.json"
    runtime = tmp_path / "runtime"
    runtime.mkdir(mode=0o700)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(tmp_path), XDG_RUNTIME_DIR=str(runtime))
    assert TILED is not None
    done = subprocess.run(
        [TILED, "--export-map", "json", str(CAMERAS_TMX), str(again)], env=env, capture_output=True, text=True,
        timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert _watchers_of(import_tiled(again).level) == _watchers_of(import_tiled(CAMERAS_TMX).level)


def test_a_tiled_camera_inside_a_wall_is_one_line_naming_it(tmp_path: Path) -> None:
    text = CAMERAS_TMX.read_text().replace('x="144" y="48"', 'x="88" y="56"')  # inside the pillar
    path = tmp_path / "bad.tmx"
    path.write_text(text)
    with pytest.raises(LevelError, match=r"cameras\[1\]\.position: \(5\.5, 3\.5\) lies inside a wall"):
        import_tiled(path)


def test_ldtk_camera_and_light_entities_become_level_keys(tmp_path: Path) -> None:
    from tests.test_ldtk import project, write

    data = project(cols=6, rows=4, csv=[1] * 6 + [1, 0, 0, 0, 0, 1] * 2 + [1] * 6,
                   entities=(("Camera", 24, 24), ("Light", 72, 40)))  # fmt: skip
    things = data["levels"][0]["layerInstances"][0]["entityInstances"]
    things[0]["fieldInstances"] = [
        {"__identifier": "heading", "__value": 90, "__type": "Float"},
        {"__identifier": "sweep", "__value": 60, "__type": "Float"},
    ]
    things[1]["fieldInstances"] = [{"__identifier": "radius", "__value": 3, "__type": "Float"}]
    data["levels"][0]["fieldInstances"] = [{"__identifier": "ambient_light", "__value": 0.3, "__type": "Float"}]
    level = import_ldtk(write(tmp_path, data)).level
    assert level.cameras == (Camera((1.5, 1.5), heading=90, sweep=60),)
    assert level.lights == (Light((4.5, 2.5), 3.0),) and level.ambient_light == 0.3


# --- Pictures ---


def test_render_draws_the_swing_and_shades_the_dark_with_a_colour_bar(tmp_path: Path) -> None:
    """Decoded: the camera's magenta is drawn, the dark floor is darker than the lamp-lit floor, the colour
    bar runs from dark to light; a fully lit level without cameras renders as it did without the keys."""
    import imageio.v3 as iio

    from guardsim.render.palette import WATCH_COLOURS

    runner = CliRunner()
    png = tmp_path / "doorway.png"
    result = runner.invoke(main, ["render", str(DOORWAY), "--png", str(png)])
    assert result.exit_code == 0 and "1 camera(s), 1 light(s), light 0.00 to 0.90" in result.output
    image = iio.imread(png)
    assert (image[..., :3] == WATCH_COLOURS["camera"]).all(axis=-1).sum() > 100
    plain = tmp_path / "plain.png"
    data = json.loads(DOORWAY.read_text())
    lit = {key: value for key, value in data.items() if key not in ("cameras", "lights", "ambient_light")}
    runner.invoke(main, ["render", str(write_level(tmp_path, lit, "lit.json")), "--png", str(plain)])
    bare = iio.imread(plain)
    assert image.shape[0] > bare.shape[0]  # the colour bar
    # The level's own cell (12, 3) is dark; the doorway's (7, 0) is lit by the lamp: both are floor.
    scale = (bare.shape[1] - 2 * 36) // 15

    def pixel(picture: np.ndarray, col: int, row: int) -> np.ndarray:
        return picture[36 + row * scale + scale // 3, 36 + col * scale + scale // 3, :3].astype(int)

    assert pixel(image, 13, 5).sum() < pixel(bare, 13, 5).sum() - 200
    assert abs(pixel(image, 7, 0).sum() - pixel(bare, 7, 0).sum()) < 60
    again = tmp_path / "again.png"
    runner.invoke(
        main, ["render", str(write_level(tmp_path, lit | {"ambient_light": 1.0}, "one.json")), "--png", str(again)]
    )
    assert again.read_bytes() == plain.read_bytes()


@pytest.mark.slow
def test_the_sneak_gif_draws_the_cameras_their_meters_and_the_dark(tmp_path: Path) -> None:
    """Decoded frames: the camera's magenta in every frame, the camera's meter bar filled red once it
    detects, and the dark floor dithered (near-black pixels among the floor's)."""
    import imageio.v3 as iio

    from guardsim.render.palette import GUARD_COLOURS, palette_rgb

    post = _post(tmp_path)
    lit = tmp_path / "lit.json"
    lit.write_text(DOORWAY.read_text().replace('"ambient_light": 0.0', '"ambient_light": 1.0'))
    for level, out in ((DOORWAY, tmp_path / "dark"), (lit, tmp_path / "lit")):
        result = CliRunner().invoke(
            main,
            [
                "sneak",
                str(level),
                "--patrol",
                str(post),
                "--to",
                "14.5,6.5",
                "--undetected",
                "--out",
                str(out),
                "--gif",
            ],
        )
        assert result.exit_code == 0, result.output
    dark = iio.imread(tmp_path / "dark" / "sneak.gif", index=None)[..., :3]
    lit_frames = iio.imread(tmp_path / "lit" / "sneak.gif", index=None)[..., :3]
    magenta = np.asarray(GUARD_COLOURS[4])
    assert all((frame == magenta).all(axis=-1).sum() > 20 for frame in dark)
    near_black = palette_rgb()[5]  # the outline entry the dark dithers with
    assert (dark[5] == near_black).all(axis=-1).sum() > (lit_frames[5] == near_black).all(axis=-1).sum() + 200
    # Caught in the doorway: the camera's bar fills with the detected red at the end.
    red = np.asarray(GUARD_COLOURS[0])
    assert (lit_frames[-1] == red).all(axis=-1).sum() > (lit_frames[0] == red).all(axis=-1).sum()


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None, reason="no chromium on PATH (apt-get install -y chromium, as .ci/run does)")
def test_the_sneak_page_draws_the_cameras_cone_meter_and_the_light_in_real_chromium(tmp_path: Path) -> None:
    """Real headless Chromium: no script error; the camera's magenta is on the canvas with the cameras
    layer and not without; the light layer darkens the dark floor and leaves the lamp-lit doorway nearly
    as it was; the page's data carries the camera's headings and its meters as sneak.json has them."""
    from tests.pages import page_json
    from tests.test_browser import cell_pixels, element, geometry, view

    out = tmp_path / "out"
    result = CliRunner().invoke(
        main,
        ["sneak", str(DOORWAY), "--patrol", str(_post(tmp_path)), "--to", "14.5,6.5", "--undetected",
         "--out", str(out), "--html"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    page = out / "sneak.html"
    data = page_json(page.read_text())
    sneak = json.loads((out / "sneak.json").read_text())
    scene = Scene.from_level(level_from(json.loads(DOORWAY.read_text())))
    watch = level_watch(scene, 0.5)
    headings = np.frombuffer(base64.b64decode(data["watch"]["cameras"][0]["headings"]), dtype="<f4")
    assert np.allclose(headings, watch.cameras[0].headings)
    meters = np.frombuffer(base64.b64decode(data["watch"]["meters"]), dtype="<f4")
    assert np.allclose(meters, np.asarray(sneak["awareness"])[:, 1], atol=1e-6)
    magenta = np.asarray(data["watch"]["camera_colour"])
    profile = tmp_path / "profile"
    dom, shown = view(page, "tick=4&layers=cameras,light&scale=40", profile)
    assert element(dom, "errors") == ""
    _, bare = view(page, "tick=4&layers=intruder&scale=40", profile)
    left, top, scale = geometry(dom)

    def on_canvas(image: np.ndarray) -> int:
        area = image[top : top + 7 * scale, left : left + 15 * scale].astype(int)
        return int((np.abs(area - magenta).sum(axis=-1) < 30).sum())

    assert on_canvas(shown) > 100 and on_canvas(bare) == 0
    dark_cell, lit_cell = np.array([[13, 5]]), np.array([[7, 0]])
    assert cell_pixels(shown, dom, dark_cell).sum() < cell_pixels(bare, dom, dark_cell).sum() - 150
    assert abs(cell_pixels(shown, dom, lit_cell).sum() - cell_pixels(bare, dom, lit_cell).sum()) < 80


def test_a_dark_corner_in_a_guards_view_is_a_hiding_spot() -> None:
    """Time to detection and exposure count the light: the side passage in front of the guard is never
    detected and unexposed in the dark, detected in a few ticks in full light."""
    data = json.loads(DOORWAY.read_text())
    found = []
    for ambient in (0.0, 1.0):
        scene = Scene.from_level(level_from(data, ambient_light=ambient))
        grid = scene.grid
        table = patrol_setup(scene).table
        post = Patrol(np.array([[grid.flat(12, 3) * 4 + 2]]), 1, "post")
        detection = GuardDetection.of_level(scene.level)
        result = sneak_check(
            grid, table, post, grid.flat(0, 3), grid.flat(14, 6), detection=detection, undetected=True,
            watch=level_watch(scene, detection.dt),
        )  # fmt: skip
        cell = grid.flat(8, 3)
        found.append((int(result.time_to_detection[cell]), float(result.exposure[cell])))
        if ambient == 0.0:
            # The safest places to wait: never detected, however long the player stays.
            assert result.hiding_spots and all(spot.lasts is None for spot in result.hiding_spots)
    (dark_lasts, dark_exposure), (lit_lasts, lit_exposure) = found
    assert dark_lasts == -1 and dark_exposure == 0.0
    assert lit_lasts > 0 and lit_exposure == 1.0


@pytest.mark.slow
def test_the_patrol_page_carries_the_light_and_the_cameras(tmp_path: Path) -> None:
    """patrol --html on a level with a camera and darkness: the page's data has both layers, shown on
    opening, the light as light_map gives it; a level without them has neither."""
    from tests.pages import page_json

    result = CliRunner().invoke(main, ["patrol", str(DOORWAY), "--out", str(tmp_path / "dark"), "--html"])
    assert result.exit_code == 0, result.output
    data = page_json((tmp_path / "dark" / "patrol.html").read_text())
    scene = Scene.from_level(level_from(json.loads(DOORWAY.read_text())))
    light = np.frombuffer(base64.b64decode(data["watch"]["light"]), dtype="<f4")
    assert np.allclose(light, light_map(scene).ravel(), atol=1e-6)
    assert len(data["watch"]["cameras"]) == 1 and {"light", "cameras"} <= set(data["default_layers"])
    plain = {
        k: v for k, v in json.loads(DOORWAY.read_text()).items() if k not in ("cameras", "lights", "ambient_light")
    }
    result = CliRunner().invoke(
        main, ["patrol", str(write_level(tmp_path, plain)), "--out", str(tmp_path / "plain"), "--html"]
    )
    assert "watch" not in page_json((tmp_path / "plain" / "patrol.html").read_text())


def test_point_sight_by_the_bresenham_rule_is_the_line_of_cells() -> None:
    """With --los bresenham a camera or lamp sees from the cell holding it (a floor cell on a cell's side),
    a target when every cell of the Bresenham line to it is floor."""
    from guardsim.vision.bresenham import bresenham_line
    from guardsim.vision.point import PointSight

    scene = scene_from(TINY_LEVELS["square-with-hole"])
    grid = scene.grid
    sight = PointSight(scene.world, grid, rule="bresenham", reach=4.0)
    floor = grid.traversable
    for eye in [(0.5, 0.5), (2.0, 3.0), (4.0, 2.5), (6.0, 6.0), (3.0, 0.0)]:
        cells, _ = sight.cells(eye, 4.0)
        col, row = sight.eye_cell(eye)
        assert floor[row, col]
        expected = []
        for cell in np.flatnonzero(floor.ravel()).tolist():
            c, r = grid.unflat(cell)
            centre = grid.centre(c, r)
            if math.hypot(centre[0] - eye[0], centre[1] - eye[1]) > 4.0 + 1e-9:
                continue
            if all(floor[y, x] for x, y in bresenham_line(col, row, c, r)):
                expected.append(cell)
        assert cells.tolist() == expected, eye


def test_a_swing_too_long_for_any_lap_is_one_line_and_exit_2(tmp_path: Path) -> None:
    """A valid but absurd turn speed makes a swing of 1e302 s: refused before a heading is listed."""
    data = json.loads(DOORWAY.read_text())
    data["cameras"][0]["turn_speed"] = 1e-300
    path = write_level(tmp_path, data)
    result = CliRunner().invoke(
        main, ["sneak", str(path), "--patrol", str(_post(tmp_path)), "--to", "14.5,6.5", "--undetected"]
    )
    assert result.exit_code == 2 and "cameras[0]'s swing of 8e+301 s is over 10000000 ticks" in result.output
    data["cameras"][0]["turn_speed"] = 0.01  # 8001 s, 16 002 ticks: over the joint lap's limit
    result = CliRunner().invoke(
        main, ["sneak", str(write_level(tmp_path, data)), "--patrol", str(_post(tmp_path)), "--to", "14.5,6.5"]
    )
    assert result.exit_code == 2 and "cameras[0]'s swing is 16002 ticks, over the limit of 10000" in result.output


def test_the_alert_gif_and_page_draw_the_cameras_on_their_own_clock(tmp_path: Path) -> None:
    """An alert episode's pictures show the camera: its magenta cone in every GIF frame, sweeping (the
    frames differ where it is), and on the page its headings from the episode's phase on (the page's tick
    t is the swing's tick phase + t) with its meter as the episode recorded it, filling at the alarm."""
    import imageio.v3 as iio

    from guardsim.alert import alert_episode
    from guardsim.render.alert import write_alert_gif
    from guardsim.render.palette import GUARD_COLOURS
    from guardsim.viewer.alerts import alert_overlays

    scene = Scene.from_level(level_from(json.loads(DOORWAY.read_text())))
    grid = scene.grid
    post = Patrol(np.array([[grid.flat(12, 3) * 4 + 2]]), 1, "post")
    route = [grid.flat(col, 0) for col in range(0, 15)]
    phase = 3
    episode = alert_episode(scene, post, source=route[0], route=route, phase=phase, max_seconds=8)
    while not episode.done:
        episode.step()
    record = episode.record
    cameras = np.asarray(record["camera_awareness"])
    assert cameras.shape == (len(record["awareness"]), 1)
    alarm = next(event.tick for event in episode.events if event.event == "alarm")
    assert cameras[alarm, 0] == 1.0 and cameras[0, 0] < 1.0

    table = patrol_setup(scene).table
    assert write_alert_gif(tmp_path / "alert.gif", scene, table, episode, suspicious=0.5) > 1
    frames = iio.imread(tmp_path / "alert.gif", index=None)[..., :3]
    magenta = (frames == np.asarray(GUARD_COLOURS[4])).all(axis=-1)
    assert all(frame.sum() > 20 for frame in magenta)
    assert (magenta[0] != magenta[len(magenta) // 2]).sum() > 20  # the cone swept

    overlays = alert_overlays(scene, table, episode, patrol=post)
    assert overlays.watch is not None and {"light", "cameras"} <= set(overlays.layers)
    sweep = level_watch(scene, 0.5).cameras[0].headings
    shown = overlays.watch.cameras[0][1]
    assert np.allclose(shown, np.roll(sweep, -phase)) and not np.allclose(shown, sweep)
    start = next(tick for tick, cell in enumerate(record["intruder"]) if cell is not None)
    assert overlays.watch.meters is not None
    assert np.allclose(overlays.watch.meters[:, 0], cameras[start : start + len(overlays.watch.meters), 0])
