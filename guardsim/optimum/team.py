"""The fewest ticks until K guards, moving at once, have together seen every reachable cell (makespan).

The objective of the multiple watchman route problem (MWRP-CP3: S. Gouru, A. Felner and J. Li, 2026):
every tick each guard steps to a 4-neighbour or waits (keeping its heading), and the answer is the
first tick at which the union of what the guards have seen covers every cell reachable from the starts.
:func:`solve_team` builds the search graph of all the starts, drops the goal cells a team sees on the
way to others (:func:`guardsim.search.residual.residual_goal`), and runs the team search of
:mod:`guardsim.search.team` until it proves the optimum or a limit stops it, as :func:`guardsim.optimum.solve`
does for one guard (``docs/optimum.md``).

Examples
--------
A corridor of 7 cells, guards seeing their cell and the next: one guard from the middle facing right
needs 6 steps (2 + 4); with a second guard at the left end, facing left, each walks right: 2 ticks.

>>> from guardsim.level import parse_level
>>> from guardsim.scene import Scene
>>> corridor = parse_level({"outer": [[0, 0], [7, 0], [7, 1], [0, 1]], "guard": {"view_range": 1.0}})
>>> scene = Scene.from_level(corridor)
>>> solve_team(scene, [((3, 0), 0)]).steps
6
>>> result = solve_team(scene, [((3, 0), 0), ((0, 0), 2)])
>>> result.steps, result.proved, [len(path) - 1 for path in result.paths]
(2, True, [2, 1])
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from guardsim.errors import ArgumentError, LevelError, LimitError
from guardsim.kernels.frontier import frontier, frontier_work
from guardsim.kernels.team_estimate import later_distances
from guardsim.search import DOMINANCE_CHECKS
from guardsim.search.astar import (
    EXPANSIONS,
    FLOOR,
    FULL,
    HEAP,
    INCUMBENT,
    INCUMBENT_NODE,
    NODES,
    PROVED,
    STATUS,
    greedy_walk,
)
from guardsim.search.beam import beam_route
from guardsim.search.graph import SearchGraph, build_search_graph, goal_bits, route_steps
from guardsim.search.heuristic import Heuristic, build_heuristic
from guardsim.search.residual import residual_goal
from guardsim.search.team import new_team_state, run_team, start_team, team_routes
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import view_table

if TYPE_CHECKING:
    from guardsim.optimum import SearchProgress
    from guardsim.scene import Scene

__all__ = ["TeamOptimumResult", "solve_team", "team_optimum_data"]

_CHUNK = 2_000


class TeamOptimumResult(NamedTuple):
    """What the team search found."""

    steps: int
    """The makespan of the best team walk found: ticks until the team has seen every goal cell (the
    optimum when :attr:`proved`)."""
    paths: tuple[tuple[tuple[int, int, int], ...], ...]
    """Per guard, in the order of the starts, ``(col, row, heading)`` at every step of its walk, the start
    first (headings as in :attr:`guardsim.optimum.OptimumResult.path`). A walk shorter than
    :attr:`steps` waits at its end."""
    proved: bool
    """Whether no team walk finishes sooner."""
    lower_bound: int
    """Proved lower bound on the optimum (equal to :attr:`steps` when proved)."""
    root_bound: int
    """The bound at the starts."""
    expansions: int
    """Nodes expanded."""
    nodes: int
    """Nodes stored."""
    stopped_by: str
    """``"proved"``, ``"expansions"``, ``"time"`` or ``"memory"``."""
    headings_matter: bool
    """Whether the search ran over states (the cone) or over cells (headings change nothing)."""
    seconds: float
    """Wall time of the call, the view table included when it was not cached."""


def solve_team(
    scene: Scene,
    starts: Sequence[tuple[tuple[int, int], int]],
    vision: VisionFunction | None = None,
    *,
    max_expansions: int | None = None,
    time_limit: float | None = None,
    memory_bytes: int | None = None,
    progress: Callable[[SearchProgress], None] | None = None,
) -> TeamOptimumResult:
    """The fewest ticks after which guards from ``starts`` have together seen every cell reachable from them.

    Parameters
    ----------
    scene
        The level, its grid and its vision.
    starts
        ``((col, row), heading)`` of each guard; every start must be reachable from the first.
    vision, max_expansions, time_limit, memory_bytes, progress
        As for :func:`guardsim.optimum.solve` (``memory_bytes`` None: its default).

    Returns
    -------
    TeamOptimumResult
        The best team walk, whether it is proved optimal, and the proved lower bound.
    """
    from guardsim.optimum import DEFAULT_MEMORY_BYTES, MAX_POSITIONS, SearchProgress

    began = time.perf_counter()
    if not starts:
        raise ArgumentError("the team search needs at least one guard")
    grid = scene.grid
    table = view_table(grid, scene.vision() if vision is None else vision)
    (first, heading), others = starts[0], list(starts[1:])
    reachable = grid.component(*first)
    for (col, row), _ in others:
        if not reachable[row, col]:
            raise LevelError(
                f"{scene.level.source}: the start cell [{col}, {row}] cannot be reached from the first "
                f"start [{first[0]}, {first[1]}]"
            )
    graph = build_search_graph(grid, table, first, heading, also=others)
    if graph.positions > MAX_POSITIONS:
        raise LimitError(
            f"the exact search is for small levels: {graph.positions} positions from these starts "
            f"(at most {MAX_POSITIONS})"
        )
    positions = np.array(
        [_position(graph.states, grid.flat(*cell), facing, graph.headings_matter) for cell, facing in starts],
        dtype=np.int64,
    )
    graph = residual_goal(graph, also=positions[1:].tolist())
    heuristic = build_heuristic(graph)
    later = later_distances(heuristic.to_watchers, positions)
    # The first incumbent: the shortest of one guard covering everything alone (the others waiting), a
    # greedy team walk, and each guard covering the cells nearest its start.
    alone, alone_steps = _first_walk(graph, heuristic, None)
    if alone_steps < 0:
        alone, alone_steps = greedy_walk(graph.successors, graph.views, graph.full, graph.start)
    if alone_steps < 0:
        raise LevelError(f"{scene.level.source}: some cell reachable from the starts is seen from nowhere")
    first_routes = [alone] + [np.array([position], dtype=np.int64) for position in positions[1:].tolist()]
    for routes, steps in (
        _greedy_team(graph.successors, graph.views, graph.full, positions),
        _nearest_shares(graph, heuristic, positions),
    ):
        if 0 <= steps < alone_steps:
            first_routes, alone_steps = routes, steps
    words = graph.full.size
    budget = DEFAULT_MEMORY_BYTES if memory_bytes is None else memory_bytes
    per_node = 8 * words + 6 * 4 + 1 + 2 * 12 + 2 * 8 + 4
    capacity = max(1024, int(budget // per_node))
    try:
        state = new_team_state(capacity, words, graph.positions, len(starts))
    except (MemoryError, ValueError) as error:
        raise LimitError(f"cannot reserve {budget // 2**20} MB for the search nodes (memory_bytes)") from error
    start_team(state, heuristic, later, positions, graph.views, graph.full, int(alone_steps) + 1)
    root_bound = int(state.bound[0])
    counters = state.counters
    stopped_by = "proved"
    while counters[STATUS] != PROVED:
        if counters[STATUS] == FULL:
            stopped_by = "memory"
            break
        chunk = _CHUNK
        if max_expansions is not None:
            chunk = min(chunk, max_expansions - int(counters[EXPANSIONS]))
            if chunk <= 0:
                stopped_by = "expansions"
                break
        if time_limit is not None and time.perf_counter() - began > time_limit:
            stopped_by = "time"
            break
        run_team(state, heuristic, later, positions, graph.successors, graph.views, graph.full, chunk, DOMINANCE_CHECKS)
        if progress is not None:
            best = int(counters[INCUMBENT]) if counters[INCUMBENT_NODE] >= 0 else int(alone_steps)
            floor = best if counters[STATUS] == PROVED else min(best, max(int(counters[FLOOR]), root_bound))
            progress(
                SearchProgress(
                    int(counters[EXPANSIONS]), int(counters[NODES]), floor, best, time.perf_counter() - began
                )
            )
    makespan = int(counters[INCUMBENT])
    if int(counters[INCUMBENT_NODE]) >= 0:
        routes = team_routes(state, int(counters[INCUMBENT_NODE]), positions)
    else:
        routes, makespan = first_routes, int(alone_steps)
    proved = stopped_by == "proved"
    floor = makespan if proved or counters[HEAP] == 0 else min(makespan, int(state.heap_key[0] // (1 << 16)))
    if not proved and max(floor, root_bound) >= makespan:
        proved, stopped_by = True, "proved"
    paths = tuple(
        tuple((*grid.unflat(cell), facing) for cell, facing in route_steps(graph, route, facing_first)[0])
        for route, (_, facing_first) in zip(routes, starts, strict=True)
    )
    longest = max(len(path) - 1 for path in paths)
    if longest != makespan:
        raise RuntimeError(f"the longest walk has {longest} steps, the search counted {makespan}")
    return TeamOptimumResult(
        makespan,
        paths,
        proved,
        makespan if proved else max(floor, root_bound),
        root_bound,
        int(counters[EXPANSIONS]),
        int(counters[NODES]),
        stopped_by,
        graph.headings_matter,
        time.perf_counter() - began,
    )


def _greedy_team(
    successors: np.ndarray, views: np.ndarray, full: np.ndarray, starts: np.ndarray
) -> tuple[list[np.ndarray], int]:
    """A team walk, greedily: the guard that has walked least takes its nearest move that sees something
    new (ties: the most new cells). Each guard's macro-move positions and the makespan (-1 if stuck)."""
    distance, queue, found, found_steps = frontier_work(successors.shape[0])
    seen = np.bitwise_or.reduce(views[starts], axis=0)
    routes = [[int(start)] for start in starts.tolist()]
    walked = [0] * starts.size
    stuck = [False] * starts.size
    while not np.array_equal(seen, full):
        moving = [k for k in range(starts.size) if not stuck[k]]
        if not moving:
            return [], -1
        guard = min(moving, key=lambda k: (walked[k], k))
        count = frontier(successors, views, routes[guard][-1], seen, distance, queue, found, found_steps)
        if count == 0:
            stuck[guard] = True
            continue
        gains = [int(np.unpackbits((views[found[i]] & ~seen).view(np.uint8)).sum()) for i in range(count)]
        best = min(range(count), key=lambda i: (int(found_steps[i]), -gains[i], i))
        routes[guard].append(int(found[best]))
        walked[guard] += int(found_steps[best])
        seen = seen | views[found[best]]
    return [np.array(route, dtype=np.int64) for route in routes], max(walked)


