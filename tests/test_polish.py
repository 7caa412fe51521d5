"""Spiral routes and the polish of a walk by simulated changes: the rings' geometry, and polished walks
that are what the loop then walks, never longer, shorter where a route wastes steps, and deterministic."""

from __future__ import annotations

import numpy as np

from guardsim import load_level
from guardsim.motion import run_episode
from guardsim.planners.lawnmower import spiral_rings, spiral_routes, swath_half_width
from guardsim.planners.polish import polish_route
from guardsim.planners.route_walk import walk_routes
from guardsim.planners.tour import Tour
from guardsim.simulation import Scene
from guardsim.vision.table import ViewTable, view_table
from tests.common import LEVELS, OPEN_ROOM, scene_from, starts

SQUARE = next(path for path in LEVELS if path.stem == "square")


def test_spiral_rings_are_a_swath_apart_until_no_middle_is_left() -> None:
    """A 60 x 60 goal and an 11-cell swath: rings 5, 16 and 27 cells in; the third's swaths meet, so
    it is the last. A 20-row strip needs one ring, whose two lanes see every row."""
    rings = spiral_rings(np.ones(60 * 60, dtype=bool), (60, 60), 11)
    assert [ring[0] for ring in rings] == [(5, 5, 0), (16, 16, 0), (27, 27, 0)]
    for ring, inset in zip(rings, (5, 16, 27), strict=True):
        rows = {row for row, _, _ in ring}
        cols = {col for _, col, _ in ring}
        assert min(rows) == min(cols) == inset and max(rows) == max(cols) == 59 - inset
        # Clockwise on screen: right along the top, down the right side, left along the bottom, up.
        assert [heading for _, _, heading in ring] == sorted(heading for _, _, heading in ring)
    strip = spiral_rings(np.ones(20 * 60, dtype=bool), (20, 60), 11)
    assert len(strip) == 1
    assert {row for row, _, heading in strip[0] if heading in (0, 2)} == {5, 14}


