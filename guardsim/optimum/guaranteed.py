"""The guaranteed search: the fewest ticks after which K guards are certain to have seen an intruder.

The intruder moves at most one cell a tick and may start anywhere in a region; a cell seen earlier may
hold it again once no guard watches it and a neighbour may (recontamination). The rule:

- tick 0: the contaminated set is the region minus every cell the guards see from their starts;
- each later tick: each guard steps to a connected 4-neighbour, facing the way it stepped, or waits
  where it is, keeping its heading; the set spreads to the connected 4-neighbours of its cells; every
  cell in a guard's view leaves it;
- the guards are certain when the set is empty.

A breadth-first search over (the guards' states, the contaminated set) finds the fewest ticks, or
exhausts every reachable pair: then no walk of K guards can ever be certain (``impossible``). Sets are
Python integers used as bitsets over the grid's cells; a pair is dropped when the same guards were
already reached, no later, with a subset of its set (spreading and clearing are monotone, so a smaller
set is never worse). Guards with the same vision are interchangeable, so their states are kept sorted.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.kernels.steps import cell_of_state, heading_of_state, state_of
from guardsim.vision.table import ViewTable

__all__ = [
    "DEFAULT_MAX_PAIRS",
    "GuaranteedResult",
    "guaranteed_data",
    "guaranteed_search",
    "search_region",
    "smallest_team",
]

#: Most (guards, set) pairs the search stores before it stops unproved.
DEFAULT_MAX_PAIRS = 500_000
#: Pairs stored between two calls of the search's ``progress``.
PROGRESS_PAIRS = 4096
#: Earlier sets of the same guards a new set is checked against for dominance.
_DOMINANCE_CHECKS = 32


class GuaranteedResult(NamedTuple):
    """What the guaranteed search found."""

    proved: bool
    """Whether the answer is settled (the search finished); false when it stopped at its pair limit."""
    steps: int | None
    """Ticks until the guards are certain; ``None`` when impossible or not settled."""
    impossible: bool
    """Whether no walk of these guards from these starts can ever be certain."""
    paths: tuple[tuple[tuple[int, int, int], ...], ...]
    """Per guard, ``(col, row, heading)`` at every tick of a fastest certain walk (empty when none)."""
    pairs: int
    """(guards, set) pairs stored."""
    seconds: float


def search_region(grid: CoverageGrid, cell: tuple[int, int] | None, radius: int) -> np.ndarray:
    """``bool (cells,)``: the cells within ``radius`` 4-connected steps of ``cell``; with ``cell`` None,
    every traversable cell."""
    if cell is None:
        return np.asarray(grid.traversable, dtype=bool).ravel().copy()
    from guardsim.kernels.distances import distances_from

    steps = distances_from(grid.neighbours, np.array([grid.flat(*cell)], dtype=np.int64))
    return steps <= radius


class _Rules:
    """The bitset rules of one grid and view table."""

    def __init__(self, grid: CoverageGrid, table: ViewTable) -> None:
        self.grid, self.table = grid, table
        cols = grid.shape[1]
        neighbours = np.asarray(grid.neighbours)
        self.shifts = (1, cols, -1, -cols)
        self.masks = []
        for direction, shift in enumerate(self.shifts):
            ok = neighbours[:, direction] >= 0
            if not np.array_equal(neighbours[ok, direction], np.flatnonzero(ok) + shift):
                raise ArgumentError("the grid's neighbours are not the cells next to each other")
            self.masks.append(_bits(np.flatnonzero(ok)))
        self._views: dict[int, int] = {}
        states = np.flatnonzero(np.repeat(np.asarray(grid.traversable).ravel(), 4))
        self.headings_matter = any(
            not np.array_equal(table.sees(int(s)), table.sees(int(s) - int(s) % 4)) for s in states.tolist()
        )
        self.neighbours = neighbours

    def view(self, state: int) -> int:
        bits = self._views.get(state)
        if bits is None:
            bits = self._views[state] = _bits(self.table.sees(state))
        return bits

    def spread(self, cells: int) -> int:
        out = cells
        for mask, shift in zip(self.masks, self.shifts, strict=True):
            moved = cells & mask
            out |= moved << shift if shift > 0 else moved >> -shift
        return out

    def moves(self, state: int) -> list[int]:
        """The states a guard in ``state`` may be in next tick (waiting first)."""
        cell = int(cell_of_state(state))
        out = [state]
        for direction in range(4):
            there = int(self.neighbours[cell, direction])
            if there >= 0:
                out.append(int(state_of(there, direction if self.headings_matter else 0)))
        return out


def _bits(cells: np.ndarray | Sequence[int]) -> int:
    value = 0
    for cell in np.asarray(cells, dtype=np.int64).tolist():
        value |= 1 << cell
    return value


def guaranteed_search(
    grid: CoverageGrid,
    table: ViewTable,
    starts: Sequence[tuple[tuple[int, int], int]],
    region: np.ndarray,
    *,
    max_pairs: int = DEFAULT_MAX_PAIRS,
    progress: Callable[[int, int], None] | None = None,
) -> GuaranteedResult:
    """The fewest ticks after which guards from ``starts`` (``((col, row), heading)`` each) are certain
    to have seen an intruder that started anywhere in ``region`` (``bool (cells,)``).

    Examples
    --------
    One guard in the middle of a 1 x 5 corridor with a range of 1 and a 360-degree view, the intruder
    anywhere: the guard steps to one end, then walks back to the other, pushing whatever is there before
    it: 3 ticks.

    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> from guardsim.vision.table import view_table
    >>> level = parse_level({"outer": [[0, 0], [5, 0], [5, 1], [0, 1]], "guard": {"view_range": 1, "fov_degrees": 360}})
    >>> scene = Scene.from_level(level)
    >>> table = view_table(scene.grid, scene.vision())
    >>> everywhere = search_region(scene.grid, None, 0)
    >>> result = guaranteed_search(scene.grid, table, [((2, 0), 0)], everywhere)
    >>> result.proved, result.steps, result.impossible, [step[:2] for step in result.paths[0]]
    (True, 3, False, [(2, 0), (3, 0), (2, 0), (1, 0)])

    ``progress(pairs stored, tick)`` is called every :data:`PROGRESS_PAIRS` pairs stored.
    """
    began = time.perf_counter()
    if not starts:
        raise ArgumentError("the guaranteed search needs at least one guard")
    rules = _Rules(grid, table)
    first = tuple(
        sorted(int(state_of(grid.flat(*cell), heading if rules.headings_matter else 0)) for cell, heading in starts)
    )
    watched = 0
    for state in first:
        watched |= rules.view(state)
    contaminated = _bits(np.flatnonzero(region)) & ~watched
    parents: dict[tuple[tuple[int, ...], int], tuple[tuple[int, ...], int] | None] = {(first, contaminated): None}
    if contaminated == 0:
        return _answer(grid, rules, parents, (first, contaminated), began, starts)
    seen_sets: dict[tuple[int, ...], list[int]] = {first: [contaminated]}
    layer = [(first, contaminated)]
    tick = 0
    while layer:
        tick += 1
        following: list[tuple[tuple[int, ...], int]] = []
        for guards, cells in layer:
            grown = rules.spread(cells)
            for team in {tuple(sorted(combo)) for combo in itertools.product(*(rules.moves(s) for s in guards))}:
                watched = 0
                for state in team:
                    watched |= rules.view(state)
                after = grown & ~watched
                key = (team, after)
                if key in parents:
                    continue
                earlier = seen_sets.setdefault(team, [])
                if any(old & ~after == 0 for old in earlier[-_DOMINANCE_CHECKS:]):
                    continue  # these guards were here no later with no more to clear
                earlier.append(after)
                parents[key] = (guards, cells)
                if progress is not None and len(parents) % PROGRESS_PAIRS == 0:
                    progress(len(parents), tick)
                if after == 0:
                    return _answer(grid, rules, parents, key, began, starts)
                following.append(key)
                if len(parents) > max_pairs:
                    return GuaranteedResult(False, None, False, (), len(parents), time.perf_counter() - began)
        layer = following
    return GuaranteedResult(True, None, True, (), len(parents), time.perf_counter() - began)


def _answer(
    grid: CoverageGrid,
    rules: _Rules,
    parents: dict[tuple[tuple[int, ...], int], tuple[tuple[int, ...], int] | None],
    key: tuple[tuple[int, ...], int],
    began: float,
    starts: Sequence[tuple[tuple[int, int], int]],
) -> GuaranteedResult:
    chain = [key]
    while (parent := parents[chain[-1]]) is not None:
        chain.append(parent)
    teams = [team for team, _ in reversed(chain)]
    # The search sorted the guards at each tick; give each guard a path by matching every tick's states
    # to legal moves from the last ones.
    paths = [[state] for state in teams[0]]
    for team in teams[1:]:
        for order in itertools.permutations(team):
            if all(order[g] in rules.moves(paths[g][-1]) for g in range(len(paths))):
                for g, state in enumerate(order):
                    paths[g].append(state)
                break
        else:  # pragma: no cover - every stored step is a legal move of the team
            raise RuntimeError("a stored step of the guaranteed search is not a team move")
    # Back to the order of ``starts``, with real headings (the first given, then each step's direction)
    # where the search ignored them.
    ordered: list[list[int]] = []
    for cell, heading in starts:
        state = int(state_of(grid.flat(*cell), heading if rules.headings_matter else 0))
        index = next(i for i, path in enumerate(paths) if path and path[0] == state)
        ordered.append(paths[index])
        paths[index] = []
    out: list[tuple[tuple[int, int, int], ...]] = []
    for (_, heading), path in zip(starts, ordered, strict=True):
        steps = []
        for tick, state in enumerate(path):
            here = int(cell_of_state(state))
            if rules.headings_matter:
                heading = int(heading_of_state(state))
            elif tick and here != int(cell_of_state(path[tick - 1])):
                heading = int(np.flatnonzero(rules.neighbours[int(cell_of_state(path[tick - 1]))] == here)[0])
            steps.append((*grid.unflat(here), heading))
        out.append(tuple(steps))
    return GuaranteedResult(True, len(teams) - 1, False, tuple(out), len(parents), time.perf_counter() - began)


def smallest_team(
    grid: CoverageGrid,
    table: ViewTable,
    start: tuple[tuple[int, int], int],
    region: np.ndarray,
    *,
    most: int = 4,
    max_pairs: int = DEFAULT_MAX_PAIRS,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[int, GuaranteedResult] | None:
    """The fewest guards, all starting at ``start``, that can become certain (with their search), or
    ``None`` when ``most`` cannot. When a team's search stops at ``max_pairs`` unsettled, that team and
    its unproved result (``proved`` false): the smallest team is that many guards or more, unknown."""
    for guards in range(1, most + 1):
        result = guaranteed_search(grid, table, [start] * guards, region, max_pairs=max_pairs, progress=progress)
        if not result.proved or not result.impossible:
            return guards, result
    return None


def guaranteed_data(
    result: GuaranteedResult,
    *,
    level: str,
    search_from: str | tuple[float, float],
    radius: int,
    teams: Sequence[tuple[tuple[int, int], int]],
    smallest_team: tuple[int, GuaranteedResult] | None,
) -> dict[str, Any]:
    """The JSON-ready document of a guaranteed search (``guardsim optimum --search-from ... --out``)."""
    from guardsim.level import HEADINGS

    return {
        "level": level,
        "search_from": search_from if search_from == "all" else list(search_from),
        "search_radius": radius,
        "guards": len(teams),
        "starts": [[cell[0], cell[1], list(HEADINGS)[facing]] for cell, facing in teams],
        "proved": result.proved,
        "steps": result.steps,
        "impossible": result.impossible,
        "smallest_team": None if smallest_team is None or not smallest_team[1].proved else smallest_team[0],
        "smallest_team_settled": smallest_team is None or smallest_team[1].proved,
        "paths": [[list(step) for step in path] for path in result.paths],
        "pairs": result.pairs,
        "seconds": round(result.seconds, 3),
    }
