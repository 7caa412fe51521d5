"""The simulation loop: a guard, its vision and a planner, tick by tick until the level is seen.

The loop owns the limits and termination; vision and planner are handed in. Nothing here draws.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from guardsim.errors import LevelError
from guardsim.grid import CoverageGrid, build_grid, start_cell
from guardsim.level import HEADINGS, Level
from guardsim.planners import make_planner
from guardsim.planners.base import GuardState, Planner
from guardsim.trace import Trace
from guardsim.vision import VisionCone, visible_cells
from guardsim.world import World

__all__ = [
    "Scene",
    "VisionFunction",
    "choose_start",
    "default_max_steps",
    "episode_generator",
    "run_batch_episode",
    "run_episode",
]

#: ``(col, row, heading) -> flat indices of the cells seen``.
VisionFunction = Callable[[int, int, int], np.ndarray]


@dataclass(frozen=True, eq=False)
class Scene:
    """A level with everything built from it once and shared by its episodes."""

    level: Level
    world: World
    grid: CoverageGrid
    cone: VisionCone

    @classmethod
    def from_level(cls, level: Level) -> Scene:
        """Build the physics world, the grid and the cone of a level."""
        world = World(level)
        grid = build_grid(level, world)
        return cls(level, world, grid, VisionCone.from_guard(level.guard, level.cell_size))

    def vision(self, *, reference: bool = False) -> VisionFunction:
        """The vision to use: the fast path by default, the per-cell-ray reference on request.

        Both give the same cells for every state; the fast path is what ``play`` and ``bench`` use.
        """
        return self.reference_vision()

    def reference_vision(self) -> VisionFunction:
        """The reference vision: one pymunk ray per cell in the cone, every tick."""

        def see(col: int, row: int, heading: int) -> np.ndarray:
            return visible_cells(self.world, self.grid, self.cone, col, row, heading)

        return see


def episode_generator(seed: int, episode: int) -> np.random.Generator:
    """The generator of episode ``episode`` in a batch seeded with ``seed``.

    It is the ``episode``-th child of ``SeedSequence(seed).spawn(...)``, built directly, so an episode
    draws the same numbers whether it runs alone, in a batch, or on any worker.

    Examples
    --------
    >>> children = np.random.SeedSequence(5).spawn(3)
    >>> bool(episode_generator(5, 2).integers(1000) == np.random.default_rng(children[2]).integers(1000))
    True
    """
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(episode,)))


def default_max_steps(grid: CoverageGrid) -> int:
    """The step limit when none is given: ten steps per traversable cell, at least 100."""
    return max(100, 10 * int(grid.traversable.sum()))


def choose_start(
    scene: Scene,
    *,
    rng: np.random.Generator,
    point: tuple[float, float] | None = None,
    heading: str | None = None,
) -> tuple[tuple[int, int], int]:
    """The start cell and heading number of an episode.

    The start is ``point`` if given, else drawn uniformly from the largest connected area; the heading
    is ``heading`` if given, else drawn uniformly from the four. The draws happen in that order, start
    first, so a given seed always gives the same episode.
    """
    grid = scene.grid
    if point is not None:
        cell = start_cell(scene.level, grid, point)
    else:
        candidates = np.flatnonzero(grid.largest_component())
        if candidates.size == 0:
            raise LevelError(f"{scene.level.source}: no cell where the guard fits; nothing to cover")
        cell = grid.unflat(int(candidates[rng.integers(candidates.size)]))
    heading_number = HEADINGS[heading] // 90 if heading is not None else int(rng.integers(4))
    return cell, heading_number


def run_batch_episode(
    scene: Scene,
    *,
    seed: int,
    episode: int,
    planner: str = "ripplefront",
    reference: bool = False,
    max_steps: int | None = None,
    **planner_options: object,
) -> Trace:
    """Episode ``episode`` of a batch seeded with ``seed``: start and heading drawn from its generator.

    This is what ``guardsim bench`` runs for each episode and ``guardsim play --seed S --episode K``
    re-runs alone; the trace is the same either way.
    """
    cell, heading = choose_start(scene, rng=episode_generator(seed, episode))
    return run_episode(
        scene,
        make_planner(planner, **planner_options),
        cell,
        heading,
        vision=scene.vision(reference=reference),
        max_steps=max_steps,
        seed=seed,
    )


def run_episode(
    scene: Scene,
    planner: Planner,
    start: tuple[int, int],
    heading: int,
    *,
    vision: VisionFunction | None = None,
    max_steps: int | None = None,
    seed: int | None = None,
) -> Trace:
    """Walk the guard from ``start`` until every reachable cell is seen or a limit stops it.

    Parameters
    ----------
    scene
        The level, world, grid and cone.
    planner
        Picks each move; it is reset here.
    start, heading
        ``(col, row)`` of a traversable cell and the first heading number.
    vision
        Which cells a state sees; :meth:`Scene.vision` by default.
    max_steps
        Step limit; :func:`default_max_steps` by default.
    seed
        Recorded in the trace only.
    """
    grid = scene.grid
    see = vision or scene.vision()
    limit = default_max_steps(grid) if max_steps is None else max_steps
    goal = grid.component(*start).ravel()
    goal_count = int(goal.sum())
    seen = np.zeros(grid.size, dtype=bool)
    first_seen = np.full(grid.size, -1, dtype=np.int64)
    cell = grid.flat(*start)
    unseen_left = goal_count
    path = [start]
    headings = [heading]
    unseen_percent: list[float] = []
    planner.reset(grid, goal)

    def look(tick: int) -> int:
        col, row = grid.unflat(cell)
        scene.world.place_guard(grid.centre(col, row))
        visible = see(col, row, heading)
        new = visible[~seen[visible]]
        seen[new] = True
        first_seen[new] = tick
        newly_goal = int(goal[new].sum())
        unseen_percent.append(round(100.0 * (unseen_left - newly_goal) / goal_count, 4))
        return newly_goal

    unseen_left -= look(0)
    outcome = "covered"
    tick = 0
    seen_view = seen.view()
    seen_view.flags.writeable = False
    goal.flags.writeable = False
    while unseen_left > 0:
        if tick >= limit:
            outcome = "step_limit"
            break
        move = planner.next_move(GuardState(tick, cell, heading, seen_view, goal))
        if move is None:
            outcome = "stuck"
            break
        target = int(grid.neighbours[cell, move])
        if target < 0:
            raise RuntimeError(f"planner {planner.name} chose a move into a wall from cell {grid.unflat(cell)}")
        tick += 1
        cell, heading = target, move
        path.append(grid.unflat(cell))
        headings.append(heading)
        unseen_left -= look(tick)
    traversable = grid.traversable
    return Trace(
        level=scene.level.name,
        planner=planner.name,
        seed=seed,
        cell_size=grid.cell_size,
        origin=grid.origin,
        shape=grid.shape,
        path=tuple(path),
        headings=tuple(headings),
        unseen_percent=tuple(unseen_percent),
        outcome=outcome,
        reachable=goal_count,
        unreachable=int(traversable.sum()) - goal_count,
        first_seen=first_seen.reshape(grid.shape),
        goal=goal.reshape(grid.shape).copy(),
        traversable=traversable.copy(),
    )
