"""Where an alert episode's guards are and what they see: on the grid, or as bodies in the physics world.

The episode (:mod:`guardsim.alert.episode`) decides every grid tick where each guard goes next: a cell
and a heading, its *decided state*. A movement carries the decided states out and looks:

- :class:`GridMovement` (``motion="grid"``): the guard is at its decided state at once and sees the view
  table's row of it; its meter moves a grid tick at a time. This is the paper's model, and what every
  alert episode did before continuous motion.
- :class:`ContinuousMovement` (``motion="continuous"``): each guard is a kinematic pymunk body in the
  scene's space that walks its decided cells in order with the follower of :mod:`guardsim.motion` at
  the guard's walking and turning speeds, ``tick_hz`` physics ticks a second. Every physics tick each
  guard looks from its body's pose (:class:`guardsim.motion.PoseVision`) and its meter moves
  ``1 / tick_hz`` seconds. A guard takes a decision only on grid ticks on which its body has at most
  one decided cell left to reach (turns cost time that a grid step does not), so the body is never
  more than about a grid tick behind its decisions.

See ``docs/alert.md`` (continuous motion).
"""

from __future__ import annotations

import math
import weakref
from collections import deque
from collections.abc import Sequence
from typing import NamedTuple, Protocol

import numpy as np
import pymunk

from guardsim.detection import AwarenessMeter, GuardDetection
from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.kernels.meter import DETECTED
from guardsim.kernels.steps import state_of
from guardsim.motion.follower import Follower, step_together
from guardsim.motion.parameters import GuardMotion
from guardsim.motion.sight import PoseVision
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable
from guardsim.world import GUARD_CATEGORY

__all__ = ["ContinuousMovement", "GridMovement", "Look", "Movement", "make_movement"]


class Look(NamedTuple):
    """What the guards saw during one grid tick."""

    seen: list[bool]
    """Per guard: the intruder was in its sight (at some physics tick of the grid tick)."""
    spotted: list[bool]
    """Per guard: it saw the intruder with its meter full (at the same physics tick)."""
    cells: np.ndarray
    """Every cell some guard saw during the tick (flat indices, possibly repeated)."""


class Movement(Protocol):
    """How an alert episode's guards move and look (see the module)."""

    name: str

    def ready(self, guard: int) -> bool:
        """Whether ``guard`` takes a decision this grid tick."""

    def follow(self, cells: Sequence[int], headings: Sequence[int]) -> None:
        """The guards' decided states after this grid tick's decisions."""

    def look(self, tick: int, intruder: int, meters: Sequence[AwarenessMeter]) -> Look:
        """Carry out grid tick ``tick`` (0: the start) and look; ``intruder`` is its cell (-1: gone)."""

    def distance(self, guard: int, cell: int) -> float:
        """World units from ``guard`` to the centre of ``cell``."""

    def pace(self, guard: int, factor: float) -> None:
        """``guard`` walks at ``factor`` times its walking speed from now on (a chase runs)."""

    def sees_at_start(self, guard: int, cell: int) -> bool:
        """Whether ``guard`` sees ``cell`` from where it starts."""

    def recorded(self) -> tuple[list[int], list[int]]:
        """The guards' cells and heading numbers to record for this tick."""

    def close(self) -> None:
        """The episode is over: give back what the movement took from the scene."""


