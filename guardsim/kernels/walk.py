"""Walking viewpoint routes ahead of time: the whole team's episode, simulated with the level's view table.

The rule each guard follows, every tick, all guards deciding on the same state and then moving at once
(as :class:`guardsim.simulation.Simulation` does):

1. drop the head of its route while that viewpoint would see no unseen goal cell;
2. its target is the head; with the route done, the nearest state that would see an unseen goal cell
   (the frontier rule, :func:`guardsim.planners.frontier.nearest_frontier`); with none, it stays;
3. standing on the target's entry cell it steps into the target; otherwise it steps down the
   breadth-first field toward the entry cell, choosing among equally short steps the one whose
   arrival state would see the most unseen goal cells (ties: keep the heading, then right, down,
   left, up).

The view table gives exactly the cells the loop's vision would, so the simulated walk is the walk the
loop will see, tick for tick.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import fill_distances, spread
from guardsim.kernels.steps import greedy_step, heading_of_state, state_of

if TYPE_CHECKING:
    from guardsim.vision.table import ViewTable

__all__ = ["WalkLog", "WalkTeam", "descent", "look", "look_along", "team_walk"]


class WalkTeam(NamedTuple):
    """The team a compiled walk starts from: each guard's cell, heading and route."""

    cells: np.ndarray
    """``int64 (guards,)``: flat cells, moved in place."""
    headings: np.ndarray
    """``int64 (guards,)``: heading numbers, turned in place."""
    routes: np.ndarray
    """``int64 (guards, longest)``: each guard's viewpoint states, padded with -1."""
    lengths: np.ndarray
    """``int64 (guards,)``: each route's length."""


class WalkLog(NamedTuple):
    """What a compiled walk writes: moves, cells and headings per tick, each guard's arrivals, and the
    tick each guard's route first reached each of its indices (left alone for indices never reached)."""

    moves: np.ndarray
    path: np.ndarray
    facing: np.ndarray
    visits: np.ndarray
    visit_count: np.ndarray
    reached: np.ndarray


@jit
def _fill_toward(
    neighbours: np.ndarray, source: int, stop: int, far: int, distance: np.ndarray, queue: np.ndarray, filled: int
) -> int:
    """Breadth-first steps to ``source``, ``far`` elsewhere, filled only until ``stop`` is reached.

    A guard at ``stop`` steps down this field to ``source`` exactly as down the full one: when ``stop``
    (at ``d`` steps) is reached every cell nearer than ``d`` has its distance, and the cells left at
    ``far`` are no nearer than ``d``, so no step down the field changes. (Most targets are near; the
    full field cost most of a simulated walk.)

    ``distance`` holds the previous fill, whose cells are ``queue[:filled]`` (``far`` elsewhere): only
    those are cleared, since clearing every cell, once per target, was most of a short fill's cost.
    Returns how many cells this fill set, all in ``queue``.
    """
    for index in range(filled):
        distance[queue[index]] = far
    distance[source] = 0
    queue[0] = source
    if source == stop:
        return 1
    return spread(neighbours, queue, 1, far, distance, stop)


@jit
def _nearest_frontier(
    neighbours: np.ndarray,
    counts: np.ndarray,
    cell: int,
    far: int,
    distance: np.ndarray,
    queue: np.ndarray,
    filled: np.ndarray,
) -> int:
    """The state :func:`~guardsim.planners.frontier.nearest_frontier` picks from ``cell``, found by a
    breadth-first search that stops at the first distance with one.

    The states entered from a cell ``c`` are ``(neighbours[c, h], h)`` (connectivity is symmetric), so
    the search meets the states in order of their entry cell's distance; among those at the least
    distance it keeps the one seeing the most unseen cells, then the lowest state number, as the full
    scan does. (The full field and scan of every state, each tick the route was done, cost most of a
    walk that ends on the frontier rule.) -1 when no reachable state sees an unseen cell.

    As in :func:`_fill_toward`, ``distance`` is ``far`` but on the previous search's cells,
    ``queue[:filled[0]]``; this search's count is left in ``filled[0]``.
    """
    for index in range(filled[0]):
        distance[queue[index]] = far
    distance[cell] = 0
    queue[0] = cell
    head, tail, level_end = 0, 1, 1
    best, best_count = -1, 0
    while head < tail:
        here = queue[head]
        head += 1
        for direction in range(4):
            other = neighbours[here, direction]
            if other < 0:
                continue
            state = state_of(other, direction)
            if counts[state] > best_count or (counts[state] > 0 and counts[state] == best_count and state < best):
                best, best_count = state, counts[state]
            if distance[other] == far:
                distance[other] = distance[here] + 1
                queue[tail] = other
                tail += 1
        if head == level_end:
            if best >= 0:
                filled[0] = tail
                return best
            level_end = tail
    filled[0] = tail
    return best


