"""The planners other than the paper's, and teams of guards: coverage, legal moves, the fields and orders
they compute against independent answers, determinism, and `guardsim play --planner --guards`.
"""

from __future__ import annotations

import json
import statistics
import subprocess
from collections import deque
from functools import cache
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner

from guardsim import load_level
from guardsim.cli import main
from guardsim.cli.common import build_scene
from guardsim.kernels.tours import improve_tour, nearest_neighbour_tour, tour_cost
from guardsim.motion import run_episode
from guardsim.planners import PLANNERS, EpisodeSetup, GuardState, RandomWalk, RippleFrontExact, Sweep, Tour
from guardsim.planners.ripplefront import FAR, ripple_sweep
from guardsim.planners.team_share import guard_share
from guardsim.planners.viewpoint_cover import greedy_cover
from guardsim.simulation import Scene, choose_start, default_max_steps
from guardsim.trace import Trace
from guardsim.vision.table import view_table
from tests.common import (
    L_ROOM,
    LEVELS,
    TINY_LEVELS,
    guardsim_command,
    level_from,
    scene_from,
    shipped_levels,
    tiny_levels,
    write_level,
)

#: Planners expected to cover a level within the loop's step limit (the random walk is not).
COVERING = [name for name in PLANNERS if name != "random-walk"]
SQUARE = next(path for path in LEVELS if path.stem == "square")


@cache
def shipped_scene(path: Path) -> Scene:
    """One scene per shipped level for the whole module, so its vision and view table are built once."""
    return Scene.from_level(load_level(path))


def assert_legal(scene: Scene, trace: Trace) -> None:
    """Every guard's every tick stays put or moves to a connected neighbour, facing the way it moved."""
    grid = scene.grid
    for path, headings in zip(trace.team_paths(), trace.team_headings()):
        for (col, row), (next_col, next_row), heading in zip(path, path[1:], headings[1:]):
            here, there = grid.flat(col, row), grid.flat(next_col, next_row)
            assert here == there or grid.neighbours[here, heading] == there


def assert_covered(scene: Scene, trace: Trace) -> None:
    """Covered within the limit, every goal cell seen by the last tick, moves legal."""
    assert trace.outcome == "covered"
    assert trace.steps <= default_max_steps(scene.grid)
    assert (trace.first_seen[trace.goal] >= 0).all()
    assert_legal(scene, trace)


@tiny_levels
@pytest.mark.parametrize("planner", list(PLANNERS))
def test_every_planner_covers_tiny_levels(level_data: dict, planner: str) -> None:
    """From three seeded random starts, with a short-sighted guard so that walking matters."""
    scene = scene_from(level_data, guard={"view_range": 2.0})
    for episode in range(3):
        assert_covered(scene, run_episode(scene, seed=3, episode=episode, planner=planner))


@shipped_levels
@pytest.mark.parametrize("planner", COVERING)
def test_planners_cover_shipped_levels(level_path: Path, planner: str) -> None:
    """Two seeded random starts per shipped level, covered within the default step limit."""
    scene = shipped_scene(level_path)
    for episode in range(2):
        assert_covered(scene, run_episode(scene, seed=0, episode=episode, planner=planner))


def test_random_walk_moves_legally_and_sees_more_on_a_shipped_level() -> None:
    """The random walk is not expected to cover 60 x 60 within the limit; its moves are legal all the same."""
    scene = shipped_scene(LEVELS[0])
    trace = run_episode(scene, seed=0, episode=0, planner="random-walk", max_steps=2000)
    assert_legal(scene, trace)
    assert trace.steps == 2000 and trace.unseen_percent[-1] < trace.unseen_percent[0]


def test_random_walk_is_deterministic_per_seed_and_differs_across_seeds() -> None:
    """The same start walked with generators from two seeds: equal traces per seed, different across."""
    scene = scene_from(TINY_LEVELS["square-with-hole"], guard={"view_range": 1.0})

    def walk(seed: int) -> str:
        return run_episode(
            scene, RandomWalk(), starts=[(0, 0)], headings=[0], max_steps=60, rng=np.random.default_rng(seed)
        ).to_json()

    assert walk(1) == walk(1)
    assert len({walk(seed) for seed in range(4)}) == 4


def breadth_first(neighbours: np.ndarray, sources: np.ndarray) -> np.ndarray:
    """Distances to the nearest source by a plain queue, -1 where none is reachable (independent of numba)."""
    distance = np.full(neighbours.shape[0], -1)
    queue = deque(int(cell) for cell in np.flatnonzero(sources))
    distance[list(queue)] = 0
    while queue:
        cell = queue.popleft()
        for other in neighbours[cell]:
            if other >= 0 and distance[other] < 0:
                distance[other] = distance[cell] + 1
                queue.append(int(other))
    return distance


