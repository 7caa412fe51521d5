"""Closed cover loops: a route that sees every goal cell once per lap, for one guard or a team.

One guard (:func:`cover_loop`):

1. viewpoints, states whose views together see the goal: the tour planner's greedy set cover
   (:func:`guardsim.planners.viewpoint_cover.greedy_cover`), or the states another planner's coverage
   walk arrived in;
2. ordered into a short closed tour with true step counts between them: the open-tour heuristics of
   :mod:`guardsim.kernels.tours` (nearest neighbour, then 2-opt and Or-opt) on the usual reduction of
   a cycle to an open tour, a copy of the first viewpoint that must come last;
3. walked (shortest paths, straight on where a choice is free) and pruned: a viewpoint whose cells the
   rest of the lap sees anyway is dropped, and the tour is ordered again.

A team (:func:`team_loops`) gets both of the two standard cyclic strategies, scored by worst idleness,
and keeps the better: one shared cycle with the guards spaced evenly along it (for the worst idleness of
a single cycle shared by ``k`` agents is its length over ``k``, the strategy Chevaleyre 2004, "Theoretical
analysis of the multi-agent patrolling problem", shows near-optimal), or split loops, a loop of its own
per guard: the better of the lap cut into ``k`` stretches of equal ticks and the goal cut into ``k``
regions by walking distance.
"""

from __future__ import annotations

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid, cell_of_state, heading_of_state, state_of
from guardsim.kernels.distances import FAR, distance_fields
from guardsim.kernels.laps import add_sights, leg_states
from guardsim.kernels.tours import improve_tour, nearest_neighbour_tour
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import PatrolScore, score_patrol, score_rank
from guardsim.planners.tour import route_costs
from guardsim.planners.viewpoint_cover import greedy_cover
from guardsim.vision.table import ViewTable

__all__ = ["LoopBuilder", "closed_tour", "team_loops"]

_NO_LEG = np.zeros(0, dtype=np.int64)

# The dummy last node's way out: dearer than any tour, so it stays last. Far below int64's range.
_NEVER_LEAVE = 10**12


def closed_tour(cost: np.ndarray) -> np.ndarray:
    """An order of nodes ``0..n-1`` (node 0 first) for a short closed tour under ``cost``.

    A copy of node 0 is appended as node ``n`` with node 0's incoming costs and no way out, so an open
    tour from node 0 ending at the copy is a cycle; the open-tour heuristics then shorten it.

    Examples
    --------
    >>> cost = np.array([[0, 1, 5, 1], [1, 0, 1, 5], [5, 1, 0, 1], [1, 5, 1, 0]])
    >>> closed_tour(cost).tolist()
    [0, 1, 2, 3]
    """
    count = cost.shape[0]
    if count <= 2:
        return np.arange(count, dtype=np.int64)
    padded = np.full((count + 1, count + 1), _NEVER_LEAVE, dtype=np.int64)
    padded[:count, :count] = cost
    padded[:count, count] = cost[:, 0]
    padded[count, count] = 0
    start = nearest_neighbour_tour(padded, 0, np.arange(1, count, dtype=np.int64))
    tour = improve_tour(padded, np.append(start, count).astype(np.int64))
    tour = tour[tour != count]
    return tour.astype(np.int64)


