"""Can a player get through *undetected*? The exact sneak search under the detection model.

A path may now be seen, as long as no guard's awareness meter fills. The intruder's situation is its
cell, the lap tick and every guard's meter. Meters are real numbers, so the search keeps labels: at each
(lap tick, cell) node, the meter vectors it has reached, each with the path that reached it. It runs
breadth first over absolute time, so the first label to reach the target is the fastest undetected
path. A label is dropped when an earlier or equal-time label at the same node has meters no higher for
every guard: the meter rule is monotone (a lower meter stays lower or equal along any continuation, and
an earlier arrival can wait out the same lap), so a dominated label's every continuation is matched by
the dominating one's. What remains is exact: when the search ends without reaching the target, no
undetected path exists from the entry ticks it started from.

With ears (``heard``, see :mod:`guardsim.kernels.gaits`) a label also holds the ticks the intruder has
stood in its cell (up to ``sneak_ticks - 1``, when it may sneak on), a label dominates only one that
has stood no longer, and no step may land where a guard hears it.
"""

from __future__ import annotations

import numpy as np

from guardsim.errors import LimitError
from guardsim.kernels.arrays import copy_into
from guardsim.kernels.compiler import jit
from guardsim.kernels.gaits import GAIT_MOVES, SILENT, SNEAK_MOVE, WALK_MOVES, gait_move
from guardsim.kernels.meter import DETECTED, meter_after

__all__ = ["MAX_LABELS", "LabelSearch", "entry_searches", "undetected_search"]

#: Most labels a graded search may keep (each about ``8 * guards + 24`` bytes).
MAX_LABELS = 20_000_000


@jit
def _grow(array: np.ndarray, needed: int) -> np.ndarray:
    if needed <= array.shape[0]:
        return array
    size = array.shape[0]
    while size < needed:
        size *= 2
    grown = np.empty((size, *array.shape[1:]), dtype=array.dtype)
    # The leading rows of a C-ordered array are its first elements: one flat copy by loop (numba's slice
    # assignment costs about two seconds to compile).
    copy_into(grown.reshape(-1), 0, array.reshape(-1))
    return grown


