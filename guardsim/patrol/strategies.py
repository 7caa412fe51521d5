"""Patrols that do not repeat, run for a fixed number of ticks through the simulation loop.

- ``staleness``: a re-implementation of the grid approach of Al Enezi and Verbrugge, "Dynamic Guard
  Patrol in Stealth Games" (AIIDE 2020, pp. 160-166, doi:10.1609/aiide.v16i1.7425). Each cell's
  staleness grows by one per tick while no guard sees it and drops to 0 when one does; a guard that
  reaches its destination picks the next one by staleness weighed against distance. Here the regions
  are the set-cover viewpoints (what one view sees), a region's staleness is the summed staleness of the
  goal cells it sees, and the guard takes the region with the most staleness per step of the way
  (``staleness / (1 + steps)``), leaving regions a teammate is heading for to that teammate.
- ``ripplefront``: the paper's RippleFront run for ever: once every goal cell has been seen, the guards
  forget what they saw and cover the level again from where they stand.
- ``random``: random goals, the common game baseline: walk the shortest way to a goal cell drawn
  uniformly, then draw the next.

All three run in :class:`guardsim.simulation.Simulation`, one coverage episode after another (it ends
an episode when the goal is seen; the next starts where the guards stand), so the tick is the loop's.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid, state_of
from guardsim.kernels.distances import FAR, distances_from
from guardsim.kernels.states import heading_of_state
from guardsim.kernels.steps import greedy_step
from guardsim.patrol.model import Patrol
from guardsim.planners.base import STAY, EpisodeSetup, GuardState, Planner
from guardsim.planners.viewpoint_cover import greedy_cover
from guardsim.scene import Scene
from guardsim.simulation import Simulation
from guardsim.vision.table import ViewTable

__all__ = ["RandomGoals", "StalenessBoard", "StalenessGuard", "run_strategy", "walk_patrol"]


def _step_towards(neighbours: np.ndarray, field: np.ndarray, cell: int, heading: int) -> int:
    """A move one step down ``field`` (keeping the heading when that is as short), or :data:`STAY`."""
    here = int(field[cell])
    if here == 0 or here >= FAR:
        return STAY
    # A breadth-first field falls by one toward its source, so the greedy step is a step down it.
    move = greedy_step(field, neighbours[cell], heading)
    return STAY if move < 0 else move


class StalenessBoard:
    """The team's shared staleness: ticks since each cell was last seen by any guard.

    Guard 0's planner advances it once per tick, marking what every guard sees from where it stands.
    """

    def __init__(self, table: ViewTable, goal: np.ndarray, viewpoints: np.ndarray) -> None:
        self.table = table
        self.goal = goal
        self.clock = 0
        self.last_seen = np.zeros(goal.size, dtype=np.int64)
        self.viewpoints = viewpoints
        pieces = [table.sees(int(state)) for state in viewpoints]
        lengths = np.array([piece.size for piece in pieces], dtype=np.int64)
        self._cells = np.concatenate(pieces).astype(np.int64) if pieces else np.zeros(0, dtype=np.int64)
        self._starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
        self._empty = lengths == 0
        self.claims: dict[int, int] = {}
        """Viewpoint index each guard is heading for."""

    def advance(self, team: Sequence[tuple[int, int]]) -> None:
        """One tick passes; every guard sees from its ``(cell, heading)``."""
        self.clock += 1
        for cell, heading in team:
            self.last_seen[self.table.sees(state_of(cell, heading))] = self.clock

    def region_staleness(self) -> np.ndarray:
        """``float (viewpoints,)``: summed staleness of the goal cells each viewpoint sees."""
        staleness = np.where(self.goal, self.clock - self.last_seen, 0).astype(np.float64)
        if self._cells.size == 0:
            return np.zeros(self.viewpoints.size)
        sums = np.add.reduceat(staleness[self._cells], self._starts)
        sums[self._empty] = 0.0
        return sums


class StalenessGuard:
    """One guard of the staleness patrol (all of a team's guards share one :class:`StalenessBoard`)."""

    name = "staleness"

    def __init__(self, board: StalenessBoard) -> None:
        self.board = board
        self.target = -1
        self._field = np.zeros(0, dtype=np.int32)

    def reset(self, setup: EpisodeSetup) -> None:
        """Keep the board and the destination: a new coverage episode changes nothing for staleness."""
        self._neighbours = setup.grid.neighbours
        self._entry = setup.grid.entry_cells

    def next_move(self, state: GuardState) -> int | None:
        """Step towards the destination; on arrival (or without one) choose the next."""
        board = self.board
        if state.guard == 0:
            board.advance(_team(state))
        here = state_of(state.cell, state.heading)
        if self.target < 0 or int(board.viewpoints[self.target]) == here:
            self._choose(state)
        if self.target < 0:
            return STAY
        target = int(board.viewpoints[self.target])
        entry = int(self._entry[target])
        if state.cell == entry:
            return int(heading_of_state(target))
        return _step_towards(self._neighbours, self._field, state.cell, state.heading)

    def _choose(self, state: GuardState) -> None:
        board = self.board
        board.claims.pop(state.guard, None)
        steps = distances_from(self._neighbours, np.array([state.cell], dtype=np.int64))
        entries = self._entry[board.viewpoints]
        distance = steps[entries].astype(np.float64) + 1.0
        score = board.region_staleness() / (1.0 + distance)
        score[distance >= FAR] = -1.0
        here = state_of(state.cell, state.heading)
        score[board.viewpoints == here] = -1.0
        for guard, claimed in board.claims.items():
            if guard != state.guard:
                score[claimed] = -1.0
        best = int(np.argmax(score))
        if score[best] < 0:
            self.target = -1
            return
        self.target = best
        board.claims[state.guard] = best
        self._field = distances_from(self._neighbours, np.array([int(entries[best])], dtype=np.int64))


class RandomGoals:
    """Walk the shortest way to a goal cell drawn uniformly; on arrival draw the next."""

    name = "random"

    def __init__(self) -> None:
        self.target = -1
        self._rng: np.random.Generator | None = None

    def reset(self, setup: EpisodeSetup) -> None:
        """Keep the destination across coverage episodes; take the episode's generator."""
        self._neighbours = setup.grid.neighbours
        self._cells = np.flatnonzero(setup.goal)
        self._rng = setup.rng

    def next_move(self, state: GuardState) -> int | None:
        """Step towards the goal cell; on arrival draw another one (never the cell it stands in)."""
        assert self._rng is not None
        if self.target < 0 or state.cell == self.target:
            if self._cells.size < 2:
                return STAY
            target = state.cell
            while target == state.cell:
                target = int(self._cells[self._rng.integers(self._cells.size)])
            self.target = target
            self._field = distances_from(self._neighbours, np.array([target], dtype=np.int64))
        return _step_towards(self._neighbours, self._field, state.cell, state.heading)


def _team(state: GuardState) -> tuple[tuple[int, int], ...]:
    return state.team or ((state.cell, state.heading),)


def walk_patrol(
    scene: Scene,
    planners: Sequence[Planner],
    starts: Sequence[tuple[int, int]],
    headings: Sequence[int],
    ticks: int,
    *,
    rng: np.random.Generator,
) -> np.ndarray:
    """``int64 (guards, ticks)``: each guard's state per tick, coverage episode after coverage episode.

    Each episode starts where the last one ended with nothing seen; an episode that ends at its start
    (the goal seen from there) is followed by a tick of standing still, so time always advances.
    """
    grid: CoverageGrid = scene.grid
    guards = len(planners)
    cells = [grid.flat(col, row) for col, row in starts]
    facing = list(headings)
    columns: list[np.ndarray] = [state_of(np.array(cells), np.array(facing))[:, None]]
    walked = 1
    while walked < ticks:
        simulation = Simulation(scene, list(planners), max_steps=ticks - walked)
        simulation.reset(starts=[grid.unflat(cell) for cell in cells], headings=facing, rng=rng)
        trace = simulation.run()
        paths, logs = trace.team_paths(), trace.team_headings()
        if trace.steps == 0:
            columns.append(columns[-1][:, -1:])
            walked += 1
            continue
        flat = np.array([[grid.flat(col, row) for col, row in path[1:]] for path in paths], dtype=np.int64)
        heads = np.array([list(log[1:]) for log in logs], dtype=np.int64)
        columns.append(state_of(flat, heads))
        walked += flat.shape[1]
        cells = flat[:, -1].tolist()
        facing = heads[:, -1].tolist()
        if trace.outcome == "stuck":
            break
    states = np.concatenate(columns, axis=1)[:, :ticks]
    if states.shape[1] < ticks:
        states = np.concatenate([states, np.repeat(states[:, -1:], ticks - states.shape[1], axis=1)], axis=1)
    assert states.shape == (guards, ticks)
    return states


def run_strategy(
    scene: Scene,
    table: ViewTable,
    goal: np.ndarray,
    strategy: str,
    starts: Sequence[tuple[int, int]],
    headings: Sequence[int],
    ticks: int,
    *,
    seed: int = 0,
) -> Patrol:
    """The walked patrol of ``staleness``, ``ripplefront`` or ``random`` for ``ticks`` ticks."""
    rng = np.random.default_rng(seed)
    guards = len(starts)
    planners: list[Planner]
    if strategy == "staleness":
        board = StalenessBoard(table, goal, greedy_cover(table, goal))
        planners = [StalenessGuard(board) for _ in range(guards)]
    elif strategy == "random":
        planners = [RandomGoals() for _ in range(guards)]
    elif strategy == "ripplefront":
        from guardsim.planners import make_planner

        planners = [make_planner("ripplefront") for _ in range(guards)]
    else:
        raise ArgumentError(f"unknown walked strategy {strategy!r}")
    states = walk_patrol(scene, planners, starts, headings, ticks, rng=rng)
    return Patrol(states, None, strategy)
