"""A repeating lap's sight, kept sparse: for each cell, the lap ticks some watcher sees it and the gains then.

:class:`~guardsim.detection.PatrolGains` holds a gain for every (watcher, lap tick, cell): 4.6 GB for one
guard's 8,826-tick lap of a 256 x 256 map, almost all of it zeros. :class:`LapSight` holds the same
numbers as events (the nonzero gains, by cell, then tick, then watcher) and each cell's seen ticks as a
bitset (one bit per (lap tick, cell)), and reads from them the maps of the sneak check (exposure, longest
unseen window, time to detection) and, where a caller still wants them, the dense arrays
(:meth:`LapSight.dense_gains`, and :func:`patrol_gains`, the dense gains of a lap: the view table is walked
for gains here alone, each gain :func:`guardsim.kernels.meter.cell_gain`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.detection.exposure import MAX_STANDING_LAPS, PatrolGains
from guardsim.detection.model import DetectionModel
from guardsim.grid import CoverageGrid
from guardsim.kernels.compiler import jit
from guardsim.kernels.meter import DETECTED, cell_gain, meter_after
from guardsim.kernels.steps import cell_of_state
from guardsim.vision.table import ViewTable

__all__ = ["LapSight", "lap_sight", "patrol_gains", "seen_bits"]


class LapSight(NamedTuple):
    """Every watcher's nonzero gains over a repeating lap, by cell."""

    period: int
    """Ticks in the lap."""
    start: np.ndarray
    """``int64 (cells + 1,)``: cell ``c``'s events are ``start[c]:start[c + 1]``, by tick then watcher."""
    tick: np.ndarray
    """``int64 (events,)``: the lap tick of each event."""
    watcher: np.ndarray
    """``int64 (events,)``: the watcher of each event (the guards, then the cameras)."""
    gain: np.ndarray
    """``float64 (events,)``: what a tick in the cell then adds to that watcher's meter (> 0; ``inf``: one
    tick detects)."""
    bits: np.ndarray
    """``uint64 (cells, words)``: bit ``t % 64`` of word ``t // 64`` set when some watcher sees the cell at
    lap tick ``t``."""
    watchers: int
    """Guards and cameras."""
    fall: float
    """What a tick out of a watcher's sight takes off its meter."""
    guard_cells: np.ndarray
    """``int64 (guards, period)``: each guard's flat cell at each lap tick."""
    dt: float
    """Seconds per tick."""
    cameras: int = 0
    """How many of the watchers (the last) are cameras."""

    @property
    def cells(self) -> int:
        """Cells of the grid."""
        return int(self.start.size) - 1

    def seen_at(self, tick: int, cell: int) -> bool:
        """Whether some watcher sees ``cell`` at lap tick ``tick`` (taken modulo the lap)."""
        tick %= self.period
        return bool((int(self.bits[cell, tick >> 6]) >> (tick & 63)) & 1)

    def seen_counts(self) -> np.ndarray:
        """``int64 (cells,)``: lap ticks at which some watcher sees each cell."""
        return _seen_counts(self.start, self.tick)

    def exposure(self) -> np.ndarray:
        """``float64 (cells,)``: the fraction of the lap each cell is seen (equal to
        :func:`~guardsim.detection.exposure_map` of the dense gains)."""
        return self.seen_counts() / self.period

    def longest_unseen(self, traversable: np.ndarray) -> np.ndarray:
        """``int64 (cells,)``: each cell's longest run of unseen ticks in the repeating lap (the period when
        never seen, -1 where no one can stand), as :func:`guardsim.sneak.hiding_windows` of the dense lap."""
        out = _longest_unseen(self.start, self.tick, self.period)
        out[~np.asarray(traversable, dtype=bool).ravel()] = -1
        return out

    def time_to_detection(self, traversable: np.ndarray) -> np.ndarray:
        """``int64 (cells,)``: :func:`~guardsim.detection.time_to_detection` from the events."""
        out = np.empty(self.cells, dtype=np.int64)
        unsettled = _time_to_detection(
            self.start, self.tick, self.watcher, self.gain, self.watchers, self.period, float(self.fall),
            np.ascontiguousarray(np.asarray(traversable, dtype=np.bool_).ravel()), MAX_STANDING_LAPS, out,
        )  # fmt: skip
        if unsettled:
            import warnings

            warnings.warn(
                f"time to detection: {unsettled} cells' meters still rose after {MAX_STANDING_LAPS} laps; "
                "counted as never detected",
                stacklevel=2,
            )
        return out

    def dense_seen(self) -> np.ndarray:
        """``bool (period, cells)``: whether some watcher sees each cell at each lap tick."""
        seen = np.zeros((self.period, self.cells), dtype=bool)
        seen[self.tick, np.repeat(np.arange(self.cells), np.diff(self.start))] = True
        return seen

    def dense_gains(self) -> PatrolGains:
        """The same gains as one ``(watchers, period, cells)`` array (``period x cells x 8`` bytes per watcher)."""
        gain = np.zeros((self.watchers, self.period, self.cells), dtype=np.float64)
        gain[self.watcher, self.tick, np.repeat(np.arange(self.cells), np.diff(self.start))] = self.gain
        return PatrolGains(gain, self.fall, self.guard_cells, self.dt, self.cameras)


