"""Shorter covering walks by large-neighbourhood search: remove some stops of a walk, put stops back
where they cost least, drop the stops nothing needs, keep the result by simulated annealing.

A walk is a list of *stops* (positions, the start first) joined by shortest paths; it sees what every
position along it sees. One iteration removes stops (a run of consecutive ones, some drawn anywhere, or
those nearest one drawn), then while some goal cell is unseen inserts, for the unseen cell whose
cheapest insertion is dearest, the watcher of it and the place in the walk that lengthen the walk least
(farthest insertion, as in tour construction; each iteration looks at a drawn share, 20 to 100 %, of
the unseen cells only, which varies the repairs: on the arena from (24, 24) at range 8, 150 steps after
2 000 iterations against 152 looking at every cell), then removes every stop whose removal leaves
every cell seen, most steps saved first. The new walk replaces the current one when it is no longer,
or with probability ``exp(-extra steps / temperature)``, the temperature falling linearly to zero over
the iterations. The exact search's first walks are myopic on large open levels; on issue 28's hard
instances this takes room-32-32-4 from (3, 0) from 252 steps to 197, the arena from (3, 1) at range 8
from 352 to 156 (docs/optimum.md).

Every random choice comes from a seeded :class:`numpy.random.Generator`; the work is counted in
iterations, so the walk is the same on every machine.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.kernels.compiler import jit
from guardsim.kernels.csr import watcher_csr
from guardsim.kernels.distances import distance_fields
from guardsim.search.graph import SearchGraph

__all__ = ["IMPROVE_MAX_POSITIONS", "improve_route"]

#: Most positions for which the search keeps all-pairs steps (``int32``; 64 MB at this size).
IMPROVE_MAX_POSITIONS = 4096
#: Most stops one iteration removes.
_MOST_REMOVED = 10
#: Iterations between two calls of ``improve_route``'s ``report`` (about 0.1-0.6 s).
REPORT_EVERY = 100
#: Temperature of the first iteration, in steps: a walk 3 steps longer is kept with probability 1/e.
_FIRST_TEMPERATURE = 3.0


@jit
def _next_step(successors: np.ndarray, steps: np.ndarray, here: int, target: int) -> int:
    """The first move (in direction order) of a shortest path from ``here`` to ``target``."""
    need = steps[here, target] - 1
    for direction in range(4):
        there = successors[here, direction]
        if there >= 0 and steps[there, target] == need:
            return there
    return -1


@jit
def _look(
    views: np.ndarray,
    successors: np.ndarray,
    steps: np.ndarray,
    stops: np.ndarray,
    count: int,
    skip: int,
    seen: np.ndarray,
) -> None:
    """``seen``: what the walk through ``stops[:count]`` (without stop ``skip``, -1 for none) sees."""
    words = seen.shape[0]
    for word in range(words):
        seen[word] = views[stops[0], word]
    here = stops[0]
    for index in range(1, count):
        if index == skip:
            continue
        target = stops[index]
        while here != target:
            here = _next_step(successors, steps, here, target)
            for word in range(words):
                seen[word] |= views[here, word]


@jit
def _sees_all(seen: np.ndarray, full: np.ndarray) -> bool:
    same = True
    for word in range(full.shape[0]):
        if seen[word] != full[word]:
            same = False
            break
    return same


@jit
def _length(steps: np.ndarray, stops: np.ndarray, count: int) -> int:
    total = 0
    for index in range(1, count):
        total += steps[stops[index - 1], stops[index]]
    return total


@jit
def _insert(stops: np.ndarray, count: int, place: int, position: int) -> int:
    for index in range(count, place, -1):
        stops[index] = stops[index - 1]
    stops[place] = position
    return count + 1


@jit
def _repair(
    views: np.ndarray,
    full: np.ndarray,
    successors: np.ndarray,
    steps: np.ndarray,
    watch_start: np.ndarray,
    watchers: np.ndarray,
    stops: np.ndarray,
    count: int,
    seen: np.ndarray,
    noise: np.ndarray,
    share: float,
) -> int:
    """Insert stops until the walk sees every goal cell (farthest insertion among the unseen cells whose
    ``noise`` is below ``share``, all when none is); returns the stop count, -1 if some unseen cell has
    no watcher."""
    goal = watch_start.shape[0] - 1
    positions = steps.shape[0]
    # What inserting each position costs and where depends on the walk only, not on the cell it is for.
    cost = np.empty(positions, dtype=np.int64)
    where = np.empty(positions, dtype=np.int64)
    while True:
        _look(views, successors, steps, stops, count, -1, seen)
        if _sees_all(seen, full):
            return count
        last = stops[count - 1]
        for position in range(positions):
            cost[position], where[position] = steps[last, position], count
            for index in range(count - 1):
                before, after = stops[index], stops[index + 1]
                extra = steps[before, position] + steps[position, after] - steps[before, after]
                if extra < cost[position]:
                    cost[position], where[position] = extra, index + 1
        dearest, dearest_place, dearest_position = -1, -1, -1
        for bit in range(goal):
            if (seen[bit >> 6] >> np.uint64(bit & 63)) & np.uint64(1):
                continue
            if noise[bit] >= share and dearest >= 0:
                continue
            cheapest, position = -1, -1
            for k in range(watch_start[bit], watch_start[bit + 1]):
                watcher = watchers[k]
                if cheapest < 0 or cost[watcher] < cheapest:
                    cheapest, position = cost[watcher], watcher
            if cheapest > dearest:
                dearest, dearest_place, dearest_position = cheapest, where[position], position
        if dearest_position < 0:
            return -1  # the unseen cells looked at are seen from nowhere
        count = _insert(stops, count, dearest_place, dearest_position)


@jit
def _drop_spare(
    views: np.ndarray,
    full: np.ndarray,
    successors: np.ndarray,
    steps: np.ndarray,
    stops: np.ndarray,
    count: int,
    seen: np.ndarray,
) -> int:
    """Remove stops whose removal leaves every cell seen, most steps saved first; returns the stop count."""
    saving = np.empty(stops.shape[0], dtype=np.int64)
    tried = np.empty(stops.shape[0], dtype=np.bool_)
    dropped = True
    while dropped:
        dropped = False
        for index in range(1, count):
            before = stops[index - 1]
            saving[index] = steps[before, stops[index]]
            if index + 1 < count:
                after = stops[index + 1]
                saving[index] += steps[stops[index], after] - steps[before, after]
            tried[index] = False
        for _ in range(1, count):
            best = -1
            for index in range(1, count):
                if not tried[index] and (best < 0 or saving[index] > saving[best]):
                    best = index
            tried[best] = True
            _look(views, successors, steps, stops, count, best, seen)
            if _sees_all(seen, full):
                for index in range(best, count - 1):
                    stops[index] = stops[index + 1]
                count -= 1
                dropped = True
                break
    return count


@jit
def _rebuild(
    views: np.ndarray,
    full: np.ndarray,
    successors: np.ndarray,
    steps: np.ndarray,
    watch_start: np.ndarray,
    watchers: np.ndarray,
    stops: np.ndarray,
    count: int,
    seen: np.ndarray,
    noise: np.ndarray,
    share: float,
) -> tuple[int, int]:
    """Repair (``noise``, ``share``: as :func:`_repair`), then drop spare stops: the stop count and the
    walk's steps (-1, -1 if the repair cannot see every cell)."""
    count = _repair(views, full, successors, steps, watch_start, watchers, stops, count, seen, noise, share)
    if count < 0:
        return -1, -1
    count = _drop_spare(views, full, successors, steps, stops, count, seen)
    return count, _length(steps, stops, count)


