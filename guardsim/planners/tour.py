"""Tour: cover the level from a few viewpoints, visited in a short order, planned at the first tick.

Per level and goal (once, shared by every episode): a greedy set cover of the goal by viewpoints, states
whose cones together see every goal cell (:mod:`guardsim.planners.viewpoint_cover`).

Per episode, at the first decision, for the whole team at once:

1. the viewpoints that still see something unseen are ordered into an open travelling-salesman tour
   from the start with true step counts (nearest neighbour, then 2-opt and Or-opt,
   :mod:`guardsim.kernels.tours`), or split into one tour per guard
   (:mod:`guardsim.planners.team_routes`);
2. the team's walk along those tours is simulated tick for tick with the level's view table
   (:mod:`guardsim.planners.route_walk`): viewpoints whose cells have all been seen meanwhile are
   skipped, and a guard whose tour is done falls back to the frontier rule;
3. the states the walk actually arrived in are routed again and walked again, as long as the walk gets
   shorter. Steps 2-3 start from several seeds, the shortest walk winning: the set-cover tour; the
   empty tour (the frontier walk, which the refinement turns into a tour of the frontier states it
   used); two descent walks (:func:`~guardsim.planners.route_walk.descent_states`); eight lawnmower
   routes, lanes one cone swath apart (:mod:`guardsim.planners.lawnmower`); and, for one guard on a
   level of at most :data:`BEAM_POSITIONS` positions, two from the exact search's graph over the
   residual goal (:mod:`guardsim.search.residual`): the arrivals of a widening beam search over its
   macro moves (:mod:`guardsim.search.beam`), which weighs each viewpoint's cost against what it
   adds, and, when at most :data:`EXACT_GOAL` goal cells are left, the exact search itself for
   :data:`EXACT_EXPANSIONS` expansions from the beam's walk: when it proves its walk optimal, that
   walk is the plan and the other seeds are not tried.

The guard then plays its part of that walk move by move. The view table gives the loop's own vision, so
the walk is what the loop records; should the world ever differ from it (say a teammate running another
planner), the guard continues with the frontier rule.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import state_of
from guardsim.kernels.distances import distance_fields, distances_between
from guardsim.kernels.states import cell_of_state
from guardsim.planners.base import STAY, EpisodeSetup, GuardState
from guardsim.planners.frontier import Frontier
from guardsim.planners.lawnmower import lane_routes, spiral_rings, spiral_routes, swath_half_width
from guardsim.planners.polish import polish_route
from guardsim.planners.route_walk import RouteWalk, descent_states, walk_routes
from guardsim.planners.team_routes import plan_routes
from guardsim.planners.viewpoint_cover import greedy_cover
from guardsim.search import search_route
from guardsim.search.beam import widening_beam_route
from guardsim.search.graph import SearchGraph, build_search_graph, goal_bits, route_steps
from guardsim.search.heuristic import Heuristic, build_heuristic
from guardsim.search.residual import residual_goal
from guardsim.vision.table import UnseenTally, level_memo, view_table

__all__ = ["LevelCover", "Tour", "route_costs"]

#: Rounds of routing again through the states a simulated walk arrived in.
REFINE_ROUNDS = 8
#: Widths of the "beam" seed's widening beam (:func:`guardsim.search.beam.widening_beam_route`).
BEAM_WIDTHS = (8, 512)
#: The widening beam's budget: estimates of the exact search's heuristic, summed over its runs.
BEAM_ESTIMATES = 50000
#: Most guard positions (states, or cells when headings do not matter) for the beam seed; above it the
#: per-start tables (steps from every position to every cell's watchers) cost too much.
BEAM_POSITIONS = 6000
#: Pivot candidates of the beam's estimate (fewer than the exact search's, for a quicker setup).
BEAM_POOL = 256
#: Largest residual goal (cells) for the "exact" seed; the exact search is quick only with few.
EXACT_GOAL = 64
#: Expansions of the exact seed's search (a deterministic budget).
EXACT_EXPANSIONS = 30_000
#: Most nodes the exact seed's search stores.
EXACT_NODES = 4 * EXACT_EXPANSIONS
#: Lawnmower routes (of eight) refined, the shortest walked first.
LAWNMOWER_REFINED = 8
#: Every seed, in the order tried.
SEEDS = ("exact", "cover", "frontier", "beam", "descent", "descent-view", "lawnmower", "spiral")
#: Changed routes walked when polishing one walk (:func:`guardsim.planners.polish.polish_route`).
POLISH_TRIALS = 1000
#: The shortest refined walks polished, one guard (0: none).
POLISHED = 1
#: Seeds from the exact search's macro moves.
MACRO_SEEDS = frozenset({"exact", "beam"})

#: Most distances the distance fields kept over one plan hold (int32: 32 MB; a one-guard plan on a
#: 60 x 60 level keeps 1100-1500 fields of 3600 cells, 20 MB).
FIELD_CELLS = 1 << 23

#: ``(cell, heading)`` of every guard.
Team = tuple[tuple[int, int], ...]


def route_costs(
    neighbours: np.ndarray,
    entry: np.ndarray,
    states: np.ndarray,
    team: Team,
    fields: dict[int, np.ndarray] | None = None,
) -> np.ndarray:
    """Steps between nodes: ``states`` (nodes ``0..k-1``), then one start per guard (never arrived at).

    Arriving in state ``b`` from node ``a`` takes the steps from ``a``'s cell to ``b``'s entry cell and
    the step into ``b``. ``fields``, if given, keeps each entry cell's distance field (one breadth-first
    search) for later calls, and is filled with those it lacks while they hold at most
    :data:`FIELD_CELLS` distances.
    """
    k = states.size
    cells = np.concatenate([cell_of_state(states), np.array([cell for cell, _ in team], dtype=np.int64)])
    cost = np.zeros((cells.size, cells.size), dtype=np.int64)
    if fields is None:
        cost[:, :k] = distances_between(neighbours, entry[states], cells).T.astype(np.int64) + 1
    elif k:
        missing = [cell for cell in np.unique(entry[states]).tolist() if cell not in fields]
        new = dict(zip(missing, distance_fields(neighbours, np.array(missing, dtype=np.int64)), strict=True))
        rows = [(fields[cell] if cell in fields else new[cell])[cells] for cell in entry[states].tolist()]
        cost[:, :k] = np.stack(rows).T.astype(np.int64) + 1
        room = FIELD_CELLS // neighbours.shape[0] - len(fields)
        fields.update(itertools.islice(new.items(), max(0, room)))
    cost[np.arange(k), np.arange(k)] = 0
    return cost


class Candidate(NamedTuple):
    """A simulated walk and the routes it walked."""

    walk: RouteWalk
    routes: list[np.ndarray]


class MacroRoutes(NamedTuple):
    """One guard's routes from the exact search's macro moves, made once per plan."""

    beam: np.ndarray | None
    """States the widening beam's walk arrives in; None when the seed does not apply."""
    exact: np.ndarray | None
    """States the exact search's best walk arrives in; None when it does not apply or found nothing
    shorter than the beam's walk without proving it optimal."""
    optimum: int
    """Steps of the exact walk when proved optimal, else -1."""


