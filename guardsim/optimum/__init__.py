"""The fewest steps a guard needs to see every reachable cell, proved by heuristic search.

:func:`solve` builds the search graph of a start (:mod:`~guardsim.search.graph`), the admissible
estimate (:mod:`~guardsim.search.heuristic`, the bounds of :mod:`guardsim.bounds` per node) and runs A*
over (position, seen cells) with macro moves (:mod:`~guardsim.search.astar`) until it proves the
optimum or a limit stops it. The limits are a number of expansions (deterministic) and, optionally,
wall time; a stopped search still returns its best walk and the proved lower bound. ``docs/optimum.md``
explains the search and gives the measured times.

Examples
--------
A corridor of 7 cells, a guard seeing its cell and the next, starting in the middle facing right: it
must see both ends, 2 + 4 steps whichever it visits first.

>>> from guardsim.level import parse_level
>>> from guardsim.scene import Scene
>>> corridor = parse_level({"outer": [[0, 0], [7, 0], [7, 1], [0, 1]], "guard": {"view_range": 1.0}})
>>> result = solve(Scene.from_level(corridor), (3, 0), 0)
>>> result.steps, result.proved, result.lower_bound
(6, True, 6)
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from guardsim.errors import ArgumentError, LevelError, LimitError
from guardsim.search import DOMINANCE_CHECKS, route_to
from guardsim.search.astar import (
    EXPANSIONS,
    FLOOR,
    FULL,
    HEAP,
    INCUMBENT,
    INCUMBENT_NODE,
    NODES,
    PROVED,
    RUNNING,
    STATUS,
    SearchState,
    greedy_walk,
    new_search_state,
    run_search,
    start_search,
)
from guardsim.search.beam import beam_route
from guardsim.search.graph import SearchGraph, build_search_graph, route_steps
from guardsim.search.heuristic import Heuristic, build_heuristic
from guardsim.search.improve import IMPROVE_MAX_POSITIONS, improve_route
from guardsim.search.pattern import build_patterns, with_pattern
from guardsim.search.residual import residual_goal
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import view_table

if TYPE_CHECKING:
    from guardsim.scene import Scene

__all__ = [
    "DEFAULT_MEMORY_BYTES",
    "MAX_POSITIONS",
    "OptimumResult",
    "SearchProgress",
    "optimum_data",
    "optimum_verdict",
    "solve",
]

#: Memory the node arrays may take by default.
DEFAULT_MEMORY_BYTES = 3 * 2**30
#: Most guard positions (states, or cells when headings do not matter) the exact search takes.
MAX_POSITIONS = 20_000
#: Width of the beam search that gives the first incumbent.
INCUMBENT_BEAM = 8
#: Most positions for which the first incumbent comes from the beam: past them a beam layer's estimates
#: over thousands of goal cells take tens of seconds before the search starts (Square's 13,720 states:
#: 32 s for 792 steps), while the greedy walk takes a tenth of a second (515 steps there).
BEAM_MAX_POSITIONS = 8_000
#: Fewest positions for which the first incumbent comes from the beam: below them the A* proves the
#: optimum in a fraction of a second from the greedy walk (the 12 x 9 room with a pillar, 377 states:
#: 118 expansions from either first walk), and compiling the beam, 4 s of a first run's 19 s of
#: compiling, would cost more than it could save.
BEAM_MIN_POSITIONS = 512
#: Expansions per compiled chunk between two looks at the clock.
_CHUNK = 2_000
#: Weighted searches run one after the other before the optimal one, for a shorter first walk (each
#: starts from the best walk so far and stops after :data:`FIRST_WALK_EXPANSIONS`): den101d from (36, 20)
#: at range 8, 235 steps from the beam, 205 after them.
FIRST_WALK_WEIGHTS = (1.5, 1.25, 1.15)
FIRST_WALK_EXPANSIONS = 20_000
#: Nodes the state of each of those searches holds (about 100 MB at the most).
_FIRST_WALK_NODES = 1 << 20
#: Expansions after which a search still unproved improves its walk in hand by large-neighbourhood
#: search (:mod:`guardsim.search.improve`): the quick proofs (the anchor's unlimited-range rows take
#: 5 to 5,421 expansions) never pay for it; a long one gains a shorter walk, which is the answer's upper
#: end when a limit stops the search and keeps more nodes out of memory (room-32-32-4 from (3, 0):
#: 252 steps before, 199 after).
IMPROVE_AFTER = 20_000
#: Iterations of that search (about 1 s on room-32-32-4, 5 s on the 2,054-cell arena at range 8).
IMPROVE_ITERATIONS = 2_000


class SearchProgress(NamedTuple):
    """Where a running search is, handed to :func:`solve`'s ``progress`` callback between chunks."""

    expansions: int
    """Nodes expanded so far."""
    nodes: int
    """Nodes stored so far."""
    lower_bound: int
    """The optimum is at least this (the least ``g + h`` left, or the estimate at the start)."""
    best: int
    """Steps of the best covering walk found so far (the optimum is at most this)."""
    seconds: float
    """Wall time since the call began."""