def _nearest_shares(graph: SearchGraph, heuristic: Heuristic, starts: np.ndarray) -> tuple[list[np.ndarray], int]:
    """A team walk: each goal cell goes to the guard whose start is nearest a watcher of it (ties to the
    first), and each guard covers its share by the one-guard beam. Routes and makespan (-1 if stuck)."""
    nearest = np.argmin(heuristic.to_watchers[starts], axis=0)
    routes, makespan = [], 0
    for guard, start in enumerate(starts.tolist()):
        others_cells = np.zeros(int(graph.goal_cells.max(initial=0)) + 1, dtype=bool)
        others_cells[graph.goal_cells[nearest != guard]] = True
        others = goal_bits(graph, others_cells)
        route, steps = _first_walk(graph._replace(start=start), heuristic, others)
        if steps < 0:
            return [], -1
        routes.append(route)
        makespan = max(makespan, int(steps))
    return routes, makespan


def _first_walk(graph: SearchGraph, heuristic: Heuristic, known: np.ndarray | None) -> tuple[np.ndarray, int]:
    """A walk of one guard from ``graph.start`` seeing every goal cell not in ``known``: the beam's as in
    :func:`guardsim.optimum.solve`, the greedy walk below ``BEAM_MIN_POSITIONS`` (the search proves such
    levels from either, and compiling the beam was 3 of the 24 s a first team run spent compiling)."""
    from guardsim.optimum import BEAM_MIN_POSITIONS

    if graph.positions >= BEAM_MIN_POSITIONS:
        return beam_route(graph, heuristic, 8, known=known)
    if known is None:
        return greedy_walk(graph.successors, graph.views, graph.full, graph.start)
    share = graph.full & ~known
    route, steps = greedy_walk(graph.successors, graph.views & share, share, graph.start)
    return route, int(steps)