@jit
def _label_search(
    neighbours: np.ndarray,
    gain: np.ndarray,
    seen: np.ndarray,
    fall: float,
    source: int,
    goal: np.ndarray,
    entries: np.ndarray,
    exhaustive: bool,
    max_labels: int,
    head: np.ndarray,
    settled: np.ndarray,
    room: int,
    heard: np.ndarray,
    cap: int,
    moves: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int, np.ndarray, np.ndarray]:
    """Breadth-first label search; returns (label node, label parent, label meters, labels kept, found
    label, label ticks still, label landed a sneaking step): the found label is the first on a ``goal``
    node, -1 when none is, -2 past ``max_labels``. Stops at the first unless ``exhaustive``. ``head``
    (all -1) and ``settled`` (all false), one entry per node, are the caller's, so that repeated searches
    share them; ``room`` is the labels to allocate at first. ``moves`` is 5 without gaits (``cap`` 0,
    ``heard`` ``(2, 1, 1)``), :data:`GAIT_MOVES` with them."""
    guards, period, cells = gain.shape
    # ``settled`` marks nodes holding a label with every meter empty, which dominates all others: most
    # edges of the search lead to one, and the small array settles them without touching the labels.
    node_of = np.empty(room, dtype=np.int64)
    parent = np.empty(room, dtype=np.int64)
    after_in_node = np.empty(room, dtype=np.int64)
    meters = np.empty((room, guards), dtype=np.float64)
    still = np.zeros(room, dtype=np.int64)
    sneaked = np.zeros(room, dtype=np.bool_)
    frontier = np.empty(1024, dtype=np.int64)
    upcoming = np.empty(1024, dtype=np.int64)
    candidate = np.empty(guards, dtype=np.float64)
    count = 0
    width = 0
    found = -1
    for phase in range(period):
        if not entries[phase]:
            continue
        detected = False
        for guard in range(guards):
            candidate[guard] = meter_after(0.0, gain[guard, phase, source], fall)
            detected = detected or candidate[guard] >= DETECTED
        if detected:
            continue
        node = phase * cells + source
        node_of[count] = node
        parent[count] = -1
        still[count] = 0
        sneaked[count] = False
        empty = cap == 0
        for guard in range(guards):
            meters[count, guard] = candidate[guard]
            empty = empty and candidate[guard] == 0.0
        settled[node] = empty
        after_in_node[count] = head[node]
        head[node] = count
        frontier = _grow(frontier, width + 1)
        frontier[width] = count
        width += 1
        count += 1
        if found < 0 and goal[phase, source]:
            found = count - 1
            if not exhaustive:
                return node_of, parent, meters, count, found, still, sneaked
    while width > 0:
        upcoming_width = 0
        for index in range(width):
            label = frontier[index]
            node = node_of[label]
            phase, cell = node // cells, node % cells
            after = (phase + 1) % period
            for move in range(moves):
                other, still_after, loud = gait_move(neighbours, heard, after, cell, still[label], cap, move)
                if other < 0 or loud:
                    continue
                next_node = after * cells + other
                if settled[next_node]:
                    continue
                detected = False
                empty = still_after == cap
                for guard in range(guards):
                    step_gain = gain[guard, after, other] if seen[after, other] else 0.0
                    candidate[guard] = meter_after(meters[label, guard], step_gain, fall)
                    detected = detected or candidate[guard] >= DETECTED
                    empty = empty and candidate[guard] == 0.0
                if detected:
                    continue
                stored = head[next_node]
                dominated = False
                while stored >= 0 and not dominated:
                    dominated = still[stored] >= still_after
                    for guard in range(guards if dominated else 0):
                        if meters[stored, guard] > candidate[guard]:
                            dominated = False
                            break
                    stored = after_in_node[stored]
                if dominated:
                    continue
                if count >= max_labels:
                    return node_of, parent, meters, count, -2, still, sneaked
                if count == node_of.shape[0]:
                    node_of = _grow(node_of, count + 1)
                    parent = _grow(parent, count + 1)
                    after_in_node = _grow(after_in_node, count + 1)
                    meters = _grow(meters, count + 1)
                    still = _grow(still, count + 1)
                    sneaked = _grow(sneaked, count + 1)
                node_of[count] = next_node
                still[count] = still_after
                sneaked[count] = move >= SNEAK_MOVE
                parent[count] = label
                for guard in range(guards):
                    meters[count, guard] = candidate[guard]
                after_in_node[count] = head[next_node]
                head[next_node] = count
                settled[next_node] = empty
                if upcoming_width == upcoming.shape[0]:
                    upcoming = _grow(upcoming, upcoming_width + 1)
                upcoming[upcoming_width] = count
                upcoming_width += 1
                count += 1
                if found < 0 and goal[after, other]:
                    found = count - 1
                    if not exhaustive:
                        return node_of, parent, meters, count, found, still, sneaked
        frontier, upcoming = upcoming, frontier
        width = upcoming_width
    return node_of, parent, meters, count, found, still, sneaked


@jit
def _entry_searches(
    neighbours: np.ndarray,
    gain: np.ndarray,
    seen: np.ndarray,
    fall: float,
    source: int,
    goal: np.ndarray,
    phases: np.ndarray,
    max_labels: int,
    heard: np.ndarray,
    cap: int,
    moves: int,
) -> np.ndarray:
    """One search per lap tick in ``phases``, entering then only; whether each reaches a goal node (-2 in
    the first entry past ``max_labels``). The node arrays are cleaned between searches, not rebuilt."""
    period, cells = gain.shape[1], gain.shape[2]
    head = np.empty(period * cells, dtype=np.int64)
    head[:] = -1
    settled = np.zeros(period * cells, dtype=np.bool_)
    entries = np.zeros(period, dtype=np.bool_)
    out = np.zeros(phases.size, dtype=np.int64)
    room = 1024
    for index in range(phases.size):
        entries[phases[index]] = True
        node_of, _, _, count, found, _, _ = _label_search(
            neighbours,
            gain,
            seen,
            fall,
            source,
            goal,
            entries,
            False,
            max_labels,
            head,
            settled,
            room,
            heard,
            cap,
            moves,
        )
        entries[phases[index]] = False
        if found == -2:
            out[index] = -2
            return out
        out[index] = 1 if found >= 0 else 0
        room = max(room, count + 1)
        for label in range(count):
            head[node_of[label]] = -1
            settled[node_of[label]] = False
    return out