class LevelCover(NamedTuple):
    """What the tour planner keeps per level and goal."""

    viewpoints: np.ndarray
    """``int64 (m,)``: state numbers (``cell * 4 + heading``) of the greedy set cover."""


class Tour:
    """Plan a short walk through set-cover viewpoints at the first tick, then walk it.

    Parameters
    ----------
    seeds
        Which first routes to refine (:data:`SEEDS`): ``"exact"`` (the exact search's walk, one guard,
        small levels), ``"cover"`` (the set-cover tour), ``"frontier"`` (the empty route, i.e. the
        frontier walk), ``"beam"`` (the arrivals of a beam search over macro moves, one guard on levels
        of at most :data:`BEAM_POSITIONS` positions), ``"descent"`` and ``"descent-view"`` (the
        nearest-unseen descent walks, one guard), ``"lawnmower"`` (boustrophedon lanes, one guard) and
        ``"spiral"`` (nested rings one swath apart, entered nearest the guard, one guard); the shortest
        refined walk (or polished one) is kept. All by default; the others are for measuring what each part
        contributes.
    refine_rounds
        Most rounds of routing again through the states a walk arrived in (0: walk the seed as it is).
    polish_trials
        Changed routes walked to polish each of the ``polished`` shortest walks (one guard; 0: none).
    polished
        How many of the shortest walks are polished.
    """

    name = "tour"

    def __init__(
        self,
        seeds: tuple[str, ...] = SEEDS,
        refine_rounds: int = REFINE_ROUNDS,
        polish_trials: int = POLISH_TRIALS,
        polished: int = POLISHED,
    ) -> None:
        if not seeds or set(seeds) - set(SEEDS):
            raise ArgumentError(f"seeds must be some of {', '.join(SEEDS)}")
        if polish_trials < 0 or polished < 0:
            raise ArgumentError("polish_trials and polished must be at least 0")
        self.seeds = tuple(seeds)
        self.refine_rounds = refine_rounds
        self.polish_trials = polish_trials
        self.polished = polished
        self.cover = LevelCover(np.zeros(0, dtype=np.int64))
        self.walk: RouteWalk | None = None
        """The team's planned walk, made at the first decision."""
        self._entry_fields: dict[int, np.ndarray] = {}

    @property
    def options(self) -> dict[str, object]:
        """The options this planner was made with."""
        return {
            "seeds": list(self.seeds),
            "refine_rounds": self.refine_rounds,
            "polish_trials": self.polish_trials,
            "polished": self.polished,
        }

    def reset(self, setup: EpisodeSetup) -> None:
        """Load (or build, once per level and goal) the viewpoint cover; the walk waits for the start."""
        self._neighbours = setup.grid.neighbours
        self._grid = setup.grid
        self._goal = setup.goal
        self._table = view_table(setup.grid, setup.vision)
        memo = level_memo(setup.grid, setup.vision)
        key = ("tour-cover", setup.goal.tobytes())
        if key not in memo:
            memo[key] = LevelCover(greedy_cover(self._table, setup.goal))
        self.cover = memo[key]
        self._memo = memo
        self._goal_key = key
        self._tally = UnseenTally(self._table, setup.goal)
        self._fallback = Frontier()
        self._fallback.reset(setup)
        self.walk = None
        self._first_tick = 0

    def next_move(self, state: GuardState) -> int | None:
        """The planned move of this tick; the frontier rule if the world left the plan (or it ran out)."""
        if self.walk is None:
            self._tally.update(state.seen)
            self.walk = self._plan(state)
            self._first_tick = state.tick
        tick = state.tick - self._first_tick
        walk, guard = self.walk, state.guard
        if (
            tick < walk.moves.shape[1]
            and walk.cells[guard, tick] == state.cell
            and walk.headings[guard, tick] == state.heading
        ):
            move = int(walk.moves[guard, tick])
            return STAY if move < 0 else move
        return self._fallback.next_move(state)

    def _plan(self, state: GuardState) -> RouteWalk:
        """The team's walk from this state; every guard of a team plans the same one, so it is shared."""
        team = state.team or ((state.cell, state.heading),)
        key = (
            self._goal_key,
            team,
            state.seen.tobytes(),
            self.seeds,
            self.refine_rounds,
            self.polish_trials,
            self.polished,
        )
        cached = self._memo.get("tour-walk")
        if cached is None or cached[0] != key:
            cached = (key, self._best_walk(state.seen, team))
            self._memo["tour-walk"] = cached
            self._entry_fields = {}
        return cached[1]

    def _best_walk(self, seen: np.ndarray, team: Team) -> RouteWalk:
        """The shortest of the refined walks from each seed (at once the exact seed's, when proved)."""
        limit = 10 * int(self._goal.sum()) + 100
        self._entry_fields = {}
        macro = self._macro_routes(team, seen) if MACRO_SEEDS & set(self.seeds) else MacroRoutes(None, None, -1)
        found: list[Candidate] = []
        for seed in self.seeds:
            if seed == "exact" and macro.exact is not None and macro.optimum >= 0:
                # The walk along a proved optimal route is optimal too (it can only skip what is seen).
                walk = self._simulate(seen, team, [macro.exact], limit)
                if walk.covered and walk.steps == macro.optimum:
                    return walk
            if seed in ("lawnmower", "spiral"):
                found.extend(self._sweep_walks(seed, seen, team, limit))
                continue
            if seed in MACRO_SEEDS:
                route = macro.exact if seed == "exact" else macro.beam
                routes = None if route is None else [route]
            else:
                routes = self._seed_routes(seed, team, seen)
            if routes is not None:
                found.append(self._refine(seen, team, routes, limit))
        found.sort(key=lambda candidate: _walk_rank(candidate.walk))
        if len(team) == 1 and self.polish_trials > 0:
            found.extend(self._polish(seen, team, found[: self.polished], limit))
        return min((candidate.walk for candidate in found), key=_walk_rank)

    def _polish(self, seen: np.ndarray, team: Team, found: list[Candidate], limit: int) -> list[Candidate]:
        """The covering walks among ``found`` polished by simulating changes to their routes."""
        polished = []
        for candidate in found:
            if not candidate.walk.covered:
                continue
            route, steps = polish_route(
                self._table, self._neighbours, self._goal, seen, team[0], candidate.routes[0],
                limit=limit, trials=self.polish_trials,
            )  # fmt: skip
            if 0 <= steps < candidate.walk.steps:
                polished.append(Candidate(self._simulate(seen, team, [route], limit), [route]))
        return polished

    def _seed_routes(self, seed: str, team: Team, seen: np.ndarray) -> list[np.ndarray] | None:
        """The set-cover tour of the viewpoints still worth visiting, empty routes (the frontier walk)
        or a descent walk's states; None when the seed does not apply."""
        if seed == "frontier":
            return [np.zeros(0, dtype=np.int64)] * len(team)
        if seed in ("descent", "descent-view"):
            if len(team) != 1:
                return None
            (cell, heading), limit = team[0], 10 * int(self._goal.sum()) + 100
            by_view = seed == "descent-view"
            table, neighbours, goal = self._table, self._neighbours, self._goal
            return [descent_states(table, neighbours, goal, seen, cell, heading, limit=limit, by_view=by_view)]
        viewpoints = self.cover.viewpoints
        return self._route(viewpoints[self._tally.counts[viewpoints] > 0], team)

    def _sweep_walks(self, seed: str, seen: np.ndarray, team: Team, limit: int) -> list[Candidate]:
        """One guard's refined walks along lanes or spirals one cone swath apart: the
        :data:`LAWNMOWER_REFINED` best of the eight lawnmower routes, or the four spirals from its cell."""
        if len(team) != 1:
            return []
        key = ("tour-" + seed, self._goal_key[1])
        if key not in self._memo:
            half = swath_half_width(self._table, self._goal, self._grid.shape[1])
            if seed == "lawnmower":
                self._memo[key] = lane_routes(self._goal, self._grid.shape, self._table.entry, 2 * half + 1)
            else:
                self._memo[key] = spiral_rings(self._goal, self._grid.shape, 2 * half + 1)
        if seed == "spiral":
            routes = spiral_routes(self._memo[key], self._grid.shape[1], self._table.entry, team[0][0])
            return [self._refine(seen, team, [route], limit) for route in routes]
        routes = self._memo[key]
        ranks = [_walk_rank(self._simulate(seen, team, [route], limit)) for route in routes]
        best = sorted(range(len(routes)), key=ranks.__getitem__)[:LAWNMOWER_REFINED]
        return [self._refine(seen, team, [routes[index]], limit) for index in best]

    def _search_tables(self, cell: int, heading: int) -> tuple[SearchGraph, Heuristic] | None:
        """The exact search's graph over the residual goal and its estimate, from one guard's start
        (kept for the latest start only: they take up to positions x goal cells x 2 bytes); None on
        levels of more than :data:`BEAM_POSITIONS` positions."""
        grid = self._grid
        key = (self._goal_key[1], cell, heading)
        cached = self._memo.get("tour-search")
        if cached is None or cached[0] != key:
            tables = None
            cells = np.flatnonzero(self._goal)
            lengths = np.diff(self._table.sight_start)[state_of(cells[:, None], np.arange(4))]
            # Headings matter (four positions per cell) as soon as one cell's headings see different counts.
            if cells.size * (4 if (lengths != lengths[:, :1]).any() else 1) <= BEAM_POSITIONS:
                graph = build_search_graph(grid, self._table, grid.unflat(cell), heading)
                if graph.positions <= BEAM_POSITIONS:
                    # The same covering walks over far fewer goal cells: a sharper estimate, smaller tables.
                    graph = residual_goal(graph)
                    tables = (graph, build_heuristic(graph, pool=BEAM_POOL))
            cached = (key, tables)
            self._memo["tour-search"] = cached
        result: tuple[SearchGraph, Heuristic] | None = cached[1]
        return result

    def _macro_routes(self, team: Team, seen: np.ndarray) -> MacroRoutes:
        """The states the beam's walk and the exact search's walk arrive in at their macro moves."""
        none = MacroRoutes(None, None, -1)
        if len(team) != 1:
            return none
        (cell, heading) = team[0]
        tables = self._search_tables(cell, heading)
        if tables is None:
            return none
        graph, heuristic = tables
        known = goal_bits(graph, seen)
        first, last = BEAM_WIDTHS
        route, steps, _ = widening_beam_route(
            graph, heuristic, known, first_width=first, most_width=last, max_estimates=BEAM_ESTIMATES
        )
        if steps < 0:
            return none
        beam = _arrivals(graph, route, heading)
        # The exact search knows only what the start sees: with more seen before, it would not be exact.
        if "exact" not in self.seeds or graph.goal_cells.size > EXACT_GOAL or (known & ~graph.views[graph.start]).any():
            return MacroRoutes(beam, None, -1)
        better, optimum, proved = search_route(
            graph, heuristic, steps, max_expansions=EXACT_EXPANSIONS, max_nodes=EXACT_NODES
        )
        exact = _arrivals(graph, better, heading) if better.size else (beam if proved else None)
        return MacroRoutes(beam, exact, optimum if proved else -1)

    def _route(self, states: np.ndarray, team: Team) -> list[np.ndarray]:
        """Per guard, an order of its share of ``states`` (state numbers)."""
        # Distance fields kept over the plan: the refinement rounds of every seed route mostly the same
        # states again, and each field is a breadth-first search.
        cost = route_costs(self._neighbours, self._table.entry, states, team, self._entry_fields)
        routes = plan_routes(cost, np.arange(states.size, cost.shape[0]), np.arange(states.size))
        return [states[route] for route in routes]

    def _refine(self, seen: np.ndarray, team: Team, routes: list[np.ndarray], limit: int) -> Candidate:
        """Walk the routes; then route again through the states the walk actually arrived in, while it helps."""
        best = Candidate(self._simulate(seen, team, routes, limit), routes)
        for _ in range(self.refine_rounds):
            visited = np.unique(np.concatenate(best.walk.visits))
            again = self._route(visited, team)
            walk = self._simulate(seen, team, again, limit)
            if _walk_rank(walk) >= _walk_rank(best.walk):
                break
            best = Candidate(walk, again)
        return best

    def _simulate(self, seen: np.ndarray, team: Team, routes: list[np.ndarray], limit: int) -> RouteWalk:
        """The team's walk along ``routes`` from the current state."""
        return walk_routes(self._table, self._neighbours, self._goal, seen, team, routes, limit=limit)


def _arrivals(graph: SearchGraph, route: np.ndarray, heading: int) -> np.ndarray:
    """The states a walk along a macro-move route (the start first) arrives in, the start left out."""
    walk, ends = route_steps(graph, route, heading)
    return np.array([state_of(*walk[end]) for end in ends[1:]], dtype=np.int64)


def _walk_rank(walk: RouteWalk) -> tuple[bool, int, int]:
    """Covered first, then fewer ticks, then fewer moves."""
    return (not walk.covered, walk.steps, walk.total_moves)