class LoopBuilder:
    """Builds and walks closed loops through viewpoints on one level and goal.

    Parameters
    ----------
    grid
        The coverage grid.
    table
        The level's view table.
    goal
        ``bool (cells,)``: the cells every lap must see.
    """

    def __init__(
        self,
        grid: CoverageGrid,
        table: ViewTable,
        goal: np.ndarray,
        *,
        legs: dict[tuple[int, int], np.ndarray] | None = None,
        thin: bool = False,
    ) -> None:
        self.grid = grid
        self.table = table
        self.goal = np.ascontiguousarray(goal, dtype=bool)
        self.neighbours = np.ascontiguousarray(grid.neighbours, dtype=np.int64)
        self.thin = thin
        """Whether viewpoints are cut to an irredundant cover of the goal before they are ordered (for
        large levels: quicker, and shorter loops from long walks; see :func:`guardsim.patrol.plan.is_large`)."""
        # Ordering again and pruning ask for the same legs many times: keep each leg once (a leg does
        # not depend on the goal, so builders of one level share them).
        self._legs: dict[tuple[int, int], np.ndarray] = {} if legs is None else legs
        self._scratch: tuple[np.ndarray, np.ndarray] | None = None

    # -- viewpoints --------------------------------------------------------------------------------

    def cover_viewpoints(self) -> np.ndarray:
        """The greedy set cover of the goal (state numbers)."""
        return greedy_cover(self.table, self.goal)

    def walk_viewpoints(self, states: np.ndarray) -> np.ndarray:
        """The arrivable states among ``states`` (a walk), in first-visit order, topped up so they see the goal.

        A goal cell none of them sees gets a state standing in it (a guard sees its own cell).
        """
        entry = self.table.entry
        states = np.asarray(states, dtype=np.int64)
        states = states[entry[states] >= 0]
        _, first = np.unique(states, return_index=True)
        chosen = list(states[np.sort(first)].tolist())
        missing = self.goal & ~self.seen_by(np.asarray(chosen, dtype=np.int64))
        for cell in np.flatnonzero(missing).tolist():
            for heading in range(4):
                if entry[state_of(cell, heading)] >= 0:
                    chosen.append(state_of(cell, heading))
                    break
        return np.asarray(chosen, dtype=np.int64)

    # -- loops -------------------------------------------------------------------------------------

    def cycle(self, viewpoints: np.ndarray) -> np.ndarray:
        """``viewpoints`` pruned and put in the order of a short closed tour (the post when none)."""
        viewpoints = np.asarray(viewpoints, dtype=np.int64)
        if viewpoints.size == 0:
            return self.post()
        if self.thin:
            # Ordering costs the square of the viewpoints (a cost matrix, then 2-opt): a long walk's
            # thousands of arrivals are first cut to those whose own views still see the goal (not the
            # legs between them, which ordering changes), and only those are ordered.
            viewpoints = self._irredundant(viewpoints)
        order = self._prune(viewpoints[self.order(viewpoints)])
        # Ordering again may shorten the lap, but the paths change, and with them the cells seen on the
        # way that pruning counted on: keep the new order only when its lap still sees the goal.
        for _ in range(4):
            again = order[self.order(order)]
            lap = self.walk(again)
            if lap.size >= self.walk(order).size or not self.lap_sees_goal(lap):
                break
            order = self._prune(again)
        return order

    def loop(self, viewpoints: np.ndarray) -> np.ndarray:
        """One lap (state per tick) of a short closed loop through ``viewpoints`` that sees the goal."""
        return self.walk(self.cycle(viewpoints))

    def post(self) -> np.ndarray:
        """A one-tick lap: standing in the goal's first cell, facing the way that sees most of the goal."""
        cells = np.flatnonzero(self.goal)
        if cells.size == 0:
            raise ArgumentError("the goal is empty: nothing to patrol")
        states = state_of(np.full(4, int(cells[0]), dtype=np.int64), np.arange(4, dtype=np.int64))
        counts = [int(self.goal[self.table.sees(int(state))].sum()) for state in states]
        return np.array([states[int(np.argmax(counts))]], dtype=np.int64)

    def walk(self, order: np.ndarray) -> np.ndarray:
        """The lap through the viewpoints ``order`` and back to the first: a state per tick, not repeating
        the first at the end. One viewpoint is a post."""
        first = int(order[0])
        pieces = [np.array([first], dtype=np.int64)]
        last = first
        for target in [*order[1:].tolist(), first]:
            if target != last:
                pieces.append(self._leg(last, target))
                last = target
        lap = np.concatenate(pieces)
        return lap[:-1] if lap.size > 1 else lap

    def path(self, start: int, target: int) -> list[int]:
        """The states after each tick from state ``start`` to arriving in state ``target``.

        A shortest walk to the cell behind ``target`` and the step into it; where several steps are
        equally short the guard keeps its heading, then prefers right, down, left, up.
        """
        return self._leg(start, target).tolist()

    def _leg(self, start: int, target: int) -> np.ndarray:
        leg = self._legs.get((start, target))
        if leg is None:
            entry = int(self.table.entry[target])
            if entry < 0:
                raise ArgumentError(f"state {target} cannot be arrived in")
            if self._scratch is None:
                self._scratch = (np.full(self.goal.size, FAR, dtype=np.int32), np.empty(self.goal.size, dtype=np.int64))
            distance, queue = self._scratch
            cell, heading = int(cell_of_state(start)), int(heading_of_state(start))
            leg = leg_states(self.neighbours, cell, heading, entry, int(target), int(FAR), distance, queue)
            if leg.size == 0:
                raise ArgumentError(f"cell {cell} cannot reach cell {entry}")
            self._legs[(start, target)] = leg
        return leg

    def lap_sees_goal(self, lap: np.ndarray) -> bool:
        """Whether the states of ``lap`` together see every goal cell."""
        return bool(np.all(self.seen_by(lap)[self.goal]))

    # -- inside ------------------------------------------------------------------------------------

    def order(self, states: np.ndarray) -> np.ndarray:
        """Indices into ``states`` in the order of a short closed tour."""
        cost = route_costs(self.neighbours, self.table.entry, states, ())
        return closed_tour(cost)

    def _prune(self, order: np.ndarray) -> np.ndarray:
        """Drop viewpoints (latest first) while the lap without them still sees the goal.

        The lap is the cycle of legs between consecutive viewpoints; dropping one swaps its two legs for
        the leg that skips it, so a trial counts the sights of those three legs only (the cells seen,
        per cell, by the lap's states; the lap sees the goal while no goal cell's count is zero).
        """
        keep = [int(state) for state in order.tolist()]
        if len(keep) <= 1:
            return np.asarray(keep, dtype=np.int64)
        after = {state: keep[(index + 1) % len(keep)] for index, state in enumerate(keep)}
        before = {following: state for state, following in after.items()}
        count = np.zeros(self.goal.size, dtype=np.int32)
        table = self.table
        missing = int(self.goal.sum())
        for state in keep:
            missing += add_sights(
                table.sight_start, table.sight, self._cycle_leg(state, after[state]), 1, count, self.goal
            )
        left = len(keep)
        for state in reversed(keep):
            if left <= 1:
                break
            previous, following = before[state], after[state]
            if left == 2:
                # The lap without it is a post: one state, no legs.
                if not self.lap_sees_goal(np.array([following], dtype=np.int64)):
                    continue
            else:
                legs = (self._cycle_leg(previous, state), self._cycle_leg(state, following))
                skip = self._cycle_leg(previous, following)
                change = add_sights(table.sight_start, table.sight, skip, 1, count, self.goal)
                for leg in legs:
                    change += add_sights(table.sight_start, table.sight, leg, -1, count, self.goal)
                if missing + change > 0:
                    for leg in legs:
                        add_sights(table.sight_start, table.sight, leg, 1, count, self.goal)
                    add_sights(table.sight_start, table.sight, skip, -1, count, self.goal)
                    continue
                missing += change
            after[previous], before[following] = following, previous
            del after[state], before[state]
            left -= 1
        return np.asarray([state for state in keep if state in after], dtype=np.int64)

    def _irredundant(self, viewpoints: np.ndarray) -> np.ndarray:
        """``viewpoints`` without those (latest first) whose cells the others' views see anyway."""
        table = self.table
        count = np.zeros(self.goal.size, dtype=np.int32)
        missing = int(self.goal.sum()) + add_sights(table.sight_start, table.sight, viewpoints, 1, count, self.goal)
        keep = np.ones(viewpoints.size, dtype=bool)
        for index in range(viewpoints.size - 1, 0, -1):
            alone = viewpoints[index : index + 1]
            if missing + add_sights(table.sight_start, table.sight, alone, -1, count, self.goal) > 0:
                add_sights(table.sight_start, table.sight, alone, 1, count, self.goal)
            else:
                keep[index] = False
        return viewpoints[keep]

    def _cycle_leg(self, start: int, target: int) -> np.ndarray:
        """The leg of a lap from viewpoint ``start`` to the next, ``target`` (none between equal states)."""
        return _NO_LEG if start == target else self._leg(start, target)

    def seen_by(self, states: np.ndarray) -> np.ndarray:
        """``bool (cells,)``: the cells any of ``states`` sees."""
        seen = np.zeros(self.goal.size, dtype=bool)
        states = np.unique(np.asarray(states, dtype=np.int64))
        first = self.table.sight_start[states]
        lengths = self.table.sight_start[states + 1] - first
        # One gather over the table's rows: position i of the result reads row start + (i - row offset).
        offsets = np.cumsum(lengths) - lengths
        seen[self.table.sight[np.repeat(first - offsets, lengths) + np.arange(int(lengths.sum()))]] = True
        return seen