def entry_searches(
    neighbours: np.ndarray,
    gain: np.ndarray,
    fall: float,
    source: int,
    goal: np.ndarray,
    phases: np.ndarray,
    *,
    seen: np.ndarray | None = None,
    max_labels: int = MAX_LABELS,
    heard: np.ndarray | None = None,
    sneak_ticks: int = 2,
) -> np.ndarray:
    """``bool (len(phases),)``: for each lap tick in ``phases``, whether a player entering ``source`` then
    (and only then) reaches a ``goal`` node (``bool (period, cells)``) undetected (with ``heard``, as in
    :func:`undetected_search`, unheard too).

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> gain = np.array([[[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]])
    >>> goal = np.array([[False, False, True], [False, False, True]])
    >>> entry_searches(neighbours, gain, 0.25, 0, goal, np.array([0, 1])).tolist()
    [True, True]
    """
    gain = np.ascontiguousarray(gain, dtype=np.float64)
    seen = np.asarray((gain > 0).any(axis=0)) if seen is None else np.ascontiguousarray(seen, dtype=np.bool_)
    out = _entry_searches(
        np.ascontiguousarray(neighbours, dtype=np.int64), gain, seen, float(fall), int(source),
        np.ascontiguousarray(goal, dtype=np.bool_), np.ascontiguousarray(phases, dtype=np.int64), int(max_labels),
        *_gait_arguments(heard, sneak_ticks),
    )  # fmt: skip
    if (out == -2).any():
        raise LimitError(f"a slack search passed {max_labels} labels; the level, lap or guards are too large for it")
    return out == 1


def _gait_arguments(heard: np.ndarray | None, sneak_ticks: int) -> tuple[np.ndarray, int, int]:
    """``heard``, ``cap`` and ``moves`` of the label search: without ears, no gaits at all."""
    if heard is None:
        return SILENT, 0, WALK_MOVES
    return np.ascontiguousarray(heard, dtype=np.bool_), int(sneak_ticks) - 1, GAIT_MOVES


