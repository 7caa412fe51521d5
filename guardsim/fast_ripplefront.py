"""The fast path of a RippleFront episode: the loop, the field and the decision compiled with numba.

It produces exactly the trace of :func:`guardsim.simulation.run_episode` with the reference vision and
:class:`guardsim.planners.RippleFront` (the equality is tested state by state and trace by trace), but:

- vision reads each state's cells from the shared :class:`~guardsim.vision_cache.VisionCache`; on a
  state not yet computed the compiled loop returns, Python fills the state, and the loop resumes;
- the field is updated incrementally: a sweep recomputes only the cells whose inputs changed (cells
  newly seen since the last sweep and the neighbours of cells whose D changed in the last sweep), which
  gives the same values as sweeping every cell, because any other cell would recompute to its old value.
"""

from __future__ import annotations

import time

import numba
import numpy as np

from guardsim.planners.ripplefront import FAR
from guardsim.vision_cache import VisionCache, try_fill

__all__ = ["COVERED", "NEED_VISION", "PAUSED", "STEP_LIMIT", "STUCK", "EpisodeArrays", "run_compiled"]

COVERED, STEP_LIMIT, STUCK, NEED_VISION, PAUSED = 0, 1, 2, 3, 4

# Slots of the loop's saved state, so a return for a missing vision state can resume exactly.
_TICK, _CELL, _HEADING, _UNSEEN, _PHASE, _PENDING, _STAMP, _STATE, _USED = range(9)
_LOOK, _DECIDE = 0, 1


@numba.njit(cache=True, nogil=True)
def _advance(
    neighbours: np.ndarray,
    goal: np.ndarray,
    cache_start: np.ndarray,
    cache_length: np.ndarray,
    cache_data: np.ndarray,
    seen: np.ndarray,
    first_seen: np.ndarray,
    distance: np.ndarray,
    pending: np.ndarray,
    next_pending: np.ndarray,
    new_values: np.ndarray,
    mark: np.ndarray,
    path: np.ndarray,
    headings: np.ndarray,
    unseen_counts: np.ndarray,
    saved: np.ndarray,
    sweeps_per_tick: int,
    limit: int,
    far: int,
    tick_budget: int,
    compiled_fill: bool,
    offsets_all: np.ndarray,
    offsets_start: np.ndarray,
    traversable: np.ndarray,
    dims: np.ndarray,
    geometry: np.ndarray,
    segments: np.ndarray,
    bucket_start: np.ndarray,
    bucket_walls: np.ndarray,
    wall_stamp: np.ndarray,
    fill_candidates: np.ndarray,
    fill_targets: np.ndarray,
    fill_verdicts: np.ndarray,
) -> int:
    tick = saved[_TICK]
    cell = saved[_CELL]
    heading = saved[_HEADING]
    unseen_left = saved[_UNSEEN]
    phase = saved[_PHASE]
    n_pending = saved[_PENDING]
    stamp = saved[_STAMP]
    while True:
        if phase == _LOOK:
            state = cell * 4 + heading
            length = cache_length[state]
            if length < 0 and compiled_fill:
                stored = try_fill(
                    state, offsets_all, offsets_start, traversable, dims, geometry, segments, bucket_start,
                    bucket_walls, wall_stamp, fill_candidates, fill_targets, fill_verdicts, cache_data,
                    saved[_USED], cache_start, cache_length,
                )  # fmt: skip
                if stored >= 0:
                    saved[_USED] += stored
                    length = stored
            if length < 0:
                saved[_TICK], saved[_CELL], saved[_HEADING] = tick, cell, heading
                saved[_UNSEEN], saved[_PHASE], saved[_PENDING], saved[_STAMP] = unseen_left, phase, n_pending, stamp
                saved[_STATE] = state
                return NEED_VISION
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
            path[tick] = cell
            headings[tick] = heading
            unseen_counts[tick] = unseen_left
            phase = _DECIDE
        outcome = -1
        if unseen_left == 0:
            outcome = COVERED
        elif tick >= limit:
            outcome = STEP_LIMIT
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
            best = -1
            best_distance = 0
            for choice in range(5):
                direction = heading if choice == 0 else choice - 1
                other = neighbours[cell, direction]
                if other >= 0 and (best < 0 or distance[other] < best_distance):
                    best = direction
                    best_distance = distance[other]
            if best < 0:
                outcome = STUCK
            else:
                tick += 1
                cell = neighbours[cell, best]
                heading = best
                phase = _LOOK
                tick_budget -= 1
                if tick_budget == 0:
                    outcome = PAUSED
        if outcome >= 0:
            saved[_TICK], saved[_CELL], saved[_HEADING] = tick, cell, heading
            saved[_UNSEEN], saved[_PHASE], saved[_PENDING], saved[_STAMP] = unseen_left, phase, n_pending, stamp
            return outcome