class GridMovement:
    """A cell per tick, seeing the view table's row of the decided state."""

    name = "grid"

    def __init__(self, grid: CoverageGrid, table: ViewTable, detection: GuardDetection, guards: int) -> None:
        self.grid, self.table, self.detection = grid, table, detection
        self.cells = [0] * guards
        self.headings = [0] * guards
        self.light: np.ndarray | None = None
        """Each cell's light (``None``: full light everywhere); a dark cell hides the intruder."""

    def ready(self, guard: int) -> bool:
        return True

    def follow(self, cells: Sequence[int], headings: Sequence[int]) -> None:
        self.cells, self.headings = list(cells), list(headings)

    def look(self, tick: int, intruder: int, meters: Sequence[AwarenessMeter]) -> Look:
        sights, seen_by = [], []
        for guard, meter in enumerate(meters):
            sight = self.table.sees(state_of(self.cells[guard], self.headings[guard]))
            sights.append(sight)
            seen = intruder >= 0 and _contains(sight, intruder)
            distance = self.distance(guard, intruder) if seen else 0.0
            lit = _light_of(self.light, intruder)
            seen = seen and meter.model.gain(self.detection.dt, distance, meter.view_range, lit) > 0
            seen_by.append(seen)
            meter.update(self.detection.dt, seen, distance, lit)
        cells = np.concatenate(sights) if sights else np.zeros(0, dtype=np.int32)
        spotted = [seen and meter.level >= DETECTED for seen, meter in zip(seen_by, meters, strict=True)]
        return Look(seen_by, spotted, cells)

    def distance(self, guard: int, cell: int) -> float:
        cols = self.grid.shape[1]
        (r1, c1), (r2, c2) = divmod(self.cells[guard], cols), divmod(cell, cols)
        return math.hypot(c1 - c2, r1 - r2) * self.grid.cell_size

    def sees_at_start(self, guard: int, cell: int) -> bool:
        return _contains(self.table.sees(state_of(self.cells[guard], self.headings[guard])), cell)

    def pace(self, guard: int, factor: float) -> None:
        pass  # on the grid a running guard takes extra steps (the episode's decision)

    def recorded(self) -> tuple[list[int], list[int]]:
        return list(self.cells), list(self.headings)

    def close(self) -> None:
        pass


