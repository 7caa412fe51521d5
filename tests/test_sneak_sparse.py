"""The sneak check without arrays over every (lap tick, cell) gives the answers of the dense searches, path
for path: the dense functions (:func:`find_sneak`, :func:`closest_call`, :func:`undetected_search`,
:func:`unseen_reach`, :func:`entry_searches`, the dense maps) are the reference, run on random loops of
the tiny levels, with light and a dark sight so that meters rise and drain."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from guardsim.detection import GuardDetection, PatrolGains, exposure_map, patrol_gains, time_to_detection
from guardsim.detection.sight import lap_sight
from guardsim.grid import CoverageGrid
from guardsim.kernels.meter import meter_gain, visibility
from guardsim.patrol import Patrol, patrol_setup
from guardsim.scene import Scene
from guardsim.sneak import closest_call, find_sneak, hiding_windows, sneak_check, undetected_search
from guardsim.sneak.grade import unseen_reach
from guardsim.sneak.graded import entry_searches
from guardsim.sneak.sweep import entry_search, sweep
from guardsim.vision.table import ViewTable
from tests.common import TINY_LEVELS, random_loop, scene_from


def _dense(
    grid: CoverageGrid, table: ViewTable, patrol: Patrol, detection: GuardDetection, source: int, target: int,
    undetected: bool,
) -> tuple[tuple[int, list[int], int] | None, int, np.ndarray, PatrolGains]:  # fmt: skip
    """The sneak check as the dense searches answer it: (start, cells, ticks in view), slack, reached cells."""
    gains = patrol_gains(grid, table, patrol.states, detection.model, view_range=detection.view_range, dt=detection.dt)
    seen = gains.seen
    neighbours = grid.neighbours
    reach = unseen_reach(neighbours, seen, target)
    entries = reach[:, source].copy()
    search = undetected_search(neighbours, gains.gain, gains.fall, source, target, exhaustive=True, seen=seen)
    path = find_sneak(neighbours, seen, source, target)
    answer = None if path is None else (path.start_tick, path.cells.tolist(), path.ticks_in_view)
    if undetected and search.found >= 0:
        start, cells = search.path()
        if path is None or path.ticks > cells.size - 1:
            answer = (start, cells.tolist(), int(seen[(start + np.arange(cells.size)) % seen.shape[0], cells].sum()))
        goal = reach.copy()
        goal[:, target] = True
        phases = np.flatnonzero(~entries)
        entries[phases] |= entry_searches(neighbours, gains.gain, gains.fall, source, goal, phases, seen=seen)
    elif path is None:
        call = closest_call(neighbours, seen, source, target)
        answer = None if call is None else (call.start_tick, call.cells.tolist(), call.ticks_in_view)
    return answer, int(entries.sum()), search.reached_cells(), gains


def _trials(name: str, seed: int) -> Iterator[tuple[Scene, ViewTable, Patrol, int, int]]:
    level = TINY_LEVELS[name] | {
        "guard": {"start": [0.5, 0.5], "heading": "right", "view_range": 3.5, "detect_near": 0.6, "detect_far": 1.6}
    }
    scene = scene_from(level)
    setup = patrol_setup(scene)
    rng = np.random.default_rng(seed)
    cells = np.flatnonzero(setup.goal)
    for trial in range(4):
        guards = 1 + trial % 2
        laps = [random_loop(scene, rng, int(rng.integers(1, 6))) for _ in range(guards)]
        period = int(np.lcm.reduce([lap.size for lap in laps]))
        patrol = Patrol(np.stack([np.tile(lap, period // lap.size) for lap in laps]), period, "test")
        for _ in range(3):
            source, target = (int(cells[rng.integers(cells.size)]) for _ in range(2))
            yield scene, setup.table, patrol, source, target


@pytest.mark.parametrize(
    ("name", "side_by_side"),
    [("square-with-hole", False), ("l-room", False), ("empty-square", False), ("l-room", True)],
)
def test_the_sparse_sneak_check_answers_as_the_dense_searches(
    name: str, side_by_side: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``side_by_side``: the check's two sweeps run in two threads, as on a big map."""
    import guardsim.sneak as sneak_module

    if side_by_side:
        monkeypatch.setattr(sneak_module, "PARALLEL_SWEEP_NODES", 0)
    rules = set()
    for scene, table, patrol, source, target in _trials(name, 11):
        detection = GuardDetection.of_level(scene.level)
        grid = scene.grid
        for undetected in (False, True):
            result = sneak_check(grid, table, patrol, source, target, detection=detection, undetected=undetected)
            answer, slack, reached, gains = _dense(grid, table, patrol, detection, source, target, undetected)
            path = result.path
            got = None if path is None else (path.start_tick, path.cells.tolist(), path.ticks_in_view)
            assert got == answer
            assert result.slack == slack
            assert np.array_equal(result.hiding, hiding_windows(gains.seen, grid.traversable))
            assert np.array_equal(result.exposure, exposure_map(gains))
            assert np.array_equal(result.time_to_detection, time_to_detection(gains, grid.traversable))
            assert {spot.cell for spot in result.hiding_spots} <= set(np.flatnonzero(reached).tolist())
            rules.add((undetected, None if path is None else (path.found, path.ticks_in_view > 0)))
    # Unseen, undetected-but-seen and caught answers all came up.
    assert (True, (True, True)) in rules and (False, (True, False)) in rules


