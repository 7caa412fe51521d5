"""Can a player get from one cell to another unseen by a repeating patrol? An exact search on the grid.

The intruder moves like a guard: each tick it steps to a connected 4-neighbour or waits. It is seen at
a tick when its cell is in any guard's view at that tick (a guard's own cell always counts). The patrol
repeats every ``period`` ticks, so the intruder's situation is fully described by its cell and the tick
modulo the period: a finite graph of ``cells x period`` nodes. Breadth-first search over that graph,
from every tick at which the entry cell is unseen, finds an unseen path whenever one exists (the search
is complete), and the fastest one. When none exists, Dijkstra's algorithm on the same graph, with a tick
in view costing more than any number of unseen ticks, finds the closest call: the path with the fewest
ticks in view (then the fewest ticks). This is the space-time search of Tremblay, Torres, Rikovitch and
Verbrugge ("An exploration tool for predicting stealthy behaviour", AIIDE 2013 workshop), made exact:
they sample the space-time grid with RRT, here every node is searched.

With ears (``heard``, see :mod:`guardsim.kernels.gaits`) the search also chooses a gait for every step
and no guard may hear a step land: its nodes are (lap tick, cell, ticks stood still), and the closest
call counts a step heard like a tick in view.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.gaits import GAIT_MOVES, SILENT, SNEAK_MOVE, WALK_MOVES, gait_move
from guardsim.kernels.heap import heap_pop, heap_push

__all__ = ["GAITS_OF_TICKS", "SneakPath", "closest_call", "find_sneak", "hiding_windows"]

#: What the intruder does in a tick of a path with gaits: waits, walks a step, or is in a sneaking step
#: (every tick of one, the landing included).
GAITS_OF_TICKS = ("wait", "walk", "sneak")


class SneakPath(NamedTuple):
    """A path of the intruder through space-time."""

    found: bool
    """Whether the path is never seen."""
    start_tick: int
    """Tick of the patrol (modulo its period) at which the intruder enters."""
    cells: np.ndarray
    """``int64 (ticks + 1,)``: flat cell at each tick from ``start_tick`` on."""
    ticks_in_view: int
    """Ticks at which the intruder is seen (0 for an unseen path)."""
    gaits: tuple[str, ...] | None = None
    """With ears: what the intruder does in each tick after entering (one of :data:`GAITS_OF_TICKS` per
    tick, ``ticks`` of them); ``None`` for a search without gaits (every step walks)."""
    steps_heard: int = 0
    """With ears: steps some guard hears land (0 for an unheard path)."""

    @property
    def ticks(self) -> int:
        """Ticks from entering to arriving."""
        return int(self.cells.size) - 1


@jit
def _dijkstra(
    neighbours: np.ndarray, seen: np.ndarray, heard: np.ndarray, cap: int, moves: int, source: int, target: int
) -> tuple[np.ndarray, np.ndarray, int, int]:
    """Dijkstra over (ticks still, lap tick, cell): the fewest ticks in view plus steps heard, then the
    fewest ticks (a tick in view or a step heard outweighs any path's other ticks: a shortest path visits
    each node at most once). Returns the parent of each node, whether the move into it was a sneaking
    step, the node reached (-1: none) and its cost. Without gaits ``cap`` is 0, ``moves`` 5 and
    ``heard`` :data:`~guardsim.kernels.gaits.SILENT`: the nodes are (lap tick, cell)."""
    period, cells = seen.shape
    layer = period * cells
    nodes = (cap + 1) * layer
    weight = nodes + 1
    best = np.empty(nodes, dtype=np.int64)
    best[:] = np.iinfo(np.int64).max
    parent = np.empty(nodes, dtype=np.int64)
    parent[:] = -2
    sneaked = np.zeros(nodes, dtype=np.bool_)
    done = np.zeros(nodes, dtype=np.bool_)
    # The heap grows as needed: most searches push far fewer entries than the moves per node they could.
    heap_keys = np.empty(period + 1024, dtype=np.int64)
    heap_nodes = np.empty(period + 1024, dtype=np.int64)
    size = 0
    for tick in range(period):
        node = tick * cells + source
        key = weight if seen[tick, source] else 0
        best[node] = key
        parent[node] = -1
        size = heap_push(heap_keys, heap_nodes, size, key, node)
    while size > 0:
        key, node, size = heap_pop(heap_keys, heap_nodes, size)
        if done[node] or key != best[node]:
            continue
        done[node] = True
        still, rest = node // layer, node % layer
        tick, cell = rest // cells, rest % cells
        if cell == target:
            return parent, sneaked, node, key
        after = (tick + 1) % period
        for move in range(moves):
            other, still_after, loud = gait_move(neighbours, heard, after, cell, still, cap, move)
            if other < 0:
                continue
            bad = (1 if seen[after, other] else 0) + (1 if loud else 0)
            next_node = (still_after * period + after) * cells + other
            cost = key + 1 + bad * weight
            if cost < best[next_node]:
                best[next_node] = cost
                parent[next_node] = node
                sneaked[next_node] = move >= SNEAK_MOVE
                if size == heap_keys.shape[0]:
                    heap_keys = np.concatenate((heap_keys, np.empty_like(heap_keys)))
                    heap_nodes = np.concatenate((heap_nodes, np.empty_like(heap_nodes)))
                size = heap_push(heap_keys, heap_nodes, size, cost, next_node)
    return parent, sneaked, -1, -1


@jit
def _bfs(
    neighbours: np.ndarray, seen: np.ndarray, heard: np.ndarray, cap: int, moves: int, source: int, target: int
) -> tuple[np.ndarray, np.ndarray, int]:
    """Breadth first over (ticks still, lap tick, cell) from every unseen entry tick: the fastest path
    never seen nor heard (every move takes a tick, so the first arrival is the fastest). Returns the
    parent of each node, whether the move into it was a sneaking step, and the node reached (-1: none).
    ``cap``, ``moves`` and ``heard`` as for :func:`_dijkstra`."""
    period, cells = seen.shape
    layer = period * cells
    nodes = (cap + 1) * layer
    parent = np.empty(nodes, dtype=np.int64)
    parent[:] = -2
    sneaked = np.zeros(nodes, dtype=np.bool_)
    queue = np.empty(nodes, dtype=np.int64)
    tail = 0
    for tick in range(period):
        if not seen[tick, source]:
            node = tick * cells + source
            parent[node] = -1
            queue[tail] = node
            tail += 1
    head = 0
    while head < tail:
        node = queue[head]
        head += 1
        still, rest = node // layer, node % layer
        tick, cell = rest // cells, rest % cells
        if cell == target:
            return parent, sneaked, node
        after = (tick + 1) % period
        for move in range(moves):
            other, still_after, loud = gait_move(neighbours, heard, after, cell, still, cap, move)
            if other < 0 or loud or seen[after, other]:
                continue
            next_node = (still_after * period + after) * cells + other
            if parent[next_node] == -2:
                parent[next_node] = node
                sneaked[next_node] = move >= SNEAK_MOVE
                queue[tail] = next_node
                tail += 1
    return parent, sneaked, -1


def tick_gaits(cells: np.ndarray, sneaked: np.ndarray, cap: int) -> tuple[str, ...]:
    """What the intruder does in each tick after the first of a path (flat ``cells`` per tick), given
    which ticks land a sneaking step (``sneaked``, a flag per tick): the ``cap`` ticks before a sneaking
    step's landing are that step's too."""
    gaits = ["walk" if cells[tick] != cells[tick - 1] else "wait" for tick in range(1, cells.size)]
    for tick in np.flatnonzero(sneaked).tolist():
        for inside in range(max(1, tick - cap), tick + 1):
            gaits[inside - 1] = "sneak"
    return tuple(gaits)


def _gait_path(
    neighbours: np.ndarray,
    seen: np.ndarray,
    heard: np.ndarray,
    sneak_ticks: int,
    source: int,
    target: int,
    strict: bool,
) -> SneakPath | None:
    seen = np.ascontiguousarray(seen, dtype=np.bool_)
    heard = np.ascontiguousarray(heard, dtype=np.bool_)
    cap = int(sneak_ticks) - 1
    neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
    if strict:
        parent, sneaked, node = _bfs(neighbours, seen, heard, cap, GAIT_MOVES, int(source), int(target))
    else:
        parent, sneaked, node, _ = _dijkstra(neighbours, seen, heard, cap, GAIT_MOVES, int(source), int(target))
    if node < 0:
        return None
    period, cells = seen.shape
    nodes = _chain(parent, node)
    start, path = _path(parent, node, cells)
    landed = sneaked[nodes]
    ticks = (start + np.arange(path.size)) % period
    in_view = int(seen[ticks, path].sum())
    moved = np.flatnonzero(path[1:] != path[:-1]) + 1
    loud = int(heard[landed[moved].astype(np.int64), ticks[moved], path[moved]].sum())
    return SneakPath(in_view + loud == 0, start, path, in_view, tick_gaits(path, landed, cap), loud)


def _chain(parent: np.ndarray, node: int) -> np.ndarray:
    """The nodes from an entry to ``node``, by the parents."""
    chain = [node]
    while parent[chain[-1]] >= 0:
        chain.append(int(parent[chain[-1]]))
    chain.reverse()
    return np.asarray(chain, dtype=np.int64)


def _path(parent: np.ndarray, node: int, cells: int) -> tuple[int, np.ndarray]:
    chain = _chain(parent, node)
    # Entries stand still 0 ticks: their nodes are lap tick * cells + cell.
    return int(chain[0] // cells), chain % cells


def find_sneak(
    neighbours: np.ndarray,
    seen: np.ndarray,
    source: int,
    target: int,
    *,
    heard: np.ndarray | None = None,
    sneak_ticks: int = 2,
) -> SneakPath | None:
    """The fastest unseen path from ``source`` to ``target`` (flat cells), or ``None`` when there is none.

    Parameters
    ----------
    neighbours
        ``int64 (cells, 4)``: the grid's connectivity.
    seen
        ``bool (period, cells)``: whether a guard sees each cell at each tick of a lap.
    heard
        With ears, ``bool (2, period, cells)``: whether a guard hears a walking (``[0]``) or sneaking
        (``[1]``) step land in each cell at each tick (:func:`guardsim.detection.hearing.lap_hearing`); the path
        then chooses a gait for every step (a sneaking step takes ``sneak_ticks`` ticks) and is never
        heard either, and :attr:`SneakPath.gaits` says what it does in each tick.

    Examples
    --------
    Three cells in a row; a guard sees the middle one at tick 0 of a two-tick lap:

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> seen = np.array([[False, True, False], [False, False, False]])
    >>> path = find_sneak(neighbours, seen, 0, 2)
    >>> path.start_tick, path.cells.tolist()
    (0, [0, 1, 2])

    With a guard in cell 2 hearing a walking step one cell away, the player sneaks (2 ticks) into cell 1:

    >>> heard = np.zeros((2, 2, 3), dtype=bool)
    >>> heard[0, :, 1:] = True
    >>> path = find_sneak(neighbours, seen, 0, 1, heard=heard)
    >>> path.cells.tolist(), path.gaits
    ([0, 0, 1], ('sneak', 'sneak'))
    """
    if heard is not None:
        return _gait_path(neighbours, seen, heard, sneak_ticks, source, target, True)
    neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
    seen = np.ascontiguousarray(seen, dtype=np.bool_)
    parent, _, node = _bfs(neighbours, seen, SILENT, 0, WALK_MOVES, int(source), int(target))
    if node < 0:
        return None
    start, cells = _path(parent, node, seen.shape[1])
    return SneakPath(True, start, cells, 0)


def closest_call(
    neighbours: np.ndarray,
    seen: np.ndarray,
    source: int,
    target: int,
    *,
    heard: np.ndarray | None = None,
    sneak_ticks: int = 2,
) -> SneakPath | None:
    """The path from ``source`` to ``target`` with the fewest ticks in view (then fewest ticks);
    ``None`` when ``target`` cannot be reached at all. With ``heard`` (see :func:`find_sneak`), the fewest
    ticks in view plus steps heard, choosing a gait for every step."""
    if heard is not None:
        return _gait_path(neighbours, seen, heard, sneak_ticks, source, target, False)
    neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
    seen = np.ascontiguousarray(seen, dtype=np.bool_)
    parent, _, node, cost = _dijkstra(neighbours, seen, SILENT, 0, WALK_MOVES, int(source), int(target))
    if node < 0:
        return None
    start, cells = _path(parent, node, seen.shape[1])
    weight = seen.size + 1
    return SneakPath(cost // weight == 0, start, cells, int(cost // weight))


def hiding_windows(seen: np.ndarray, traversable: np.ndarray) -> np.ndarray:
    """``int64 (cells,)``: each cell's longest run of unseen ticks in the repeating lap (the period when
    never seen, -1 where no one can stand)."""
    period = seen.shape[0]
    doubled = np.concatenate([seen, seen], axis=0)
    longest = np.zeros(seen.shape[1], dtype=np.int64)
    run = np.zeros(seen.shape[1], dtype=np.int64)
    for row in doubled:
        run = np.where(row, 0, run + 1)
        np.maximum(longest, run, out=longest)
    longest = np.minimum(longest, period)
    longest[~traversable.ravel()] = -1
    return longest
