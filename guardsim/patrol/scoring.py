"""Idleness: how long each cell goes unwatched under a patrol.

A cell's idleness at a tick is the ticks since a guard last saw it (0 at a tick it is seen). Its worst
gap is the most ticks in a row it goes unseen, which is its largest idleness. The level's worst idleness
is the largest worst gap over the goal cells, its mean idleness the idleness averaged over goal cells and
ticks. A repeating patrol is scored exactly, over one lap taken cyclically (its steady state); a patrol
that does not repeat is scored over the ticks after a warm-up, every cell counting as seen at tick 0.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from guardsim.errors import ArgumentError, LimitError
from guardsim.kernels.compiler import jit
from guardsim.patrol.model import Patrol
from guardsim.vision.table import ViewTable

__all__ = ["MAX_TIMELINE_BYTES", "NEVER", "PatrolScore", "score_patrol", "score_rank", "seen_timeline"]

#: A cell's worst gap when a repeating patrol never sees it: it stays unwatched for ever.
NEVER = -1
#: Most bytes a seen timeline may take (one a tick and cell): Berlin_1_256's one-guard lap takes 578 MB,
#: duskwood's 22 784-tick lap 6 GB. The scores, the sneak check and alert's sneaking intruder read the
#: lap's sight sparse instead (:class:`guardsim.detection.sight.LapSight`); the pages and GIFs of a lap
#: still build one.
MAX_TIMELINE_BYTES = 2 * 2**30


class PatrolScore(NamedTuple):
    """How well a patrol watches the goal."""

    worst_gap: np.ndarray
    """``int64 (cells,)``: each goal cell's most ticks in a row unseen; :data:`NEVER` for a cell a
    repeating patrol never sees; -2 outside the goal."""
    worst_idleness: int | None
    """The largest worst gap over the goal; ``None`` when some goal cell is never seen."""
    mean_idleness: float | None
    """Idleness averaged over goal cells and the ticks scored; ``None`` when some goal cell is never seen."""
    never_seen: int
    """Goal cells a repeating patrol never sees."""
    ticks_scored: int
    """Ticks the figures are taken over (the period for a repeating patrol)."""


@jit
def _fill_timeline(sight_start: np.ndarray, sight: np.ndarray, states: np.ndarray, out: np.ndarray) -> None:
    for guard in range(states.shape[0]):
        for tick in range(states.shape[1]):
            state = states[guard, tick]
            for index in range(sight_start[state], sight_start[state + 1]):
                out[tick, sight[index]] = True


def seen_timeline(table: ViewTable, states: np.ndarray, cells: int) -> np.ndarray:
    """``bool (ticks, cells)``: whether any guard sees each cell at each tick of ``states`` (guards, ticks).

    Raises
    ------
    LimitError
        When it would take more than :data:`MAX_TIMELINE_BYTES`.
    """
    states = np.ascontiguousarray(states, dtype=np.int64)
    needed = int(states.shape[1]) * int(cells)
    if needed > MAX_TIMELINE_BYTES:
        raise LimitError(
            f"a seen timeline of {states.shape[1]} ticks x {cells} cells would take {-(-needed // 2**20)} MB, over "
            f"the limit of {MAX_TIMELINE_BYTES // 2**20} MB (guardsim.patrol.scoring.MAX_TIMELINE_BYTES)"
        )
    out = np.zeros((states.shape[1], cells), dtype=np.bool_)
    _fill_timeline(table.sight_start, table.sight, states, out)
    return out


@jit
def _idleness(
    sight_start: np.ndarray,
    sight: np.ndarray,
    states: np.ndarray,
    goal: np.ndarray,
    warmup: int,
    total: int,
    worst: np.ndarray,
    last: np.ndarray,
) -> int:
    """Walk ``total`` ticks of ``states`` (guards, ticks; repeated), scoring from ``warmup`` on; returns the
    idleness summed over goal cells and scored ticks, and fills ``worst`` (each cell's largest idleness).

    Every cell counts as seen at tick 0. A cell's idleness is settled when it is next seen (and at the
    end), a whole run of unseen ticks at once, so the work is the sights looked up, not ticks x cells.
    """
    period = states.shape[1]
    summed = 0
    for cell in range(last.shape[0]):
        last[cell] = 0
    for tick in range(total):
        row = tick % period
        for guard in range(states.shape[0]):
            state = states[guard, row]
            for index in range(sight_start[state], sight_start[state + 1]):
                cell = sight[index]
                if last[cell] != tick:
                    if goal[cell]:
                        summed += _settle(cell, last[cell], tick - 1, warmup, worst)
                    last[cell] = tick
    for cell in range(last.shape[0]):
        if goal[cell]:
            summed += _settle(cell, last[cell], total - 1, warmup, worst)
    return summed


@jit
def _settle(cell: int, seen: int, high: int, warmup: int, worst: np.ndarray) -> int:
    """Ticks ``seen + 1 .. high`` unseen, idle 1, 2, ...: their idleness summed (those from ``warmup`` on),
    and the cell's worst raised to the last of them."""
    low = max(seen + 1, warmup)
    if high < low:
        return 0
    if high - seen > worst[cell]:
        worst[cell] = high - seen
    return (low - seen + high - seen) * (high - low + 1) // 2


