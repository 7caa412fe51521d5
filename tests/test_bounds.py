"""Lower bounds: never above the true optimum (found by exhaustive search on tiny levels), exact where
worked out by hand, never above any planner's steps on the shipped levels, and the command line.

The optimum is a breadth-first search over (state, seen cells) with the seen cells as a bitmask, so the
levels here are kept to a few dozen cells and short view ranges.
"""

from __future__ import annotations

import functools
import subprocess
from collections import deque
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim import load_level
from guardsim.bounds import lower_bounds, state_distances
from guardsim.bounds.clusters import choose_clusters
from guardsim.cli import main
from guardsim.kernels.trees import cluster_distances, spanning_tree_weight, subset_tree_weight
from guardsim.motion import run_episode
from guardsim.planners import PLANNERS, make_planner
from guardsim.simulation import Scene
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import view_table
from tests.common import (
    EMPTY_SQUARE,
    LEVELS,
    SHORT_SIGHTED,
    SQUARE_WITH_HOLE,
    STRIP,
    STRIP_CELLS,
    guardsim_command,
    optimum_steps,
    scene_from,
    shipped_levels,
    short_sighted,
    starts,
    write_level,
)

#: Levels where the best bound equals the optimum from at least one of the starts tried.
EXACT_SOMEWHERE = {"corridor", "room-3x5", "l-room"}


def own_cell_only(scene: Scene) -> VisionFunction:
    """A guard that sees nothing but its own cell: any vision function must do."""

    def see(col: int, row: int, _heading: int) -> np.ndarray:
        return np.array([scene.grid.flat(col, row)], dtype=np.int64)

    return see


@short_sighted
def test_bounds_never_exceed_the_optimum(name: str) -> None:
    """Both bounds are at most the exhaustive optimum from spread starts and every heading."""
    scene = scene_from(SHORT_SIGHTED[name])
    vision = scene.vision()
    gaps = []
    for start in starts(scene):
        for heading in range(4):
            optimum = optimum_steps(scene, start, heading, vision)
            bounds = lower_bounds(scene, start, heading, vision)
            assert bounds.eccentricity <= optimum, (start, heading)
            assert bounds.cluster <= optimum, (start, heading)
            assert bounds.best == max(bounds.eccentricity, bounds.cluster)
            gaps.append(optimum - bounds.best)
            # Not vacuous: never below half the optimum on these levels (0.55 is the worst measured).
            assert 2 * bounds.best >= optimum, (start, heading, bounds, optimum)
    if name in EXACT_SOMEWHERE:
        assert min(gaps) == 0


#: A 2 x 4 room, small enough for a guard that sees only its own cell to be searched exhaustively.
ROOM_2X4: dict[str, Any] = {"name": "room 2 x 4", "outer": [[0, 0], [4, 0], [4, 2], [0, 2]]}


@pytest.mark.parametrize(
    ("line_of_sight", "data"),
    [
        ("bresenham", SHORT_SIGHTED["l-room"]),
        ("bresenham", SHORT_SIGHTED["pillar"]),
        ("own-cell", STRIP),
        ("own-cell", ROOM_2X4),
    ],
    ids=["bresenham-l-room", "bresenham-pillar", "own-cell-corridor", "own-cell-room-2x4"],
)
def test_bounds_hold_for_other_visions(line_of_sight: str, data: dict[str, Any]) -> None:
    """The bounds ask only the vision function: the Bresenham rule and a blind guard are bounded too.

    (A blind guard must walk onto every cell, so its exhaustive search grows fast: tiny levels only.)
    """
    if line_of_sight == "bresenham":
        scene = Scene.from_level(scene_from(data).level, line_of_sight="bresenham")
        vision = scene.vision()
    else:
        scene = scene_from(data)
        vision = own_cell_only(scene)
    for start in starts(scene, most=4):
        optimum = optimum_steps(scene, start, 0, vision)
        bounds = lower_bounds(scene, start, 0, vision)
        assert 0 < bounds.best <= optimum


def test_own_cell_eccentricity_is_the_farthest_walk() -> None:
    """Seeing only its own cell, a guard must walk to every cell: the eccentricity bound is the largest
    number of moves from the start cell to a cell (breadth-first over cells, headings aside)."""
    scene = scene_from(SHORT_SIGHTED["l-room"])
    grid = scene.grid
    moves = {grid.flat(0, 0): 0}
    queue = deque([grid.flat(0, 0)])
    while queue:
        cell = queue.popleft()
        for other in grid.neighbours[cell].tolist():
            if other >= 0 and other not in moves:
                moves[other] = moves[cell] + 1
                queue.append(other)
    for heading in range(4):
        assert lower_bounds(scene, (0, 0), heading, own_cell_only(scene)).eccentricity == max(moves.values())


