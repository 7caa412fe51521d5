"""The simulation loop: guards, their vision and their planners, tick by tick until the level is seen.

One tick, for every guard at once: each planner decides on the same state, every guard moves (guards
may share a cell), then every guard looks and the cells it sees are marked seen. The start is tick 0 and
has only the look. The loop owns the limits and termination; a planner that offers an
:class:`~guardsim.planners.base.Accelerator` (RippleFront does) advances the same state by whole ticks
in compiled code. Nothing here draws.

Examples
--------
Step a guard tick by tick from a game loop, reading its position in world coordinates:

>>> from guardsim.level import parse_level
>>> from guardsim.scene import Scene
>>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [6, 0], [6, 4], [0, 4]]}))
>>> sim = Simulation(scene)
>>> sim.reset(starts=[(0, 0)], headings=[0])
>>> while not sim.done:
...     sim.step()
>>> sim.tick, sim.outcome, sim.positions[0]
(1, 'covered', (0.5, 1.5))
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.kernels.distances import FAR
from guardsim.planners import make_planner
from guardsim.planners.base import (
    OUTCOME,
    RUNNING,
    STAY,
    TICK,
    UNSEEN,
    Accelerator,
    EpisodeArrays,
    EpisodeSetup,
    GuardState,
    Planner,
)
from guardsim.scene import Scene
from guardsim.simulation.reads import EpisodeReads
from guardsim.starts import check_headings, checked_starts, episode_start, team_starts
from guardsim.trace import OUTCOMES, Trace
from guardsim.vision.rules import VisionFunction

if TYPE_CHECKING:
    pass

__all__ = ["Simulation", "default_max_steps"]


def default_max_steps(grid: CoverageGrid) -> int:
    """The step limit when none is given: ten steps per traversable cell, at least 100."""
    return max(100, 10 * int(grid.traversable.sum()))


class Simulation(EpisodeReads):
    """One episode of a guard (or a team) on a scene, advanced by :meth:`step` or run by :meth:`run`.

    Parameters
    ----------
    scene
        The level, world, grid and vision.
    planner
        A planner name from :data:`guardsim.planners.PLANNERS` (one fresh planner per guard, made with
        ``planner_options``), or planner objects, one per guard (a single object for one guard).
    guards
        Team size, with a planner name; with planner objects, their number.
    max_steps
        Step limit in ticks; :func:`default_max_steps` by default.
    vision
        Which cells a state sees; the scene's cache by default.
    reference
        Use the reference vision and no accelerator: the plain loop, for checking the fast path.
    record_field
        Keep guard 0's planner field (its ``distance`` array, RippleFront's D) at every tick, for the
        trace's :attr:`~guardsim.trace.Trace.field`. The compiled tick then runs one tick per call.
    planner_options
        Options for :func:`~guardsim.planners.make_planner`.
    """

    def __init__(
        self,
        scene: Scene,
        planner: str | Planner | Sequence[Planner] = "ripplefront",
        *,
        guards: int = 1,
        max_steps: int | None = None,
        vision: VisionFunction | None = None,
        reference: bool = False,
        record_field: bool = False,
        **planner_options: Any,
    ) -> None:
        if isinstance(planner, str):
            if guards < 1:
                raise ArgumentError("a team needs at least one guard")
            self.planners: list[Planner] = [make_planner(planner, **planner_options) for _ in range(guards)]
        else:
            self.planners = list(cast("Sequence[Planner]", planner)) if isinstance(planner, Sequence) else [planner]
            if not self.planners:
                raise ArgumentError("a team needs at least one guard")
        self.scene = scene
        self.limit = default_max_steps(scene.grid) if max_steps is None else int(max_steps)
        self.vision: VisionFunction = vision or scene.vision(reference=reference)
        self.reference = reference
        self.record_field = record_field
        self._fields: list[np.ndarray] = []
        self.seed: int | None = None
        self._episode: EpisodeArrays | None = None
        self._accelerator: Accelerator | None = None
        self._setup_done = False

    # -- starting -------------------------------------------------------------------------------

    def reset(
        self,
        *,
        seed: int | None = None,
        episode: int | None = None,
        starts: Sequence[tuple[int, int]] | None = None,
        headings: Sequence[int] | None = None,
        rng: np.random.Generator | None = None,
        seen: np.ndarray | None = None,
    ) -> None:
        """Start a new episode and look from the start (tick 0).

        Without ``starts``, guard 0 starts as ``guardsim play --seed SEED [--episode K]`` would (the
        level's start, or one drawn from the seed), and teammates are drawn after it. With ``starts``
        (``(col, row)`` cells, one per guard) and ``headings`` (heading numbers, 0 right, 1 down, 2
        left, 3 up), those are used, and ``rng`` (or a generator from ``seed``) feeds the planners.
        ``seen`` (``bool (rows, cols)``) marks cells already seen before the start (first seen at tick
        0), so an episode can carry on from another one's coverage.
        """
        guards = len(self.planners)
        self.seed = seed
        if starts is None:
            generator, cell, heading = episode_start(self.scene, seed=seed or 0, episode=episode)
            cells, facing = team_starts(self.scene, (cell, heading), guards, rng=generator)
            facing = check_headings(headings, guards) or facing
        else:
            cells, facing = checked_starts(self.scene.grid, starts, headings, guards)
            generator = rng if rng is not None else np.random.default_rng(seed or 0)
        if rng is not None:
            generator = rng
        grid = self.scene.grid
        goal = np.zeros(grid.size, dtype=bool)
        for col, row in cells:
            goal |= grid.component(col, row).ravel()
        episode_arrays = EpisodeArrays(
            seen=np.zeros(grid.size, dtype=bool),
            first_seen=np.full(grid.size, -1, dtype=np.int64),
            goal=goal,
            cells=np.zeros((guards, self.limit + 1), dtype=np.int64),
            headings=np.zeros((guards, self.limit + 1), dtype=np.int64),
            unseen_counts=np.zeros(self.limit + 1, dtype=np.int64),
            counters=np.array([0, int(goal.sum()), RUNNING], dtype=np.int64),
        )
        if seen is not None:
            known = np.asarray(seen, dtype=bool).ravel()
            if known.size != grid.size:
                raise ArgumentError(f"seen has {known.size} cells; the grid has {grid.size}")
            episode_arrays.seen[known] = True
            episode_arrays.first_seen[known] = 0
            episode_arrays.counters[UNSEEN] -= int((goal & known).sum())
        for number, ((col, row), heading) in enumerate(zip(cells, facing)):
            episode_arrays.cells[number, 0] = grid.flat(col, row)
            episode_arrays.headings[number, 0] = heading
        self._episode = episode_arrays
        self._seen_view = episode_arrays.seen.view()
        self._seen_view.flags.writeable = False
        self._goal_view = goal.view()
        self._goal_view.flags.writeable = False
        self._accelerator = None
        for number, planner in enumerate(self.planners):
            planner.reset(EpisodeSetup(grid, self._goal_view, self.vision, generator, number, guards))
        if guards == 1 and not self.reference:
            offer = getattr(self.planners[0], "accelerator", None)
            if offer is not None:
                self._accelerator = offer(EpisodeSetup(grid, self._goal_view, self.vision, generator, 0, 1))
        self._fields = []
        self._look(0)
        self._check_end()

    # -- the tick -------------------------------------------------------------------------------

    def step(self) -> None:
        """Advance every guard by one tick: decide, move, look. Does nothing once the episode is done."""
        episode = self._require()
        if self.done:
            return
        if self._accelerator is not None:
            self._accelerator.advance(episode, self.limit, 1)
            self._place_guard()
            self._record_field()
            return
        tick = int(episode.counters[TICK])
        grid = self.scene.grid
        guards = len(self.planners)
        cells = episode.cells[:, tick].tolist()
        facing = episode.headings[:, tick].tolist()
        team = tuple(zip(cells, facing)) if guards > 1 else ()
        moves = [
            planner.next_move(
                GuardState(tick, cells[number], facing[number], self._seen_view, self._goal_view, number, team)
            )
            for number, planner in enumerate(self.planners)
        ]
        self._record_field()
        if all(move is None for move in moves):
            episode.counters[OUTCOME] = OUTCOMES.index("stuck")
            return
        for number, move in enumerate(moves):
            if move is not None and move != STAY:
                target = int(grid.neighbours[cells[number], move])
                if target < 0:
                    raise RuntimeError(
                        f"planner {self.planners[number].name} chose a move into a wall from cell "
                        f"{grid.unflat(cells[number])}"
                    )
                cells[number], facing[number] = target, move
        tick += 1
        episode.cells[:, tick] = cells
        episode.headings[:, tick] = facing
        episode.counters[TICK] = tick
        self._look(tick)
        self._check_end()

    def run(self) -> Trace:
        """Run the episode to its end (covered, step limit or stuck) and return its trace."""
        episode = self._require()
        if not self.done:
            if self._accelerator is not None and not self.record_field:
                self._accelerator.advance(episode, self.limit, -1)
                self._place_guard()
            while not self.done:
                self.step()
        return self.trace()

    def _look(self, tick: int) -> None:
        """Every guard looks from where it stands at ``tick``; the cells it sees are marked seen."""
        episode = self._require()
        grid = self.scene.grid
        seen, first_seen = episode.seen, episode.first_seen
        newly_goal = 0
        for number in range(len(self.planners)):
            col, row = grid.unflat(int(episode.cells[number, tick]))
            visible = self.vision(col, row, int(episode.headings[number, tick]))
            new = visible[~seen[visible]]
            seen[new] = True
            first_seen[new] = tick
            newly_goal += int(episode.goal[new].sum())
        episode.counters[UNSEEN] -= newly_goal
        episode.unseen_counts[tick] = episode.counters[UNSEEN]
        self._place_guard()

    def _place_guard(self) -> None:
        """Put guard 0's body in the physics space where the guard now stands (the world has one body)."""
        self.scene.world.place_guard(self.positions[0])

    def _record_field(self) -> None:
        """Keep guard 0's field as it decided this tick's move (the field of the tick before the move)."""
        if not self.record_field:
            return
        distance = getattr(self.planners[0], "distance", None)
        if distance is None:
            raise ArgumentError(f"planner {self.planners[0].name} keeps no field to record")
        field = np.asarray(distance, dtype=np.int64).reshape(self.scene.grid.shape)
        self._fields.append(np.where(field >= FAR, -1, field).astype(np.int32))

    def _check_end(self) -> None:
        episode = self._require()
        if episode.counters[UNSEEN] == 0:
            episode.counters[OUTCOME] = OUTCOMES.index("covered")
        elif episode.counters[TICK] >= self.limit:
            episode.counters[OUTCOME] = OUTCOMES.index("step_limit")

    def _require(self) -> EpisodeArrays:
        if self._episode is None:
            raise RuntimeError("call reset() before stepping the simulation")
        return self._episode

    def trace(self) -> Trace:
        """The record of the episode so far (complete once :attr:`done`)."""
        episode = self._require()
        ticks = self.tick + 1
        planner = self.planners[0]
        return Trace.of_episode(
            self.scene,
            planner=planner.name,
            seed=self.seed,
            cells=episode.cells[:, :ticks],
            headings=episode.headings[:, :ticks],
            unseen=episode.unseen_counts[:ticks],
            outcome=self.outcome or "running",
            first_seen=episode.first_seen,
            goal=episode.goal,
            planner_options=dict(getattr(planner, "options", {})),
            field=self._recorded_field(ticks),
        )

    def _recorded_field(self, ticks: int) -> np.ndarray | None:
        if not self.record_field:
            return None
        rows, cols = self.scene.grid.shape
        fields = self._fields[:ticks] or [np.full((rows, cols), -1, dtype=np.int32)]
        fields += [fields[-1]] * (ticks - len(fields))
        return np.stack(fields)
