"""What every state of a level sees, and which states see each cell, computed once per level.

A state is a cell and a heading, numbered by :func:`guardsim.grid.state_of`. The table asks the episode's vision
function about every state of every traversable cell once; it depends only on the grid and the vision,
so it is kept for as long as both exist and shared by every episode and planner of the level.
Planners that look ahead (frontier, tour) read it; they never look at the line-of-sight rule itself.
"""

from __future__ import annotations

import weakref
from typing import Any, NamedTuple

import numpy as np

from guardsim.errors import LimitError
from guardsim.grid import HEADINGS_PER_CELL, CoverageGrid, state_of
from guardsim.kernels.compiler import jit
from guardsim.kernels.csr import invert_csr
from guardsim.vision.rules import VisionFunction

__all__ = ["UnseenTally", "ViewTable", "estimate_entries", "level_memo", "view_table"]


class ViewTable(NamedTuple):
    """Visible cells per state and watching states per cell, as flat (CSR) arrays.

    A NamedTuple of arrays, so compiled code takes it whole.
    """

    sight_start: np.ndarray
    """``int64 (states + 1,)``: state ``s`` sees ``sight[sight_start[s]:sight_start[s + 1]]``."""
    sight: np.ndarray
    """``int32``: flat cell indices, state after state, each state's ascending."""
    watch_start: np.ndarray
    """``int64 (cells + 1,)``: cell ``c`` is seen by ``watchers[watch_start[c]:watch_start[c + 1]]``."""
    watchers: np.ndarray
    """``int32``: state numbers, cell after cell, each cell's ascending."""
    entry: np.ndarray
    """``int64 (states,)``: the cell a guard steps from to arrive in the state, -1 if none."""

    def sees(self, state: int) -> np.ndarray:
        """Flat indices of the cells ``state`` sees."""
        return self.sight[self.sight_start[state] : self.sight_start[state + 1]]


#: Most (state, cell seen) pairs a view table may hold. The table, its inverse and the vision cache behind it
#: keep about 12 bytes a pair, so this is about 600 MB and 10 s of sight checks; the largest real map here
#: (Berlin_1_256, 256 x 256) needs 8.1 million. A fine grid with a long view range asks for billions; the
#: table stops there with a one-line error instead.
MAX_VIEW_ENTRIES = 50_000_000

#: Traversable cells whose states are asked first, spread evenly over the level, to estimate the table's
#: size before any of it is built (a 500 x 500 open level at a long range used to take 46 s and 2.3 GB
#: to reach the limit).
ESTIMATE_SAMPLE_CELLS = 256

#: The sample stops early once its states have seen this many cells (and at least
#: :data:`ESTIMATE_MIN_CELLS` cells were asked): a budget in work, so the estimate stays deterministic.
ESTIMATE_BUDGET = 2_000_000
ESTIMATE_MIN_CELLS = 16


def _spread_order(count: int) -> np.ndarray:
    """``0 .. count - 1`` in bit-reversed order, so any prefix is spread over the whole range."""
    bits = max(1, (count - 1).bit_length())
    keys = [int(f"{index:0{bits}b}"[::-1], 2) for index in range(count)]
    return np.argsort(np.asarray(keys), kind="stable")


def estimate_entries(grid: CoverageGrid, vision: VisionFunction) -> int:
    """How many (state, cell seen) pairs the view table of ``grid`` and ``vision`` will hold.

    Extrapolated from the states of at most :data:`ESTIMATE_SAMPLE_CELLS` traversable cells spread
    evenly over the level, fewer when they see a lot (:data:`ESTIMATE_BUDGET`); exact when the level has
    no more traversable cells than the sample.
    """
    cells = np.flatnonzero(grid.traversable.ravel())
    if cells.size == 0:
        return 0
    picks = np.unique(cells[np.linspace(0, cells.size - 1, min(cells.size, ESTIMATE_SAMPLE_CELLS)).astype(np.int64)])
    seen = 0
    asked = 0
    fill_many = getattr(vision, "fill_many", None)
    if fill_many is not None:  # a VisionCache computes the sample in compiled code, as the table after it
        fill_many(state_of(picks[:, None], np.arange(HEADINGS_PER_CELL)).ravel())
    for cell in picks[_spread_order(picks.size)].tolist():
        col, row = grid.unflat(cell)
        for heading in range(HEADINGS_PER_CELL):
            seen += len(vision(col, row, heading))
        asked += 1
        if seen > ESTIMATE_BUDGET and asked >= ESTIMATE_MIN_CELLS:
            break
    if asked == cells.size:
        return seen
    return seen * int(cells.size) // asked


def _too_big(grid: CoverageGrid, limit: int, entries: int, estimated: bool) -> LimitError:
    about = "about " if estimated else "more than "
    return LimitError(
        f"what every guard state sees would fill {about}{entries} cells, over the limit of {limit} "
        f"(max_view_entries), on a grid of {grid.shape[0]} x {grid.shape[1]} cells"
    )