class EpisodeArrays:
    """What the compiled loop leaves behind; turned into a Trace by the simulation."""

    def __init__(
        self, path: np.ndarray, headings: np.ndarray, unseen_counts: np.ndarray, first_seen: np.ndarray, outcome: int
    ) -> None:
        self.path = path
        """Flat cell index per tick."""
        self.headings = headings
        """Heading number per tick."""
        self.unseen_counts = unseen_counts
        """Reachable cells still unseen, per tick."""
        self.first_seen = first_seen
        """Tick each cell was first seen, -1 if never (flat)."""
        self.outcome = outcome
        """One of COVERED, STEP_LIMIT, STUCK."""


def run_compiled(
    cache: VisionCache,
    neighbours: np.ndarray,
    goal: np.ndarray,
    start_cell: int,
    heading: int,
    *,
    sweeps_per_tick: int,
    limit: int,
    tick_seconds: list[float] | None = None,
) -> EpisodeArrays:
    """Run one RippleFront episode with the compiled loop, filling vision states as it meets them.

    With ``tick_seconds``, the loop returns after every tick and the wall time of each tick (vision,
    field and decision, vision fills included) is appended to it: for benchmarks only, as the extra
    calls cost a few microseconds each.
    """
    budget = 1 if tick_seconds is not None else -1
    began = time.perf_counter()
    cells = goal.size
    seen = np.zeros(cells, dtype=np.bool_)
    first_seen = np.full(cells, -1, dtype=np.int64)
    distance = np.zeros(cells, dtype=np.int32)
    pending = np.zeros(cells, dtype=np.int64)
    next_pending = np.zeros(cells, dtype=np.int64)
    new_values = np.zeros(cells, dtype=np.int32)
    mark = np.full(cells, -1, dtype=np.int64)
    path = np.zeros(limit + 1, dtype=np.int64)
    headings = np.zeros(limit + 1, dtype=np.int64)
    unseen_counts = np.zeros(limit + 1, dtype=np.int64)
    saved = np.zeros(9, dtype=np.int64)
    saved[_CELL], saved[_HEADING], saved[_UNSEEN] = start_cell, heading, int(goal.sum())
    while True:
        saved[_USED] = cache.used
        outcome = _advance(
            neighbours,
            goal,
            cache.start,
            cache.length,
            cache.data,
            seen,
            first_seen,
            distance,
            pending,
            next_pending,
            new_values,
            mark,
            path,
            headings,
            unseen_counts,
            saved,
            sweeps_per_tick,
            limit,
            int(FAR),
            budget,
            cache.compiled_fill,
            *cache.fill_arrays,
        )
        cache.used = int(saved[_USED])
        if outcome == NEED_VISION:
            cache.fill(int(saved[_STATE]))
            continue
        if tick_seconds is not None:
            now = time.perf_counter()
            tick_seconds.append(now - began)
            began = now
        if outcome != PAUSED:
            break
    ticks = int(saved[_TICK]) + 1
    return EpisodeArrays(path[:ticks], headings[:ticks], unseen_counts[:ticks], first_seen, outcome)
