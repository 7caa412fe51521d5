"""The search pieces the exact solver (:mod:`guardsim.optimum`) and the tour planner share.

- :mod:`~guardsim.search.graph`: the search graph of a start (viewpoint positions, macro moves between
  them, what each sees);
- :mod:`~guardsim.search.heuristic`: the admissible estimate per node;
- :mod:`~guardsim.search.astar`: A* over (position, seen cells) with macro moves, bounded in work;
- :mod:`~guardsim.search.beam`: beam searches for good walks fast;
- :mod:`~guardsim.search.residual`: the goal left after part of a walk.

:func:`search_route` runs the exact search over a built graph; :func:`guardsim.optimum.solve` adds the
limits, progress and result a caller of the solver wants.
"""

from __future__ import annotations

import numpy as np

from guardsim.search.astar import (
    INCUMBENT,
    INCUMBENT_NODE,
    PROVED,
    STATUS,
    SearchState,
    new_search_state,
    run_search,
    start_search,
)
from guardsim.search.graph import SearchGraph
from guardsim.search.heuristic import Heuristic

__all__ = ["DOMINANCE_CHECKS", "route_to", "search_route"]

#: Earlier nodes at the same position a new node is checked against for dominance.
DOMINANCE_CHECKS = 16


def search_route(
    graph: SearchGraph, heuristic: Heuristic, incumbent: int, *, max_expansions: int, max_nodes: int
) -> tuple[np.ndarray, int, bool]:
    """The exact search over a built graph (the tour planner's "exact" seed), bounded in work only.

    Looks for a covering walk shorter than ``incumbent`` steps (one already in hand). Returns its
    macro-move positions (the start first; empty when none was found), its steps (``incumbent`` when
    none) and whether no walk shorter than those steps exists.
    """
    state = new_search_state(max_nodes, graph.full.size, graph.positions)
    start_search(state, heuristic, graph.views, graph.full, graph.start, incumbent)
    run_search(state, heuristic, graph.successors, graph.views, graph.full, max_expansions, DOMINANCE_CHECKS)
    counters = state.counters
    node = int(counters[INCUMBENT_NODE])
    route = route_to(state, node) if node >= 0 else np.zeros(0, dtype=np.int64)
    return route, int(counters[INCUMBENT]), bool(counters[STATUS] == PROVED)


def route_to(state: SearchState, node: int) -> np.ndarray:
    """The macro-move positions from the root to ``node``."""
    route = []
    while node >= 0:
        route.append(int(state.position[node]))
        node = int(state.parent[node])
    return np.array(route[::-1], dtype=np.int64)