@jit
def look(table: ViewTable, goal: np.ndarray, seen: np.ndarray, counts: np.ndarray, counting: bool, state: int) -> int:
    """Mark what ``state`` sees as seen, and, when ``counting``, keep ``counts`` (unseen goal cells per
    state) in step; the number of goal cells newly seen."""
    sight, watch_start, watchers = table.sight, table.watch_start, table.watchers
    new = 0
    for index in range(table.sight_start[state], table.sight_start[state + 1]):
        cell = sight[index]
        if not seen[cell]:
            seen[cell] = True
            if goal[cell]:
                new += 1
                if counting:
                    for other in range(watch_start[cell], watch_start[cell + 1]):
                        counts[watchers[other]] -= 1
    return new


@jit
def look_along(
    table: ViewTable, goal: np.ndarray, seen: np.ndarray, path: np.ndarray, facing: np.ndarray, begin: int, end: int
) -> None:
    """Mark as seen what a walk sees from its ticks ``begin`` to ``end - 1`` (cells ``path``, headings
    ``facing``)."""
    no_counts = np.zeros(0, dtype=np.int32)
    for tick in range(begin, end):
        look(table, goal, seen, no_counts, False, state_of(path[tick], facing[tick]))


@jit
def _unseen_seen_by(table: ViewTable, goal: np.ndarray, seen: np.ndarray, state: int) -> int:
    """Unseen goal cells ``state`` would see, counted from its sight."""
    sight = table.sight
    count = 0
    for index in range(table.sight_start[state], table.sight_start[state + 1]):
        cell = sight[index]
        if goal[cell] and not seen[cell]:
            count += 1
    return count