def _spaced(lap: np.ndarray, guards: int) -> np.ndarray:
    """The lap shared by ``guards`` guards, guard ``g`` starting ``g * period / guards`` ticks along it."""
    period = lap.size
    offsets = [round(guard * period / guards) for guard in range(guards)]
    return np.stack([np.roll(lap, -offset) for offset in offsets])


def _split(builder: LoopBuilder, lap: np.ndarray, guards: int) -> np.ndarray:
    """The lap cut into ``guards`` stretches of equal ticks, each made a loop of its own.

    Each guard's loop must see what its stretch of the shared lap sees; it is built like the shared
    one (greedy cover of that part, ordered, pruned). Cuts at up to 8 rotations of the lap are tried;
    the one whose longest loop is shortest wins. Shorter loops wait at their last state to the common
    period, so the team still repeats.
    """
    period = lap.size
    best: list[np.ndarray] | None = None
    # A thin (large-level) builder tries two cuts, not eight: each cut is a full loop per guard.
    cuts = 2 if builder.thin else 8
    for rotation in range(0, period, max(1, period // cuts)):
        turned = np.roll(lap, -rotation)
        bounds = [round(part * period / guards) for part in range(guards + 1)]
        laps = []
        for part in range(guards):
            # More guards than ticks: the last stretches would be empty; each gets at least one tick.
            begin = min(bounds[part], period - 1)
            stretch = turned[begin : max(bounds[part + 1], begin + 1)]
            part_goal = builder.goal & builder.seen_by(stretch)
            sub = LoopBuilder(builder.grid, builder.table, part_goal, legs=builder._legs, thin=builder.thin)
            laps.append(sub.loop(sub.cover_viewpoints()) if part_goal.any() else stretch[:1])
        if best is None or max(part.size for part in laps) < max(part.size for part in best):
            best = laps
        if period < cuts * guards:
            break
    assert best is not None
    return _padded(best)


def _regions(builder: LoopBuilder, guards: int, rounds: int = 10) -> np.ndarray:
    """The goal cut into ``guards`` regions by walking distance, each patrolled by a loop of its own.

    Seeds are spread by farthest-point sampling over walking distance, each goal cell goes to its
    nearest seed, and each seed moves to the cell nearest its region's centroid, for up to ``rounds``
    rounds (Lloyd's iteration on the grid). Each region gets the single-guard loop of its cells.
    """
    goal_cells = np.flatnonzero(builder.goal)
    cols = builder.grid.shape[1]
    seeds = [int(goal_cells[0])]
    for _ in range(guards - 1):
        nearest = distance_fields(builder.neighbours, np.asarray(seeds, dtype=np.int64)).min(axis=0)
        seeds.append(int(np.argmax(np.where(builder.goal, nearest, -1))))
    owner = np.zeros(goal_cells.size, dtype=np.int64)
    for _ in range(rounds):
        fields = distance_fields(builder.neighbours, np.asarray(seeds, dtype=np.int64))
        owner = np.argmin(fields[:, goal_cells], axis=0)
        moved = []
        for part in range(guards):
            members = goal_cells[owner == part]
            if members.size == 0:
                moved.append(seeds[part])
                continue
            x, y = members % cols, members // cols
            moved.append(int(members[np.argmin((x - x.mean()) ** 2 + (y - y.mean()) ** 2)]))
        if moved == seeds:
            break
        seeds = moved
    laps = []
    for part in range(guards):
        part_goal = np.zeros_like(builder.goal)
        part_goal[goal_cells[owner == part]] = True
        if not part_goal.any():
            laps.append(builder.walk(builder.cycle(builder.cover_viewpoints()))[:1])
            continue
        sub = LoopBuilder(builder.grid, builder.table, part_goal, legs=builder._legs, thin=builder.thin)
        laps.append(sub.loop(sub.cover_viewpoints()))
    return _padded(laps)


def _padded(laps: list[np.ndarray]) -> np.ndarray:
    """Laps of one team at the common period: the shorter ones wait at their last state."""
    longest = max(part.size for part in laps)
    return np.stack([np.concatenate([part, np.full(longest - part.size, part[-1], dtype=np.int64)]) for part in laps])


def team_loops(
    builder: LoopBuilder, viewpoints: np.ndarray, guards: int, *, planner: str = "cover", lap: np.ndarray | None = None
) -> tuple[Patrol, dict[str, PatrolScore]]:
    """The loop patrol of ``guards`` guards through ``viewpoints``, and the score of each team strategy.

    One guard walks the loop. A team gets the shared cycle and the split loops, and keeps the one with
    the lower worst idleness (then mean idleness; ties to the shared cycle).
    """
    if lap is None:
        lap = builder.walk(builder.cycle(viewpoints))
    if guards == 1:
        patrol = Patrol(lap[None, :], lap.size, "loop", planner=planner)
        return patrol, {"single": score_patrol(builder.table, patrol, builder.goal)}
    shared_states = _spaced(lap, guards)
    # Split loops two ways, the lap cut into stretches and the goal cut into regions; the better is "split".
    cuts = [_split(builder, lap, guards), _regions(builder, guards)]
    cut_scores = [score_patrol(builder.table, Patrol(cut, cut.shape[1], "loop"), builder.goal) for cut in cuts]
    split_states = cuts[min(range(2), key=lambda index: score_rank(cut_scores[index]))]
    candidates = {
        "shared": Patrol(shared_states, shared_states.shape[1], "loop", planner=planner, team="shared"),
        "split": Patrol(split_states, split_states.shape[1], "loop", planner=planner, team="split"),
    }
    scores = {name: score_patrol(builder.table, patrol, builder.goal) for name, patrol in candidates.items()}

    chosen = min(candidates, key=lambda name: (*score_rank(scores[name]), name != "shared"))
    other = "split" if chosen == "shared" else "shared"
    note = (
        f"team of {guards}: {chosen} (worst idleness {scores[chosen].worst_idleness}, mean "
        f"{_mean(scores[chosen])}) beats {other} (worst {scores[other].worst_idleness}, mean {_mean(scores[other])})"
    )
    patrol = candidates[chosen]
    return Patrol(patrol.states, patrol.period, "loop", planner=planner, team=chosen, notes=(note,)), scores


def _mean(score: PatrolScore) -> str:
    return "none" if score.mean_idleness is None else f"{score.mean_idleness:.1f}"
