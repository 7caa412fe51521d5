"""The measures of a level's difficulty, each from a named source, over one :class:`~guardsim.design.analysis.Analysis`.

- :func:`path_distance_risk`: after Tremblay, Torres and Verbrugge ("Measuring risk in stealth games",
  FDG 2014), whose follow-up study found plain distance to the guards matched players' judgement of risk
  best: how close, on foot, the nearest guard is at each tick of a path.
- :func:`distinct_ways`: undetected paths from entry to goal that share no corridor.
- :func:`direct_entries`: the lap ticks from which a player walking the fewest steps, never waiting,
  gets through unseen (the sneak check's slack with no time to wait in hiding).
- :func:`readability`: turns, backtracks and loop length of each guard's lap, after Zhang and Verbrugge
  (AIIDE 2018): players expect short, simple guard paths.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from guardsim.detection import PatrolGains
from guardsim.detection.sight import LapSight
from guardsim.grid import CoverageGrid, cell_of_state, heading_of_state
from guardsim.kernels.distances import FAR, distances_between, distances_from
from guardsim.patrol import Patrol
from guardsim.sneak import undetected_search

__all__ = [
    "ENDPOINT_STEPS",
    "MAX_WAYS",
    "GuardReadability",
    "direct_entries",
    "distinct_ways",
    "path_distance_risk",
    "readability",
]

#: Ways through counted at most (a level with this many is wide open).
MAX_WAYS = 4
#: Steps on foot from the entry or the goal within which every way may share cells (a room's doorway).
ENDPOINT_STEPS = 2


def path_distance_risk(
    grid: CoverageGrid, guard_cells: np.ndarray, start_tick: int, cells: np.ndarray, reach: float
) -> float:
    """The mean over a path's ticks of ``max(0, 1 - d / reach)``, ``d`` the distance on foot (world
    units, through connected moves) from the intruder to the nearest guard at that tick: 0 when no guard
    ever comes within ``reach``, 1 when one stands on the path all along.

    ``guard_cells``: ``int64 (guards, period)``, each guard's flat cell at each lap tick; the path enters
    at lap tick ``start_tick``.

    Examples
    --------
    A corridor of five cells, a guard posted at the right end; a path standing at the left end:

    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> grid = Scene.from_level(parse_level({"outer": [[0, 0], [5, 0], [5, 1], [0, 1]]})).grid
    >>> path_distance_risk(grid, np.array([[4]]), 0, np.array([0, 0]), reach=8.0)
    0.5
    """
    cells = np.asarray(cells, dtype=np.int64)
    period = guard_cells.shape[1]
    ticks = (start_tick + np.arange(cells.size)) % period
    here = guard_cells[:, ticks]
    unique_path, path_index = np.unique(cells, return_inverse=True)
    unique_guard, guard_index = np.unique(here, return_inverse=True)
    steps = distances_between(grid.neighbours, unique_path, unique_guard).astype(np.float64)
    steps[steps >= FAR] = math.inf
    nearest = steps[path_index[None, :], guard_index.reshape(here.shape)].min(axis=0) * grid.cell_size
    return float(np.clip(1.0 - nearest / reach, 0.0, 1.0).mean())


def distinct_ways(
    grid: CoverageGrid,
    gains: PatrolGains,
    source: int,
    target: int,
    first: np.ndarray | None = None,
    *,
    limit: int = MAX_WAYS,
) -> list[np.ndarray]:
    """Undetected paths from ``source`` to ``target`` that share no corridor, at most ``limit``.

    Each way is the fastest undetected path (:func:`guardsim.sneak.undetected_search`) that avoids the
    corridors of the ways before it; a way's corridor is its cells and their 4-neighbours, apart from the
    cells within :data:`ENDPOINT_STEPS` steps of the entry or the goal (every way leaves the one and
    reaches the other). Two paths down the same two-cell-wide corridor are one way; two paths round the
    two sides of a pillar are two. ``first``: the first way's cells when the caller has them.

    Examples
    --------
    An empty 9 x 9 room with no guard: a way along the middle row, then one along each side.

    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> grid = Scene.from_level(parse_level({"outer": [[0, 0], [9, 0], [9, 9], [0, 9]]})).grid
    >>> gains = PatrolGains(np.zeros((1, 1, 81)), 0.1, np.zeros((1, 1), dtype=np.int64), 0.1)
    >>> len(distinct_ways(grid, gains, grid.flat(0, 4), grid.flat(8, 4)))
    3
    """
    neighbours = np.array(grid.neighbours, dtype=np.int64)
    near = (distances_from(neighbours, np.array([source])) <= ENDPOINT_STEPS) | (
        distances_from(neighbours, np.array([target])) <= ENDPOINT_STEPS
    )
    seen = gains.seen
    ways: list[np.ndarray] = []
    while len(ways) < limit:
        if ways or first is None:
            search = undetected_search(neighbours, gains.gain, gains.fall, source, target, seen=seen)
            if search.found < 0:
                break
            cells = search.path()[1]
        else:
            cells = np.asarray(first, dtype=np.int64)
        ways.append(cells)
        corridor = np.zeros(grid.size, dtype=bool)
        corridor[cells] = True
        around = neighbours[cells].ravel()
        corridor[around[around >= 0]] = True
        corridor &= ~near
        # A corridor cell can no longer be entered (its cells stay, so the arrays keep their shape).
        neighbours[np.isin(neighbours, np.flatnonzero(corridor))] = -1
    return ways


def direct_entries(grid: CoverageGrid, sight: LapSight, source: int, target: int) -> np.ndarray:
    """``bool (period,)``: the lap ticks from which a player entering ``source`` reaches ``target`` unseen
    in the fewest steps on foot: every tick a step along some shortest way, never a tick waiting.

    A path of exactly the fewest steps ``D`` is at a cell ``k`` steps from the entry and ``D - k`` from the
    target at its ``k``-th tick, so the ticks are counted layer by layer over those cells: a cell of layer
    ``k`` is reached from the entry ticks ``t`` at which it is unseen at lap tick ``t + k`` and some
    neighbour of layer ``k - 1`` was reached. The sneak check's slack counts the ticks from which a
    player who may wait in hiding gets through; these are the ticks from which one who does not wait does.

    Examples
    --------
    A corridor of five cells, its middle cell watched at lap tick 1 of a 2-tick lap: a player walking
    from the left end reaches the middle two ticks after entering, at the lap tick it entered at.

    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> grid = Scene.from_level(parse_level({"outer": [[0, 0], [5, 0], [5, 1], [0, 1]]})).grid
    >>> bits = np.zeros((5, 1), dtype=np.uint64)
    >>> bits[2, 0] = 2
    >>> nothing = np.zeros(0, dtype=np.int64)
    >>> sight = LapSight(2, np.zeros(6, dtype=np.int64), nothing, nothing, np.zeros(0), bits, 1, 0.1,
    ...                  np.zeros((1, 2), dtype=np.int64), 0.1)
    >>> direct_entries(grid, sight, 0, 4).tolist()
    [True, False]
    """
    neighbours = np.asarray(grid.neighbours, dtype=np.int64)
    period = sight.period
    from_source = distances_from(neighbours, np.array([source])).astype(np.int64)
    to_target = distances_from(neighbours, np.array([target])).astype(np.int64)
    steps = int(from_source[target])
    if steps >= FAR:
        return np.zeros(period, dtype=bool)
    on_way = np.flatnonzero(from_source + to_target == steps)
    on_way = on_way[np.argsort(from_source[on_way], kind="stable")]
    layers = np.split(on_way, np.flatnonzero(np.diff(from_source[on_way])) + 1)
    # Each cell's position in its layer, to find a neighbour's row in the layer before.
    row = np.full(neighbours.shape[0], -1, dtype=np.int64)
    # The sets of ticks are kept packed, as the sight's bits are, and counted in the lap tick the walk
    # is on the cell (the entry tick plus k): a step moves every set one tick on, round the lap's end.
    words = sight.bits.shape[1]
    last_word, last_bit = (period - 1) // 64, np.uint64((period - 1) % 64)
    one = np.uint64(1)
    valid = np.full(words, ~np.uint64(0), dtype=np.uint64)
    valid[last_word + 1 :] = 0
    valid[last_word] = (one << last_bit << one) - one if last_bit < 63 else ~np.uint64(0)
    reached = np.zeros((0, words), dtype=np.uint64)
    for k, layer in enumerate(layers):
        unseen = ~sight.bits[layer] & valid
        if k:
            before = np.zeros_like(unseen)
            for move in range(4):
                other = neighbours[layer, move]
                index = np.where(other >= 0, row[np.maximum(other, 0)], -1)
                # A neighbour in the layer before has its row there; any other cell is -1 or a later layer's.
                index = np.where((other >= 0) & (from_source[np.maximum(other, 0)] == k - 1), index, -1)
                has = index >= 0
                before[has] |= reached[index[has]]
            # One tick on: each word's bits up one, the top bit of the word below carried in, and the
            # lap's last tick round to its first.
            moved = before << one
            moved[:, 1:] |= before[:, :-1] >> np.uint64(63)
            moved[:, 0] |= (before[:, last_word] >> last_bit) & one
            unseen &= moved & valid
        row[layer] = np.arange(layer.size)
        reached = unseen
    arrived = np.unpackbits(reached[0].view(np.uint8), bitorder="little")[:period].astype(bool)
    # A walk on the goal at lap tick t + steps entered at lap tick t.
    return np.roll(arrived, -(steps % period))


class GuardReadability(NamedTuple):
    """How simple one guard's lap is to read."""

    loop_length: int
    """Moves per lap (a post: 0)."""
    cells: int
    """Different cells the lap visits."""
    turns: int
    """Changes of heading per lap (a U-turn counts as one turn and one backtrack)."""
    backtracks: int
    """Moves straight back to the cell just left."""

    @property
    def complexity(self) -> float:
        """Turns and backtracks per move, clipped to [0, 1]: 0 a straight line or a post."""
        return min(1.0, (self.turns + self.backtracks) / self.loop_length) if self.loop_length else 0.0


def readability(patrol: Patrol) -> list[GuardReadability]:
    """Each guard's turns, backtracks and loop length over one lap (taken cyclically).

    Examples
    --------
    A guard pacing between two cells (right, then back left): two moves, two U-turns.

    >>> from guardsim.grid import state_of
    >>> readability(Patrol(np.array([[state_of(0, 0), state_of(1, 0), state_of(0, 2)]])[:, 1:], 2, "loop"))
    [GuardReadability(loop_length=2, cells=2, turns=2, backtracks=2)]
    """
    out = []
    for states in patrol.states:
        cells = np.asarray(cell_of_state(states))
        headings = np.asarray(heading_of_state(states))
        after = np.roll(cells, -1)
        moved = after != cells
        turns = int((np.roll(headings, -1) != headings).sum())
        # A backtrack: a move back onto the cell the guard stood on before its previous move.
        move_from = cells[moved]
        move_to = after[moved]
        backtracks = int((move_to == np.roll(move_from, 1)).sum()) if move_from.size > 1 else 0
        out.append(GuardReadability(int(moved.sum()), int(np.unique(cells).size), turns, backtracks))
    return out