def test_ripplefront_exact_field_is_the_breadth_first_distance() -> None:
    """On the square with a pillar, a scattered seen mask: the field equals a plain BFS and the ripple's limit."""
    scene = scene_from(TINY_LEVELS["square-with-hole"])
    grid = scene.grid
    goal = grid.component(0, 0).ravel()
    seen = goal & (np.random.default_rng(5).random(grid.size) < 0.8)
    planner = RippleFrontExact()
    planner.reset(EpisodeSetup(grid, goal, scene.vision(), np.random.default_rng(0)))
    planner.next_move(GuardState(0, 0, 0, seen, goal))
    expected = breadth_first(grid.neighbours, goal & ~seen)
    assert np.array_equal(planner.distance[goal], expected[goal])
    assert (planner.distance[~goal] == FAR).all()
    ripple = np.zeros(grid.size, dtype=np.int32)
    for _ in range(grid.size):
        ripple = ripple_sweep(ripple, seen | ~goal, grid.neighbours)
    assert np.array_equal(ripple[goal], planner.distance[goal])


@tiny_levels
def test_sweep_stands_on_every_reachable_cell_when_it_sees_only_its_own(level_data: dict) -> None:
    """With view range 0.5 a guard sees only its cell: covering means visiting, and sweep does."""
    scene = scene_from(level_data, guard={"view_range": 0.5})
    trace = run_episode(scene, seed=0, episode=0, planner="sweep")
    assert_covered(scene, trace)
    visited = np.zeros(scene.grid.shape, dtype=bool)
    for col, row in trace.path:
        visited[row, col] = True
    assert np.array_equal(visited, trace.goal)


def test_sweep_visits_every_cell_of_a_shipped_level_blind() -> None:
    """The same on the square level (3500 cells), boustrophedon lanes and jumps."""
    data = json.loads(SQUARE.read_text(encoding="utf-8"))
    scene = scene_from(data, guard={**data["guard"], "view_range": 0.5})
    cell, heading = choose_start(scene, rng=np.random.default_rng(0))
    trace = run_episode(scene, [Sweep()], starts=[cell], headings=[heading])
    assert trace.covered
    assert len(set(trace.path)) == trace.reachable
    assert trace.steps < 1.3 * trace.reachable


@tiny_levels
def test_tour_viewpoints_cover_every_goal_cell_of_tiny_levels(level_data: dict) -> None:
    """The greedy set cover sees every cell of the largest connected area."""
    scene = scene_from(level_data, guard={"view_range": 2.0})
    assert_cover_is_complete(scene)


@shipped_levels
def test_tour_viewpoints_cover_every_goal_cell(level_path: Path) -> None:
    """On a 60 x 60 level with the paper's cone, far fewer viewpoints than cells."""
    scene = shipped_scene(level_path)
    assert assert_cover_is_complete(scene) < scene.grid.traversable.sum() / 10


def test_greedy_cover_picks_as_a_full_scan_does() -> None:
    """The cover's picks, step by step, are those of the rule read plainly: the arrivable state that sees
    the most goal cells not yet covered, the lowest state on a tie, until none sees one; then, latest
    pick first, a pick is dropped when the others see all its goal cells."""
    scene = shipped_scene(Path("levels/mgs_docks.json"))
    grid = scene.grid
    table = view_table(grid, scene.vision())
    goal = grid.traversable.ravel() & (np.arange(grid.size) % 2 == 0)
    candidates = np.flatnonzero((table.entry >= 0) & np.repeat(goal, 4))
    sees = {
        int(state): set(table.sees(int(state)).tolist()) & set(np.flatnonzero(goal).tolist()) for state in candidates
    }
    left, picks = set(np.flatnonzero(goal).tolist()), []
    while True:
        gains = {state: len(cells & left) for state, cells in sees.items()}
        best = max(gains.values(), default=0)
        if best == 0:
            break
        state = min(state for state, gain in gains.items() if gain == best)
        picks.append(state)
        left -= sees[state]
    for position in range(len(picks) - 1, -1, -1):
        others = set().union(*(sees[state] for k, state in enumerate(picks) if k != position))
        if sees[picks[position]] <= others:
            del picks[position]
    assert greedy_cover(table, goal).tolist() == picks