def build_view_table(grid: CoverageGrid, vision: VisionFunction, *, max_entries: int | None = None) -> ViewTable:
    """Ask ``vision`` about every state of every traversable cell; states of other cells see nothing.

    Raises :class:`~guardsim.errors.LimitError` when the table would hold more than ``max_entries``
    (state, cell) pairs (:data:`MAX_VIEW_ENTRIES` by default): before building it when the estimate of
    :func:`estimate_entries` is over, else as soon as the count passes the limit.
    """
    limit = MAX_VIEW_ENTRIES if max_entries is None else max_entries
    estimate = estimate_entries(grid, vision)
    if estimate > limit:
        raise _too_big(grid, limit, estimate, estimated=True)
    states = state_of(grid.size, 0)
    lengths = np.zeros(states, dtype=np.int64)
    traversable = np.flatnonzero(grid.traversable.ravel())
    sights = getattr(vision, "sights", None)
    if sights is not None:  # a VisionCache computes the states in bulk, in compiled code (issue 15)
        sight = _sights_in_bulk(grid, sights, traversable, lengths, limit)
    else:
        sight = _sights_state_by_state(grid, vision, traversable, lengths, limit, estimate)
    sight_start = np.zeros(states + 1, dtype=np.int64)
    np.cumsum(lengths, out=sight_start[1:])
    watch_start, watchers = invert_csr(sight_start, sight, grid.size)
    return ViewTable(sight_start, sight, watch_start, watchers, grid.entry_cells)


#: States a VisionCache is asked for at once: the limit still stops a table soon after it is passed.
_BULK_STATES = 4096


def _sights_in_bulk(
    grid: CoverageGrid, sights: Any, traversable: np.ndarray, lengths: np.ndarray, limit: int
) -> np.ndarray:
    """Every traversable state's cells from ``sights`` (``VisionCache.sights``), slice after slice;
    ``lengths`` is filled per state."""
    asked = state_of(traversable[:, None], np.arange(HEADINGS_PER_CELL)).ravel()
    parts = []
    total = 0
    for begin in range(0, asked.size, _BULK_STATES):
        chunk = asked[begin : begin + _BULK_STATES]
        lengths[chunk], part = sights(chunk)
        total += part.size
        if total > limit:
            raise _too_big(grid, limit, limit, estimated=False)
        parts.append(part)
    return np.concatenate(parts).astype(np.int32, copy=False) if parts else np.zeros(0, dtype=np.int32)


def _sights_state_by_state(
    grid: CoverageGrid, vision: VisionFunction, traversable: np.ndarray, lengths: np.ndarray, limit: int, estimate: int
) -> np.ndarray:
    """Every traversable state's cells, asking ``vision`` one state at a time; ``lengths`` is filled."""
    # One growing buffer rather than an array per state: millions of small arrays cost ~100 bytes each.
    sight = np.empty(min(limit, max(1024, estimate + estimate // 8)), dtype=np.int32)
    total = 0
    for cell in traversable.tolist():
        col, row = grid.unflat(cell)
        for heading in range(HEADINGS_PER_CELL):
            cells = np.asarray(vision(col, row, heading), dtype=np.int32)
            lengths[state_of(cell, heading)] = cells.size
            if total + cells.size > limit:
                raise _too_big(grid, limit, limit, estimated=False)
            if total + cells.size > sight.size:
                sight = np.resize(sight, min(limit, 2 * (total + cells.size)))
            sight[total : total + cells.size] = cells
            total += cells.size
    return sight[:total].copy()


# grid -> vision -> memo; entries vanish with the grid or the vision function.
_MEMOS: weakref.WeakKeyDictionary[CoverageGrid, weakref.WeakKeyDictionary[Any, dict[Any, Any]]] = (
    weakref.WeakKeyDictionary()
)


def level_memo(grid: CoverageGrid, vision: VisionFunction) -> dict[Any, Any]:
    """A dictionary kept for as long as ``grid`` and ``vision`` live: per-level precomputation goes here.

    A vision function that cannot be weakly referenced gets a fresh, unshared dictionary.
    """
    by_vision = _MEMOS.setdefault(grid, weakref.WeakKeyDictionary())
    try:
        return by_vision.setdefault(vision, {})
    except TypeError:
        return {}


def view_table(grid: CoverageGrid, vision: VisionFunction) -> ViewTable:
    """The :class:`ViewTable` of a level and vision, built on first use and then shared."""
    memo = level_memo(grid, vision)
    if "views" not in memo:
        memo["views"] = build_view_table(grid, vision)
    return memo["views"]


@jit
def _goal_counts(sight_start: np.ndarray, sight: np.ndarray, goal: np.ndarray, counts: np.ndarray) -> None:
    for state in range(counts.shape[0]):
        total = 0
        for index in range(sight_start[state], sight_start[state + 1]):
            total += goal[sight[index]]
        counts[state] = total


@jit
def _discount(cells: np.ndarray, watch_start: np.ndarray, watchers: np.ndarray, counts: np.ndarray) -> None:
    for cell in cells:
        for index in range(watch_start[cell], watch_start[cell + 1]):
            counts[watchers[index]] -= 1


class UnseenTally:
    """How many unseen goal cells each state would see, kept up to date as cells get seen.

    Each cell is discounted once, the first time :meth:`update` finds it seen, so an episode costs as
    much as one pass over the table.

    Parameters
    ----------
    table
        The level's :class:`ViewTable`.
    goal
        ``bool (cells,)``: the cells the episode must see.
    """

    def __init__(self, table: ViewTable, goal: np.ndarray) -> None:
        self.table = table
        self.counts = np.zeros(table.entry.size, dtype=np.int32)
        """``int32 (states,)``: unseen goal cells each state sees."""
        _goal_counts(table.sight_start, table.sight, goal.astype(np.bool_), self.counts)
        self._counted = ~goal

    def update(self, seen: np.ndarray) -> None:
        """Discount the goal cells seen since the last call."""
        new = np.flatnonzero(seen & ~self._counted)
        if new.size:
            self._counted[new] = True
            _discount(new, self.table.watch_start, self.table.watchers, self.counts)
