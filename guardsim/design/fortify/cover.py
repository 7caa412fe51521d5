"""Which candidates break which counterexample paths, and the hitting sets over them.

Every watcher has a meter of its own, so a path (a cell per tick from an entry lap tick) is caught by a
set of watchers exactly when one of them alone catches it. Sealing a level is then a hitting-set
problem: each counterexample path found is the set of candidates that catch it, and every placement
that seals the level must hold one candidate of each. The smallest hitting set of the paths found so far
is thus a lower bound on the watchers any sealing placement needs; when it seals, it is the fewest.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.meter import DETECTED, meter_after

__all__ = ["HittingSet", "catches", "disjoint_bound", "min_hitting_set"]


@jit
def _fills(values: np.ndarray, fall: float) -> np.ndarray:
    """``bool (watchers,)``: whether each watcher's meter fills over its gains along a path (``values``:
    ``float64 (watchers, ticks)``, the gain of the path's cell at each of its ticks)."""
    out = np.zeros(values.shape[0], dtype=np.bool_)
    for watcher in range(values.shape[0]):
        level = 0.0
        for tick in range(values.shape[1]):
            level = meter_after(level, values[watcher, tick], fall)
            if level >= DETECTED:
                out[watcher] = True
                break
    return out


def catches(gains: Sequence[np.ndarray], start: int, cells: np.ndarray, fall: float, *, undetected: bool) -> np.ndarray:
    """``bool (len(gains),)``: which watchers catch a path entering at lap tick ``start``.

    ``gains`` holds each watcher's ``float64 (period, cells)`` gains over its own period (the lap the
    path's ticks count in is a multiple of it). Under the undetected rule a watcher catches the path when
    its meter fills on it; under the unseen rule, when it sees any of its cells.

    >>> gain = np.array([[0.0, 0.6, 0.6]])
    >>> catches([gain, gain / 2], 0, np.array([0, 1, 2]), 0.1, undetected=True).tolist()
    [True, False]
    >>> catches([gain / 2], 0, np.array([0, 1, 2]), 0.1, undetected=False).tolist()
    [True]
    """
    ticks = start + np.arange(cells.size)
    out = np.zeros(len(gains), dtype=np.bool_)
    # Watchers of the same period are replayed together.
    periods: dict[int, list[int]] = {}
    for index, gain in enumerate(gains):
        periods.setdefault(int(gain.shape[0]), []).append(index)
    for period, members in periods.items():
        values = np.stack([gains[index][ticks % period, cells] for index in members])
        # Unseen: any sighting catches.
        out[members] = _fills(np.ascontiguousarray(values), float(fall)) if undetected else (values > 0).any(axis=1)
    return out


def disjoint_bound(sets: Sequence[frozenset[int]]) -> int:
    """A lower bound on any hitting set's size: a greedy pack of pairwise disjoint sets, smallest first
    (each needs a member of its own). An empty set cannot be hit: the bound is then ``len(sets) + 1``
    read as "none".

    >>> disjoint_bound([frozenset({1, 2}), frozenset({2, 3}), frozenset({4})])
    2
    """
    used: set[int] = set()
    count = 0
    for members in sorted(sets, key=lambda s: (len(s), sorted(s))):
        if not members:
            return len(sets) + 1
        if used.isdisjoint(members):
            used |= members
            count += 1
    return count


class HittingSet:
    """A smallest hitting set by branch and bound, within a budget of search nodes.

    ``kinds`` gives each candidate's kind index and ``caps`` the most candidates of each kind a set may
    hold. :meth:`smallest` returns the set, or ``None`` when none smaller than ``below`` exists; it
    raises :class:`OverflowError` when the budget runs out first.

    >>> HittingSet([frozenset({0, 1}), frozenset({1, 2}), frozenset({3})], [0, 0, 0, 0], [4]).smallest(4)
    [1, 3]
    """

    def __init__(
        self, sets: Sequence[frozenset[int]], kinds: Sequence[int], caps: Sequence[int], *, budget: int = 200_000
    ):
        self.sets = [tuple(sorted(members)) for members in sets]
        self.kinds = list(kinds)
        self.caps = list(caps)
        self.budget = budget
        self.nodes = 0
        self.best: list[int] | None = None

    def smallest(self, below: int) -> list[int] | None:
        self.best = None
        self._below = below
        self._branch([], [0] * len(self.caps))
        return self.best

    def _branch(self, chosen: list[int], counts: list[int]) -> None:
        self.nodes += 1
        if self.nodes > self.budget:
            raise OverflowError("hitting-set budget spent")
        picked = set(chosen)
        open_sets = [members for members in self.sets if picked.isdisjoint(members)]
        if not open_sets:
            self.best = sorted(chosen)
            self._below = len(chosen)
            return
        if len(chosen) + disjoint_bound([frozenset(s) for s in open_sets]) >= self._below:
            return
        allowed = [[c for c in members if counts[self.kinds[c]] < self.caps[self.kinds[c]]] for members in open_sets]
        # Branch on the open set with the fewest choices, lowest candidates first: a fixed order.
        options = min(allowed, key=len)
        for candidate in options:
            counts[self.kinds[candidate]] += 1
            chosen.append(candidate)
            self._branch(chosen, counts)
            chosen.pop()
            counts[self.kinds[candidate]] -= 1
            if len(chosen) + 1 >= self._below:
                return


def min_hitting_set(
    sets: Sequence[frozenset[int]], kinds: Sequence[int], caps: Sequence[int], *, below: int, budget: int = 200_000
) -> tuple[list[int] | None, bool]:
    """The smallest hitting set under ``below`` members (``None``: none), and whether the search finished
    within ``budget`` nodes (when not, the set is ``None`` and proves nothing)."""
    search = HittingSet(sets, kinds, caps, budget=budget)
    try:
        return search.smallest(below), True
    except OverflowError:
        return None, False
