"""Continuous motion: speeds, turns, walls, coverage, determinism and the two vision paths."""

from __future__ import annotations

import csv
import itertools
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner, Result

from guardsim import load_level
from guardsim.cli import main
from guardsim.motion import ContinuousSimulation, GuardMotion, PoseVision, pose_visible_cells, pull_route, run_episode
from guardsim.motion.follower import Follower
from guardsim.scene import Scene
from guardsim.trace import Trace
from guardsim.vision.rules import LineOfSight
from tests.common import LEVELS, REPO, TINY_LEVELS, guardsim_command, level_from, scene_from, tiny_levels, write_level

MOTION = GuardMotion(move_speed=2.0, turn_speed=180.0, tick_hz=30.0)
#: A corridor 20 long and 1 wide, seen only a step ahead.
CORRIDOR = {"name": "corridor", "outer": [[0, 0], [20, 0], [20, 1], [0, 1]], "guard": {"view_range": 1.0}}
#: Two rooms joined by a gap of 0.5, narrower than the guard (radius 0.3).
NARROW_GAP = {
    "name": "narrow gap",
    "outer": [[0, 0], [9, 0], [9, 5], [0, 5]],
    "holes": [[[4, 0], [5, 0], [5, 2.25], [4, 2.25]], [[4, 2.75], [5, 2.75], [5, 5], [4, 5]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}
PLANNERS = ("ripplefront", "tour", "frontier", "sweep")
_SHIPPED: dict[str, Scene] = {}


def shipped(name: str) -> Scene:
    path = next(path for path in LEVELS if path.stem == name)
    return _SHIPPED.setdefault(name, Scene.from_level(load_level(path)))


def run_ticks(simulation: ContinuousSimulation, check: object = None) -> Trace:
    """Step to the end, calling ``check(simulation)`` after every tick."""
    while not simulation.done:
        simulation.step()
        if callable(check):
            check(simulation)
    return simulation.trace()


def pose_steps(trace: Trace) -> tuple[np.ndarray, np.ndarray]:
    assert trace.poses is not None
    moved = np.hypot(np.diff(trace.poses[:, 1]), np.diff(trace.poses[:, 2]))
    turned = np.abs((np.diff(trace.poses[:, 3]) + 180.0) % 360.0 - 180.0)
    return moved, turned


@pytest.mark.parametrize("planner", PLANNERS)
@pytest.mark.parametrize("level", ["mgs_docks", "king_snurre"])
def test_never_faster_than_move_speed_nor_turn_speed(level: str, planner: str) -> None:
    trace = run_episode(shipped(level), planner, seed=0, episode=3, motion=MOTION)
    moved, turned = pose_steps(trace)
    assert trace.covered
    assert moved.max() <= MOTION.move_speed / MOTION.tick_hz + 1e-9
    assert turned.max() <= MOTION.turn_speed / MOTION.tick_hz + 1e-9
    # It does walk at full speed and turn at full rate somewhere: the limits are the binding ones.
    assert moved.max() > 0.99 * MOTION.move_speed / MOTION.tick_hz
    assert turned.max() > 0.99 * MOTION.turn_speed / MOTION.tick_hz


@pytest.mark.parametrize("turn_speed", [90.0, 180.0, 400.0])
def test_u_turn_takes_at_least_180_over_turn_speed(turn_speed: float) -> None:
    scene = scene_from(CORRIDOR)
    motion = GuardMotion(move_speed=2.0, turn_speed=turn_speed, tick_hz=30.0)
    follower = Follower(scene.world, motion, (10.5, 0.5), 0.0)
    ticks = 0
    # A corner straight behind: the guard turns in place, then walks while finishing the turn.
    while abs((follower.heading - 180.0 + 180.0) % 360.0 - 180.0) > 1e-9:
        follower.walk_to((2.5, 0.5))
        ticks += 1
    assert ticks / motion.tick_hz >= 180.0 / turn_speed - 1e-9
    assert ticks == math.ceil(180.0 / (turn_speed / motion.tick_hz) - 1e-9)


def test_every_u_turn_of_an_episode_lasts_its_angle_over_turn_speed() -> None:
    trace = run_episode(shipped("mgs_docks"), "tour", seed=0, motion=MOTION)
    assert trace.poses is not None and trace.measures["u_turns"] > 0
    turned = (np.diff(trace.poses[:, 3]) + 180.0) % 360.0 - 180.0
    sign = np.sign(np.where(np.abs(turned) > 1e-7, turned, 0.0))
    runs, start = [], 0
    for index in range(1, len(sign) + 1):
        if index == len(sign) or sign[index] != sign[start]:
            if sign[start] != 0:
                runs.append((index - start, abs(turned[start:index].sum())))
            start = index
    for ticks, angle in runs:
        assert ticks / MOTION.tick_hz >= angle / MOTION.turn_speed - 1e-9
    assert sum(angle >= 135 - 1e-6 for _, angle in runs) == trace.measures["u_turns"]


@pytest.mark.parametrize("move_speed", [1.0, 2.0, 3.7])
def test_straight_corridor_walked_in_length_over_move_speed(move_speed: float) -> None:
    scene = scene_from(CORRIDOR)
    grid = scene.grid
    motion = GuardMotion(move_speed=move_speed, turn_speed=180.0, tick_hz=30.0)
    route = pull_route(scene.world, grid, [grid.flat(col, 0) for col in range(20)], 0.3)
    assert route.points.tolist() == [[0.5, 0.5], [19.5, 0.5]]
    follower = Follower(scene.world, motion, (0.5, 0.5), 0.0)
    ticks = 0
    while not follower.walk_to(route.points[1]):
        ticks += 1
    ticks += 1
    assert abs(ticks / motion.tick_hz - 19.0 / move_speed) <= 1 / motion.tick_hz
    assert follower.position == (19.5, 0.5)


def test_corridor_episode_walks_at_move_speed() -> None:
    scene = scene_from(CORRIDOR, guard={"view_range": 1.0, "start": [0.5, 0.5], "heading": "right"})
    trace = run_episode(scene, "ripplefront", motion=MOTION)
    assert trace.covered and trace.poses is not None
    walked = trace.poses[-1, 1] - trace.poses[0, 1]
    # The last cell is seen from the one before it; every tick but the last is a full step.
    assert walked == pytest.approx(18.0)
    assert abs(trace.seconds - walked / MOTION.move_speed) <= 1 / MOTION.tick_hz + 1e-9
    assert trace.measures["turns"] == 0 and trace.measures["in_place_s"] == 0


def _no_overlap(simulation: ContinuousSimulation) -> None:
    world = simulation.scene.world
    for hit in world.space.shape_query(world.guard_shape):
        if hit.shape in world.walls:
            assert all(point.distance >= -1e-9 for point in hit.contact_point_set.points), simulation.position
    assert world.fits(world.guard_body.position, world.guard_shape.radius - 1e-9)


@pytest.mark.parametrize("planner", ["ripplefront", "tour", "sweep"])
@pytest.mark.parametrize("case", ["square-with-hole", "l-room", "split-rooms", "narrow-gap", "mgs_docks"])
def test_body_never_overlaps_a_wall(case: str, planner: str) -> None:
    if case == "mgs_docks":
        scene = shipped(case)
    else:
        scene = scene_from(NARROW_GAP if case == "narrow-gap" else TINY_LEVELS[case])
    simulation = ContinuousSimulation(scene, planner, motion=MOTION)
    simulation.reset(seed=0)
    trace = run_ticks(simulation, _no_overlap)
    assert trace.covered


def test_never_passes_a_gap_narrower_than_its_diameter() -> None:
    scene = scene_from(NARROW_GAP)
    for planner in PLANNERS:
        trace = run_episode(scene, planner, motion=MOTION)
        assert trace.covered and trace.poses is not None
        assert trace.poses[:, 1].max() <= 4.0 - 0.3 + 1e-9
        assert not trace.goal[:, 5:].any()
    wide = scene_from(NARROW_GAP, holes=[[[4, 0], [5, 0], [5, 2], [4, 2]], [[4, 3], [5, 3], [5, 5], [4, 5]]])
    trace = run_episode(wide, "ripplefront", motion=MOTION)
    assert trace.covered and trace.poses is not None and trace.poses[:, 1].max() > 5.3


@tiny_levels
@pytest.mark.parametrize("planner", PLANNERS)
def test_every_reachable_cell_seen_when_covered(level_data: dict, planner: str) -> None:
    trace = run_episode(scene_from(level_data), planner, motion=MOTION)
    assert trace.covered
    assert (trace.first_seen[trace.goal] >= 0).all()
    assert trace.unseen_percent[-1] == 0
    assert len(trace.path) == len(trace.poses) == trace.steps + 1  # type: ignore[arg-type]


def test_same_seed_same_poses_byte_for_byte() -> None:
    scene = shipped("king_snurre")
    first = run_episode(scene, "tour", seed=4, episode=2, motion=MOTION)
    again = run_episode(Scene.from_level(scene.level), "tour", seed=4, episode=2, motion=MOTION)
    assert first.poses is not None and again.poses is not None
    assert first.poses.tobytes() == again.poses.tobytes()
    assert first.to_json() == again.to_json()
    other = run_episode(scene, "tour", seed=4, episode=3, motion=MOTION)
    assert other.poses is not None and other.poses.tobytes() != first.poses.tobytes()


@pytest.mark.slow
@pytest.mark.parametrize("level", ["mgs_docks", "passages"])
def test_fast_and_reference_vision_agree_tick_for_tick(level: str) -> None:
    scene = shipped(level)
    trace = run_episode(scene, "tour", seed=0, motion=MOTION)
    assert trace.poses is not None
    fast = PoseVision(scene.world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls)
    for _, x, y, heading in trace.poses.tolist():
        assert (
            fast(x, y, heading).tolist()
            == pose_visible_cells(scene.world, scene.grid, scene.cone, x, y, heading).tolist()
        )


@pytest.mark.parametrize("case", ["square-with-hole", "split-rooms", "square"])
def test_reference_episode_equals_fast_episode(case: str) -> None:
    scene = shipped(case) if case == "square" else scene_from(TINY_LEVELS[case])
    fast = run_episode(scene, "ripplefront", seed=1, episode=0, motion=MOTION)
    reference = run_episode(scene, "ripplefront", seed=1, episode=0, motion=MOTION, reference=True)
    assert fast.poses is not None and reference.poses is not None
    assert fast.poses.tobytes() == reference.poses.tobytes()
    assert (fast.first_seen == reference.first_seen).all()


@pytest.mark.parametrize("level", ["mgs_docks", "king_snurre"])
def test_pose_vision_at_a_cell_centre_is_the_grid_vision(level: str) -> None:
    scene = shipped(level)
    grid = scene.grid
    fast = PoseVision(scene.world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls)
    cells = np.flatnonzero(grid.traversable.ravel())[::7]
    for cell in cells.tolist():
        col, row = grid.unflat(cell)
        for heading in range(4):
            assert fast(*grid.centre(col, row), 90.0 * heading).tolist() == scene.vision()(col, row, heading).tolist()


def test_pulled_route_keeps_a_dead_end_detour() -> None:
    scene = scene_from(TINY_LEVELS["empty-square"])
    grid = scene.grid
    # Along the top row, down into the corner and back up, on along the top.
    cells = [(0, 0), (1, 0), (1, 1), (1, 2), (1, 1), (1, 0), (2, 0), (3, 0)]
    route = pull_route(scene.world, grid, [grid.flat(c, r) for c, r in cells], 0.3)
    assert [1.5, 2.5] in route.points.tolist()
    assert route.points[-1].tolist() == [3.5, 0.5]


def test_grid_route_around_a_pillar_is_pulled_into_clear_diagonals() -> None:
    scene = scene_from(TINY_LEVELS["square-with-hole"])
    grid = scene.grid
    cells = [(0, 0), (1, 0), (1, 1), (2, 1), (3, 1), (4, 1), (4, 2), (5, 2), (5, 3)]
    route = pull_route(scene.world, grid, [grid.flat(c, r) for c, r in cells], 0.3)
    points = route.points.tolist()
    assert points[0] == [0.5, 0.5] and points[-1] == [5.5, 3.5]
    assert len(points) < len(cells)
    for a, b in itertools.pairwise(points):
        assert scene.world.sweep_clear(tuple(a), tuple(b), 0.3)


def test_continuous_trace_round_trips_through_json() -> None:
    trace = run_episode(scene_from(TINY_LEVELS["l-room"]), "tour", motion=MOTION)
    data = json.loads(trace.to_json())
    assert data["motion"] == "continuous" and data["tick_hz"] == 30.0
    assert len(data["poses"]) == trace.steps + 1 and data["poses"][0][0] == 0.0
    back = Trace.from_data(data)
    assert back.motion == "continuous" and back.poses is not None
    assert np.allclose(back.poses, trace.poses, atol=1e-6)
    assert back.measures == trace.measures


def test_grid_trace_json_has_no_motion_keys() -> None:
    from guardsim.simulation import Simulation

    simulation = Simulation(scene_from(TINY_LEVELS["l-room"]), "ripplefront")
    simulation.reset(seed=0)
    data = json.loads(simulation.run().to_json())
    assert "motion" not in data and "poses" not in data


def test_time_limit_ends_the_episode() -> None:
    trace = run_episode(shipped("square"), "ripplefront", seed=0, motion=MOTION, max_seconds=10.0)
    assert trace.outcome == "step_limit"
    assert trace.seconds == pytest.approx(10.0)
    assert trace.steps == 300


def test_motion_parameters_validated() -> None:
    with pytest.raises(ValueError, match="move_speed"):
        GuardMotion(move_speed=0)
    with pytest.raises(ValueError, match="tick_hz"):
        GuardMotion(tick_hz=math.inf)


def cli(*args: object) -> Result:
    return CliRunner().invoke(main, [str(arg) for arg in args])


def test_play_continuous_reports_seconds_and_writes_poses(tmp_path: Path) -> None:
    level = write_level(tmp_path, {**TINY_LEVELS["l-room"], "guard": {"start": [0.5, 0.5], "move_speed": 1.0}})
    trace_path = tmp_path / "trace.json"
    result = cli("play", level, "--motion", "continuous", "--turn-speed", "90", "--trace", trace_path)
    assert result.exit_code == 0, result.output
    summary = result.stdout.strip()
    assert "\n" not in summary and "s of game time" in summary and "U-turns" in summary
    data = json.loads(trace_path.read_text(encoding="utf-8"))
    assert (data["motion"], data["move_speed"], data["turn_speed"], data["tick_hz"]) == ("continuous", 1.0, 90.0, 30.0)
    assert f"{data['seconds']:.1f} s of game time" in summary
    faster = cli("play", level, "--motion", "continuous", "--move-speed", "3", "--trace", trace_path)
    assert faster.exit_code == 0, faster.output
    assert json.loads(trace_path.read_text(encoding="utf-8"))["seconds"] < data["seconds"]


def test_play_grid_summary_gives_the_steps_based_turns(tmp_path: Path) -> None:
    result = cli("play", write_level(tmp_path, TINY_LEVELS["l-room"]), "--planner", "tour")
    assert result.exit_code == 0, result.output
    assert "per 100 steps" in result.stdout and "s of game time" not in result.stdout


@pytest.mark.parametrize(
    ("options", "message"),
    [(("--guards", "2"), "walks one guard"), (("--move-speed", "0"), "")],
)
def test_play_continuous_refuses_what_it_cannot_do(tmp_path: Path, options: tuple[str, ...], message: str) -> None:
    result = cli("play", write_level(tmp_path, TINY_LEVELS["l-room"]), "--motion", "continuous", *options)
    assert result.exit_code == 2
    assert message in result.output


def test_level_motion_keys_are_validated(tmp_path: Path) -> None:
    level = write_level(tmp_path, {**TINY_LEVELS["l-room"], "guard": {"turn_speed": -5}})
    result = cli("play", level, "--motion", "continuous")
    assert result.exit_code == 2
    assert "guard.turn_speed" in result.output and "positive" in result.output


def test_bench_continuous_rows_and_summary(tmp_path: Path) -> None:
    level = write_level(tmp_path, TINY_LEVELS["square-with-hole"])
    out = tmp_path / "out"
    result = cli("bench", level, "--motion", "continuous", "--planner", "ripplefront,tour", "--episodes", "2",
                 "--workers", "1", "--out", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "seconds med" in result.stdout.splitlines()[0]
    with (out / "results.csv").open(encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == 4 and {row["motion"] for row in rows} == {"continuous"}
    for row in rows:
        trace = run_episode(scene_from(TINY_LEVELS["square-with-hole"]), row["planner"], motion="continuous", seed=0, episode=int(row["episode"]))  # fmt: skip
        assert float(row["game_seconds"]) == trace.seconds and int(row["steps"]) == trace.steps
        assert int(row["u_turns"]) == trace.measures["u_turns"] and row["best_bound"] == ""
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["run"]["motion"] == "continuous"
    assert all(group["motion"]["game_seconds"]["count"] == 2 for group in summary["groups"])


def test_play_continuous_in_a_real_process() -> None:
    result = subprocess.run(
        [*guardsim_command(), "play", str(REPO / "levels" / "square.json"), "--motion", "continuous"],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("Square: covered after ") and "s of game time" in result.stdout


@pytest.mark.parametrize(("seed", "episode"), [(0, None), (3, 4)])
def test_continuous_starts_where_the_grid_episode_starts(seed: int, episode: int | None) -> None:
    from guardsim.simulation import Simulation

    scene = shipped("passages")
    grid_run = Simulation(scene, "tour")
    grid_run.reset(seed=seed, episode=episode)
    grid_trace = grid_run.run()
    trace = run_episode(scene, "tour", seed=seed, episode=episode, motion=MOTION, max_seconds=5)
    assert trace.poses is not None
    assert trace.start == grid_trace.start and trace.headings[0] == grid_trace.headings[0]
    x, y = scene.grid.centre(*grid_trace.start)
    assert trace.poses[0].tolist() == [0.0, x, y, 90.0 * grid_trace.headings[0]]
    # The first plan is the grid episode itself: the guard heads for the grid route's first corner.
    second = grid_trace.path[1]
    cx, cy = scene.grid.centre(*second)
    assert np.hypot(trace.poses[1, 1] - cx, trace.poses[1, 2] - cy) <= np.hypot(x - cx, y - cy)


# -- the Bresenham rule from a continuous pose ---------------------------------------------------------------

_BRESENHAM: dict[str, Scene] = {}


def bresenham_scene(name: str) -> Scene:
    path = next(path for path in LEVELS if path.stem == name)
    return _BRESENHAM.setdefault(name, Scene.from_level(load_level(path), line_of_sight=LineOfSight.BRESENHAM))


@pytest.mark.slow
def test_bresenham_fast_and_reference_vision_agree_tick_for_tick() -> None:
    """Under --los bresenham the cone comes from the pose and the line from the eye's cell: the compiled
    lines and the Python reference give the same cells on every tick of a whole episode."""
    scene = bresenham_scene("passages")
    trace = run_episode(scene, "ripplefront", seed=0, motion=MOTION)
    assert trace.poses is not None and trace.outcome == "covered" and trace.line_of_sight == "bresenham"
    fast = PoseVision(
        scene.world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls, rule=LineOfSight.BRESENHAM
    )
    for _, x, y, heading in trace.poses.tolist():
        reference = pose_visible_cells(scene.world, scene.grid, scene.cone, x, y, heading, rule=LineOfSight.BRESENHAM)
        assert fast(x, y, heading).tolist() == reference.tolist()


def test_bresenham_pose_vision_at_a_cell_centre_is_the_grid_bresenham_vision() -> None:
    scene = bresenham_scene("mgs_docks")
    grid = scene.grid
    fast = PoseVision(
        scene.world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls, rule=LineOfSight.BRESENHAM
    )
    vision = scene.vision()
    for cell in np.flatnonzero(grid.traversable.ravel())[::7].tolist():
        col, row = grid.unflat(cell)
        for heading in range(4):
            assert fast(*grid.centre(col, row), 90.0 * heading).tolist() == vision(col, row, heading).tolist()


@tiny_levels
def test_bresenham_continuous_episode_covers_and_equals_its_reference(level_data: dict) -> None:
    """Every reachable cell is seen when covered, and the reference loop walks the same poses."""
    scene = Scene.from_level(level_from(level_data), line_of_sight=LineOfSight.BRESENHAM)
    fast = run_episode(scene, "ripplefront", seed=2, episode=1, motion=MOTION)
    reference = run_episode(scene, "ripplefront", seed=2, episode=1, motion=MOTION, reference=True)
    assert fast.poses is not None and reference.poses is not None
    assert fast.poses.tobytes() == reference.poses.tobytes()
    if fast.outcome == "covered":
        assert ((fast.first_seen >= 0) | ~fast.goal).all()


def test_play_continuous_with_bresenham(tmp_path: Path) -> None:
    trace_path = tmp_path / "trace.json"
    result = cli("play", REPO / "levels" / "square.json", "--motion", "continuous", "--los", "bresenham",
                 "--trace", trace_path)  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(trace_path.read_text(encoding="utf-8"))
    assert (data["motion"], data["line_of_sight"], data["outcome"]) == ("continuous", "bresenham", "covered")
