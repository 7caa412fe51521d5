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
from guardsim.search.pattern import _cover, build_pattern, build_patterns, pattern_table, with_pattern
from guardsim.search.residual import residual_goal
from guardsim.simulation import Scene
from guardsim.vision.table import view_table
from tests.common import optimum_steps, scene_from, starts
from tests.test_improve import _pillared_room
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


def _start_value(graph: SearchGraph, bits: np.ndarray, tables: np.ndarray) -> int:
    """The largest of the tables' values at the start (stacked as :func:`build_patterns` gives them)."""
    seen = graph.views[graph.start]
    best = 0
    for picks, table in zip(bits.tolist(), tables, strict=True):
        subset = sum(1 << index for index, bit in enumerate(picks) if seen[bit >> 6] >> (bit & 63) & 1)
        best = max(best, int(table[subset, graph.start]))
    return best


@pytest.mark.parametrize("name", list(GUARDS), ids=list(GUARDS))
def test_the_pattern_bound_is_at_most_the_optimum_and_the_search_still_proves_it(name: str) -> None:
    raised = 0
    for scene, start, heading, graph in _levels(name, 2032, 6):
        optimum = optimum_steps(scene, start, heading, scene.vision())
        bits, tables = build_patterns(graph, 2)
        assert bits.shape[1] >= 1 or optimum == 0
        value = _start_value(graph, bits, tables)
        assert value <= optimum, (start, heading)
        plain = build_heuristic(graph)
        heuristic = with_pattern(plain, bits, tables)
        state = new_search_state(1 << 16, graph.full.size, graph.positions)
        start_search(state, heuristic, graph.views, graph.full, graph.start, 1 << 14)
        # The start's estimate is the larger of the plain one and the tables'.
        before = new_search_state(16, graph.full.size, graph.positions)
        start_search(before, plain, graph.views, graph.full, graph.start, 1 << 14)
        assert state.estimate[0] == max(before.estimate[0], value) or optimum == 0
        raised += value > before.estimate[0]
        run_search(state, heuristic, graph.successors, graph.views, graph.full, 1 << 20, DOMINANCE_CHECKS, 1.0, True)
        assert state.counters[STATUS] == PROVED and state.counters[INCUMBENT] == optimum, (start, heading)
    assert raised  # the tables are more than the plain estimate somewhere, else this test checks nothing


def test_the_same_graph_gives_the_same_table_and_a_budget_caps_it() -> None:
    _, _, _, graph = _levels("bresenham-360-1", 2033, 1)[0]
    bits, table, walk = build_pattern(graph)
    again_bits, again_table, again_walk = build_pattern(graph)
    assert np.array_equal(bits, again_bits) and np.array_equal(table, again_table)
    assert np.array_equal(walk, again_walk) and walk[0] == graph.start
    small_bits, small_table, _ = build_pattern(graph, most_entries=4 * graph.positions)
    assert small_bits.size == 2 and small_table.shape == (4, graph.positions)
    assert np.array_equal(small_bits, bits[:2])  # picks are added one at a time, the first ones kept
    reports: list[tuple[int, int]] = []
    build_pattern(graph, most_entries=4 * graph.positions, report=lambda picks, value: reports.append((picks, value)))
    assert [picks for picks, _ in reports] == [1, 2] and reports[0][1] <= reports[1][1]


def test_the_second_table_picks_against_the_first_tables_walk() -> None:
    scene, start = _pillared_room()
    graph = residual_goal(build_search_graph(scene.grid, view_table(scene.grid, scene.vision()), start, 0))
    bits, tables = build_patterns(graph, 2, most_entries=8 * graph.positions)
    first_bits, first_table, walk = build_pattern(graph, most_entries=8 * graph.positions)
    second_bits, second_table, _ = build_pattern(graph, most_entries=8 * graph.positions, walk=walk)
    assert bits.shape == (2, 3) and tables.shape == (2, 8, graph.positions)
    assert np.array_equal(bits, [first_bits, second_bits]) and np.array_equal(tables, [first_table, second_table])
    # The second table's first pick is a cell the first table's walk leaves unseen.
    seen = np.bitwise_or.reduce(graph.views[walk], axis=0)
    bit = int(second_bits[0])
    assert not seen[bit >> 6] >> np.uint64(bit & 63) & np.uint64(1)


@pytest.mark.slow  # 8 s: the table of a 819-position map
@pytest.mark.skipif(not (SHARED / "random-32-32-20.map").exists(), reason="shared maps missing")
def test_on_random_32_32_20_the_table_proves_93_at_the_start() -> None:
    # The figure docs/optimum.md gives: the search's own estimate at this start is 69.
    from guardsim.cli.common import build_scene
    from tests.common import import_map

    scene = build_scene(import_map(SHARED / "random-32-32-20.map").level, "bresenham", 360.0, None)
    graph = residual_goal(build_search_graph(scene.grid, view_table(scene.grid, scene.vision()), (0, 0), 0))
    bits, table, _ = build_pattern(graph)
    assert bits.size == 17
    assert table[_cover(graph.views, bits)[graph.start], graph.start] == 93
