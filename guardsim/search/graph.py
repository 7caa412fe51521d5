"""The graph the exact search walks: guard positions, their moves and what each one sees, as bitsets.

A *position* is what the guard's future depends on. With the paper's cone it is the state (cell and
heading, the direction of the last step): the heading decides what the guard sees. When every cell's
four headings see the same cells (a 360-degree view), the heading changes nothing, and positions are the
cells themselves; the graph is then four times smaller. Only positions reachable from the start are kept.

What a position sees is a bitset over the *goal* (the cells reachable from the start), ``uint64`` words,
goal cell ``i`` being bit ``i % 64`` of word ``i // 64``.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from guardsim.grid import HEADINGS_PER_CELL, CoverageGrid, cell_of_state, heading_of_state, state_of
from guardsim.kernels.arrays import true_indices
from guardsim.kernels.compiler import jit
from guardsim.kernels.csr import predecessors, watcher_csr
from guardsim.kernels.distances import fill_states
from guardsim.kernels.estimate import UNREACHABLE
from guardsim.vision.table import ViewTable

__all__ = [
    "FAR",
    "SearchGraph",
    "build_search_graph",
    "goal_bits",
    "route_steps",
    "search_positions",
    "watcher_distances",
]

#: Distance to a target the position cannot reach (the estimate's own marker).
FAR = UNREACHABLE


class SearchGraph(NamedTuple):
    """Positions, moves and views of one start."""

    successors: np.ndarray
    """``int64 (positions, 4)``: the position one step in each direction leads to, -1 for none."""
    views: np.ndarray
    """``uint64 (positions, words)``: goal cells each position sees, as bitsets."""
    states: np.ndarray
    """``int64 (positions,)``: a state number (:func:`guardsim.grid.state_of`) of each position; heading 0
    when headings do not matter."""
    goal_cells: np.ndarray
    """``int64 (goal,)``: flat cell index of each goal cell (bit ``i`` stands for ``goal_cells[i]``)."""
    full: np.ndarray
    """``uint64 (words,)``: the bitset of the whole goal."""
    start: int
    """The start position."""
    headings_matter: bool
    """Whether positions are states (True) or cells (False)."""

    @property
    def positions(self) -> int:
        """Number of positions."""
        return int(self.successors.shape[0])


def _same_sight(table: ViewTable, cells: np.ndarray) -> bool:
    """Whether each cell's four headings see the same cells."""
    for cell in cells.tolist():
        first = table.sees(state_of(cell, 0))
        for heading in range(1, HEADINGS_PER_CELL):
            other = table.sees(state_of(cell, heading))
            if other.size != first.size or not np.array_equal(other, first):
                return False
    return True


@jit
def _reachable_states(neighbours: np.ndarray, start_state: int) -> np.ndarray:
    """States reachable from ``start_state``, ascending."""
    distance = np.empty(state_of(neighbours.shape[0], 0), dtype=np.int32)
    fill_states(neighbours, start_state, -1, distance)
    reached = np.empty(distance.shape[0], dtype=np.bool_)
    for state in range(distance.shape[0]):
        reached[state] = distance[state] >= 0
    return true_indices(reached)


@jit
def _views(
    states: np.ndarray, sight_start: np.ndarray, sight: np.ndarray, goal_index: np.ndarray, words: int
) -> np.ndarray:
    views = np.zeros((states.shape[0], words), dtype=np.uint64)
    for position in range(states.shape[0]):
        state = states[position]
        for index in range(sight_start[state], sight_start[state + 1]):
            bit = goal_index[sight[index]]
            if bit >= 0:
                views[position, bit >> 6] |= np.uint64(1) << np.uint64(bit & 63)
    return views


