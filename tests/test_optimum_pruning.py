"""The exact search's pruning keeps the optimum: its A* alone (no first walk in hand) against the
breadth-first optimum on random tiny levels, with and without dropping shadowed moves.

A move of the search is shadowed when a shortest path from the node reaches it through another move's
position (``guardsim.kernels.frontier.drop_shadowed``; its plain rule is tested in ``test_optimum.py``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from guardsim.optimum import _weighted_walks
from guardsim.search import DOMINANCE_CHECKS
from guardsim.search.astar import INCUMBENT, PROVED, STATUS, greedy_walk, new_search_state, run_search, start_search
from guardsim.search.graph import build_search_graph, route_steps
from guardsim.search.heuristic import build_heuristic
from guardsim.search.residual import residual_goal
from guardsim.simulation import Scene
from guardsim.vision.table import view_table
from tests.common import optimum_steps, scene_from, starts


def _random_level(generator: np.random.Generator, width: int, height: int, guard: dict[str, Any]) -> dict[str, Any]:
    """A ``width`` x ``height`` room with a few unit pillars, none touching another or the wall."""
    holes: list[list[list[int]]] = []
    taken: set[tuple[int, int]] = set()
    for _ in range(int(generator.integers(0, 4))):
        col, row = int(generator.integers(1, width - 1)), int(generator.integers(1, height - 1))
        if any((col + dc, row + dr) in taken for dc in (-1, 0, 1) for dr in (-1, 0, 1)):
            continue
        taken.add((col, row))
        holes.append([[col, row], [col + 1, row], [col + 1, row + 1], [col, row + 1]])
    return {"outer": [[0, 0], [width, 0], [width, height], [0, height]], "holes": holes, "guard": guard}


GUARDS: dict[str, tuple[dict[str, Any], str]] = {
    "cone-1.5": ({"view_range": 1.5}, "pymunk"),
    "bresenham-360-1": ({"view_range": 1.0, "fov_degrees": 360}, "bresenham"),
    "bresenham-360-2": ({"view_range": 2.0, "fov_degrees": 360}, "bresenham"),
    "bresenham-cone-2": ({"view_range": 2.0, "fov_degrees": 90}, "bresenham"),
}


def _astar_alone(scene: Scene, start: tuple[int, int], heading: int, shadows: bool) -> int:
    """The A* optimum with no first walk in hand (``guardsim.optimum.solve`` starts from the beam's walk,
    which is often optimal on tiny levels: a search that lost every optimal walk would still "prove" it)."""
    graph = residual_goal(build_search_graph(scene.grid, view_table(scene.grid, scene.vision()), start, heading))
    heuristic = build_heuristic(graph)
    state = new_search_state(1 << 16, graph.full.size, graph.positions)
    start_search(state, heuristic, graph.views, graph.full, graph.start, 1 << 14)
    run_search(state, heuristic, graph.successors, graph.views, graph.full, 1 << 20, DOMINANCE_CHECKS, 1.0, shadows)
    assert state.counters[STATUS] == PROVED
    return int(state.counters[INCUMBENT])


@pytest.mark.parametrize("name", list(GUARDS), ids=list(GUARDS))
def test_optimum_with_pruning_is_the_brute_force_optimum_on_random_levels(name: str) -> None:
    guard, sight = GUARDS[name]
    generator = np.random.default_rng(2028)
    for _ in range(8):
        width, height = int(generator.integers(3, 6)), int(generator.integers(3, 5))
        level = scene_from(_random_level(generator, width, height, guard)).level
        scene = Scene.from_level(level, line_of_sight=sight)
        for start in starts(scene, most=3):
            heading = int(generator.integers(4))
            optimum = optimum_steps(scene, start, heading, scene.vision())
            assert _astar_alone(scene, start, heading, shadows=True) == optimum, (width, height, start, heading)
            assert _astar_alone(scene, start, heading, shadows=False) == optimum


@pytest.mark.parametrize("name", list(GUARDS), ids=list(GUARDS))
def test_the_weighted_first_walks_are_real_walks_between_the_optimum_and_the_greedy_walk(name: str) -> None:
    guard, sight = GUARDS[name]
    generator = np.random.default_rng(2029)
    shorter = 0
    for _ in range(6):
        width, height = int(generator.integers(4, 6)), int(generator.integers(3, 5))
        scene = Scene.from_level(scene_from(_random_level(generator, width, height, guard)).level, line_of_sight=sight)
        for start in starts(scene, most=3):
            graph = residual_goal(build_search_graph(scene.grid, view_table(scene.grid, scene.vision()), start, 0))
            greedy, greedy_steps = greedy_walk(graph.successors, graph.views, graph.full, graph.start)
            route, steps = _weighted_walks(graph, build_heuristic(graph), greedy, int(greedy_steps), 0.0, None)
            assert optimum_steps(scene, start, 0, scene.vision()) <= steps <= greedy_steps
            assert len(route_steps(graph, route, 0)[0]) - 1 == steps  # rebuilt, it has the steps counted
            shorter += steps < greedy_steps
    assert shorter > 0 or name == "bresenham-360-2"  # there the greedy walk is already optimal