class OptimumResult(NamedTuple):
    """What the exact search found."""

    steps: int
    """Steps of the best covering walk found (the optimum when :attr:`proved`)."""
    path: tuple[tuple[int, int, int], ...]
    """``(col, row, heading)`` at every step of that walk, the start first; the heading is the first
    heading at the start and the direction of the last step after it."""
    proved: bool
    """Whether no shorter covering walk exists."""
    lower_bound: int
    """Proved lower bound on the optimum (equal to :attr:`steps` when proved)."""
    root_bound: int
    """The estimate at the start (the per-node bound evaluated once)."""
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
    weight: float = 1.0
    """The ``weight`` asked for: when above 1, :attr:`proved` means "at most ``weight`` times the
    optimum", and :attr:`lower_bound` is the proved bound."""


def solve(
    scene: Scene,
    start: tuple[int, int],
    heading: int,
    vision: VisionFunction | None = None,
    *,
    max_expansions: int | None = None,
    time_limit: float | None = None,
    memory_bytes: int = DEFAULT_MEMORY_BYTES,
    progress: Callable[[SearchProgress], None] | None = None,
    weight: float = 1.0,
    seed: int = 0,
    improve: bool = True,
    pattern: bool = True,
    first_walk: bool = True,
) -> OptimumResult:
    """The fewest steps after which a guard from ``(start, heading)`` has seen every cell reachable from it.

    Parameters
    ----------
    scene
        The level, its grid and its vision.
    start, heading
        ``(col, row)`` of the start cell and the first heading number (0 right, 1 down, 2 left, 3 up).
    vision
        Which cells a state sees: the scene's cache by default (any vision function works).
    max_expansions
        Stop after this many expansions (deterministic). None: no limit.
    time_limit
        Stop after about this many seconds of search. The search is the same however fast the machine,
        but where it stops is not: a time-limited run's best walk and bound can depend on the machine.
    memory_bytes
        Most memory for the stored nodes; the search stops (unproved) when they are full.
    progress
        Called after every chunk of expansions (2 000) with where the search is; it does not change
        the search.
    weight
        W >= 1: weighted A* (heap on ``g + W * h``), which stops once the walk in hand is proved at most
        W times the optimum. 1: the optimum itself.
    seed
        Seeds the random choices of the walk improvement a long search makes (:data:`IMPROVE_AFTER`).
    improve
        Whether a long search improves its walk at all (a caller that wants only the lower bound, as
        ``guardsim bounds``, saves the 1-12 s it takes).
    pattern
        Whether a long search (:data:`IMPROVE_AFTER` expansions unproved) builds a pattern database
        (:mod:`guardsim.search.pattern`, 2-10 s) and starts again with it in its estimate.
    first_walk
        Whether the search starts from a short first walk (the beam and the weighted searches, seconds
        to tens of seconds on levels of a few hundred cells); without, from the greedy walk. A caller
        that wants only a lower bound within a small budget (``guardsim bounds``) spends it all on the
        optimal search instead: the bound does not depend on the first walk.

    Returns
    -------
    OptimumResult
        The best walk, whether it is proved optimal, and the proved lower bound.
    """
    began = time.perf_counter()
    table = view_table(scene.grid, scene.vision() if vision is None else vision)
    graph = build_search_graph(scene.grid, table, start, heading)
    if graph.positions > MAX_POSITIONS:
        raise LimitError(
            f"the exact search is for small levels: {graph.positions} positions from this start "
            f"(at most {MAX_POSITIONS})"
        )
    # The same covering walks over far fewer goal cells (those seen on the way to others are dropped).
    graph = residual_goal(graph)
    heuristic = build_heuristic(graph)
    # A short first walk keeps every node whose f reaches it out of memory; the beam finds one in
    # bounded work on small levels (the greedy walk is the fallback, and the first walk on large and tiny ones).
    greedy, greedy_steps = np.zeros(0, dtype=np.int64), -1
    if first_walk and BEAM_MIN_POSITIONS <= graph.positions <= BEAM_MAX_POSITIONS:
        greedy, greedy_steps = beam_route(graph, heuristic, INCUMBENT_BEAM)
    if greedy_steps < 0:
        greedy, greedy_steps = greedy_walk(graph.successors, graph.views, graph.full, graph.start)
    if greedy_steps < 0:
        raise LevelError(f"{scene.level.source}: some cell reachable from the start is seen from nowhere")

    def tell(best: int, floor: int, expansions: int = 0, nodes: int = 0) -> None:
        if progress is not None:
            progress(SearchProgress(expansions, nodes, min(floor, best), best, time.perf_counter() - began))

    def tell_before(best: int, before: int, where: tuple[int, int, int]) -> None:
        tell(min(best, before), *where)

    def tell_pattern(_picks: int, value: int, best: int, where: tuple[int, int, int]) -> None:
        tell(best, max(where[0], value), *where[1:])

    if weight == 1.0 and first_walk:
        greedy, greedy_steps = _weighted_walks(
            graph, heuristic, greedy, int(greedy_steps), began, time_limit, lambda best, floor: tell(best, floor)
        )
    words = graph.full.size
    per_node = 8 * words + 5 * 4 + 2 * 12 + 2 * 8
    capacity = max(1024, int(memory_bytes // per_node))
    try:
        state = new_search_state(capacity, words, graph.positions)
    except (MemoryError, ValueError) as error:  # numpy: "Maximum allowed dimension exceeded"
        raise LimitError(f"cannot reserve {memory_bytes // 2**20} MB for the search nodes (memory_bytes)") from error
    if not (weight >= 1.0 and np.isfinite(weight)):
        raise ArgumentError(f"weight must be a finite number >= 1, not {weight!r}")
    start_search(state, heuristic, graph.views, graph.full, graph.start, greedy_steps + 1, float(weight))
    root_bound = int(state.estimate[0])
    stopped_by = "proved"
    counters = state.counters
    # The heap's least f bounds the optimum whenever it is read (an admissible estimate; some node of an
    # optimal walk is always in the heap), but it can fall back as the lazy estimates come in: the bound
    # reported, as it goes and at the end, is the largest read so far (it fell from 160 to 158 between
    # two progress lines on room-32-32-4, and the end said 162).
    floor_seen = root_bound
    done_before = 0  # expansions of the search before it started again with a pattern database
    # When a search still unproved runs long: the walk improvement, then the pattern databases.
    long_at = (
        IMPROVE_AFTER
        if (improve or pattern) and BEAM_MIN_POSITIONS <= graph.positions <= IMPROVE_MAX_POSITIONS
        else None
    )
    while counters[STATUS] != PROVED:
        if counters[STATUS] == FULL:
            stopped_by = "memory"
            break
        budget = _CHUNK
        if max_expansions is not None:
            budget = min(budget, max_expansions - done_before - int(counters[EXPANSIONS]))
            if budget <= 0:
                stopped_by = "expansions"
                break
        if time_limit is not None and time.perf_counter() - began > time_limit:
            stopped_by = "time"
            break
        run_search(
            state, heuristic, graph.successors, graph.views, graph.full, budget, DOMINANCE_CHECKS, float(weight), True
        )
        if weight == 1.0 and counters[STATUS] != PROVED:
            floor_seen = max(floor_seen, int(counters[FLOOR]))
        if long_at is not None and counters[STATUS] == RUNNING and counters[EXPANSIONS] >= long_at:
            long_at = None
            deadline = None if time_limit is None else began + time_limit
            best_now = int(counters[INCUMBENT]) if counters[INCUMBENT_NODE] >= 0 else int(greedy_steps)
            where = (floor_seen if weight == 1.0 else root_bound, int(counters[EXPANSIONS]), int(counters[NODES]))
            if improve:
                report = functools.partial(tell_before, before=best_now, where=where)
                greedy, greedy_steps = _improve(graph, state, greedy, int(greedy_steps), seed, deadline, report)
            if pattern:
                # A stronger estimate for the rest of the search: the nodes so far were weighed with the
                # weaker one, so the search starts again from the start with it, the walk in hand as its
                # incumbent (the bound read so far stays proved).
                if counters[INCUMBENT_NODE] >= 0:
                    greedy, greedy_steps = route_to(state, int(counters[INCUMBENT_NODE])), int(counters[INCUMBENT])
                told = functools.partial(tell_pattern, best=int(greedy_steps), where=where)
                heuristic = with_pattern(heuristic, *build_patterns(graph, deadline=deadline, report=told))
                done_before += int(counters[EXPANSIONS])
                del state
                state = new_search_state(capacity, words, graph.positions)
                counters = state.counters
                start_search(state, heuristic, graph.views, graph.full, graph.start, greedy_steps + 1, float(weight))
                root_bound = max(root_bound, int(state.estimate[0]))
                floor_seen = max(floor_seen, root_bound)
        if progress is not None:
            best = int(counters[INCUMBENT]) if counters[INCUMBENT_NODE] >= 0 else int(greedy_steps)
            floor = best if counters[STATUS] == PROVED else min(best, floor_seen)
            if weight != 1.0:
                floor = _weighted_floor(best, weight) if counters[STATUS] == PROVED else root_bound
            tell(best, floor, done_before + int(counters[EXPANSIONS]), int(counters[NODES]))
    incumbent = int(counters[INCUMBENT])
    if int(counters[INCUMBENT_NODE]) >= 0:
        route = route_to(state, int(counters[INCUMBENT_NODE]))
    else:
        route, incumbent = greedy, int(greedy_steps)
    proved = stopped_by == "proved"
    floor = (
        incumbent
        if proved or counters[HEAP] == 0
        else min(incumbent, max(floor_seen, int(state.heap_key[0] // (1 << 16))))
    )
    if weight != 1.0:
        # A weighted key bounds nothing: only the weighted proof (or the start's estimate) does.
        floor = _weighted_floor(incumbent, weight) if proved else root_bound
    if not proved and max(floor, root_bound) >= incumbent:
        # The walk in hand already meets the proved bound: it is optimal, whatever stopped the search.
        proved, stopped_by = True, "proved"
    grid = scene.grid
    path = tuple((*grid.unflat(cell), facing) for cell, facing in route_steps(graph, route, heading)[0])
    if len(path) - 1 != incumbent:
        raise RuntimeError(f"the walk has {len(path) - 1} steps, the search counted {incumbent}")
    return OptimumResult(
        incumbent,
        path,
        proved,
        max(floor, root_bound) if not proved or weight != 1.0 else incumbent,
        root_bound,
        done_before + int(counters[EXPANSIONS]),
        int(counters[NODES]),
        stopped_by,
        graph.headings_matter,
        time.perf_counter() - began,
        float(weight),
    )


def _weighted_walks(
    graph: SearchGraph,
    heuristic: Heuristic,
    route: np.ndarray,
    steps: int,
    began: float,
    time_limit: float | None,
    report: Callable[[int, int], None] | None = None,
) -> tuple[np.ndarray, int]:
    """The shortest of ``route`` and the walks the searches of :data:`FIRST_WALK_WEIGHTS` find, each
    bounded in expansions (and by ``time_limit``): a weighted search goes deep fast, and a walk it finds
    keeps more nodes out of the optimal search and is the answer's upper end when that search stops.
    ``report(best steps, start's estimate)`` is called after every chunk of expansions (the searches
    took 11 s on the arena at range 8, too long to be silent)."""
    words, capacity = graph.full.size, min(_FIRST_WALK_NODES, 64 * FIRST_WALK_EXPANSIONS)
    for weight in FIRST_WALK_WEIGHTS:
        state = new_search_state(capacity, words, graph.positions)
        start_search(state, heuristic, graph.views, graph.full, graph.start, steps + 1, weight)
        counters = state.counters
        while counters[STATUS] == RUNNING and counters[EXPANSIONS] < FIRST_WALK_EXPANSIONS:
            if time_limit is not None and time.perf_counter() - began > time_limit:
                break
            budget = min(_CHUNK, FIRST_WALK_EXPANSIONS - int(counters[EXPANSIONS]))
            run_search(
                state, heuristic, graph.successors, graph.views, graph.full, budget, DOMINANCE_CHECKS, weight, True
            )
            if report is not None:
                found = int(counters[INCUMBENT]) if counters[INCUMBENT_NODE] >= 0 else steps
                report(min(steps, found), int(state.estimate[0]))
        if counters[INCUMBENT_NODE] >= 0 and counters[INCUMBENT] <= steps:
            route, steps = route_to(state, int(counters[INCUMBENT_NODE])), int(counters[INCUMBENT])
    return route, steps


def _improve(
    graph: SearchGraph,
    state: SearchState,
    route: np.ndarray,
    steps: int,
    seed: int,
    deadline: float | None,
    report: Callable[[int], None] | None = None,
) -> tuple[np.ndarray, int]:
    """The walk in hand (the search's, else ``route``), improved by :func:`improve_route`; when shorter,
    it becomes the search's incumbent (as the first walk is: the search then looks for one no longer)."""
    counters = state.counters
    if counters[INCUMBENT_NODE] >= 0:
        route, steps = route_to(state, int(counters[INCUMBENT_NODE])), int(counters[INCUMBENT])
    rng = np.random.default_rng(seed)
    better, better_steps = improve_route(graph, route, IMPROVE_ITERATIONS, rng, deadline=deadline, report=report)
    if better_steps < steps:
        route, steps = better, better_steps
        counters[INCUMBENT], counters[INCUMBENT_NODE] = better_steps + 1, -1
    return route, steps


def _weighted_floor(incumbent: int, weight: float) -> int:
    """The bound a finished weighted search proves: the incumbent is at most ``weight`` times the optimum."""
    return int(np.ceil(incumbent / weight - 1e-9))


def optimum_verdict(result: OptimumResult, weight: float = 1.0) -> str:
    """What a search found, in a line: the optimum (or a walk within ``weight`` times it, or the best walk
    and the lower bound when a limit stopped it), whether it is proved, and what the search took."""
    if result.proved and weight > 1.0:
        verdict = (
            f"{result.steps} steps, within {weight:g} x the optimum (optimum between {result.lower_bound} "
            f"and {result.steps})"
        )
    elif result.proved:
        verdict = f"optimum {result.steps} steps"
    else:
        verdict = f"best found {result.steps} steps (stopped by {result.stopped_by}; optimum >= {result.lower_bound})"
    return (
        f"{verdict}; proved: {str(result.proved).lower()}; start bound {result.root_bound}; "
        f"{result.expansions} expansions, {result.nodes} nodes, {result.seconds:.1f} s"
    )


def optimum_data(
    result: OptimumResult, scene: Scene, *, level: str, start: tuple[int, int], heading: int, weight: float
) -> dict[str, Any]:
    """The JSON-ready document of a search (``guardsim optimum --out``; docs/optimum.md)."""
    from guardsim.level import HEADINGS

    return {
        "level": level,
        "start": list(start),
        "heading": list(HEADINGS)[heading],
        "line_of_sight": scene.line_of_sight.value,
        "fov_degrees": scene.cone.fov_degrees,
        "view_range": scene.cone.view_range,
        "steps": result.steps,
        "proved": result.proved,
        "weight": weight,
        "lower_bound": result.lower_bound,
        "start_bound": result.root_bound,
        "stopped_by": result.stopped_by,
        "expansions": result.expansions,
        "nodes": result.nodes,
        "seconds": round(result.seconds, 3),
        "path": [list(step) for step in result.path],
    }