def score_timeline(timeline: np.ndarray, goal: np.ndarray, *, periodic: bool, warmup: int = 0) -> PatrolScore:
    """Score a seen timeline (see :func:`seen_timeline`); ``periodic``: it is one lap, repeated for ever."""
    # A timeline is a view table whose tick t is a state seeing the cells seen at t, walked by one guard.
    timeline = np.asarray(timeline, dtype=bool)
    ticks, cells = np.nonzero(timeline)
    sight_start = np.zeros(timeline.shape[0] + 1, dtype=np.int64)
    np.cumsum(np.bincount(ticks, minlength=timeline.shape[0]), out=sight_start[1:])
    steps = np.arange(timeline.shape[0], dtype=np.int64)[None, :]
    return _score(sight_start, cells.astype(np.int32), steps, goal, periodic=periodic, warmup=warmup)


def _score(
    sight_start: np.ndarray, sight: np.ndarray, states: np.ndarray, goal: np.ndarray, *, periodic: bool, warmup: int
) -> PatrolScore:
    goal = np.ascontiguousarray(goal, dtype=np.bool_)
    states = np.ascontiguousarray(states, dtype=np.int64)
    ticks = states.shape[1]
    worst = np.zeros(goal.size, dtype=np.int64)
    last = np.empty(goal.size, dtype=np.int64)
    if periodic:
        # After one lap every cell seen in the lap has been seen, so the second lap is the steady state.
        summed = _idleness(sight_start, sight, states, goal, ticks, 2 * ticks, worst, last)
        never = goal & (last < ticks)
        worst[never] = NEVER
        scored = ticks
    else:
        if not 0 <= warmup < ticks:
            raise ArgumentError(f"warm-up of {warmup} ticks leaves nothing of {ticks} ticks to score")
        summed = _idleness(sight_start, sight, states, goal, warmup, ticks, worst, last)
        never = np.zeros_like(goal)
        scored = ticks - warmup
    worst[~goal] = -2
    count = int(never.sum())
    cells = int(goal.sum())
    if count:
        return PatrolScore(worst, None, None, count, scored)
    return PatrolScore(
        worst,
        int(worst[goal].max(initial=0)),
        float(summed / (cells * scored)) if cells else 0.0,
        0,
        scored,
    )


def score_patrol(table: ViewTable, patrol: Patrol, goal: np.ndarray, *, warmup: int = 0) -> PatrolScore:
    """Score a patrol: exactly over a lap when it repeats, after ``warmup`` ticks when it does not.

    Examples
    --------
    A post that sees cells 0 and 1 from state 0, and a two-cell goal: never unwatched.

    >>> table = ViewTable(np.array([0, 2, 2, 2, 2]), np.array([0, 1], dtype=np.int32), np.zeros(3, dtype=np.int64),
    ...                   np.zeros(0, dtype=np.int32), np.full(4, -1))
    >>> score = score_patrol(table, Patrol(np.array([[0]]), 1, "loop"), np.array([True, True]))
    >>> score.worst_idleness, score.mean_idleness
    (0, 0.0)
    """
    return _score(
        table.sight_start, table.sight, patrol.states, goal, periodic=patrol.period is not None, warmup=warmup
    )


def score_rank(score: PatrolScore) -> tuple[float, float]:
    """Sort key of scores, best first: lower worst idleness, then lower mean (never seen: worst of all)."""
    worst = np.inf if score.worst_idleness is None else float(score.worst_idleness)
    return worst, np.inf if score.mean_idleness is None else score.mean_idleness