def test_the_lap_sight_holds_each_watchers_gain_by_the_rule() -> None:
    """Every (guard, lap tick, cell) the guard's state sees, and no other, holds the meter rule's gain at
    that distance and light, written out here over the view table; the dense gains scatter the same."""
    for scene, table, patrol, _, _ in _trials("l-room", 3):
        detection = GuardDetection.of_level(scene.level)
        model, grid = detection.model, scene.grid
        light = np.linspace(0.0, 1.0, grid.size)
        arguments: dict[str, Any] = {"view_range": detection.view_range, "dt": detection.dt, "light": light}
        sparse = lap_sight(grid, table, patrol.states, model, **arguments)
        expected = np.zeros((patrol.states.shape[0], patrol.period, grid.size))
        cols = grid.shape[1]
        for guard, row in enumerate(patrol.states.tolist()):
            for tick, state in enumerate(row):
                own = state // 4
                for cell in table.sees(state).tolist():
                    distance = grid.cell_size * math.hypot(cell // cols - own // cols, cell % cols - own % cols)
                    seen = visibility(distance, model.dark_sight, float(light[cell]))
                    expected[guard, tick, cell] = meter_gain(
                        detection.dt, distance, detection.view_range, model.detect_near, model.detect_far, seen
                    )
        dense = sparse.dense_gains()
        assert np.allclose(dense.gain, expected, rtol=1e-12, atol=0.0)
        assert np.array_equal(dense.gain > 0, expected > 0) and (expected > 0).any() and (expected == 0).any()
        assert np.array_equal(patrol_gains(grid, table, patrol.states, model, **arguments).gain, dense.gain)
        assert np.array_equal(sparse.dense_seen(), (expected > 0).any(axis=0))
        assert sparse.fall == model.fall(detection.dt) and np.array_equal(sparse.guard_cells, patrol.states // 4)


def test_the_sweeps_reach_what_the_dense_searches_reach() -> None:
    """Backwards unseen and forwards undetected, flooded in no order, against the dense searches; the
    fewest ticks of every entry tick at once against one entry tick searched alone."""
    for scene, table, patrol, source, target in _trials("square-with-hole", 5):
        detection = GuardDetection.of_level(scene.level)
        grid = scene.grid
        arguments: dict[str, Any] = {"view_range": detection.view_range, "dt": detection.dt}
        gains = patrol_gains(grid, table, patrol.states, detection.model, **arguments)
        sight = lap_sight(grid, table, patrol.states, detection.model, **arguments)
        neighbours = grid.neighbours
        period = patrol.period
        reach = unseen_reach(neighbours, gains.seen, target)
        backwards = sweep(sight, neighbours, target, -1, graded=False, forward=False, flood=True, max_labels=10**6)
        bits = np.unpackbits(backwards.reached.view(np.uint8), axis=1, bitorder="little")[:, :period].T
        assert np.array_equal(bits.astype(bool), reach)
        dense = undetected_search(neighbours, gains.gain, gains.fall, source, target, exhaustive=True)
        forwards = sweep(sight, neighbours, source, target, graded=True, flood=True, max_labels=10**6)
        assert np.array_equal(forwards.cells, dense.reached_cells())
        fastest = sweep(sight, neighbours, source, target, graded=True, max_labels=10**6)
        assert fastest.ticks == (-1 if dense.found < 0 else dense.path()[1].size - 1)
        if fastest.ticks >= 0:
            assert fastest.entry == dense.path()[0]
            alone = entry_search(sight, neighbours, source, fastest.entry, target, graded=True, max_labels=10**6)
            assert alone.found and alone.cells.tolist() == dense.path()[1].tolist()


def test_the_sneak_route_is_the_dense_fastest_unseen_path_or_closest_call() -> None:
    """What alert's sneaking intruder walks: :func:`sneak_route` over the sparse sight, against
    :func:`find_sneak` then :func:`closest_call` over the dense lap (and, with ears, their gaits)."""
    from guardsim.detection.hearing import lap_hearing
    from guardsim.level.model import IntruderSpec
    from guardsim.sneak import floor_sight, sneak_route

    kinds = set()
    for name in ("square-with-hole", "l-room"):
        for scene, table, patrol, source, target in _trials(name, 7):
            detection = GuardDetection.of_level(scene.level)
            grid = scene.grid
            sight = lap_sight(grid, table, patrol.states, detection.model, view_range=detection.view_range, dt=1.0)
            seen = sight.dense_seen()
            ears = lap_hearing(grid.neighbours, patrol.states, IntruderSpec(walk_noise=1.5), grid.cell_size)
            for heard in (None, ears):
                dense = find_sneak(grid.neighbours, seen, source, target, heard=heard)
                dense = dense or closest_call(grid.neighbours, seen, source, target, heard=heard)
                got = sneak_route(floor_sight(sight, grid), source, target, heard=heard)
                assert (got is None) == (dense is None)
                if got is not None and dense is not None:
                    assert got.start_tick == dense.start_tick and got.cells.tolist() == dense.cells.tolist()
                    assert got.found == dense.found and got.gaits == dense.gaits
                    kinds.add((heard is None, got.found))
    assert {(True, True), (True, False), (False, True)} <= kinds