@jit
def _count_unseen(table: ViewTable, goal: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """``int32 (states,)``: unseen goal cells each state would see, from the watchers of the unseen cells."""
    counts = np.zeros(table.entry.shape[0], dtype=np.int32)
    watch_start, watchers = table.watch_start, table.watchers
    for cell in range(goal.shape[0]):
        if goal[cell] and not seen[cell]:
            for other in range(watch_start[cell], watch_start[cell + 1]):
                counts[watchers[other]] += 1
    return counts


@jit
def team_walk(
    neighbours: np.ndarray,
    table: ViewTable,
    goal: np.ndarray,
    seen: np.ndarray,
    team: WalkTeam,
    limit: int,
    far: int,
    log: WalkLog,
) -> int:
    """Walk the team (moved in place) until the goal is seen or ``limit`` ticks; the ticks walked.

    How many unseen goal cells a state would see is counted from its sight while the guards follow
    their routes (a few states a tick); only once a guard needs the frontier rule, which asks many
    states, are the counts of every state kept, updated as cells are seen (each seen cell has some 200
    watching states on the shipped levels, so keeping them all along cost most of a walk).
    """
    entry = table.entry
    cells, headings, routes, lengths = team.cells, team.headings, team.routes, team.lengths
    moves, path, facing, visits, visit_count = log.moves, log.path, log.facing, log.visits, log.visit_count
    reached = log.reached
    guards = cells.shape[0]
    cell_count = neighbours.shape[0]
    unseen = 0
    for cell in range(cell_count):
        if goal[cell] and not seen[cell]:
            unseen += 1
    position = np.zeros(guards, dtype=np.int64)
    target = np.empty(guards, dtype=np.int64)
    target[:] = -1
    # Each field and the frontier search keep their own queue: it lists the cells to clear next time.
    fields = np.empty((guards, cell_count), dtype=np.int32)
    fields[:] = far
    field_queues = np.empty((guards, cell_count), dtype=np.int64)
    field_filled = np.zeros(guards, dtype=np.int64)
    here = np.empty(cell_count, dtype=np.int32)
    here[:] = far
    queue = np.empty(cell_count, dtype=np.int64)
    here_filled = np.zeros(1, dtype=np.int64)
    decided = np.empty(guards, dtype=np.int64)
    counts = np.zeros(0, dtype=np.int32)
    counting = False
    for guard in range(guards):
        path[guard, 0] = cells[guard]
        facing[guard, 0] = headings[guard]
        if lengths[guard] > 0:
            reached[guard, 0] = 0
    tick = 0
    while unseen > 0 and tick < limit:
        for guard in range(guards):
            while position[guard] < lengths[guard]:
                head = routes[guard, position[guard]]
                if (counts[head] if counting else _unseen_seen_by(table, goal, seen, head)) > 0:
                    break
                position[guard] += 1
                if position[guard] < lengths[guard]:
                    reached[guard, position[guard]] = tick
            if position[guard] < lengths[guard]:
                goal_state = routes[guard, position[guard]]
            else:
                if not counting:
                    counts, counting = _count_unseen(table, goal, seen), True
                goal_state = _nearest_frontier(neighbours, counts, cells[guard], far, here, queue, here_filled)
            move = -1
            if goal_state >= 0:
                field = fields[guard]
                cell = cells[guard]
                if goal_state != target[guard] or field[cell] == far:
                    target[guard] = goal_state
                    field_filled[guard] = _fill_toward(
                        neighbours, entry[goal_state], cell, far, field, field_queues[guard], field_filled[guard]
                    )
                if cell == entry[goal_state]:
                    move = heading_of_state(goal_state)
                else:
                    best_view = -1
                    for choice in range(5):
                        direction = headings[guard] if choice == 0 else choice - 1
                        other = neighbours[cell, direction]
                        if other < 0 or field[other] >= field[cell]:
                            continue
                        arrival = state_of(other, direction)
                        view = counts[arrival] if counting else _unseen_seen_by(table, goal, seen, arrival)
                        if view > best_view:
                            move, best_view = direction, view
            decided[guard] = move
        for guard in range(guards):
            move = decided[guard]
            moves[guard, tick] = move
            if move >= 0:
                cells[guard] = neighbours[cells[guard], move]
                headings[guard] = move
        tick += 1
        for guard in range(guards):
            path[guard, tick] = cells[guard]
            facing[guard, tick] = headings[guard]
            state = state_of(cells[guard], headings[guard])
            if state == target[guard] and decided[guard] >= 0:
                visits[guard, visit_count[guard]] = state
                visit_count[guard] += 1
            unseen -= look(table, goal, seen, counts, counting, state)
    return tick


@jit
def descent(
    neighbours: np.ndarray,
    sight_start: np.ndarray,
    sight: np.ndarray,
    goal: np.ndarray,
    seen: np.ndarray,
    cell: int,
    heading: int,
    limit: int,
    far: int,
    by_view: bool,
) -> np.ndarray:
    cells = neighbours.shape[0]
    field = np.empty(cells, dtype=np.int32)
    sources = np.empty(cells, dtype=np.int64)
    states = np.empty(limit, dtype=np.int64)
    count = 0
    for _ in range(limit):
        unseen = 0
        for other in range(cells):
            if goal[other] and not seen[other]:
                sources[unseen] = other
                unseen += 1
        if unseen == 0:
            break
        fill_distances(neighbours, sources[:unseen], far, field)
        move, best, best_view = -1, field[cell], -1
        if not by_view:
            # RippleFront's own step (ripplefront-exact), taken only downhill.
            move = greedy_step(field, neighbours[cell], heading)
            if move >= 0 and field[neighbours[cell, move]] >= best:
                move = -1
        for choice in range(5 if by_view else 0):
            direction = heading if choice == 0 else choice - 1
            there = neighbours[cell, direction]
            # Downhill only; among equally short moves the one that sees the most unseen goal cells.
            if there < 0 or field[there] > best or (field[there] == best and move < 0):
                continue
            view = 0
            arrive = state_of(there, direction)
            for index in range(sight_start[arrive], sight_start[arrive + 1]):
                view += goal[sight[index]] and not seen[sight[index]]
            if field[there] < best or view > best_view:
                move, best, best_view = direction, field[there], view
        if move < 0:
            break
        cell, heading = neighbours[cell, move], move
        state = state_of(cell, heading)
        states[count] = state
        count += 1
        for index in range(sight_start[state], sight_start[state + 1]):
            seen[sight[index]] = True
    return states[:count]
