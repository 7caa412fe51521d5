"""The simulation loop: a guard, its vision and a planner, tick by tick until the level is seen.

The loop owns the limits and termination; vision and planner are handed in. Nothing here draws.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from guardsim.bresenham import bresenham_visible
from guardsim.errors import LevelError
from guardsim.fast_ripplefront import run_compiled
from guardsim.grid import CoverageGrid, build_grid, start_cell
from guardsim.level import HEADINGS, Level
from guardsim.planners import make_planner
from guardsim.planners.base import STAY, EpisodeSetup, GuardState, Planner, VisionFunction
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
    "run_team_episode",
    "team_starts",
]


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
    def from_level(cls, level: Level, *, line_of_sight: str = "pymunk") -> Scene:
        """Build the physics world, the grid and the cone of a level.

        ``line_of_sight`` is ``"pymunk"`` (rays against the walls) or ``"bresenham"`` (grid lines; see
        :mod:`guardsim.bresenham`).
        """
        world = World(level)
        grid = build_grid(level, world)
        cone = VisionCone.from_guard(level.guard, level.cell_size, grid_shape=grid.shape)
        return cls(level, world, grid, cone, VisionCache(world, grid, cone, line_of_sight=line_of_sight))

    def vision(self, *, reference: bool = False) -> VisionFunction:
        """The vision to use: the shared cache by default, the per-cell-ray reference on request.

        Both give the same cells for every state (tested on every state of the shipped levels).
        """
        return self.reference_vision() if reference else self.vision_cache

    @property
    def line_of_sight(self) -> str:
        """The line-of-sight rule, ``"pymunk"`` or ``"bresenham"``."""
        return self.vision_cache.line_of_sight

    def reference_vision(self) -> VisionFunction:
        """The reference vision: one pymunk ray (or Bresenham line) per cell in the cone, every tick."""
        if self.line_of_sight == "bresenham":

            def see_on_grid(col: int, row: int, heading: int) -> np.ndarray:
                return bresenham_visible(self.grid.traversable, col, row, self.cone.offsets[heading])

            return see_on_grid

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


def team_starts(
    scene: Scene,
    first: tuple[tuple[int, int], int],
    guards: int,
    *,
    rng: np.random.Generator,
) -> tuple[list[tuple[int, int]], list[int]]:
    """Starts and headings of a team: ``first`` for guard 0, the others drawn from its connected area.

    Each further guard draws a cell uniformly from the cells reachable from guard 0, then a heading,
    in guard order, after guard 0's own draws, so one guard's episode is the same with or without
    this call.
    """
    cells, headings = [first[0]], [first[1]]
    area = np.flatnonzero(scene.grid.component(*first[0]))
    for _ in range(guards - 1):
        cells.append(scene.grid.unflat(int(area[rng.integers(area.size)])))
        headings.append(int(rng.integers(4)))
    return cells, headings


def run_batch_episode(
    scene: Scene,
    *,
    seed: int,
    episode: int,
    planner: str = "ripplefront",
    guards: int = 1,
    reference: bool = False,
    max_steps: int | None = None,
    **planner_options: object,
) -> Trace:
    """Episode ``episode`` of a batch seeded with ``seed``: starts and headings drawn from its generator.

    This is what ``guardsim bench`` runs for each episode and ``guardsim play --seed S --episode K``
    re-runs alone; the trace is the same either way. The same generator then feeds the planners.
    """
    rng = episode_generator(seed, episode)
    cells, headings = team_starts(scene, choose_start(scene, rng=rng), guards, rng=rng)
    planners = [make_planner(planner, **planner_options) for _ in range(guards)]
    return run_team_episode(
        scene, planners, cells, headings, rng=rng, reference=reference, max_steps=max_steps, seed=seed
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
    rng: np.random.Generator | None = None,
) -> Trace:
    """One guard walks from ``start`` until every reachable cell is seen or a limit stops it.

    See :func:`run_team_episode` for the parameters; this is the team of one.
    """
    return run_team_episode(
        scene,
        [planner],
        [start],
        [heading],
        vision=vision,
        reference=reference,
        max_steps=max_steps,
        seed=seed,
        rng=rng,
    )


def run_team_episode(
    scene: Scene,
    planners: Sequence[Planner],
    starts: Sequence[tuple[int, int]],
    headings: Sequence[int],
    *,
    vision: VisionFunction | None = None,
    reference: bool = False,
    max_steps: int | None = None,
    seed: int | None = None,
    rng: np.random.Generator | None = None,
) -> Trace:
    """Walk a team of guards, one planner each, until every reachable cell is seen or a limit stops them.

    Each tick every planner decides on the same state, then all guards move at once (guards may share a
    cell), then all look. A single :class:`RippleFront` guard with the default vision runs on the
    compiled fast path (:mod:`guardsim.fast_ripplefront`); ``reference=True`` runs this loop with the
    reference vision and the planner's full-grid sweeps instead. Both give the same trace.

    Parameters
    ----------
    scene
        The level, world, grid and cone.
    planners, starts, headings
        One planner, ``(col, row)`` start cell and first heading number per guard.
    vision
        Which cells a state sees; :meth:`Scene.vision` by default.
    reference
        Use the reference vision, for checking the fast path.
    max_steps
        Step limit (ticks); :func:`default_max_steps` by default.
    seed
        Recorded in the trace only.
    rng
        The generator handed to the planners; a fresh one from ``seed`` (or 0) by default.

    Returns
    -------
    Trace
        Guard 0's path as ``path``; with several guards, every guard's in ``guard_paths``.
    """
    grid = scene.grid
    limit = default_max_steps(grid) if max_steps is None else max_steps
    goal = np.zeros(grid.size, dtype=bool)
    for start in starts:
        goal |= grid.component(*start).ravel()
    single = len(planners) == 1
    if single and vision is None and not reference and type(planners[0]) is RippleFront:
        arrays = run_compiled(
            scene.vision_cache,
            grid.neighbours,
            goal,
            grid.flat(*starts[0]),
            headings[0],
            sweeps_per_tick=planners[0].sweeps_per_tick,
            limit=limit,
        )
        path = list(zip((arrays.path % grid.shape[1]).tolist(), (arrays.path // grid.shape[1]).tolist()))
        return _trace(
            scene,
            planners[0].name,
            seed,
            goal,
            paths=[path],
            headings=[arrays.headings.tolist()],
            unseen_counts=arrays.unseen_counts.tolist(),
            first_seen=arrays.first_seen,
            outcome=OUTCOMES[arrays.outcome],
        )
    see = vision or scene.vision(reference=reference)
    generator = rng if rng is not None else np.random.default_rng(seed or 0)
    seen = np.zeros(grid.size, dtype=bool)
    first_seen = np.full(grid.size, -1, dtype=np.int64)
    cells = [grid.flat(*start) for start in starts]
    facing = list(headings)
    unseen_left = int(goal.sum())
    paths = [[tuple(start)] for start in starts]
    heading_log = [[heading] for heading in headings]
    unseen_counts: list[int] = []
    seen_view = seen.view()
    seen_view.flags.writeable = False
    goal.flags.writeable = False
    for number, planner in enumerate(planners):
        planner.reset(EpisodeSetup(grid, goal, see, generator, number, len(planners)))

    def look(tick: int) -> int:
        newly_goal = 0
        for cell, heading in zip(cells, facing):
            col, row = grid.unflat(cell)
            scene.world.place_guard(grid.centre(col, row))
            visible = see(col, row, heading)
            new = visible[~seen[visible]]
            seen[new] = True
            first_seen[new] = tick
            newly_goal += int(goal[new].sum())
        unseen_counts.append(unseen_left - newly_goal)
        return newly_goal

    unseen_left -= look(0)
    outcome = "covered"
    tick = 0
    while unseen_left > 0:
        if tick >= limit:
            outcome = "step_limit"
            break
        team = tuple(zip(cells, facing)) if not single else ()
        moves = [
            planner.next_move(GuardState(tick, cells[number], facing[number], seen_view, goal, number, team))
            for number, planner in enumerate(planners)
        ]
        if all(move is None for move in moves):
            outcome = "stuck"
            break
        tick += 1
        for number, move in enumerate(moves):
            if move is not None and move != STAY:
                target = int(grid.neighbours[cells[number], move])
                if target < 0:
                    raise RuntimeError(
                        f"planner {planners[number].name} chose a move into a wall from cell {grid.unflat(cells[number])}"
                    )
                cells[number], facing[number] = target, move
            paths[number].append(grid.unflat(cells[number]))
            heading_log[number].append(facing[number])
        unseen_left -= look(tick)
    return _trace(
        scene,
        planners[0].name,
        seed,
        goal,
        paths=paths,
        headings=heading_log,
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
    paths: list[list[tuple[int, int]]],
    headings: list[list[int]],
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
        path=tuple(paths[0]),
        headings=tuple(headings[0]),
        unseen_percent=tuple(round(100.0 * count / goal_count, 4) for count in unseen_counts),
        outcome=outcome,
        reachable=goal_count,
        unreachable=int(traversable.sum()) - goal_count,
        first_seen=first_seen.reshape(grid.shape),
        goal=goal.reshape(grid.shape).copy(),
        traversable=traversable.copy(),
        guard_paths=tuple(tuple(path) for path in paths) if len(paths) > 1 else (),
        guard_headings=tuple(tuple(log) for log in headings) if len(paths) > 1 else (),
    )