def seen_bits(start: np.ndarray, tick: np.ndarray, period: int) -> np.ndarray:
    """``uint64 (cells, words)``: the seen-tick bitsets of events ``start``/``tick`` (see :class:`LapSight`)."""
    bits = np.zeros((start.size - 1, (period + 63) // 64), dtype=np.uint64)
    _fill_bits(start, tick, bits)
    return bits


@jit
def _fill_bits(start: np.ndarray, tick: np.ndarray, bits: np.ndarray) -> None:
    for cell in range(start.shape[0] - 1):
        for event in range(start[cell], start[cell + 1]):
            bits[cell, tick[event] >> 6] |= np.uint64(1) << np.uint64(tick[event] & 63)


@jit
def _guard_events(
    sight_start: np.ndarray,
    sight: np.ndarray,
    states: np.ndarray,
    cols: int,
    cell_size: float,
    near: float,
    far: float,
    view_range: float,
    dt: float,
    dark_sight: float,
    light: np.ndarray,
    counts: np.ndarray,
    cell_of: np.ndarray,
    tick_of: np.ndarray,
    watcher_of: np.ndarray,
    gain_of: np.ndarray,
    fill: bool,
) -> int:
    """Count (``fill`` false: ``counts`` per cell) or list the guards' nonzero gains, tick by tick, guard by
    guard; each gain is :func:`guardsim.kernels.meter.cell_gain`, as the dense gains' are."""
    count = 0
    for tick in range(states.shape[1]):
        for guard in range(states.shape[0]):
            state = states[guard, tick]
            own = cell_of_state(state)
            for index in range(sight_start[state], sight_start[state + 1]):
                cell = sight[index]
                value = cell_gain(own, cell, cols, cell_size, near, far, view_range, dt, dark_sight, light[cell])
                if value > 0.0:
                    if fill:
                        cell_of[count] = cell
                        tick_of[count] = tick
                        watcher_of[count] = guard
                        gain_of[count] = value
                    else:
                        counts[cell] += 1
                    count += 1
    return count


def lap_sight(
    grid: CoverageGrid,
    table: ViewTable,
    states: np.ndarray,
    model: DetectionModel,
    *,
    view_range: float,
    dt: float,
    light: np.ndarray | None = None,
    cameras: np.ndarray | None = None,
) -> LapSight:
    """The sparse :class:`LapSight` of the lap ``states`` (arguments as :func:`patrol_gains`)."""
    states = np.ascontiguousarray(states, dtype=np.int64)
    guards, period = states.shape
    lit = np.ones(grid.size, dtype=np.float64) if light is None else np.ascontiguousarray(light, dtype=np.float64)
    arguments = (
        table.sight_start, table.sight, states, grid.shape[1], float(grid.cell_size), float(model.detect_near),
        float(model.detect_far), float(view_range), float(dt), float(model.dark_sight), lit,
    )  # fmt: skip
    counts = np.zeros(grid.size, dtype=np.int64)
    empty_int, empty_float = np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.float64)
    total = _guard_events(*arguments, counts, empty_int, empty_int, empty_int, empty_float, False)
    cell = np.empty(total, dtype=np.int64)
    tick = np.empty(total, dtype=np.int64)
    watcher = np.empty(total, dtype=np.int64)
    gain = np.empty(total, dtype=np.float64)
    _guard_events(*arguments, counts, cell, tick, watcher, gain, True)
    extra = 0
    if cameras is not None and cameras.shape[0]:
        extra = cameras.shape[0]
        which, when, where = np.nonzero(cameras > 0)
        cell = np.concatenate((cell, where))
        tick = np.concatenate((tick, when))
        watcher = np.concatenate((watcher, guards + which))
        gain = np.concatenate((gain, cameras[which, when, where]))
    # The guards' events come by tick then guard already; a stable sort by cell keeps that order.
    order = np.argsort(cell, kind="stable") if extra == 0 else np.lexsort((watcher, tick, cell))
    start = np.zeros(grid.size + 1, dtype=np.int64)
    np.cumsum(np.bincount(cell, minlength=grid.size), out=start[1:])
    tick, watcher, gain = tick[order], watcher[order], gain[order]
    return LapSight(
        period, start, tick, watcher, gain, seen_bits(start, tick, period), guards + extra,
        model.fall(dt), cell_of_state(states), float(dt), extra,
    )  # fmt: skip


def patrol_gains(
    grid: CoverageGrid,
    table: ViewTable,
    states: np.ndarray,
    model: DetectionModel,
    *,
    view_range: float,
    dt: float,
    light: np.ndarray | None = None,
    cameras: np.ndarray | None = None,
) -> PatrolGains:
    """The gains of a lap of ``states`` (``int64 (guards, period)``, a patrol's states) as one dense
    ``(watchers, period, cells)`` array: :func:`lap_sight`'s, scattered.

    ``view_range`` is the guards' view range in world units (the distance at which ``detect_far``
    applies) and ``dt`` the seconds per tick (:func:`~guardsim.detection.grid_tick_seconds`). ``light``
    (``float64 (cells,)``, default all 1) is each cell's light, ``cameras`` (``float64 (cameras, period,
    cells)``) the cameras' own gains over the same lap, appended after the guards'
    (:func:`guardsim.detection.watch.lap_gains` builds both for a level).
    """
    sight = lap_sight(grid, table, states, model, view_range=view_range, dt=dt, light=light, cameras=cameras)
    return sight.dense_gains()


@jit
def _seen_counts(start: np.ndarray, tick: np.ndarray) -> np.ndarray:
    """Distinct ticks per cell (a cell's events are by tick)."""
    out = np.zeros(start.shape[0] - 1, dtype=np.int64)
    for cell in range(out.shape[0]):
        last = -1
        for event in range(start[cell], start[cell + 1]):
            if tick[event] != last:
                out[cell] += 1
                last = tick[event]
    return out


@jit
def _longest_unseen(start: np.ndarray, tick: np.ndarray, period: int) -> np.ndarray:
    out = np.empty(start.shape[0] - 1, dtype=np.int64)
    for cell in range(out.shape[0]):
        if start[cell] == start[cell + 1]:
            out[cell] = period
            continue
        first, last = tick[start[cell]], tick[start[cell + 1] - 1]
        # The run that wraps round the end of the lap, then the gaps between seen ticks.
        best = first + period - last - 1
        for event in range(start[cell] + 1, start[cell + 1]):
            gap = tick[event] - tick[event - 1] - 1
            if gap > best:
                best = gap
        out[cell] = best
    return out


@jit
def _apply(
    levels: np.ndarray,
    gains: np.ndarray,
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    event: int,
    end: int,
    phase: int,
    fall: float,
) -> tuple[int, bool]:
    """One tick at lap tick ``phase`` for the meters ``levels``: the events from ``event`` on at that tick
    are its gains (0 for the other watchers). Returns the next event and whether a meter filled."""
    for index in range(gains.shape[0]):
        gains[index] = 0.0
    while event < end and tick[event] == phase:
        gains[watcher[event]] = gain[event]
        event += 1
    filled = False
    for index in range(levels.shape[0]):
        levels[index] = meter_after(levels[index], gains[index], fall)
        if levels[index] >= DETECTED:
            filled = True
    return event, filled


@jit
def _all_empty(levels: np.ndarray) -> bool:
    # A loop, not all(): numba compiles no generator.
    for index in range(levels.shape[0]):  # noqa: SIM110
        if levels[index] != 0.0:
            return False
    return True


@jit
def _standing(
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    first: int,
    end: int,
    watchers: int,
    period: int,
    fall: float,
    entry: int,
    limit: int,
) -> int:
    """:func:`guardsim.detection.exposure._standing` on one cell's events ``first:end``: ticks a player
    entering at lap tick ``entry`` stands before a meter fills, -1 when none does within ``limit``. Ticks
    with every meter empty and no gain are skipped in one go (they leave the meters empty)."""
    levels = np.zeros(watchers)
    gains = np.zeros(watchers)
    event = first
    while event < end and tick[event] < entry:
        event += 1
    step = 0
    while step < limit:
        phase = (entry + step) % period
        if phase == 0 and step > 0:
            event = first
        if _all_empty(levels) and (event == end or tick[event] != phase):
            # Jump to the next tick with a gain (or the lap's end, where the events start again).
            following = tick[event] if event < end else period
            step += following - phase
            continue
        event, filled = _apply(levels, gains, tick, watcher, gain, event, end, phase, fall)
        if filled:
            return step + 1
        step += 1
    return -1


@jit
def _ever_detected(
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    first: int,
    end: int,
    watchers: int,
    period: int,
    fall: float,
    max_laps: int,
) -> int:
    """:func:`guardsim.detection.exposure._ever_detected` on one cell's events: 1, 0 or -1."""
    levels = np.zeros(watchers)
    before = np.zeros(watchers)
    gains = np.zeros(watchers)
    for _ in range(max_laps):
        for index in range(watchers):
            before[index] = levels[index]
        event = first
        phase = 0
        while phase < period:
            if _all_empty(levels) and (event == end or tick[event] != phase):
                phase = tick[event] if event < end else period
                continue
            event, filled = _apply(levels, gains, tick, watcher, gain, event, end, phase, fall)
            if filled:
                return 1
            phase += 1
        same = True
        for index in range(watchers):
            if levels[index] != before[index]:
                same = False
        if same:
            return 0
    return -1


@jit
def _time_to_detection(
    start: np.ndarray,
    tick: np.ndarray,
    watcher: np.ndarray,
    gain: np.ndarray,
    watchers: int,
    period: int,
    fall: float,
    traversable: np.ndarray,
    max_laps: int,
    out: np.ndarray,
) -> int:
    unsettled = 0
    for cell in range(out.shape[0]):
        first, end = start[cell], start[cell + 1]
        if not traversable[cell]:
            out[cell] = -2
            continue
        if first == end:
            out[cell] = -1
            continue
        ever = _ever_detected(tick, watcher, gain, first, end, watchers, period, fall, max_laps)
        if ever <= 0:
            out[cell] = -1
            unsettled += ever == -1
            continue
        # As the dense version: the worst entry is the shortest, over the entry ticks in some sight.
        best = -1
        last = -1
        for event in range(first, end):
            entry = tick[event]
            if entry == last:
                continue
            last = entry
            ticks = _standing(tick, watcher, gain, first, end, watchers, period, fall, entry, (max_laps + 1) * period)
            if ticks > 0 and (best < 0 or ticks < best):
                best = ticks
        out[cell] = best
    return unsettled
