"""The sneak check: can a player cross a patrolled level unseen (or undetected), and where can it hide?

- :mod:`~guardsim.sneak.search`: the exact space-time search (unseen path, closest call, hiding windows).
- :mod:`~guardsim.sneak.graded`: the same search under the detection model (undetected paths).
- :mod:`~guardsim.sneak.grade`: a path's meters replayed, its risk, and the slack of the lap.

See ``docs/patrols.md`` and ``docs/detection.md``.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import Any, NamedTuple

import numpy as np

from guardsim.detection import GuardDetection, PatrolGains
from guardsim.detection.exposure import MAX_DENSE_NODES
from guardsim.detection.hearing import lap_hearing
from guardsim.detection.sight import LapSight, seen_bits
from guardsim.detection.watch import MAX_JOINT_LAP, LevelWatch, joint_lap, lap_sight_of
from guardsim.errors import ArgumentError, LimitError
from guardsim.grid import CoverageGrid
from guardsim.kernels.distances import distances_from
from guardsim.level.model import IntruderSpec
from guardsim.patrol.model import Patrol
from guardsim.sneak.grade import PathGrade, grade_path, unseen_reach
from guardsim.sneak.graded import MAX_LABELS, entry_searches, undetected_search
from guardsim.sneak.search import SneakPath, closest_call, find_sneak, hiding_windows, tick_gaits
from guardsim.sneak.sweep import Sweep, entry_search, sweep
from guardsim.vision.table import ViewTable

__all__ = [
    "HIDING_SPOTS_LISTED",
    "MAX_CLOSEST_CALL_NODES",
    "MAX_SNEAK_NODES",
    "FloorSight",
    "HidingSpot",
    "PathGrade",
    "SneakMemo",
    "SneakPath",
    "SneakResult",
    "check_sneak_size",
    "closest_call",
    "find_sneak",
    "floor_sight",
    "grade_path",
    "hiding_windows",
    "sneak_check",
    "sneak_data",
    "sneak_route",
    "undetected_search",
]

#: Hiding spots listed in sneak.json.
HIDING_SPOTS_LISTED = 10


class HidingSpot(NamedTuple):
    """A cell a player can reach from the entry and stand in."""

    cell: int
    """Flat cell index."""
    lasts: int | None
    """Ticks a player standing there lasts before detection, entering at the worst lap tick; ``None``:
    never detected."""
    exposure: float
    """Fraction of the lap some guard sees the cell."""


class SneakResult(NamedTuple):
    """The answer of the sneak check."""

    path: SneakPath | None
    """The fastest path meeting the search's rule when one exists (unseen; undetected with
    ``undetected=True``), else the closest call; ``None`` when the target cannot be reached at all."""
    period: int
    sight: LapSight
    """What the patrol (and the level's cameras) see at each tick of the lap, and the gains then."""
    hiding: np.ndarray
    """``int64 (cells,)``: each cell's longest unseen window (see :func:`hiding_windows`)."""
    undetected: bool
    """Whether the search's rule was "undetected" (else "unseen")."""
    grade: PathGrade | None
    """The path replayed through the guards' meters."""
    slack: int
    """Lap ticks from which a player entering can reach the target under the search's rule."""
    exposure: np.ndarray
    """``float64 (cells,)``: fraction of the lap each cell is in some guard's view."""
    time_to_detection: np.ndarray
    """``int64 (cells,)``: see :func:`guardsim.detection.time_to_detection` (-1 never, -2 no floor)."""
    hiding_spots: tuple[HidingSpot, ...]
    """The best places to wait reachable undetected from the entry, safest first (at most
    :data:`HIDING_SPOTS_LISTED`)."""
    lap: Patrol | None = None
    """The patrol repeated over the joint lap with the level's cameras (the patrol itself without them):
    what :attr:`period` and the path's lap ticks count in."""
    unheard: bool = False
    """Whether the search's rule also required that no guard hear a step (the path then has gaits)."""

    @property
    def seen(self) -> np.ndarray:
        """``bool (period, cells)``: what the patrol sees at each tick of its lap (built on each call:
        ``period x cells`` bytes; :meth:`LapSight.seen_at` reads one node)."""
        return self.sight.dense_seen()

    @property
    def gains(self) -> PatrolGains:
        """The gains as one dense array (built on each call: ``8 x watchers x period x cells`` bytes)."""
        return self.sight.dense_gains()

    @property
    def found(self) -> bool:
        """Whether a path meeting the search's rule exists."""
        return self.path is not None and self.path.found


class SneakMemo:
    """The backward unseen sweeps of sneak checks (the nodes from which each target is reached unseen),
    kept for later checks: a check whose grid, seen lap ticks and target equal an earlier one's takes that
    sweep instead of running it again (about half of a check on a big map).

    The sweep reads nothing else (no meter, no entry, no gain), so a kept one is the sweep that would be
    run, bit for bit. ``earlier``: a memo to look in too (``guardsim watch``: the last save's checks);
    :meth:`forget_earlier` lets it go once the checks are done, so memos do not chain.
    """

    def __init__(self, earlier: SneakMemo | None = None) -> None:
        self._kept: list[tuple[np.ndarray, np.ndarray, int, int, Sweep]] = []
        self._earlier = earlier
        self.hits = 0
        """Sweeps taken from the earlier memo."""

    def find(self, neighbours: np.ndarray, bits: np.ndarray, period: int, target: int) -> Sweep | None:
        """The kept sweep to ``target`` over exactly these neighbours and seen bits of a ``period``-tick
        lap, if any."""
        for memo in (self, self._earlier):
            for kept_neighbours, kept_bits, kept_period, kept_target, found in [] if memo is None else memo._kept:
                if (
                    kept_target == target
                    and kept_period == period
                    and kept_bits.shape == bits.shape
                    and np.array_equal(kept_neighbours, neighbours)
                    and np.array_equal(kept_bits, bits)
                ):
                    if memo is not self:
                        self.hits += 1
                        self.keep(neighbours, bits, period, target, found)
                    return found
        return None

    def keep(self, neighbours: np.ndarray, bits: np.ndarray, period: int, target: int, found: Sweep) -> None:
        """Keep the backward sweep to ``target`` over these neighbours and seen bits (not copied: the
        caller does not change them)."""
        self._kept.append((neighbours, bits, period, target, found))

    def forget_earlier(self) -> None:
        """Let the earlier memo go (what this one took from it, it keeps)."""
        self._earlier = None


#: (floor cell, lap tick) nodes from which the two sweeps of a check run side by side (below, a thread costs more
#: than it saves).
PARALLEL_SWEEP_NODES = 1_000_000

#: Most (floor cell, lap tick) nodes a sneak search may cover: about :data:`SNEAK_BITS_PER_NODE` bits of
#: memory each at the search's peak (the lap's seen ticks, the nodes reached unseen backwards from the
#: target and undetected forwards from the entry, and a flood's pending nodes, as bitsets of a row per
#: floor cell, and the lap's sight events), besides the level's view table: 8 billion nodes is about 5.6 GB.
MAX_SNEAK_NODES = 8_000_000_000
#: Peak memory per (floor cell, lap tick) node of a sneak search, in bits, rounded up (measured: 5.3 on
#: duskwood's 4-guard 22 784-tick lap, 2.8 GB in all with its 670 MB view table; docs/performance.md).
SNEAK_BITS_PER_NODE = 6


def check_sneak_size(grid: CoverageGrid, period: int) -> None:
    """Refuse, before any work, a sneak search of ``grid`` over a ``period``-tick lap whose (floor cell,
    lap tick) nodes are over :data:`MAX_SNEAK_NODES` (a one-line :class:`~guardsim.errors.LimitError`
    naming the memory and the limit to raise)."""
    _check_nodes(period, int(np.count_nonzero(grid.traversable)))


def _check_nodes(period: int, floor: int) -> None:
    """Refuse a sneak search over :data:`MAX_SNEAK_NODES` (floor cell, lap tick) nodes."""
    nodes = period * floor
    if nodes > MAX_SNEAK_NODES:
        raise LimitError(
            f"the sneak search would have {nodes} (floor cell, lap tick) nodes ({floor} floor cells x a "
            f"{period}-tick lap), about {_gigabytes(nodes)} GB, over the limit of {MAX_SNEAK_NODES} nodes (about "
            f"{_gigabytes(MAX_SNEAK_NODES)} GB; raise guardsim.sneak.MAX_SNEAK_NODES, or patrol with a shorter lap)"
        )


def _gigabytes(nodes: int) -> str:
    return f"{nodes * SNEAK_BITS_PER_NODE / 2**33:.1f}"


def sneak_check(
    grid: CoverageGrid,
    table: ViewTable,
    patrol: Patrol,
    source: int,
    target: int,
    *,
    detection: GuardDetection,
    undetected: bool = False,
    watch: LevelWatch | None = None,
    max_lap: int = MAX_JOINT_LAP,
    unheard: bool = False,
    intruder: IntruderSpec | None = None,
    max_labels: int = MAX_LABELS,
    memo: SneakMemo | None = None,
) -> SneakResult:
    """Search for an unseen path (``undetected=True``: an undetected one) from cell ``source`` to cell
    ``target`` (flat indices) under ``patrol``, and grade it under ``detection``.

    ``unheard=True`` also chooses a gait for every step (walking: one tick; sneaking: ``sneak_ticks``) so
    that no guard hears a step land, by the noise rule of :mod:`guardsim.kernels.noise` with the noise
    keys of ``intruder`` (the level's ``intruder``; default: silent steps); the path's
    :attr:`~guardsim.sneak.search.SneakPath.gaits` say what it does in each tick.

    ``watch`` (:func:`guardsim.detection.watch.level_watch`) adds the level's cameras as watchers and its
    light to every meter; the search then runs over the joint lap of the patrol and the cameras' swings
    (at most ``max_lap`` ticks). ``max_labels`` bounds the labels with some meter up a search keeps.

    The answer is that of :func:`find_sneak`, :func:`undetected_search` (from every entry tick, on past the
    target), :func:`~guardsim.sneak.grade.unseen_reach` and :func:`entry_searches` over the dense lap, path
    for path; it is found without an array over every (lap tick, cell) (:mod:`guardsim.sneak.sweep`).

    Raises
    ------
    LimitError
        When the period times the cells is over :data:`MAX_SNEAK_NODES`, the joint lap over ``max_lap``,
        or a search keeps more than ``max_labels`` labels with some meter up.
    """
    if patrol.period is None:
        raise ArgumentError("the sneak check needs a repeating patrol (its period is null)")
    # Up front, before the lap's sight is built.
    check_sneak_size(grid, joint_lap(patrol.period, watch, max_lap=max_lap))
    sight, states = lap_sight_of(grid, table, patrol.states, detection, watch, max_lap=max_lap)
    lap = patrol if states.shape[1] == patrol.period else Patrol(states, states.shape[1], patrol.strategy)
    period = sight.period
    intruder = IntruderSpec() if intruder is None else intruder
    neighbours = grid.neighbours
    heard = lap_hearing(neighbours, states, intruder, grid.cell_size) if unheard else None
    # When no walking step is ever heard, walking is never worse than sneaking (a sneaking step is waits
    # and a step): the searches without gaits answer exactly, with their own paths.
    audible = heard if heard is not None and heard[0].any() else None
    ticks = intruder.sneak_ticks
    if audible is not None:
        # With gaits the searches are dense, over every cell (their own limit, MAX_DENSE_NODES).
        nodes = period * grid.size * ticks
        path, entries, reached = _with_gaits(sight, neighbours, source, target, undetected, audible, ticks, nodes)
    else:
        # The searches run on the floor's rows alone, while the sight's own rows (a row per cell) are set
        # aside, then rebuilt from its events (see _floor_rows).
        on = floor_sight(sight, grid)
        sight = sight._replace(bits=np.zeros((0, sight.bits.shape[1]), dtype=np.uint64))
        path, entries, on_floor = _without_gaits(
            on.rows, on.neighbours, on.renumbered(source), on.renumbered(target), undetected, period * on.floor.size,
            max_labels, memo,
        )  # fmt: skip
        path = on.path(path)
        reached = np.zeros(grid.size, dtype=bool)
        reached[on.floor] = on_floor
        del on
        sight = sight._replace(bits=seen_bits(sight.start, sight.tick, period))
    if unheard and path is not None and path.gaits is None:
        path = path._replace(gaits=tick_gaits(path.cells, np.zeros(path.cells.size, dtype=bool), 0))
    grade = (
        None if path is None else grade_path(grid, table, states, detection, path.start_tick, path.cells, watch=watch)
    )
    lasts = sight.time_to_detection(grid.traversable)
    exposure = sight.exposure()
    return SneakResult(
        path,
        period,
        sight,
        sight.longest_unseen(grid.traversable),
        undetected,
        grade,
        int(entries.sum()),
        exposure,
        lasts,
        _hiding_spots(reached, lasts, exposure),
        lap,
        unheard,
    )


class FloorSight(NamedTuple):
    """A lap's sight and the grid's moves on the floor cells alone, renumbered in the same order (so the
    searches find the same paths): what the sneak searches run on (:func:`floor_sight`)."""

    rows: LapSight
    """The sight's events and seen-tick rows of the floor cells, the ``i``-th floor cell as cell ``i``."""
    neighbours: np.ndarray
    """``int64 (floor cells, 4)``: the grid's neighbours, renumbered."""
    floor: np.ndarray
    """``int64 (floor cells,)``: the flat cell of each, ascending."""

    def renumbered(self, cell: int) -> int:
        """The renumbered index of flat floor cell ``cell``."""
        return int(np.searchsorted(self.floor, cell))

    def path(self, path: SneakPath | None) -> SneakPath | None:
        """``path`` (renumbered cells) in flat cells."""
        return None if path is None else path._replace(cells=self.floor[path.cells])


def floor_sight(sight: LapSight, grid: CoverageGrid) -> FloorSight:
    """``sight`` and ``grid``'s moves on the floor cells alone.

    The searches' bitsets have a row per cell. A wall's row is never written, but it shares memory pages
    with the floor rows beside it (a row of a 22 784-tick lap is 2.8 kB), so rows for every cell cost
    memory for every cell: duskwood's (49 % floor) `sneak --undetected` took 4.1 GB with them, 2.8 GB
    with the floor's alone."""
    floor = np.flatnonzero(np.asarray(grid.traversable).ravel())
    index = np.full(grid.size, -1, dtype=np.int64)
    index[floor] = np.arange(floor.size)
    counts = np.diff(sight.start)[floor]
    start = np.zeros(floor.size + 1, dtype=np.int64)
    np.cumsum(counts, out=start[1:])
    events = np.repeat(sight.start[floor] - start[:-1], counts) + np.arange(int(start[-1]))
    rows = sight._replace(
        start=start, tick=sight.tick[events], watcher=sight.watcher[events], gain=sight.gain[events],
        bits=sight.bits[floor],
    )  # fmt: skip
    around = grid.neighbours[floor]
    return FloorSight(rows, np.where(around >= 0, index[np.maximum(around, 0)], -1), floor)


def _without_gaits(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    target: int,
    undetected: bool,
    nodes: int,
    max_labels: int,
    memo: SneakMemo | None = None,
) -> tuple[SneakPath | None, np.ndarray, np.ndarray]:
    """The path, the entry ticks that get through and the cells reached from the entry, found without an
    array over every (lap tick, cell) (:mod:`guardsim.sneak.sweep`)."""
    period = sight.period
    remaining = distances_from(neighbours, np.array([target])).astype(np.int64)
    # Backwards from the target: the nodes from which it is reached unseen (the unseen slack); kept from an
    # earlier check when its grid, seen ticks and target are the same.
    reach = None if memo is None else memo.find(neighbours, sight.bits, period, target)
    with ThreadPoolExecutor(max_workers=1) as pool:
        # Every entry tick at once, on past the target: every cell it reaches is a place the player can get
        # to. It reads nothing of the sweep backwards, so a big one runs beside it (the kernels release the
        # interpreter): on two cores the check takes the longer of the two, not their sum.
        forwards = partial(sweep, sight, neighbours, source, target, graded=True, flood=True, max_labels=max_labels)
        ahead = pool.submit(forwards) if reach is None and nodes >= PARALLEL_SWEEP_NODES else None
        if reach is None:
            reach = sweep(sight, neighbours, target, -1, graded=False, forward=False, flood=True, max_labels=max_labels)
            if memo is not None:
                memo.keep(neighbours, sight.bits, period, target, reach)
        search = forwards() if ahead is None else ahead.result()
    path, entries, _ = _unseen(sight, neighbours, source, target, remaining, reach, max_labels)
    if undetected and search.cells[target]:
        # An unseen path as fast is the better answer (no guard's meter moves at all): only a faster
        # undetected one replaces it.
        ticks, entry, cells = _fastest(
            sight, neighbours, source, target, remaining, graded=True, entries=np.ones(period, dtype=bool),
            ceiling=-1 if path is None else path.ticks - 1, max_labels=max_labels,
        )  # fmt: skip
        if ticks >= 0:
            if cells is None:
                cells = entry_search(
                    sight, neighbours, source, entry, target, graded=True, bound=ticks, remaining=remaining,
                    max_labels=max_labels,
                ).cells  # fmt: skip
            phases = (entry + np.arange(cells.size)) % period
            in_view = (sight.bits[cells, phases >> 6] >> (phases & 63).astype(np.uint64)) & np.uint64(1)
            path = SneakPath(True, entry, cells, int(in_view.sum()))
        entries = entries | _undetected_entries(sight, neighbours, source, target, reach.reached, entries, max_labels)
    elif path is None:
        path = _closest_call(sight, neighbours, source, target, nodes)
    return path, entries, search.cells


def _unseen(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    target: int,
    remaining: np.ndarray,
    reach: Sweep | None,
    max_labels: int,
) -> tuple[SneakPath | None, np.ndarray, Sweep]:
    """The fastest unseen path (``None``: none), the entry ticks from which one exists and the backward
    sweep from the target that found them (``reach``: that sweep, run already)."""
    if reach is None:
        # Backwards from the target: the nodes from which it is reached unseen (the unseen slack).
        reach = sweep(sight, neighbours, target, -1, graded=False, forward=False, flood=True, max_labels=max_labels)
    entries = _ticks_of(reach.reached[source], sight.period)
    if not entries.any():
        return None, entries, reach
    ticks, entry, cells = _fastest(
        sight, neighbours, source, target, remaining, graded=False, entries=entries, max_labels=max_labels
    )
    if cells is None:
        cells = entry_search(
            sight, neighbours, source, entry, target, graded=False, bound=ticks, remaining=remaining,
            max_labels=max_labels,
        ).cells  # fmt: skip
    return SneakPath(True, entry, cells, 0), entries, reach


def _closest_call(sight: LapSight, neighbours: np.ndarray, source: int, target: int, nodes: int) -> SneakPath | None:
    """:func:`closest_call` over the dense lap, refused over :data:`MAX_CLOSEST_CALL_NODES`."""
    if nodes > MAX_CLOSEST_CALL_NODES:
        raise LimitError(
            f"no unseen path, and the closest call's search would have {nodes} (cell, lap tick) nodes, over "
            f"the limit of {MAX_CLOSEST_CALL_NODES}: ask for an undetected path instead"
        )
    return closest_call(neighbours, sight.dense_seen(), source, target)


def sneak_route(
    sight: FloorSight,
    source: int,
    target: int,
    *,
    heard: np.ndarray | None = None,
    sneak_ticks: int = 2,
    max_labels: int = MAX_LABELS,
) -> SneakPath | None:
    """The fastest path from ``source`` to ``target`` (flat floor cells) unseen under ``sight``
    (:func:`floor_sight`), else the closest call; ``None`` when the target cannot be reached at all. The
    same path as :func:`find_sneak`, then :func:`closest_call`, over the dense lap, found without it when
    no step is ``heard`` (with ears, :func:`find_sneak`'s ``heard`` over every cell, the searches choose
    gaits over the dense lap of the floor).

    Raises
    ------
    LimitError
        When a dense search would be over :data:`MAX_CLOSEST_CALL_NODES` nodes (the closest call, and
        every search with ears).
    """
    rows, neighbours = sight.rows, sight.neighbours
    start, goal = sight.renumbered(source), sight.renumbered(target)
    nodes = rows.period * rows.cells
    if heard is None:
        remaining = distances_from(neighbours, np.array([goal])).astype(np.int64)
        path, _, _ = _unseen(rows, neighbours, start, goal, remaining, None, max_labels)
        return sight.path(path if path is not None else _closest_call(rows, neighbours, start, goal, nodes))
    if nodes * sneak_ticks > MAX_CLOSEST_CALL_NODES:
        raise LimitError(
            f"a sneak path with gaits would search {nodes * sneak_ticks} (floor cell, lap tick, ticks stood still) "
            f"nodes, over the limit of {MAX_CLOSEST_CALL_NODES}"
        )
    seen, ears = rows.dense_seen(), np.ascontiguousarray(heard[:, :, sight.floor])
    path = find_sneak(neighbours, seen, start, goal, heard=ears, sneak_ticks=sneak_ticks)
    path = path or closest_call(neighbours, seen, start, goal, heard=ears, sneak_ticks=sneak_ticks)
    return sight.path(path)


def _with_gaits(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    target: int,
    undetected: bool,
    heard: np.ndarray,
    sneak_ticks: int,
    nodes: int,
) -> tuple[SneakPath | None, np.ndarray, np.ndarray]:
    """:func:`_without_gaits` when a walking step can be heard: the searches choose a gait for every step
    (:mod:`guardsim.kernels.gaits`), over the dense lap (the sweeps take no gaits)."""
    if nodes > MAX_DENSE_NODES:
        raise LimitError(
            f"the unheard search would have {nodes} (cell, lap tick, ticks stood still) nodes, over the limit of "
            f"{MAX_DENSE_NODES} for a search with gaits"
        )
    gains = sight.dense_gains()
    seen = gains.seen
    reach = unseen_reach(neighbours, seen, target, heard=heard, sneak_ticks=sneak_ticks)
    entries = reach[:, source].copy()
    # One search from every entry tick, on past the target: its first arrival is the fastest undetected
    # path, and every cell it reaches is a place the player can get to.
    search = undetected_search(
        neighbours, gains.gain, gains.fall, source, target, exhaustive=True, seen=seen, heard=heard,
        sneak_ticks=sneak_ticks,
    )  # fmt: skip
    path = find_sneak(neighbours, seen, source, target, heard=heard, sneak_ticks=sneak_ticks)
    if undetected and search.found >= 0:
        start, cells = search.path()
        # An unseen path as fast is the better answer: no guard's meter moves at all.
        if path is None or path.ticks > cells.size - 1:
            in_view = int(seen[(start + np.arange(cells.size)) % sight.period, cells].sum())
            path = SneakPath(True, start, cells, in_view, search.gaits())
        entries = entries | _gaited_undetected_entries(
            neighbours, gains, seen, source, target, reach, heard, sneak_ticks
        )
    elif path is None:
        path = closest_call(neighbours, seen, source, target, heard=heard, sneak_ticks=sneak_ticks)
    return path, entries, search.reached_cells()


#: Most (cell, lap tick) nodes of the closest-call search (:func:`closest_call`), dense: about 30 bytes each.
MAX_CLOSEST_CALL_NODES = MAX_DENSE_NODES


def _fastest(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    target: int,
    remaining: np.ndarray,
    *,
    graded: bool,
    entries: np.ndarray,
    ceiling: int = -1,
    max_labels: int,
) -> tuple[int, int, np.ndarray | None]:
    """The fewest ticks to ``target`` from the lap ticks ``entries``, the least entry tick doing it and,
    when found on the way, its path (ticks -1: none within ``ceiling``, when given).

    No path is shorter than the steps to the target: the first entry ticks are tried alone within that
    bound (the first that manages it is the answer). Then bounded sweeps of every entry tick at once, the
    bound raised until the target is reached, then unbounded."""
    shortest = int(remaining[source])
    if ceiling < 0 or shortest <= ceiling:
        for phase in np.flatnonzero(entries)[:ENTRIES_TRIED_ALONE]:
            alone = entry_search(
                sight, neighbours, source, int(phase), target, graded=graded, bound=shortest, remaining=remaining,
                max_labels=max_labels,
            )  # fmt: skip
            if alone.found:
                return shortest, int(phase), alone.cells
    slack = 0
    while True:
        bound = shortest + slack
        if ceiling >= 0:
            bound = min(bound, ceiling)
        elif slack > 4 * sight.period:
            bound = -1
        found = sweep(
            sight, neighbours, source, target, graded=graded, bound=bound, remaining=remaining,
            entries=entries, max_labels=max_labels,
        )  # fmt: skip
        if found.ticks >= 0 or bound < 0 or bound == ceiling:
            return found.ticks, found.entry, None
        slack = max(16, 4 * slack)


#: Entry ticks :func:`_fastest` tries one at a time before searching all of them at once.
ENTRIES_TRIED_ALONE = 32


def _ticks_of(words: np.ndarray, period: int) -> np.ndarray:
    """``bool (period,)``: the lap ticks set in one cell's row of bitset words."""
    return np.unpackbits(words.view(np.uint8), bitorder="little")[:period].astype(bool)


def _undetected_entries(
    sight: LapSight,
    neighbours: np.ndarray,
    source: int,
    target: int,
    reach: np.ndarray,
    unseen: np.ndarray,
    max_labels: int,
) -> np.ndarray:
    """The lap ticks from which an undetected path exists and no unseen one, one search per entry tick.

    A search may stop on any node an unseen path leads on from (``reach``): out of sight the meters only
    drain, so what got there undetected gets through."""
    found = np.zeros_like(unseen)
    for phase in np.flatnonzero(~unseen):
        found[phase] = entry_search(
            sight, neighbours, source, int(phase), target, graded=True, goal=reach, max_labels=max_labels
        ).found
    return found


def _gaited_undetected_entries(
    neighbours: np.ndarray,
    gains: PatrolGains,
    seen: np.ndarray,
    source: int,
    target: int,
    reach: np.ndarray,
    heard: np.ndarray,
    sneak_ticks: int,
) -> np.ndarray:
    """:func:`_undetected_entries` with gaits, over the dense lap."""
    goal = reach.copy()
    goal[:, target] = True
    known = reach[:, source]
    phases = np.flatnonzero(~known)
    found = np.zeros_like(known)
    found[phases] = entry_searches(
        neighbours, gains.gain, gains.fall, source, goal, phases, seen=seen, heard=heard, sneak_ticks=sneak_ticks
    )
    return found


def _hiding_spots(reached: np.ndarray, lasts: np.ndarray, exposure: np.ndarray) -> tuple[HidingSpot, ...]:
    cells = np.flatnonzero(reached & (lasts != -2))
    # Never detected first, then the longest lasting, then the least seen, then by cell for a fixed order.
    never = lasts[cells] == -1
    order = np.lexsort((cells, exposure[cells], -lasts[cells], ~never))
    return tuple(
        HidingSpot(int(cell), None if lasts[cell] == -1 else int(lasts[cell]), float(exposure[cell]))
        for cell in cells[order][:HIDING_SPOTS_LISTED]
    )


def sneak_data(result: SneakResult, grid: CoverageGrid, **header: Any) -> dict[str, Any]:
    """sneak.json: ``found``, ``start_tick``, ``path`` (``[col, row]`` per tick), ``ticks``, the path's
    grade (``detected``, ``peak_awareness``, ``ticks_in_view``, ``closest_distance``, ``risk``), ``slack``,
    the hiding spots and the exposure and time-to-detection maps (docs/patrols.md lists every key)."""
    path = result.path
    grade = result.grade
    rows, cols = grid.shape
    hiding = result.hiding.reshape(rows, cols)
    never = int(((result.hiding == result.period) & grid.traversable.ravel()).sum())
    lasts = result.time_to_detection.reshape(rows, cols)
    exposure = result.exposure.reshape(rows, cols)
    traversable = grid.traversable
    return {
        **header,
        # Cells are [col, row] of the grid whose top-left corner is ``origin`` (world units: a Tiled
        # map's tile coordinates), as in patrol.json and traces.
        "cell_size": grid.cell_size,
        "origin": list(grid.origin),
        "period": result.period,
        "rule": "undetected" if result.undetected else "unseen",
        "found": result.found,
        "reachable": path is not None,
        "start_tick": None if path is None else path.start_tick,
        "path": None if path is None else [list(grid.unflat(int(cell))) for cell in path.cells],
        "ticks": None if path is None else path.ticks,
        "ticks_in_view": None if grade is None else grade.ticks_in_view,
        "closest_call": path is not None and not path.found,
        "detected": None if grade is None else grade.detected,
        "detected_at": None if grade is None else grade.detected_at,
        "peak_awareness": None
        if grade is None
        else {"overall": round(grade.peak, 6), "by_guard": [round(value, 6) for value in grade.peak_by_guard]},
        "awareness": None if grade is None else [[round(float(v), 6) for v in row] for row in grade.meters],
        "closest_distance": None
        if grade is None or grade.closest_distance is None
        else round(grade.closest_distance, 6),
        "risk": None if grade is None else round(grade.risk, 6),
        "slack": result.slack,
        "never_seen_cells": never,
        "longest_unseen": [[None if value < 0 else int(value) for value in row] for row in hiding.tolist()],
        "exposure": [
            [round(float(value), 6) if traversable[r, c] else None for c, value in enumerate(row)]
            for r, row in enumerate(exposure.tolist())
        ],
        "time_to_detection": [[None if value < 0 else int(value) for value in row] for row in lasts.tolist()],
        "hiding_spots": [
            {"cell": list(grid.unflat(spot.cell)), "lasts": spot.lasts, "exposure": round(spot.exposure, 6)}
            for spot in result.hiding_spots
        ],
        **(_ears_data(result) if result.unheard else {}),
    }


def _ears_data(result: SneakResult) -> dict[str, Any]:
    """sneak.json's keys of an ``--unheard`` search: the rule, what the path does in each tick and the
    steps heard (a closest call's)."""
    path = result.path
    return {
        "unheard": True,
        "gaits": None if path is None or path.gaits is None else list(path.gaits),
        "steps_heard": None if path is None else path.steps_heard,
    }