def _position(states: np.ndarray, cell: int, heading: int, headings_matter: bool) -> int:
    """The graph position of a start (states are ascending)."""
    state = cell * 4 + (heading if headings_matter else 0)
    index = int(np.searchsorted(states, state))
    if index >= states.size or int(states[index]) != state:  # pragma: no cover - every start is in the graph
        raise RuntimeError(f"the start state {state} is not in the search graph")
    return index


def team_optimum_data(
    result: TeamOptimumResult, scene: Scene, *, level: str, starts: Sequence[tuple[tuple[int, int], int]]
) -> dict[str, Any]:
    """The JSON-ready document of a team search (``guardsim optimum --guards K --out``; docs/optimum.md)."""
    from guardsim.level import HEADINGS

    return {
        "level": level,
        "guards": len(starts),
        "starts": [[cell[0], cell[1], list(HEADINGS)[facing]] for cell, facing in starts],
        "objective": "makespan",
        "line_of_sight": scene.line_of_sight.value,
        "fov_degrees": scene.cone.fov_degrees,
        "view_range": scene.cone.view_range,
        "steps": result.steps,
        "proved": result.proved,
        "lower_bound": result.lower_bound,
        "start_bound": result.root_bound,
        "stopped_by": result.stopped_by,
        "expansions": result.expansions,
        "nodes": result.nodes,
        "seconds": round(result.seconds, 3),
        "paths": [[list(step) for step in path] for path in result.paths],
    }
