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

from guardsim.kernels.compiler import jit
from guardsim.patrol.model import Patrol
from guardsim.vision.table import ViewTable

__all__ = ["NEVER", "PatrolScore", "score_patrol", "score_rank", "seen_timeline"]

#: A cell's worst gap when a repeating patrol never sees it: it stays unwatched for ever.
NEVER = -1


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
    """``bool (ticks, cells)``: whether any guard sees each cell at each tick of ``states`` (guards, ticks)."""
    states = np.ascontiguousarray(states, dtype=np.int64)
    out = np.zeros((states.shape[1], cells), dtype=np.bool_)
    _fill_timeline(table.sight_start, table.sight, states, out)
    return out


@jit
def _idleness(timeline: np.ndarray, goal: np.ndarray, warmup: int, total: int, worst: np.ndarray) -> float:
    """Walk ``total`` ticks of ``timeline`` (repeated), scoring from ``warmup`` on; returns the idleness sum."""
    period = timeline.shape[0]
    cells = timeline.shape[1]
    last = np.zeros(cells, dtype=np.int64)
    summed = 0.0
    for tick in range(total):
        row = tick % period
        for cell in range(cells):
            if timeline[row, cell]:
                last[cell] = tick
            if tick >= warmup and goal[cell]:
                idle = tick - last[cell]
                summed += idle
                if idle > worst[cell]:
                    worst[cell] = idle
    return summed


def score_timeline(timeline: np.ndarray, goal: np.ndarray, *, periodic: bool, warmup: int = 0) -> PatrolScore:
    """Score a seen timeline (see :func:`seen_timeline`); ``periodic``: it is one lap, repeated for ever."""
    goal = np.ascontiguousarray(goal, dtype=np.bool_)
    ticks = timeline.shape[0]
    worst = np.zeros(goal.size, dtype=np.int64)
    if periodic:
        # After one lap every cell seen in the lap has been seen, so the second lap is the steady state.
        summed = _idleness(timeline, goal, ticks, 2 * ticks, worst)
        never = goal & ~timeline.any(axis=0)
        worst[never] = NEVER
        scored = ticks
    else:
        if not 0 <= warmup < ticks:
            raise ValueError(f"warm-up of {warmup} ticks leaves nothing of {ticks} ticks to score")
        summed = _idleness(timeline, goal, warmup, ticks, worst)
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
    timeline = seen_timeline(table, patrol.states, goal.size)
    return score_timeline(timeline, goal, periodic=patrol.period is not None, warmup=warmup)


def score_rank(score: PatrolScore) -> tuple[float, float]:
    """Sort key of scores, best first: lower worst idleness, then lower mean (never seen: worst of all)."""
    worst = np.inf if score.worst_idleness is None else float(score.worst_idleness)
    return worst, np.inf if score.mean_idleness is None else score.mean_idleness
