"""The simulation loop: a guard, its vision and a planner, tick by tick until the level is seen.

The loop owns the limits and termination; vision and planner are handed in. Nothing here draws.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from guardsim.errors import LevelError
from guardsim.fast_ripplefront import run_compiled
from guardsim.grid import CoverageGrid, build_grid, start_cell
from guardsim.level import HEADINGS, Level
from guardsim.planners import make_planner
from guardsim.planners.base import GuardState, Planner
from guardsim.planners.ripplefront import RippleFront
from guardsim.trace import OUTCOMES, Trace
from guardsim.vision import VisionCone, visible_cells
from guardsim.vision_cache import VisionCache
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
    vision_cache: VisionCache
    """Visible cells per state, filled as episodes meet them and shared by all of them."""

    @classmethod
    def from_level(cls, level: Level) -> Scene:
        """Build the physics world, the grid and the cone of a level."""
        world = World(level)
        grid = build_grid(level, world)
        cone = VisionCone.from_guard(level.guard, level.cell_size, grid_shape=grid.shape)
        return cls(level, world, grid, cone, VisionCache(world, grid, cone))

    def vision(self, *, reference: bool = False) -> VisionFunction:
        """The vision to use: the shared cache by default, the per-cell-ray reference on request.

        Both give the same cells for every state (tested on every state of the shipped levels).
        """
        return self.reference_vision() if reference else self.vision_cache

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
        reference=reference,
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
    reference: bool = False,
    max_steps: int | None = None,
    seed: int | None = None,
) -> Trace:
    """Walk the guard from ``start`` until every reachable cell is seen or a limit stops it.

    A :class:`RippleFront` planner with the default vision runs on the compiled fast path
    (:mod:`guardsim.fast_ripplefront`); ``reference=True`` runs the plain loop with the reference
    vision and full-grid sweeps instead. Both give the same trace.

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
    reference
        Use the reference vision and the planner's own loop, for checking the fast path.
    max_steps
        Step limit; :func:`default_max_steps` by default.
    seed
        Recorded in the trace only.
    """
    grid = scene.grid
    limit = default_max_steps(grid) if max_steps is None else max_steps
    goal = grid.component(*start).ravel()
    if vision is None and not reference and isinstance(planner, RippleFront):
        arrays = run_compiled(
            scene.vision_cache,
            grid.neighbours,
            goal,
            grid.flat(*start),
            heading,
            sweeps_per_tick=planner.sweeps_per_tick,
            limit=limit,
        )
        return _trace(
            scene,
            planner.name,
            seed,
            goal,
            path=list(zip((arrays.path % grid.shape[1]).tolist(), (arrays.path // grid.shape[1]).tolist())),
            headings=arrays.headings.tolist(),
            unseen_counts=arrays.unseen_counts.tolist(),
            first_seen=arrays.first_seen,
            outcome=OUTCOMES[arrays.outcome],
        )
    see = vision or scene.vision(reference=reference)
    seen = np.zeros(grid.size, dtype=bool)
    first_seen = np.full(grid.size, -1, dtype=np.int64)
    cell = grid.flat(*start)
    unseen_left = int(goal.sum())
    path = [start]
    headings = [heading]
    unseen_counts: list[int] = []
    planner.reset(grid, goal)

    def look(tick: int) -> int:
        col, row = grid.unflat(cell)
        scene.world.place_guard(grid.centre(col, row))
        visible = see(col, row, heading)
        new = visible[~seen[visible]]
        seen[new] = True
        first_seen[new] = tick
        newly_goal = int(goal[new].sum())
        unseen_counts.append(unseen_left - newly_goal)
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
    return _trace(
        scene,
        planner.name,
        seed,
        goal,
        path=path,
        headings=headings,
        unseen_counts=unseen_counts,
        first_seen=first_seen,
        outcome=outcome,
    )


def _trace(
    scene: Scene,
    planner: str,
    seed: int | None,
    goal: np.ndarray,
    *,
    path: list[tuple[int, int]],
    headings: list[int],
    unseen_counts: list[int],
    first_seen: np.ndarray,
    outcome: str,
) -> Trace:
    """Assemble a trace; both loops share it so their traces agree to the byte."""
    grid = scene.grid
    goal_count = int(goal.sum())
    traversable = grid.traversable
    return Trace(
        level=scene.level.name,
        planner=planner,
        seed=seed,
        cell_size=grid.cell_size,
        origin=grid.origin,
        shape=grid.shape,
        path=tuple(path),
        headings=tuple(headings),
        unseen_percent=tuple(round(100.0 * count / goal_count, 4) for count in unseen_counts),
        outcome=outcome,
        reachable=goal_count,
        unreachable=int(traversable.sum()) - goal_count,
        first_seen=first_seen.reshape(grid.shape),
        goal=goal.reshape(grid.shape).copy(),
        traversable=traversable.copy(),
    )