def build_search_graph(
    grid: CoverageGrid,
    table: ViewTable,
    start: tuple[int, int],
    heading: int,
    also: Sequence[tuple[tuple[int, int], int]] = (),
) -> SearchGraph:
    """The positions reachable from ``(start, heading)``, their moves and their views.

    Parameters
    ----------
    grid
        The coverage grid.
    table
        The level's view table for the vision to solve with.
    start
        ``(col, row)`` of the start cell.
    heading
        The first heading (ignored when headings do not change what a guard sees).
    also
        More ``((col, row), heading)`` starts in the same goal (a team's): positions reachable from any
        start are kept; :attr:`SearchGraph.start` stays the first.
    """
    neighbours = np.ascontiguousarray(grid.neighbours, dtype=np.int64)
    start_cell = grid.flat(*start)
    states, goal_cells, headings_matter = _graph_states(grid, table, start, heading, also)
    goal_index = np.full(grid.size, -1, dtype=np.int64)
    goal_index[goal_cells] = np.arange(goal_cells.size)
    words = max(1, (goal_cells.size + 63) // 64)
    position_of = np.full(grid.size * HEADINGS_PER_CELL, -1, dtype=np.int64)
    position_of[states] = np.arange(states.size)
    cells = cell_of_state(states)
    successors = np.full((states.size, 4), -1, dtype=np.int64)
    for direction in range(4):
        there = neighbours[cells, direction]
        ok = there >= 0
        arrive: np.ndarray = state_of(
            np.asarray(there[ok], dtype=np.int64),
            np.full(int(ok.sum()), direction if headings_matter else 0, dtype=np.int64),
        )
        successors[ok, direction] = position_of[arrive]
    first = state_of(start_cell, heading if headings_matter else 0)
    views = _views(states, table.sight_start, table.sight, goal_index, words)
    full = np.zeros(words, dtype=np.uint64)
    for bit in range(goal_cells.size):
        full[bit >> 6] |= np.uint64(1) << np.uint64(bit & 63)
    return SearchGraph(successors, views, states, goal_cells, full, int(position_of[first]), headings_matter)


def search_positions(grid: CoverageGrid, table: ViewTable, start: tuple[int, int], heading: int) -> int:
    """How many positions :func:`build_search_graph` would have, without building their views (a bitset
    of the goal cells per position: 8 GB on a 512 x 512 map)."""
    return int(_graph_states(grid, table, start, heading, ())[0].size)


def _graph_states(
    grid: CoverageGrid,
    table: ViewTable,
    start: tuple[int, int],
    heading: int,
    also: Sequence[tuple[tuple[int, int], int]],
) -> tuple[np.ndarray, np.ndarray, bool]:
    """The search graph's states (its positions, in order), its goal cells, and whether headings matter."""
    neighbours = np.ascontiguousarray(grid.neighbours, dtype=np.int64)
    start_cell = grid.flat(*start)
    goal_cells = np.flatnonzero(grid.component(*start).ravel()).astype(np.int64)
    headings_matter = not _same_sight(table, goal_cells)
    if headings_matter:
        states = _reachable_states(neighbours, state_of(start_cell, heading))
        for (col, row), facing in also:
            states = np.union1d(states, _reachable_states(neighbours, state_of(grid.flat(col, row), facing)))
    else:
        states = state_of(goal_cells, np.zeros_like(goal_cells))
    return states, goal_cells, headings_matter


@jit
def _watcher_distances(
    successors: np.ndarray, views: np.ndarray, goal: int, far: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    positions = successors.shape[0]
    pred_start, pred = predecessors(successors)
    counts, watchers = watcher_csr(views, goal)
    distance = np.full((goal, positions), far, dtype=np.int16)
    queue = np.empty(positions, dtype=np.int64)
    for bit in range(goal):
        row = distance[bit]
        tail = 0
        for k in range(counts[bit], counts[bit + 1]):
            row[watchers[k]] = 0
            queue[tail] = watchers[k]
            tail += 1
        head = 0
        while head < tail:
            position = queue[head]
            head += 1
            for k in range(pred_start[position], pred_start[position + 1]):
                other = pred[k]
                if row[other] == far:
                    row[other] = row[position] + 1
                    queue[tail] = other
                    tail += 1
    return distance, counts, watchers


def watcher_distances(graph: SearchGraph) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steps from every position to the nearest watcher of every goal cell, and the watchers themselves.

    Returns
    -------
    distance
        ``int16 (goal, positions)``: fewest steps from a position to any position seeing the goal cell
        (:data:`FAR` if none is reachable).
    watch_start, watchers
        CSR: goal cell ``i`` is seen from positions ``watchers[watch_start[i]:watch_start[i + 1]]``.
    """
    return _watcher_distances(graph.successors, graph.views, int(graph.goal_cells.size), FAR)


def heading_of(graph: SearchGraph, position: int) -> int:
    """The heading of a position (0 when headings do not matter)."""
    return int(heading_of_state(graph.states[position]))


def route_steps(graph: SearchGraph, route: np.ndarray, heading: int) -> tuple[list[tuple[int, int]], list[int]]:
    """A walk through the positions of ``route`` (the start first) along shortest paths.

    Returns ``(cell, heading)`` at every step (the first heading is ``heading``, later ones the direction
    of each step) and the step at which the walk reaches each position of ``route``.
    """
    steps = [int(route[0])]
    ends = [0]
    for target in route[1:].tolist():
        steps.extend(_shortest_path(graph.successors, steps[-1], target)[1:])
        ends.append(len(steps) - 1)
    walk = [(int(cell_of_state(graph.states[steps[0]])), heading)]
    for before, position in itertools.pairwise(steps):
        direction = int(np.flatnonzero(graph.successors[before] == position)[0])
        walk.append((int(cell_of_state(graph.states[position])), direction))
    return walk, ends


def _shortest_path(successors: np.ndarray, source: int, target: int) -> list[int]:
    """Positions of a shortest path from ``source`` to ``target`` (both included)."""
    parent = np.full(successors.shape[0], -2, dtype=np.int64)
    parent[source] = -1
    frontier = [source]
    while frontier and parent[target] == -2:
        following = []
        for here in frontier:
            for there in successors[here].tolist():
                if there >= 0 and parent[there] == -2:
                    parent[there] = here
                    following.append(there)
        frontier = following
    path = [target]
    while parent[path[-1]] >= 0:
        path.append(int(parent[path[-1]]))
    return path[::-1]


def goal_bits(graph: SearchGraph, cells: np.ndarray) -> np.ndarray:
    """The goal bitset of the goal cells among ``cells`` (``bool (grid cells,)``)."""
    bits = np.flatnonzero(np.asarray(cells, dtype=bool)[graph.goal_cells])
    words = np.zeros_like(graph.full)
    np.bitwise_or.at(words, bits >> 6, np.left_shift(np.uint64(1), (bits & 63).astype(np.uint64)))
    return words
