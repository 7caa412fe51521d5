"""RippleFront's accelerator: the tick (look, sweep, decide, move) compiled with numba.

It advances the loop's own :class:`~guardsim.planners.base.EpisodeArrays` exactly as
:class:`guardsim.simulation.Simulation` would with :class:`~guardsim.planners.RippleFront`'s
``next_move`` (the equality is tested state by state and trace by trace), but:

- vision reads each state's cells from the shared :class:`~guardsim.vision.cache.VisionCache`, filling
  a missing state itself when the wall screen settles every ray; on a close call the compiled loop
  returns, Python (pymunk) fills the state, and the loop resumes;
- the field is updated incrementally: a sweep recomputes only the cells whose inputs changed (cells
  newly seen since the last sweep and the neighbours of cells whose D changed in the last sweep), which
  gives the same values as sweeping every cell, because any other cell would recompute to its old value.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import FAR
from guardsim.kernels.fill import FillArrays, try_fill
from guardsim.kernels.steps import greedy_step, state_of
from guardsim.planners.base import OUTCOME, TICK, UNSEEN, EpisodeArrays
from guardsim.vision.cache import VisionCache

__all__ = ["COLD_START_CELLS", "CompiledRippleFront", "compiling_pays", "is_compiled"]

#: Traversable cells up to which one episode on the plain loop (about 1 s at this size) is quicker than
#: compiling the fast path on a fresh install (about 4 s; measured by benchmarks/cold_start.py).
COLD_START_CELLS = 10_000

# Kernel returns besides the outcomes (0 covered, 1 step limit, 2 stuck).
_NEED_VISION, _PAUSED = 3, 4
_COVERED, _STEP_LIMIT, _STUCK = 0, 1, 2
# The phases of a tick: the loop returns for a missing vision state between the move and the look.
_LOOK, _DECIDE = 0, 1


class FieldState(NamedTuple):
    """The incremental field's state, kept between calls to the kernel."""

    distance: np.ndarray
    """``int32 (cells,)``: the field D (shared with the planner object)."""
    pending: np.ndarray
    """``int64 (cells,)``: the cells the next sweep recomputes (the first ``resume[1]``)."""
    next_pending: np.ndarray
    new_values: np.ndarray
    mark: np.ndarray
    """``int64 (cells,)``: the sweep stamp at which a cell was last queued."""
    resume: np.ndarray
    """``int64 (5,)``: phase, pending count, stamp, the state to fill on a return for vision, and the
    ticks left to run (negative: no limit)."""


@jit
def _advance(
    neighbours: np.ndarray,
    episode: EpisodeArrays,
    field: FieldState,
    cache_start: np.ndarray,
    cache_length: np.ndarray,
    cache_data: np.ndarray,
    used: np.ndarray,
    fill: FillArrays,
    compiled_fill: bool,
    sweeps_per_tick: int,
    limit: int,
    far: int,
) -> int:
    seen, first_seen, goal = episode.seen, episode.first_seen, episode.goal
    distance, pending, next_pending, new_values, mark = (
        field.distance, field.pending, field.next_pending, field.new_values, field.mark,
    )  # fmt: skip
    tick = episode.counters[TICK]
    unseen_left = episode.counters[UNSEEN]
    cell = episode.cells[0, tick]
    heading = episode.headings[0, tick]
    phase, n_pending, stamp, tick_budget = field.resume[0], field.resume[1], field.resume[2], field.resume[4]
    while True:
        if phase == _LOOK:
            state = state_of(cell, heading)
            length = cache_length[state]
            if length < 0 and compiled_fill:
                stored = try_fill(state, fill, cache_data, used[0], cache_start, cache_length)
                if stored >= 0:
                    used[0] += stored
                    length = stored
            if length < 0:
                field.resume[0], field.resume[1], field.resume[2], field.resume[3] = phase, n_pending, stamp, state
                field.resume[4] = tick_budget
                episode.counters[TICK], episode.counters[UNSEEN] = tick, unseen_left
                episode.cells[0, tick], episode.headings[0, tick] = cell, heading
                return _NEED_VISION
            begin = cache_start[state]
            for k in range(begin, begin + length):
                other = cache_data[k]
                if not seen[other]:
                    seen[other] = True
                    first_seen[other] = tick
                    if goal[other]:
                        unseen_left -= 1
                    if mark[other] != stamp:
                        mark[other] = stamp
                        pending[n_pending] = other
                        n_pending += 1
            episode.cells[0, tick] = cell
            episode.headings[0, tick] = heading
            episode.unseen_counts[tick] = unseen_left
            phase = _DECIDE
        outcome = -1
        if unseen_left == 0:
            outcome = _COVERED
        elif tick >= limit:
            outcome = _STEP_LIMIT
        elif tick_budget == 0:
            outcome = _PAUSED
        if outcome < 0:
            for _ in range(sweeps_per_tick):
                # Jacobi: every new value from the old field, then apply them all.
                for index in range(n_pending):
                    here = pending[index]
                    value = 0
                    if seen[here]:
                        nearest = far
                        for direction in range(4):
                            other = neighbours[here, direction]
                            if other >= 0 and distance[other] < nearest:
                                nearest = distance[other]
                        value = min(nearest + 1, far)
                    new_values[index] = value
                stamp += 1
                n_next = 0
                for index in range(n_pending):
                    here = pending[index]
                    if new_values[index] != distance[here]:
                        distance[here] = new_values[index]
                        for direction in range(4):
                            other = neighbours[here, direction]
                            if other >= 0 and mark[other] != stamp:
                                mark[other] = stamp
                                next_pending[n_next] = other
                                n_next += 1
                for index in range(n_next):
                    pending[index] = next_pending[index]
                n_pending = n_next
            best = greedy_step(distance, neighbours[cell], heading)
            if best < 0:
                outcome = _STUCK
            else:
                tick += 1
                cell = neighbours[cell, best]
                heading = best
                phase = _LOOK
                tick_budget -= 1
        if outcome >= 0:
            field.resume[0], field.resume[1], field.resume[2], field.resume[4] = phase, n_pending, stamp, tick_budget
            episode.counters[TICK], episode.counters[UNSEEN] = tick, unseen_left
            if outcome != _PAUSED:
                episode.counters[OUTCOME] = outcome
            return outcome