@jit
def _walk(successors: np.ndarray, steps: np.ndarray, stops: np.ndarray, count: int) -> np.ndarray:
    """Every position of the walk through ``stops[:count]``."""
    walk = np.empty(_length(steps, stops, count) + 1, dtype=np.int64)
    walk[0] = stops[0]
    here, length = stops[0], 1
    for index in range(1, count):
        while here != stops[index]:
            here = _next_step(successors, steps, here, stops[index])
            walk[length] = here
            length += 1
    return walk


def _removed(rng: np.random.Generator, stops: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Which stops (never the start) one iteration removes, as a mask."""
    count = stops.size
    remove = np.zeros(count, dtype=bool)
    if count < 2:
        return remove
    k = int(rng.integers(1, min(_MOST_REMOVED, count - 1) + 1))
    kind = int(rng.integers(3))
    if kind == 0:  # a run of consecutive stops
        first = int(rng.integers(1, count - k + 1))
        remove[first : first + k] = True
    elif kind == 1:  # stops drawn anywhere
        remove[1 + rng.choice(count - 1, size=k, replace=False)] = True
    else:  # the stops nearest a drawn one
        centre = stops[int(rng.integers(1, count))]
        nearest = np.argsort(steps[centre, stops[1:]], kind="stable")[:k]
        remove[1 + nearest] = True
    return remove


def improve_route(
    graph: SearchGraph,
    route: np.ndarray,
    iterations: int,
    rng: np.random.Generator,
    *,
    deadline: float | None = None,
    report: Callable[[int], None] | None = None,
) -> tuple[np.ndarray, int]:
    """A covering walk at most as long as ``route``'s, by ``iterations`` of large-neighbourhood search.

    Parameters
    ----------
    graph
        The search graph (at most :data:`IMPROVE_MAX_POSITIONS` positions).
    route
        Positions of a covering walk (the start first), joined by shortest paths: macro moves or every step.
    iterations
        Iterations to run (the work; the result depends on it, not on the machine).
    rng
        Every random choice.
    deadline
        ``time.perf_counter()`` after which no further iteration starts.
    report
        Called with the best walk's steps every :data:`REPORT_EVERY` iterations (a caller's progress).

    Returns
    -------
    tuple
        Every position of the best walk found (the start first) and its steps.
    """
    if graph.positions > IMPROVE_MAX_POSITIONS:
        raise ArgumentError(f"improve_route keeps all-pairs steps: at most {IMPROVE_MAX_POSITIONS} positions")
    successors, views, full = graph.successors, graph.views, graph.full
    steps = distance_fields(successors, np.arange(graph.positions, dtype=np.int64))
    watch_start, watchers = watcher_csr(views, int(graph.goal_cells.size))
    room = int(route.size + graph.goal_cells.size + 1)
    seen = np.empty_like(full)
    work = np.empty(room, dtype=np.int64)
    work[: route.size] = route
    noise = np.zeros(graph.goal_cells.size)
    count, length = _rebuild(
        views, full, successors, steps, watch_start, watchers, work, int(route.size), seen, noise, 1.0
    )
    if count < 0:
        raise ArgumentError("some goal cell is seen from no position reachable from the start")
    current = work[:count].copy()
    current_length = length
    best, best_length = current.copy(), length
    for iteration in range(iterations):
        if deadline is not None and time.perf_counter() > deadline:
            break
        if report is not None and iteration % REPORT_EVERY == 0:
            report(best_length)
        kept = current[~_removed(rng, current, steps)]
        work[: kept.size] = kept
        noise = rng.random(graph.goal_cells.size)
        share = float(rng.uniform(0.2, 1.0))
        count, length = _rebuild(
            views, full, successors, steps, watch_start, watchers, work, int(kept.size), seen, noise, share
        )
        temperature = _FIRST_TEMPERATURE * (1.0 - iteration / iterations)
        worse = length - current_length
        if worse <= 0 or (temperature > 0 and rng.random() < np.exp(-worse / temperature)):
            current, current_length = work[:count].copy(), length
            if length < best_length:
                best, best_length = current.copy(), length
    return _walk(successors, steps, best, int(best.size)), int(best_length)