def test_spirals_enter_each_ring_nearest_the_guard() -> None:
    """Four spirals, every state enterable; the two walked outside in start at the outer ring's stop
    nearest the start, the two walked inside out elsewhere (the innermost ring here is a point in the
    pillar, left out)."""
    scene = scene_from(OPEN_ROOM)
    table = view_table(scene.grid, scene.vision())
    goal = scene.grid.largest_component().ravel()
    rows, cols = scene.grid.shape
    rings = spiral_rings(goal, (rows, cols), 2 * swath_half_width(table, goal, cols) + 1)
    start = 20 * cols + 3
    routes = spiral_routes(rings, cols, table.entry, start)
    assert len(routes) == 4
    assert len(rings) == 3 and {(row, col) for row, col, _ in rings[-1]} == {(11, 11)}
    outer = {row * cols + col for row, col, _ in rings[0]}
    for number, route in enumerate(routes):
        assert (table.entry[route] >= 0).all()
        first_row, first_col = divmod(int(route[0]) // 4, cols)
        if number < 2:
            nearest = min(abs(row - 20) + abs(col - 3) for row, col, _ in rings[0])
            assert abs(first_row - 20) + abs(first_col - 3) == nearest
        else:
            assert int(route[0]) // 4 not in outer


def _walk_inputs(scene: Scene) -> tuple[ViewTable, np.ndarray, np.ndarray, np.ndarray]:
    table = view_table(scene.grid, scene.vision())
    goal = scene.grid.largest_component().ravel()
    return table, scene.grid.neighbours, goal, np.zeros(goal.size, dtype=bool)


def test_polished_route_walks_as_promised_and_never_longer() -> None:
    """From spread starts: the polished route's walk (walked again by the loop's rule) takes exactly the
    ticks the polish reported, no more than the route's own; with no trials the route is kept."""
    scene = scene_from(OPEN_ROOM)
    table, neighbours, goal, seen = _walk_inputs(scene)
    rows, cols = scene.grid.shape
    rings = spiral_rings(goal, (rows, cols), 2 * swath_half_width(table, goal, cols) + 1)
    shorter = 0
    for col, row in starts(scene, most=4):
        start = (row * cols + col, 0)
        route = spiral_routes(rings, cols, table.entry, start[0])[0]
        before = walk_routes(table, neighbours, goal, seen, (start,), [route], limit=5000)
        assert before.covered
        kept, steps = polish_route(table, neighbours, goal, seen, start, route, limit=5000, trials=0)
        assert steps == before.steps and np.array_equal(kept, route)
        polished, steps = polish_route(table, neighbours, goal, seen, start, route, limit=5000, trials=400)
        after = walk_routes(table, neighbours, goal, seen, (start,), [polished], limit=5000)
        assert after.covered and after.steps == steps <= before.steps
        again, _ = polish_route(table, neighbours, goal, seen, start, route, limit=5000, trials=400)
        assert np.array_equal(again, polished)
        shorter += steps < before.steps
    assert shorter >= 2


def test_polish_drops_a_detour() -> None:
    """A route with a useless far corner in the middle of it: the polish leaves it out (or moves it)
    and the walk gets shorter; a route whose walk cannot cover the goal is reported as such."""
    scene = scene_from(OPEN_ROOM)
    table, neighbours, goal, seen = _walk_inputs(scene)
    rows, cols = scene.grid.shape
    rings = spiral_rings(goal, (rows, cols), 2 * swath_half_width(table, goal, cols) + 1)
    start = (cols + 1, 0)
    route = spiral_routes(rings, cols, table.entry, start[0])[0]
    corner = (rows - 1) * cols + cols - 1
    detour = np.insert(route, 1, corner * 4 + 0)
    before = walk_routes(table, neighbours, goal, seen, (start,), [detour], limit=5000)
    polished, steps = polish_route(table, neighbours, goal, seen, start, detour, limit=5000, trials=300)
    assert steps < before.steps
    assert corner * 4 not in polished[:2].tolist()
    _, none = polish_route(table, neighbours, goal, seen, start, route, limit=10, trials=50)
    assert none == -1


def test_tour_polish_never_hurts_and_is_what_the_loop_walks() -> None:
    """Square, three bench starts: tour with its polish is never longer than without and shorter on at
    least one, and the loop records the walk it planned."""
    scene = Scene.from_level(load_level(SQUARE))
    shorter = 0
    for episode in range(3):
        polished = run_episode(scene, seed=0, episode=episode, planner="tour")
        plain = run_episode(scene, seed=0, episode=episode, planner="tour", polish_trials=0)
        assert polished.covered and polished.steps <= plain.steps
        shorter += polished.steps < plain.steps
    assert shorter >= 1
    start, heading = (27, 48), 3
    planner = Tour()
    trace = run_episode(scene, planner, starts=[start], headings=[heading])
    assert planner.walk is not None and planner.walk.steps == trace.steps


def test_polish_stops_at_its_tick_budget() -> None:
    """A tick budget below one trial's walk leaves the route as it was, however many trials are allowed."""
    scene = scene_from(OPEN_ROOM)
    table, neighbours, goal, seen = _walk_inputs(scene)
    rows, cols = scene.grid.shape
    rings = spiral_rings(goal, (rows, cols), 2 * swath_half_width(table, goal, cols) + 1)
    start = (cols + 1, 0)
    route = np.insert(spiral_routes(rings, cols, table.entry, start[0])[0], 1, ((rows - 1) * cols + cols - 1) * 4)
    before = walk_routes(table, neighbours, goal, seen, (start,), [route], limit=5000)
    kept, steps = polish_route(table, neighbours, goal, seen, start, route, limit=5000, trials=300, max_ticks=1)
    assert steps == before.steps and np.array_equal(kept, route)
    _, polished = polish_route(table, neighbours, goal, seen, start, route, limit=5000, trials=300)
    assert polished < before.steps
