"""The exact search's pattern database (``guardsim.search.pattern``): its table is the brute-force
fewest steps through the picks' watchers, its value never exceeds the optimum, the A* with it still
proves the brute-force optimum, and the same graph gives the same table."""

from __future__ import annotations

from collections import deque
from pathlib import Path

import numpy as np
import pytest

from guardsim.search import DOMINANCE_CHECKS
from guardsim.search.astar import INCUMBENT, PROVED, STATUS, new_search_state, run_search, start_search
from guardsim.search.graph import SearchGraph, build_search_graph
from guardsim.search.heuristic import build_heuristic
from guardsim.search.pattern import _cover, build_pattern, pattern_table, with_pattern
from guardsim.search.residual import residual_goal
from guardsim.simulation import Scene
from guardsim.vision.table import view_table
from tests.common import optimum_steps, scene_from, starts
from tests.test_optimum_pruning import GUARDS, _random_level

SHARED = Path(__file__).resolve().parents[2] / "shared" / "maps" / "movingai"


def _levels(name: str, seed: int, count: int) -> list[tuple[Scene, tuple[int, int], int, SearchGraph]]:
    """Random tiny levels of one guard kind, with spread starts and their residual search graphs."""
    guard, sight = GUARDS[name]
    generator = np.random.default_rng(seed)
    found = []
    for _ in range(count):
        width, height = int(generator.integers(3, 6)), int(generator.integers(3, 5))
        scene = Scene.from_level(scene_from(_random_level(generator, width, height, guard)).level, line_of_sight=sight)
        for start in starts(scene, most=2):
            heading = int(generator.integers(4))
            table = view_table(scene.grid, scene.vision())
            found.append((scene, start, heading, residual_goal(build_search_graph(scene.grid, table, start, heading))))
    return found


def _through_picks(successors: np.ndarray, cover: np.ndarray, picks: int, position: int, seen: int) -> int:
    """Breadth first over (position, picks seen) from one pair: the fewest steps until all are seen."""
    everything = (1 << picks) - 1
    first = (position, seen | int(cover[position]))
    steps = {first: 0}
    queue = deque([first])
    while queue:
        here, mask = queue.popleft()
        if mask == everything:
            return steps[here, mask]
        for there in successors[here].tolist():
            if there >= 0:
                after = (there, mask | int(cover[there]))
                if after not in steps:
                    steps[after] = steps[here, mask] + 1
                    queue.append(after)
    return 255


@pytest.mark.parametrize("name", list(GUARDS), ids=list(GUARDS))
def test_the_table_is_the_brute_force_walk_through_the_picks(name: str) -> None:
    generator = np.random.default_rng(7)
    checked = 0
    for _, _, _, graph in _levels(name, 2031, 4):
        goal = int(graph.goal_cells.size)
        picks = int(min(goal, generator.integers(1, 5)))
        bits = np.sort(generator.choice(goal, size=picks, replace=False)).astype(np.int64)
        cover = _cover(graph.views, bits)
        table = pattern_table(np.ascontiguousarray(graph.successors), cover, picks)
        assert table.shape == (1 << picks, graph.positions)
        for seen in range(1 << picks):
            for position in range(graph.positions):
                if seen | int(cover[position]) == seen:  # the entries a search reads
                    expected = _through_picks(graph.successors, cover, picks, position, seen)
                    assert table[seen, position] == expected, (seen, position)
                    checked += 1
    assert checked > 100


@pytest.mark.parametrize("name", list(GUARDS), ids=list(GUARDS))
def test_the_pattern_bound_is_at_most_the_optimum_and_the_search_still_proves_it(name: str) -> None:
    raised = 0
    for scene, start, heading, graph in _levels(name, 2032, 6):
        optimum = optimum_steps(scene, start, heading, scene.vision())
        bits, table = build_pattern(graph)
        assert bits.size >= 1 or optimum == 0
        seen_at_start = graph.views[graph.start]
        subset = sum(1 << index for index, bit in enumerate(bits.tolist()) if seen_at_start[bit >> 6] >> (bit & 63) & 1)
        value = int(table[subset, graph.start])
        assert value <= optimum, (start, heading)
        plain = build_heuristic(graph)
        heuristic = with_pattern(plain, bits, table)
        state = new_search_state(1 << 16, graph.full.size, graph.positions)
        start_search(state, heuristic, graph.views, graph.full, graph.start, 1 << 14)
        # The start's estimate is the larger of the plain one and the table's.
        before = new_search_state(16, graph.full.size, graph.positions)
        start_search(before, plain, graph.views, graph.full, graph.start, 1 << 14)
        assert state.estimate[0] == max(before.estimate[0], value) or optimum == 0
        raised += value > before.estimate[0]
        run_search(state, heuristic, graph.successors, graph.views, graph.full, 1 << 20, DOMINANCE_CHECKS, 1.0, True)
        assert state.counters[STATUS] == PROVED and state.counters[INCUMBENT] == optimum, (start, heading)
    assert raised  # the table is more than the plain estimate somewhere, else this test checks nothing


def test_the_same_graph_gives_the_same_table_and_a_budget_caps_it() -> None:
    _, _, _, graph = _levels("bresenham-360-1", 2033, 1)[0]
    bits, table = build_pattern(graph)
    again_bits, again_table = build_pattern(graph)
    assert np.array_equal(bits, again_bits) and np.array_equal(table, again_table)
    small_bits, small_table = build_pattern(graph, most_entries=4 * graph.positions)
    assert small_bits.size == 2 and small_table.shape == (4, graph.positions)
    assert np.array_equal(small_bits, bits[:2])  # picks are added one at a time, the first ones kept
    reports: list[tuple[int, int]] = []
    build_pattern(graph, most_entries=4 * graph.positions, report=lambda picks, value: reports.append((picks, value)))
    assert [picks for picks, _ in reports] == [1, 2] and reports[0][1] <= reports[1][1]


@pytest.mark.slow  # 8 s: the table of a 819-position map
@pytest.mark.skipif(not (SHARED / "random-32-32-20.map").exists(), reason="shared maps missing")
def test_on_random_32_32_20_the_table_proves_93_at_the_start() -> None:
    # The figure docs/optimum.md gives: the search's own estimate at this start is 69.
    from guardsim.cli.common import build_scene
    from guardsim.importers import import_map

    scene = build_scene(import_map(SHARED / "random-32-32-20.map").level, "bresenham", 360.0, None)
    graph = residual_goal(build_search_graph(scene.grid, view_table(scene.grid, scene.vision()), (0, 0), 0))
    bits, table = build_pattern(graph)
    assert bits.size == 17
    assert table[_cover(graph.views, bits)[graph.start], graph.start] == 93