class LabelSearch:
    """The labels of one graded search, kept to read paths and reached cells from."""

    def __init__(
        self,
        node_of: np.ndarray,
        parent: np.ndarray,
        meters: np.ndarray,
        count: int,
        found: int,
        cells: int,
        sneaked: np.ndarray | None = None,
        sneak_ticks: int = 0,
    ):
        self.node_of = node_of[:count]
        self.parent = parent[:count]
        self.meters = meters[:count]
        self.found = found
        self.cells = cells
        self.sneaked = None if sneaked is None else sneaked[:count]
        """With gaits: whether each label landed a sneaking step."""
        self.sneak_ticks = sneak_ticks

    @property
    def labels(self) -> int:
        """Labels kept."""
        return int(self.node_of.size)

    def _chain(self) -> list[int]:
        chain = [self.found]
        while self.parent[chain[-1]] >= 0:
            chain.append(int(self.parent[chain[-1]]))
        chain.reverse()
        return chain

    def path(self) -> tuple[int, np.ndarray]:
        """The found label's entry lap tick and its flat cell per tick."""
        nodes = self.node_of[self._chain()]
        return int(nodes[0] // self.cells), (nodes % self.cells).astype(np.int64)

    def gaits(self) -> tuple[str, ...] | None:
        """With gaits, what the found path does in each tick after entering (see
        :attr:`guardsim.sneak.search.SneakPath.gaits`); ``None`` without."""
        if self.sneaked is None:
            return None
        from guardsim.sneak.search import tick_gaits

        chain = self._chain()
        return tick_gaits(self.node_of[chain] % self.cells, self.sneaked[chain], self.sneak_ticks - 1)

    def reached_cells(self) -> np.ndarray:
        """``bool (cells,)``: the cells some undetected path reaches (after an exhaustive search)."""
        reached = np.zeros(self.cells, dtype=np.bool_)
        reached[self.node_of % self.cells] = True
        return reached


def undetected_search(
    neighbours: np.ndarray,
    gain: np.ndarray,
    fall: float,
    source: int,
    target: int | np.ndarray,
    entries: np.ndarray | None = None,
    *,
    exhaustive: bool = False,
    seen: np.ndarray | None = None,
    max_labels: int = MAX_LABELS,
    heard: np.ndarray | None = None,
    sneak_ticks: int = 2,
) -> LabelSearch:
    """Search for the fastest undetected path from ``source`` to ``target`` (flat cells).

    With ``heard`` (``bool (2, period, cells)``, :func:`guardsim.detection.hearing.lap_hearing`), the
    path chooses a gait for every step (a sneaking step takes ``sneak_ticks`` ticks) and no step lands
    where a guard hears it; :meth:`LabelSearch.gaits` says what it does in each tick.

    ``target`` may instead be a ``bool (period, cells)`` array of goal nodes (a path ends on reaching
    any). ``entries`` (``bool (period,)``) limits the lap ticks the intruder may enter at (default: all).
    ``exhaustive`` goes on past the goal, to every label reachable (see
    :meth:`LabelSearch.reached_cells`). ``seen`` is ``(gain > 0).any(axis=0)``, when the caller has it. Read the answer from the returned :class:`LabelSearch`
    (``found`` < 0: none).

    Raises
    ------
    LimitError
        When the search would keep more than ``max_labels`` labels.

    Examples
    --------
    Three cells in a row, one guard seeing the middle one at both ticks of a two-tick lap, half the
    meter a tick, draining a quarter a tick. Walking through takes one tick in view (half full):

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> gain = np.array([[[0.0, 0.5, 0.0], [0.0, 0.5, 0.0]]])
    >>> search = undetected_search(neighbours, gain, 0.25, 0, 2)
    >>> search.path()[1].tolist()
    [0, 1, 2]
    >>> undetected_search(neighbours, gain * 2, 0.25, 0, 2).found
    -1
    """
    gain = np.ascontiguousarray(gain, dtype=np.float64)
    period, cells = gain.shape[1], gain.shape[2]
    entries = np.ones(period, dtype=np.bool_) if entries is None else np.ascontiguousarray(entries, dtype=np.bool_)
    if isinstance(target, np.ndarray):
        goal = np.ascontiguousarray(target, dtype=np.bool_)
    else:
        goal = np.zeros((period, cells), dtype=np.bool_)
        goal[:, int(target)] = True
    gaits = _gait_arguments(heard, sneak_ticks)
    node_of, parent, meters, count, found, _, sneaked = _label_search(
        np.ascontiguousarray(neighbours, dtype=np.int64), gain,
        (gain > 0).any(axis=0) if seen is None else np.ascontiguousarray(seen, dtype=np.bool_), float(fall),
        int(source), goal, entries, bool(exhaustive), int(max_labels),
        np.full(period * cells, -1, dtype=np.int64), np.zeros(period * cells, dtype=np.bool_),
        # Room for a label per node to start with: most nodes keep one (all meters empty).
        period * cells + 1, *gaits,
    )  # fmt: skip
    if found == -2:
        raise LimitError(
            f"the undetected-path search passed {max_labels} labels ((cell, lap tick, meters) states kept); "
            "the level, lap or guards are too large for it"
        )
    if heard is None:
        return LabelSearch(node_of, parent, meters, count, found, cells)
    return LabelSearch(node_of, parent, meters, count, found, cells, sneaked, int(sneak_ticks))