class CompiledRippleFront:
    """The compiled tick of one RippleFront guard seeing through a :class:`VisionCache`.

    It shares the planner's field (``distance``), so the planner may be stepped by ``next_move`` and by
    this accelerator in any mix: after a sweep it did not make, the next sweep recomputes every cell.
    """

    def __init__(self, neighbours: np.ndarray, cache: VisionCache, distance: np.ndarray, sweeps_per_tick: int) -> None:
        cells = distance.size
        self.neighbours = neighbours
        self.cache = cache
        self.sweeps_per_tick = sweeps_per_tick
        self.field = FieldState(
            distance,
            np.zeros(cells, dtype=np.int64),
            np.zeros(cells, dtype=np.int64),
            np.zeros(cells, dtype=np.int32),
            np.full(cells, -1, dtype=np.int64),
            np.array([_DECIDE, 0, 0, 0, -1], dtype=np.int64),
        )
        self._known = np.zeros(cells, dtype=bool)
        self.stale = False
        """Set when someone else swept the field: the next sweep then recomputes every cell."""

    def advance(self, episode: EpisodeArrays, limit: int, ticks: int) -> None:
        """Run up to ``ticks`` ticks (-1: to the end) of the episode from its current tick boundary."""
        field = self.field
        if self.stale:
            count = self.neighbours.shape[0]
            field.pending[:count] = np.arange(count)
            field.resume[1] = count
            field.resume[2] += 1
            self.stale = False
        else:
            # Cells seen since this accelerator last looked (by the loop's look at the start, say) must
            # enter the next sweep, as they would have had its own look seen them.
            new = np.flatnonzero(episode.seen & ~self._known)
            stamp = field.resume[2]
            queued = new[field.mark[new] != stamp]
            count = int(field.resume[1])
            field.pending[count : count + queued.size] = queued
            field.mark[queued] = stamp
            field.resume[1] = count + queued.size
        field.resume[0] = _DECIDE
        field.resume[4] = ticks
        cache = self.cache
        used = np.array([cache.used], dtype=np.int64)
        while True:
            returned = _advance(
                self.neighbours, episode, field, cache.start, cache.length, cache.data, used,
                cache.fill_arrays, cache.compiled_fill, self.sweeps_per_tick, limit, int(FAR),
            )  # fmt: skip
            cache.used = int(used[0])
            if returned != _NEED_VISION:
                break
            cache.fill(int(field.resume[3]))
            used[0] = cache.used
        self._known[:] = episode.seen


def is_compiled() -> bool:
    """Whether the compiled tick is ready without compiling: built in this process, or in numba's cache."""
    if _advance.signatures:
        return True
    try:
        # numba keeps no public way to ask; its cache index is empty (or absent) until a run has saved
        # the compiled tick for this very source.
        kernel: Any = _advance
        return bool(kernel._cache._cache_file._load_index())
    except (AttributeError, OSError):
        # A numba whose cache is laid out otherwise: assume ready, i.e. keep the fast path.
        return True


def compiling_pays(grid: CoverageGrid) -> bool:
    """Whether one RippleFront episode on ``grid`` should take the compiled tick: it is ready, or the
    grid is too large for the plain loop to beat the compiler."""
    return is_compiled() or int(grid.traversable.sum()) > COLD_START_CELLS