@pytest.mark.parametrize("middle", range(2, STRIP_CELLS - 2))
def test_corridor_cluster_bound_is_exact(middle: int) -> None:
    """From cell m of an N-cell corridor, facing right (2 <= m <= N - 3), worked out by hand.

    Cell 0 is seen only from (1, left) and (0, left); cell N-1 only from (N-2, right) and (N-1, right).
    The two watcher sets are N - 3 steps apart either way, and m - 1 and N - 2 - m steps from the start,
    so the cluster bound is N - 3 + min(m - 1, N - 2 - m); walking to the nearer end and then to the
    other achieves it, so it is the optimum.
    """
    scene = scene_from(STRIP)
    expected = STRIP_CELLS - 3 + min(middle - 1, STRIP_CELLS - 2 - middle)
    bounds = lower_bounds(scene, (middle, 0), 0)
    assert bounds.cluster == expected == optimum_steps(scene, (middle, 0), 0, scene.vision())
    assert bounds.eccentricity == max(middle - 1, STRIP_CELLS - 2 - middle) < expected


def test_corridor_eccentricity_is_exact_from_the_end() -> None:
    """From cell 0 facing right, the far end is first seen from (N-2, right): N - 2 steps, the optimum."""
    scene = scene_from(STRIP)
    bounds = lower_bounds(scene, (0, 0), 0)
    assert bounds.eccentricity == STRIP_CELLS - 2 == optimum_steps(scene, (0, 0), 0, scene.vision())
    assert bounds.best == STRIP_CELLS - 2


def test_seen_from_the_start_means_zero() -> None:
    """A guard that sees the whole room from its start needs no step at all."""
    scene = scene_from(EMPTY_SQUARE, guard={"view_range": 10.0, "fov_degrees": 360})
    assert lower_bounds(scene, (0, 0), 0)[:4] == (0, 0, 0, 0)


def random_clusters(scene: Scene, seed: int) -> tuple[np.ndarray, int]:
    """Disjoint clusters of cells taken greedily in a random order: the label of every state and the
    number of clusters (watchers count when reachable from the first cell, facing right)."""
    grid = scene.grid
    table = view_table(grid, scene.vision())
    start = int(np.flatnonzero(grid.traversable.ravel())[0])
    distance = state_distances(grid.neighbours, start * 4)
    order = np.random.default_rng(seed).permutation(np.flatnonzero(grid.component(*grid.unflat(start)).ravel()))
    label, kept = choose_clusters(order, table.watch_start, table.watchers, distance)
    return label, len(kept)


def fewest_steps(from_state: dict[int, np.ndarray], sources: np.ndarray, targets: np.ndarray) -> int:
    """Fewest steps from any of ``sources`` to any of ``targets``, given each source's distances."""
    reached = [from_state[int(source)][targets] for source in sources]
    return min(int(row[row >= 0].min()) for row in reached if (row >= 0).any())


@pytest.mark.parametrize("name", ["pillar", "empty-square", "l-room"])
def test_cluster_distances_by_brute_force(name: str) -> None:
    """Each entry is the fewest steps from any watcher of one cluster to any of the other, either way
    round, as found by a search from every single state."""
    scene = scene_from(SHORT_SIGHTED[name])
    grid = scene.grid
    for seed in range(3):
        label, clusters = random_clusters(scene, seed)
        matrix = cluster_distances(grid.neighbours, label, clusters)
        members = [np.flatnonzero(label == cluster) for cluster in range(clusters)]
        from_state = {int(s): state_distances(grid.neighbours, int(s)) for s in np.flatnonzero(label >= 0)}
        for a in range(clusters):
            for b in range(clusters):
                ahead = fewest_steps(from_state, members[a], members[b])
                behind = fewest_steps(from_state, members[b], members[a])
                assert matrix[a, b] == min(ahead, behind)


@pytest.mark.parametrize("name", ["pillar", "empty-square", "shipped"])
def test_spanning_tree_two_ways(name: str) -> None:
    """The two-search spanning tree weighs the same as Prim's over the pairwise cluster distances."""
    scene = shipped_scene(LEVELS[0]) if name == "shipped" else scene_from(SHORT_SIGHTED[name])
    for seed in range(3):
        label, clusters = random_clusters(scene, seed)
        matrix = cluster_distances(scene.grid.neighbours, label, clusters)
        weight = spanning_tree_weight(scene.grid.neighbours, label, clusters)
        assert weight == subset_tree_weight(matrix, np.arange(clusters)) > 0