def assert_cover_is_complete(scene: Scene) -> int:
    """The union of the viewpoints' visible cells contains the goal; each viewpoint can be arrived in."""
    grid = scene.grid
    goal = grid.largest_component().ravel()
    table = view_table(grid, scene.vision())
    viewpoints = greedy_cover(table, goal)
    seen = np.zeros(grid.size, dtype=bool)
    for state in viewpoints:
        seen[table.sees(int(state))] = True
        assert table.entry[state] >= 0
    assert (seen | ~goal).all()
    return int(viewpoints.size)


@pytest.mark.slow
@shipped_levels
def test_tour_beats_ripplefront_on_median_steps(level_path: Path) -> None:
    """Five seeded random starts per shipped level: tour's median steps are below RippleFront's."""
    scene = shipped_scene(level_path)

    def median(planner: str) -> float:
        return statistics.median(run_episode(scene, seed=1, episode=e, planner=planner).steps for e in range(5))

    assert median("tour") < median("ripplefront")


def test_tour_walks_exactly_the_walk_it_planned() -> None:
    """The simulated walk made at the first tick is the trace the loop records, tick for tick."""
    scene = shipped_scene(LEVELS[0])
    cell, heading = choose_start(scene, rng=np.random.default_rng(4))
    planner = Tour()
    trace = run_episode(scene, planner, starts=[cell], headings=[heading])
    assert planner.walk is not None
    assert planner.walk.steps == trace.steps
    assert [scene.grid.unflat(int(c)) for c in planner.walk.cells[0]] == list(trace.path)


@pytest.mark.slow
@shipped_levels
@pytest.mark.parametrize("planner", ["ripplefront", "tour"])
def test_more_guards_shorter_makespan(level_path: Path, planner: str) -> None:
    """Two episodes per level: 2 guards cover in fewer ticks than 1, and 4 in fewer than 2."""
    scene = shipped_scene(level_path)
    for episode in range(2):
        steps = []
        for guards in (1, 2, 4):
            trace = run_episode(scene, seed=2, episode=episode, planner=planner, guards=guards)
            assert_covered(scene, trace)
            assert trace.guards == guards
            steps.append(trace.steps)
        assert steps[0] > steps[1] > steps[2], steps


@pytest.mark.parametrize("planner", COVERING)
def test_every_planner_covers_with_a_team(planner: str) -> None:
    """Three guards on the L room, each with its own planner object, cover it with legal moves."""
    scene = scene_from(L_ROOM, guard={"view_range": 2.0})
    trace = run_episode(scene, seed=0, episode=0, planner=planner, guards=3)
    assert_covered(scene, trace)
    assert len(trace.guard_paths) == 3


def corridor(cells: int) -> np.ndarray:
    """Neighbour table of a 1 x ``cells`` corridor."""
    neighbours = np.full((cells, 4), -1, dtype=np.int64)
    neighbours[:-1, 0] = np.arange(1, cells)
    neighbours[1:, 2] = np.arange(cells - 1)
    return neighbours


def test_guard_share_splits_by_distance_and_falls_back_when_empty() -> None:
    """Guards at cells 1 and 8 of a 10-cell corridor split it at the middle; a guard with no share chases all."""
    neighbours = corridor(10)
    targets = np.ones(10, dtype=bool)
    team = ((1, 0), (8, 2))
    first, second = (guard_share(neighbours, targets, team, guard) for guard in (0, 1))
    assert np.flatnonzero(first).tolist() == [0, 1, 2, 3, 4]
    assert np.flatnonzero(second).tolist() == [5, 6, 7, 8, 9]
    only_left = np.zeros(10, dtype=bool)
    only_left[0] = True
    assert guard_share(neighbours, only_left, team, 1).tolist() == only_left.tolist()


def test_ripplefront_team_spreads_out() -> None:
    """Two RippleFront guards starting on the same cell of the square level part ways within 60 ticks."""
    scene = shipped_scene(SQUARE)
    planners = [PLANNERS["ripplefront"]() for _ in range(2)]
    cell, _ = choose_start(scene, rng=np.random.default_rng(0))
    trace = run_episode(scene, planners, starts=[cell, cell], headings=[0, 2], max_steps=60)
    first, second = trace.guard_paths
    (a_col, a_row), (b_col, b_row) = first[-1], second[-1]
    assert abs(a_col - b_col) + abs(a_row - b_row) > 20


