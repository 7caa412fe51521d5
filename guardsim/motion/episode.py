"""Continuous motion: the guard is a pymunk body walking the planner's route at game speeds.

One physics tick (``1 / tick_hz`` seconds): the follower sets the body's velocity and angular velocity
toward the next corner of the route (:mod:`guardsim.motion.follower`), the space steps, and the guard
looks from its new pose (:mod:`guardsim.motion.sight`). The planners still decide on the grid: a plan is a
grid episode (:class:`guardsim.simulation.Simulation`) from the guard's cell and nearest heading with the
cells seen so far, run to its end; its route is pulled taut (:mod:`guardsim.motion.smoothing`) and walked.
The guard drops the rest of a route as soon as every cell that rest was going to show has been seen (its
cone sweeps while it turns and sees more than the grid guard), and plans again; at a route's end it
faces the planner's last heading if cells planned from there are still unseen, then plans again. See
``docs/motion.md``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from guardsim.motion.follower import Follower
from guardsim.motion.measures import FRACTIONS, continuous_measures
from guardsim.motion.parameters import GuardMotion
from guardsim.motion.sight import PoseVision, pose_visible_cells
from guardsim.motion.smoothing import Waypoints, pull_route
from guardsim.planners import make_planner
from guardsim.scene import Scene
from guardsim.simulation import Simulation, default_max_steps
from guardsim.starts import check_headings, checked_starts, episode_start
from guardsim.trace import Trace

__all__ = ["ContinuousSimulation", "default_max_seconds"]

_RUNNING = None
# Plans in a row that let the guard see nothing new before the episode counts as stuck.
_FRUITLESS_PLANS = 3


def default_max_seconds(scene: Scene, motion: GuardMotion) -> float:
    """The time limit when none is given: the grid's step limit (:func:`default_max_steps`) walked at
    ``move_speed``, one cell per step."""
    return default_max_steps(scene.grid) * scene.grid.cell_size / motion.move_speed


class ContinuousSimulation:
    """One guard in continuous motion on a scene, advanced a physics tick at a time.

    Parameters
    ----------
    scene
        The level, world, grid and vision: pymunk rays from the pose, or the Bresenham line from the
        cell the eye is in (``LineOfSight.BRESENHAM``), the cone along the heading either way.
    planner
        A planner name (a fresh planner, made with ``planner_options``, decides each plan).
    motion
        Walking and turning speeds and the tick rate; the level guard's, else the defaults.
    max_seconds
        Game-time limit; :func:`default_max_seconds` by default.
    max_steps
        Step limit of each grid plan; :func:`~guardsim.simulation.default_max_steps` by default.
    reference
        Look with the reference vision (a pymunk ray per cell) and plan with the reference grid loop.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [12, 0], [12, 3], [0, 3]]}))
    >>> sim = ContinuousSimulation(scene, "ripplefront", motion=GuardMotion(move_speed=2, turn_speed=180))
    >>> sim.reset(starts=[(0, 1)], headings=[0])
    >>> trace = sim.run()
    >>> trace.outcome, trace.seconds, sim.position
    ('covered', 7.9, (8.233333, 2.5))
    """

    def __init__(
        self,
        scene: Scene,
        planner: str = "ripplefront",
        *,
        motion: GuardMotion | None = None,
        max_seconds: float | None = None,
        max_steps: int | None = None,
        reference: bool = False,
        **planner_options: Any,
    ) -> None:
        self.scene = scene
        self.planner = planner
        self.planner_options = planner_options
        self.motion = motion or GuardMotion.of_guard(scene.level.guard)
        seconds = default_max_seconds(scene, self.motion) if max_seconds is None else float(max_seconds)
        self.limit = max(0, math.ceil(seconds * self.motion.tick_hz - 1e-9))
        self.plan_steps = max_steps
        self.reference = reference
        cache = scene.vision_cache
        self._vision = PoseVision(
            scene.world, scene.grid, scene.cone, cache.fill_arrays.walls, rule=scene.line_of_sight
        )
        self.seed: int | None = None
        self._ready = False

    # -- starting -------------------------------------------------------------------------------

    def reset(
        self,
        *,
        seed: int | None = None,
        episode: int | None = None,
        starts: Sequence[tuple[int, int]] | None = None,
        headings: Sequence[int] | None = None,
        rng: np.random.Generator | None = None,
    ) -> None:
        """Start at a cell centre facing a heading number and look (tick 0); the arguments are
        :meth:`guardsim.Simulation.reset`'s, for one guard.

        Without ``starts``, as ``guardsim play --seed SEED [--episode K]`` starts (the level's start, or one
        drawn); with ``starts`` (one ``(col, row)`` cell) and ``headings`` (one heading number), there;
        ``rng`` (or the start's generator) feeds the planners.
        """
        scene, grid = self.scene, self.scene.grid
        self.seed = seed
        if starts is None:
            generator, start, drawn = episode_start(scene, seed=seed or 0, episode=episode)
            facing = check_headings(headings, 1)
            heading = drawn if facing is None else facing[0]
        else:
            generator = np.random.default_rng(seed or 0)
            [start], [heading] = checked_starts(grid, starts, headings, 1)
        self._rng = rng if rng is not None else generator
        self.start = (int(start[0]), int(start[1]))
        self.start_heading = int(heading) % 4
        self._goal = grid.component(*self.start).ravel()
        self._goal_count = int(self._goal.sum())
        self._seen = np.zeros(grid.size, dtype=bool)
        self._first_seen = np.full(grid.size, -1, dtype=np.int64)
        self._unseen = self._goal_count
        self._tick = 0
        self._outcome: str | None = _RUNNING
        self._log = _Log(64)
        self._plans = 0
        self._fruitless = 0
        self._seen_at_plan = 0
        self._planned = np.zeros(1, dtype=np.int64)
        self._planned_tick = np.full(grid.size, -1, dtype=np.int64)
        self._needed = -1
        self._route = Waypoints(np.zeros((0, 2)), np.zeros(0, dtype=np.int64))
        self._corner = 0
        self._final_heading: float | None = None
        centre = grid.centre(*self.start)
        self.follower = Follower(scene.world, self.motion, centre, 90.0 * self.start_heading)
        self._ready = True
        self._look()
        self._check_end()
        if self._outcome is _RUNNING:
            self._choose()

    # -- the tick -------------------------------------------------------------------------------

    def step(self) -> None:
        """One physics tick: steer, step the space, look. Does nothing once the episode is done."""
        self._require()
        if self._outcome is not _RUNNING:
            return
        follower = self.follower
        if follower.facing is not None:
            decide = follower.turn_to(follower.facing)
        else:
            decide = follower.walk_to(self._route.points[self._corner])
            if decide:
                self._corner += 1
        self._tick += 1
        self._look()
        self._check_end()
        if decide and self._outcome is _RUNNING:
            self._choose()

    def run(self) -> Trace:
        """Run to the end (covered, time limit or stuck) and return the trace."""
        self._require()
        while self._outcome is _RUNNING:
            self.step()
        return self.trace()

    # -- deciding -------------------------------------------------------------------------------

    def _choose(self) -> None:
        """At a corner, a faced heading or the start: walk on, face the planner's last heading, or plan."""
        follower = self.follower
        points, ticks = self._route.points, self._route.ticks
        if 0 < self._corner < len(points):
            if self._needed_after(int(ticks[self._corner - 1])):
                return
        elif self._final_heading is not None:
            final, self._final_heading = self._final_heading, None
            if self._needed_after(int(ticks[-1]) - 1) and _angle_between(final, follower.heading) > 1e-9:
                follower.facing = final
                return
        while self._outcome is _RUNNING:
            if self._plan():
                return
            if self._outcome is not _RUNNING:
                return
            last, self._final_heading = self._final_heading, None
            if last is not None and _angle_between(last, follower.heading) > 1e-9:
                follower.facing = last
                return

    def _needed_after(self, tick: int) -> bool:
        """Whether a cell the current plan shows after route tick ``tick`` is still unseen."""
        planned = self._planned
        while self._needed >= 0 and planned[self._needed] == 0:
            self._needed -= 1
        return self._needed > tick

    def _plan(self) -> bool:
        """A grid episode from the guard's cell and nearest heading with the cells seen so far; its route
        pulled taut becomes the route walked. Returns whether it moves the guard."""
        scene, grid, follower = self.scene, self.scene.grid, self.follower
        if self._seen_at_plan == self._goal_count - self._unseen and self._plans:
            self._fruitless += 1
        else:
            self._fruitless = 0
        self._seen_at_plan = self._goal_count - self._unseen
        if self._fruitless >= _FRUITLESS_PLANS:
            self._outcome = "stuck"
            return False
        self._plans += 1
        cell = grid.cell_of(follower.position)
        assert cell is not None
        heading = round(follower.heading / 90.0) % 4
        simulation = Simulation(
            scene,
            [make_planner(self.planner, **self.planner_options)],
            max_steps=self.plan_steps,
            reference=self.reference,
        )
        saved = follower.save()
        simulation.reset(starts=[cell], headings=[heading], rng=self._rng, seen=self._seen.reshape(grid.shape))
        plan = simulation.run()
        follower.restore(saved)
        route = [grid.flat(col, row) for col, row in plan.path]
        self._route = pull_route(scene.world, grid, route, scene.level.guard.radius)
        self._corner = 1
        self._final_heading = 90.0 * plan.headings[-1]
        planned_tick = plan.first_seen.ravel().astype(np.int64)
        planned_tick[self._seen | ~self._goal] = -1
        self._planned_tick = planned_tick
        self._planned = np.bincount(planned_tick[planned_tick >= 0], minlength=len(route)).astype(np.int64)
        self._needed = len(self._planned) - 1
        return len(self._route.points) > 1

    # -- looking --------------------------------------------------------------------------------

    def _look(self) -> None:
        follower = self.follower
        x, y = follower.position
        if self.reference:
            scene = self.scene
            visible = pose_visible_cells(
                scene.world, scene.grid, scene.cone, x, y, follower.heading, rule=scene.line_of_sight
            )
            new = visible[~self._seen[visible]]
        else:
            new = self._vision.unseen_visible(x, y, follower.heading, self._seen)
        tick = self._tick
        if new.size:
            self._seen[new] = True
            self._first_seen[new] = tick
            self._unseen -= int(self._goal[new].sum())
            planned = self._planned_tick[new]
            planned = planned[planned >= 0]
            if planned.size:
                np.subtract.at(self._planned, planned, 1)
        grid = self.scene.grid
        cell = grid.cell_of((x, y))
        self._log.append(
            tick / self.motion.tick_hz, x, y, follower.heading,
            -1 if cell is None else grid.flat(*cell), round(follower.heading / 90.0) % 4, self._unseen,
        )  # fmt: skip

    def _check_end(self) -> None:
        if self._unseen == 0:
            self._outcome = "covered"
        elif self._tick >= self.limit:
            self._outcome = "step_limit"

    def _require(self) -> None:
        if not self._ready:
            raise RuntimeError("call reset() before stepping the simulation")

    # -- what a game reads ----------------------------------------------------------------------

    @property
    def tick(self) -> int:
        """Physics ticks since the start."""
        return self._tick

    @property
    def time(self) -> float:
        """Game seconds since the start."""
        return self._tick / self.motion.tick_hz

    @property
    def done(self) -> bool:
        """Whether the episode has ended."""
        return self._outcome is not _RUNNING

    @property
    def outcome(self) -> str | None:
        """``"covered"``, ``"step_limit"`` (the time limit) or ``"stuck"`` once done; ``None`` while running."""
        return self._outcome

    @property
    def position(self) -> tuple[float, float]:
        """The body's position, world units (rounded to 6 decimals for reading)."""
        x, y = self.follower.position
        return (round(x, 6), round(y, 6))

    @property
    def heading_degrees(self) -> float:
        """The body's heading in degrees (0 along +x, 90 along +y; y down)."""
        return self.follower.heading

    @property
    def seen(self) -> np.ndarray:
        """``bool (rows, cols)``: cells seen so far (a copy)."""
        return self._seen.reshape(self.scene.grid.shape).copy()

    @property
    def coverage(self) -> float:
        """Fraction of the goal cells seen so far."""
        return 1.0 if self._goal_count == 0 else 1.0 - self._unseen / self._goal_count

    @property
    def plans(self) -> int:
        """Grid plans made so far."""
        return self._plans

    def trace(self) -> Trace:
        """The record of the episode so far; its ticks are physics ticks."""
        self._require()
        log = self._log
        ticks = log.size
        poses = log.poses[:ticks].copy()
        trace = Trace.of_episode(
            self.scene,
            planner=self.planner,
            seed=self.seed,
            cells=log.cells[None, :ticks],
            headings=log.headings[None, :ticks],
            unseen=log.unseen[:ticks],
            outcome=self._outcome or "running",
            first_seen=self._first_seen,
            goal=self._goal,
            planner_options=dict(self.planner_options),
            motion="continuous",
            move_speed=self.motion.move_speed,
            turn_speed=self.motion.turn_speed,
            tick_hz=self.motion.tick_hz,
            seconds=round(self._tick / self.motion.tick_hz, 6),
            poses=poses,
        )
        ticks_to: dict[str, int | None] = {"cover": self._tick if self._outcome == "covered" else None}
        for fraction in FRACTIONS:
            ticks_to[f"t{round(100 * fraction)}"] = trace.steps_to_fraction(fraction)
        measures = continuous_measures(poses, self.motion.tick_hz, ticks_to)
        measures["plans"] = self._plans
        object.__setattr__(trace, "measures", measures)
        return trace


class _Log:
    """Per-tick records in arrays that double when full."""

    def __init__(self, capacity: int) -> None:
        self.size = 0
        self.poses = np.zeros((capacity, 4), dtype=np.float64)
        self.cells = np.zeros(capacity, dtype=np.int64)
        self.headings = np.zeros(capacity, dtype=np.int64)
        self.unseen = np.zeros(capacity, dtype=np.int64)

    def append(self, t: float, x: float, y: float, heading: float, cell: int, number: int, unseen: int) -> None:
        if self.size == len(self.cells):
            self.poses = np.concatenate([self.poses, np.zeros_like(self.poses)])
            self.cells, self.headings, self.unseen = (
                np.concatenate([log, np.zeros_like(log)]) for log in (self.cells, self.headings, self.unseen)
            )
        index = self.size
        self.poses[index] = (t, x, y, heading)
        self.cells[index] = cell
        self.headings[index] = number
        self.unseen[index] = unseen
        self.size = index + 1


def _angle_between(a: float, b: float) -> float:
    return abs((a - b + 180.0) % 360.0 - 180.0)