class ContinuousMovement:
    """Each guard a kinematic body in the scene's space, walking its decided cells (see the module).

    The bodies are added to the scene's space when the episode starts and removed when it ends
    (:meth:`close`, or when the movement is garbage-collected); between physics ticks they are at rest, so
    another user of the space that steps it does not move them.
    """

    name = "continuous"

    def __init__(self, scene: Scene, motion: GuardMotion, dt: float, guards: int) -> None:
        self.scene, self.grid, self.motion = scene, scene.grid, motion
        self.dt = float(dt)
        """Seconds per grid tick."""
        self.light: np.ndarray | None = None
        """Each cell's light (``None``: full light everywhere); a dark cell hides the intruder."""
        world = scene.world
        self._vision = PoseVision(
            world, scene.grid, scene.cone, scene.vision_cache.fill_arrays.walls, rule=scene.line_of_sight
        )
        radius = max(scene.level.guard.radius, 1e-6)
        self._bodies: list[pymunk.Body] = []
        shapes: list[pymunk.Shape] = []
        for _ in range(guards):
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            shape = pymunk.Circle(body, radius)
            shape.filter = pymunk.ShapeFilter(categories=GUARD_CATEGORY)
            self._bodies.append(body)
            shapes.append(shape)
        self._owned: list[pymunk.Body | pymunk.Shape] = [*self._bodies, *shapes]
        world.space.add(*self._owned)
        self._release = weakref.finalize(self, _remove, world.space, self._owned)
        self.followers: list[Follower] = []
        self._queues: list[deque[tuple[str, int, int]]] = [deque() for _ in range(guards)]
        """Per guard: what its body has still to do, in order: ``("walk", cell, direction)`` (a step to a
        neighbouring cell, ``direction`` the step's heading number) or ``("turn", cell, heading)`` in place."""
        self._decided: list[tuple[int, int]] = []
        self.physics_tick = 0
        self._poses: list[list[tuple[float, float, float, float]]] = [[] for _ in range(guards)]
        self.peaks = [0.0] * guards
        """Per guard: the highest meter level during the last grid tick."""

    # -- following --------------------------------------------------------------------------------

    def ready(self, guard: int) -> bool:
        return len(self._queues[guard]) <= 1

    def follow(self, cells: Sequence[int], headings: Sequence[int]) -> None:
        grid = self.grid
        if not self.followers:  # the start: every body on its decided cell centre, facing its heading
            for guard, (cell, heading) in enumerate(zip(cells, headings, strict=True)):
                centre = grid.centre(*grid.unflat(int(cell)))
                self.followers.append(
                    Follower(self.scene.world, self.motion, centre, 90.0 * heading, body=self._bodies[guard])
                )
                self._decided.append((int(cell), int(heading)))
            return
        for guard, (cell, heading) in enumerate(zip(cells, headings, strict=True)):
            before = self._decided[guard]
            if (cell, heading) == before:
                continue
            if cell == before[0]:
                self._queues[guard].append(("turn", int(cell), int(heading)))
            else:
                # A step's direction from the cells themselves (runs of steps one way are walked as one
                # segment); a decided cell is always a 4-neighbour of the one before.
                found = np.flatnonzero(grid.neighbours[before[0]] == cell)
                if found.size == 0:
                    raise RuntimeError(f"guard {guard} decided a cell that is not a neighbour of its last")
                self._queues[guard].append(("walk", int(cell), int(found[0])))
            self._decided[guard] = (int(cell), int(heading))

    def _aim(self, guard: int) -> None:
        """Set ``guard``'s velocities for the next physics tick toward the first thing in its queue; a
        straight run of steps is walked as one segment (no stop at each cell centre)."""
        follower, queue = self.followers[guard], self._queues[guard]
        while queue:
            kind, _, heading = queue[0]
            if kind == "turn":
                follower.aim_turn(90.0 * heading)
                return
            last = _run_end(queue)
            if not follower.aim_walk(self.grid.centre(*self.grid.unflat(queue[last][1]))):
                return
            for _ in range(last + 1):  # already there
                queue.popleft()
        follower.aim_hold()

    def _settled(self, guard: int) -> None:
        """Drop from ``guard``'s queue what its body has done this physics tick."""
        follower, queue, grid = self.followers[guard], self._queues[guard], self.grid
        if not queue:
            return
        kind, _, heading = queue[0]
        if kind == "turn":
            if _angle_between(follower.heading, 90.0 * heading) <= 1e-9:
                queue.popleft()
            return
        x, y = follower.position
        last = _run_end(queue)
        end = grid.centre(*grid.unflat(queue[last][1]))
        left = math.hypot(end[0] - x, end[1] - y)
        # A cell of the run is done once the body is no farther from the run's end than the cell is.
        for _ in range(last + 1):
            centre = grid.centre(*grid.unflat(queue[0][1]))
            if math.hypot(end[0] - centre[0], end[1] - centre[1]) + 1e-9 < left:
                break
            queue.popleft()

    # -- looking ----------------------------------------------------------------------------------

    def look(self, tick: int, intruder: int, meters: Sequence[AwarenessMeter]) -> Look:
        guards = len(meters)
        seen_by, spotted, sights = [False] * guards, [False] * guards, []
        self.peaks = [meter.level for meter in meters]
        # Physics ticks that end within grid tick ``tick`` (a grid tick need not hold a whole number of
        # them); tick 0 is the look from where the guards start.
        steps = math.floor(tick * self.dt * self.motion.tick_hz + 1e-9) - self.physics_tick if tick else 0
        for moved in [False] if tick == 0 else [True] * steps:
            if moved:
                for guard in range(guards):
                    self._aim(guard)
                step_together(self.followers)
                self.physics_tick += 1
                for guard in range(guards):
                    self._settled(guard)
            for guard, meter in enumerate(meters):
                follower = self.followers[guard]
                sight = self._vision(*follower.position, follower.heading)
                sights.append(sight)
                seen = intruder >= 0 and _contains(sight, intruder)
                distance = self.distance(guard, intruder) if seen else 0.0
                lit = _light_of(self.light, intruder)
                seen = seen and meter.model.gain(self.motion.dt, distance, meter.view_range, lit) > 0
                meter.update(self.motion.dt, seen, distance, lit)
                self.peaks[guard] = max(self.peaks[guard], meter.level)
                seen_by[guard] = seen_by[guard] or seen
                spotted[guard] = spotted[guard] or (seen and meter.level >= DETECTED)
            self._log()
        cells = np.concatenate(sights) if sights else np.zeros(0, dtype=np.int64)
        return Look(seen_by, spotted, cells)

    def _log(self) -> None:
        t = self.physics_tick / self.motion.tick_hz
        for guard, follower in enumerate(self.followers):
            self._poses[guard].append((t, follower.position[0], follower.position[1], follower.heading))

    def distance(self, guard: int, cell: int) -> float:
        x, y = self.followers[guard].position
        centre = self.grid.centre(*self.grid.unflat(cell))
        return math.hypot(centre[0] - x, centre[1] - y)

    def pace(self, guard: int, factor: float) -> None:
        self.followers[guard].set_pace(factor)

    def sees_at_start(self, guard: int, cell: int) -> bool:
        follower = self.followers[guard]
        return _contains(self._vision(*follower.position, follower.heading), cell)

    def recorded(self) -> tuple[list[int], list[int]]:
        grid, cells, headings = self.grid, [], []
        for follower in self.followers:
            own = grid.cell_of(follower.position)
            cells.append(-1 if own is None else grid.flat(*own))
            headings.append(round(follower.heading / 90.0) % 4)
        return cells, headings

    def pose(self, guard: int) -> tuple[float, float, float]:
        """``(x, y, heading_degrees)`` of ``guard``'s body now."""
        follower = self.followers[guard]
        return (follower.position[0], follower.position[1], follower.heading)

    @property
    def poses(self) -> np.ndarray:
        """``float64 (guards, physics ticks + 1, 4)``: ``t, x, y, heading_degrees`` of each body at every
        physics tick from the start (as the continuous :class:`~guardsim.trace.Trace`'s ``poses``)."""
        return np.asarray(self._poses, dtype=np.float64)

    def close(self) -> None:
        self._release()