def test_open_tour_improves_on_nearest_neighbour_and_keeps_its_start() -> None:
    """Random asymmetric costs on 40 nodes: a permutation, node 0 first, never longer than the NN tour."""
    rng = np.random.default_rng(0)
    points = rng.random((40, 2)) * 100
    cost = np.rint(np.abs(points[:, None, :] - points[None, :, :]).sum(axis=2)).astype(np.int64)
    cost += rng.integers(0, 3, size=cost.shape)
    first = nearest_neighbour_tour(cost, 0, np.arange(1, 40))
    improved = improve_tour(cost, first)
    assert improved[0] == 0 and sorted(improved.tolist()) == list(range(40))
    assert tour_cost(cost, improved) < tour_cost(cost, first)


def test_open_tour_finds_the_optimum_of_a_line() -> None:
    """Points on a line visited from one end: the best open tour walks straight along it."""
    positions = np.array([0, 7, 2, 9, 4, 1, 8, 3, 6, 5])
    cost = np.abs(positions[:, None] - positions[None, :]).astype(np.int64)
    start = int(np.argmin(positions))
    others = np.array([node for node in range(10) if node != start])
    tour = improve_tour(cost, nearest_neighbour_tour(cost, start, others[::-1].copy()))
    assert tour_cost(cost, tour) == 9


@pytest.mark.parametrize("planner", list(PLANNERS))
def test_play_runs_every_planner_with_a_team(tmp_path: Path, planner: str) -> None:
    """`guardsim play LEVEL --planner NAME --guards 2 --gif` writes a GIF that decodes, and says the team size."""
    level = write_level(tmp_path, {**L_ROOM, "guard": {**L_ROOM["guard"], "view_range": 2.0}})
    gif = tmp_path / "team.gif"
    result = CliRunner().invoke(
        main, ["play", str(level), "--planner", planner, "--guards", "2", "--gif", str(gif), "--max-steps", "400"]
    )
    assert result.exit_code == 0, result.output
    assert "2 guards" in result.output
    assert iio.imread(gif, index=None).ndim == 4


def test_play_with_one_guard_is_unchanged_by_the_guards_option() -> None:
    """--guards 1 prints the same line as no option, apart from the time."""
    runner = CliRunner()
    plain = runner.invoke(main, ["play", str(SQUARE), "--planner", "tour"])
    one = runner.invoke(main, ["play", str(SQUARE), "--planner", "tour", "--guards", "1"])
    assert plain.exit_code == one.exit_code == 0
    assert plain.output.rsplit(",", 1)[0] == one.output.rsplit(",", 1)[0]
    assert "guards" not in plain.output


def test_play_team_in_a_real_process(tmp_path: Path) -> None:
    """One real subprocess run: four tour guards on the square level, a trace with four paths."""
    trace_path = tmp_path / "team.json"
    command = [*guardsim_command(), "play", str(SQUARE), "--planner", "tour", "--guards", "4", "--episode", "3"]
    completed = subprocess.run(
        [*command, "--trace", str(trace_path)], capture_output=True, text=True, check=False, timeout=300
    )
    assert completed.returncode == 0, completed.stderr
    assert "covered" in completed.stdout and "4 guards" in completed.stdout
    trace = Trace.from_data(json.loads(trace_path.read_text(encoding="utf-8")))
    assert len(trace.guard_paths) == 4
    expected = run_episode(shipped_scene(SQUARE), seed=0, episode=3, planner="tour", guards=4)
    assert trace.to_json() == expected.to_json()


@pytest.mark.parametrize(
    "options",
    [{"seeds": ("cover",), "refine_rounds": 0}, {"seeds": ("cover",)}, {"seeds": ("frontier",)}],
    ids=["cover", "cover+refine", "frontier+refine"],
)
def test_tour_parts_cover_alone(options: dict) -> None:
    """Each part of tour that benchmarks/planners.py measures covers on its own, alone and in a team."""
    scene = scene_from(TINY_LEVELS["square-with-hole"], guard={"view_range": 2.0})
    for guards in (1, 2):
        trace = run_episode(
            scene, [Tour(**options) for _ in range(guards)], starts=[(0, 0), (5, 5)][:guards], headings=[0, 2][:guards]
        )
        assert_covered(scene, trace)


def test_tour_rejects_unknown_seeds() -> None:
    with pytest.raises(ValueError, match="seeds"):
        Tour(seeds=("nearest",))


@pytest.mark.parametrize("planner", COVERING)
def test_planners_work_with_the_bresenham_sight_rule(planner: str) -> None:
    """The planners only use the episode's vision function, so Bresenham 360-degree sight just works."""
    scene = build_scene(level_from(TINY_LEVELS["square-with-hole"]), "bresenham", 360.0)
    for guards in (1, 2):
        assert_covered(scene, run_episode(scene, seed=0, episode=1, planner=planner, guards=guards))