@short_sighted
def test_every_planner_needs_at_least_the_optimum(name: str) -> None:
    """On tiny levels every planner (random walk included) covers, in no fewer steps than the optimum."""
    scene = scene_from(SHORT_SIGHTED[name])
    start = starts(scene, most=3)[1]
    optimum = optimum_steps(scene, start, 1, scene.vision())
    bound = lower_bounds(scene, start, 1).best
    for planner in PLANNERS:
        trace = run_episode(scene, make_planner(planner), starts=[start], headings=[1], seed=3)
        assert trace.outcome == "covered", planner
        assert bound <= optimum <= trace.steps, planner


@functools.cache
def shipped_scene(level_path: Path) -> Scene:
    """One scene per shipped level for the whole module, so its view table is built once."""
    return Scene.from_level(load_level(level_path))


#: Seeds per planner (episode K of seed K). A random walk reaches the step limit in most 60 x 60
#: episodes, which bound nothing, so it gets one (it is checked on the tiny levels, where it covers).
SEEDS = {"random-walk": (0,)}


@shipped_levels
@pytest.mark.parametrize("planner", list(PLANNERS))
def test_bounds_never_exceed_planner_steps(level_path: Path, planner: str) -> None:
    """On every shipped level, the best bound is at most the steps of every covered bench episode.

    Every planner in ``PLANNERS`` runs, so new planners are covered as they land.
    """
    scene = shipped_scene(level_path)
    for seed in SEEDS.get(planner, (0, 1, 2)):
        trace = run_episode(scene, seed=seed, episode=seed, planner=planner)
        bounds = lower_bounds(scene, trace.path[0], trace.headings[0])
        assert bounds.best > 0
        if trace.outcome == "covered":
            assert bounds.best <= trace.steps, (seed, bounds, trace.steps)


def test_bounds_are_deterministic() -> None:
    """Separately built scenes give the same bounds (timings aside)."""
    level = load_level(Path(__file__).resolve().parent.parent / "levels" / "passages.json")
    first = lower_bounds(Scene.from_level(level), (5, 50), 3)
    second = lower_bounds(Scene.from_level(level), (5, 50), 3)
    assert first[:4] == second[:4]


def test_cli_prints_the_bounds(tmp_path: Path) -> None:
    """`guardsim bounds` on the corridor from its middle: the hand-worked figures and the timings."""
    path = write_level(tmp_path, STRIP)
    result = CliRunner().invoke(main, ["bounds", str(path), "--start", "3.5,0.5", "--heading", "right"])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("corridor: from 3.5,0.5 (cell [3, 0]) facing right (7 reachable cells): ")
    assert "eccentricity bound 2, cluster bound 6 (2 clusters), path bound 6, best bound 6 steps;" in result.stdout
    assert "view table " in result.stdout and "bounds " in result.stdout


def test_cli_episode_start_matches_bench(tmp_path: Path) -> None:
    """--seed S --episode K bounds the start that bench's episode K starts from."""
    path = write_level(tmp_path, SHORT_SIGHTED["pillar"])
    result = CliRunner().invoke(main, ["bounds", str(path), "--seed", "4", "--episode", "2"])
    trace = run_episode(scene_from(SHORT_SIGHTED["pillar"]), seed=4, episode=2)
    (col, row), heading = trace.path[0], trace.headings[0]
    assert f"(cell [{col}, {row}]) facing {['right', 'down', 'left', 'up'][heading]} " in result.stdout


def test_cli_bad_start_is_one_line(tmp_path: Path) -> None:
    """A start inside the pillar: one error line naming the file, status 2."""
    path = write_level(tmp_path, SQUARE_WITH_HOLE)
    result = CliRunner().invoke(main, ["bounds", str(path), "--start", "3,3"])
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"guardsim: error: {path}: start (3, 3) is in cell [3, 3], where the guard (radius 0.3) does not fit"
    ]


def test_console_script_bounds(tmp_path: Path) -> None:
    """The real `guardsim bounds` process with the Bresenham rule."""
    path = write_level(tmp_path, STRIP)
    completed = subprocess.run(
        [
            *guardsim_command(),
            "bounds",
            str(path),
            "--start",
            "0.5,0.5",
            "--heading",
            "right",
            "--los",
            "bresenham",
            "--fov",
            "90",
            "--view-range",
            "1",
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert completed.returncode == 0, completed.stderr
    assert "best bound 5 steps" in completed.stdout