def make_movement(
    motion: str | GuardMotion,
    scene: Scene,
    table: ViewTable,
    detection: GuardDetection,
    *,
    dt: float,
    guards: int,
) -> GridMovement | ContinuousMovement:
    """The movement ``motion`` names (``"grid"`` or ``"continuous"``, the level guard's speeds), or
    continuous motion at the speeds of a :class:`~guardsim.motion.GuardMotion`."""
    if isinstance(motion, GuardMotion):
        return ContinuousMovement(scene, motion, dt, guards)
    if motion == "grid":
        return GridMovement(scene.grid, table, detection, guards)
    if motion == "continuous":
        return ContinuousMovement(scene, GuardMotion.of_guard(scene.level.guard), dt, guards)
    raise ArgumentError(f"unknown motion {motion!r}; choose from grid, continuous")


def _remove(space: pymunk.Space, owned: list[pymunk.Body | pymunk.Shape]) -> None:
    present = [item for item in owned if item in space.bodies or item in space.shapes]
    if present:
        space.remove(*present)


def _run_end(queue: deque[tuple[str, int, int]]) -> int:
    """Index of the last step of the straight run the queue starts with (steps the same way)."""
    heading, last = queue[0][2], 0
    while last + 1 < len(queue) and queue[last + 1][0] == "walk" and queue[last + 1][2] == heading:
        last += 1
    return last


def _angle_between(a: float, b: float) -> float:
    return abs((a - b + 180.0) % 360.0 - 180.0)


def _contains(sorted_cells: np.ndarray, cell: int) -> bool:
    index = int(np.searchsorted(sorted_cells, cell))
    return index < sorted_cells.size and int(sorted_cells[index]) == cell


def _light_of(light: np.ndarray | None, cell: int) -> float:
    """The light of the intruder's cell (1 without a light map or without an intruder): a dark cell hides
    it from a guard looking at it from beyond its dark sight."""
    return 1.0 if light is None or cell < 0 else float(light[cell])
