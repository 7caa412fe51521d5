"""Polishing a one-guard route by simulating its walk: local search over the viewpoints, ticks as the cost.

Routing viewpoints by step counts between them misjudges what the walk sees on the way; a viewpoint
one cell over, facing elsewhere, or left out may let the walk cover the level sooner. This tries such
changes one at a time, each judged by walking the changed route with the loop's own rule
(:func:`guardsim.kernels.walk.team_walk`), and keeps any that ends the walk sooner (first
improvement, sweeping the route from its head, again while a sweep helps).

The changes to the viewpoint at index ``j`` of the route: leave it out; turn it to each other heading;
move it 1 to ``reach`` cells in each direction, keeping its heading or facing the way it moved; swap
it with the next one. The walk before the tick its route first reached index ``j`` cannot change, so
each trial resumes there from a copy of what had been seen by then (half the walk, on average); a
trial stops as soon as it can no longer end sooner. The budget is a number of trials, and of ticks
walked by them (so that the long walks of a big level do not multiply its cost), so the result depends
on nothing but the inputs.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.distances import FAR
from guardsim.kernels.states import cell_of_state, heading_of_state, state_of
from guardsim.kernels.walk import WalkLog, WalkTeam, look_along, team_walk
from guardsim.vision.table import ViewTable

__all__ = ["POLISH_REACH", "POLISH_TICKS", "polish_route"]

#: Most cells a viewpoint is moved in one change.
POLISH_REACH = 6
#: Most ticks the trials of one polish walk, summed (a trial is charged the ticks it may walk, and
#: runs only if they fit): about 0.2 s of walking. 1000 trials on a 60 x 60 level walk at most 400 000.
POLISH_TICKS = 2_000_000


def polish_route(
    table: ViewTable,
    neighbours: np.ndarray,
    goal: np.ndarray,
    seen: np.ndarray,
    start: tuple[int, int],
    route: np.ndarray,
    *,
    limit: int,
    trials: int,
    reach: int = POLISH_REACH,
    max_ticks: int = POLISH_TICKS,
) -> tuple[np.ndarray, int]:
    """A route whose walk from ``start`` covers the goal in fewer ticks, and those ticks.

    Parameters
    ----------
    table, neighbours, goal, seen
        As :func:`~guardsim.planners.route_walk.walk_routes` takes them.
    start
        The guard's ``(cell, heading)``.
    route
        State numbers of its viewpoints, in order; its walk must cover the goal within ``limit`` ticks.
    limit
        Most ticks of a walk.
    trials
        Most changed routes walked (the search's budget).
    reach
        Most cells a viewpoint moves in one change.
    max_ticks
        Most ticks the trials walk, summed (the budget's other half).

    Returns the best route found (``route`` itself when no change helped) and its walk's ticks, or
    ``(route, -1)`` when ``route``'s walk does not cover the goal.
    """
    cell, heading = start
    best, steps = _polish(
        np.ascontiguousarray(neighbours, dtype=np.int64),
        table,
        np.ascontiguousarray(goal, dtype=np.bool_),
        np.ascontiguousarray(seen, dtype=np.bool_),
        int(cell),
        int(heading),
        np.ascontiguousarray(route, dtype=np.int64),
        int(limit),
        int(trials),
        int(reach),
        int(max_ticks),
        int(FAR),
    )
    return best, int(steps)


def _resume(
    neighbours: np.ndarray,
    table: ViewTable,
    goal: np.ndarray,
    seen: np.ndarray,
    cell: int,
    heading: int,
    route: np.ndarray,
    limit: int,
    far: int,
    log: WalkLog,
) -> int:
    """Ticks of one guard's walk along ``route`` from this state (``seen`` changes), or -1 when it does
    not cover the goal within ``limit`` ticks."""
    team = WalkTeam(
        np.array([cell], dtype=np.int64),
        np.array([heading], dtype=np.int64),
        route.reshape(1, route.size).copy() if route.size else np.full((1, 1), -1, dtype=np.int64),
        np.array([route.size], dtype=np.int64),
    )
    log.visit_count[0] = 0
    log.reached[0, :] = -1
    ticks = int(team_walk(neighbours, table, goal, seen, team, int(limit), far, log))
    return -1 if bool((goal & ~seen).any()) else ticks


def _change(
    route: np.ndarray, index: int, choice: int, neighbours: np.ndarray, entry: np.ndarray, reach: int, out: np.ndarray
) -> int:
    """Write the route from ``index`` on, with change number ``choice`` made there, into ``out``; its
    length, or -1 when that change does not apply (a wall in the way, a state no step enters, no change)."""
    size = route.size
    state = int(route[index])
    cell, heading = cell_of_state(state), heading_of_state(state)
    tail = route[index + 1 :]
    if choice == 0:
        out[: tail.size] = tail
        return int(tail.size)
    choice -= 1
    if choice < 3:
        changed = state_of(cell, (heading + 1 + choice) % 4)
    else:
        choice -= 3
        if choice < 8 * reach:
            steps, rest = choice // 8 + 1, choice % 8
            direction, turn = rest // 2, rest % 2
            other = cell
            for _ in range(steps):
                other = int(neighbours[other, direction])
                if other < 0:
                    return -1
            if turn == 1 and direction == heading:
                return -1
            changed = state_of(other, direction if turn == 1 else heading)
        elif choice == 8 * reach and index + 1 < size:
            out[0] = route[index + 1]
            out[1] = state
            out[2 : tail.size + 1] = tail[1:]
            return int(tail.size) + 1
        else:
            return -1
    if entry[changed] < 0:
        return -1
    out[0] = changed
    out[1 : tail.size + 1] = tail
    return int(tail.size) + 1


def _polish(
    neighbours: np.ndarray,
    table: ViewTable,
    goal: np.ndarray,
    seen: np.ndarray,
    cell: int,
    heading: int,
    route: np.ndarray,
    limit: int,
    trials: int,
    reach: int,
    max_ticks: int,
    far: int,
) -> tuple[np.ndarray, int]:
    # Plain Python around the compiled walk: a trial is one compiled call, so compiling this loop (and
    # its chain of callers above ``team_walk``, about 3.5 s on first use) would buy nothing.
    size = route.size
    longest = size + 1
    moves = np.full((1, limit), -1, dtype=np.int64)
    path = np.zeros((1, limit + 1), dtype=np.int64)
    facing = np.zeros((1, limit + 1), dtype=np.int64)
    visits = np.zeros((1, limit), dtype=np.int64)
    reached = np.full((1, longest), -1, dtype=np.int64)
    log = WalkLog(moves, path, facing, visits, np.zeros(1, dtype=np.int64), reached)
    # The current route's walk: cells, headings and the tick each index was first reached.
    base_path = np.zeros(limit + 1, dtype=np.int64)
    base_facing = np.zeros(limit + 1, dtype=np.int64)
    base_reached = np.full(longest, -1, dtype=np.int64)
    trial_seen = seen.copy()
    best = _resume(neighbours, table, goal, trial_seen, cell, heading, route, limit, far, log)
    if best < 0:
        return route, -1
    base_path[: best + 1] = path[0, : best + 1]
    base_facing[: best + 1] = facing[0, : best + 1]
    base_reached[:size] = reached[0, :size]
    route = route.copy()
    changed = np.empty(longest, dtype=np.int64)
    choices = 1 + 3 + 8 * reach + 1
    used = walked = 0
    improved = True
    while improved and used < trials and walked < max_ticks:
        improved = False
        # What was seen when the current walk reached the index being changed, walked forward index by index.
        here_seen, here_tick = seen.copy(), 0
        index = 0
        while index < route.size and used < trials and walked < max_ticks:
            tick = int(base_reached[index])
            if tick < 0:
                break
            if here_tick < tick:
                look_along(table, goal, here_seen, base_path, base_facing, here_tick + 1, tick + 1)
                here_tick = tick
            room = best - tick - 1
            for choice in range(choices):
                if room <= 0 or used >= trials or walked + room > max_ticks:
                    break
                length = _change(route, index, choice, neighbours, table.entry, reach, changed)
                if length < 0:
                    continue
                used += 1
                walked += room
                trial_seen[:] = here_seen
                ticks = _resume(
                    neighbours, table, goal, trial_seen,
                    int(base_path[tick]), int(base_facing[tick]), changed[:length], room, far, log,
                )  # fmt: skip
                if ticks < 0:
                    continue
                best = tick + ticks
                base_path[tick : tick + ticks + 1] = path[0, : ticks + 1]
                base_facing[tick : tick + ticks + 1] = facing[0, : ticks + 1]
                base_reached[index:] = -1
                for later in range(length):
                    if reached[0, later] >= 0:
                        base_reached[index + later] = tick + reached[0, later]
                route = np.concatenate((route[:index], changed[:length].copy()))
                improved = True
                break
            index += 1
    return route, best
