"""A level with everything built from it once: the physics world, the coverage grid and the vision.

A :class:`Scene` is what every episode on a level shares; it sits upstream of the planners and the
simulation loop, so tools that only need the grid or the vision (validation, bounds) need neither.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
import pymunk

from guardsim.grid import CoverageGrid, build_grid
from guardsim.level import Level
from guardsim.vision.cone import VisionCone
from guardsim.vision.rays import visible_cells
from guardsim.vision.rules import LineOfSight, VisionFunction
from guardsim.world import World

if TYPE_CHECKING:
    from guardsim.vision.cache import VisionCache
    from guardsim.vision.table import ViewTable

__all__ = ["Scene"]


@dataclass(frozen=True, eq=False)
class Scene:
    """A level with its world, grid, cone and vision cache, built once and shared by its episodes.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [4, 0], [4, 3], [0, 3]]}))
    >>> scene.grid.shape, scene.line_of_sight.value, scene.vision()(0, 0, 0).tolist()
    ((3, 4), 'pymunk', [0, 1, 2, 3, 5, 6, 7, 10, 11])
    """

    level: Level
    world: World
    grid: CoverageGrid
    cone: VisionCone
    rule: LineOfSight = LineOfSight.PYMUNK
    """The line-of-sight rule."""

    @cached_property
    def vision_cache(self) -> VisionCache:
        """Visible cells per state, filled as episodes meet them and shared by all of them.

        Built on first use: the cache is compiled code, which validation and previews never need.
        """
        from guardsim.vision.cache import VisionCache

        return VisionCache(self.world, self.grid, self.cone, line_of_sight=self.rule)

    @classmethod
    def from_level(
        cls,
        level: Level,
        *,
        line_of_sight: LineOfSight | str = LineOfSight.PYMUNK,
        fov_degrees: float | None = None,
        view_range: float | None = None,
        space: pymunk.Space | None = None,
        walls_in_space: bool = False,
    ) -> Scene:
        """Build the physics world, the grid and the cone of a level: the one scene factory.

        Parameters
        ----------
        level
            The level.
        line_of_sight
            :attr:`LineOfSight.PYMUNK` (rays against the walls) or :attr:`LineOfSight.BRESENHAM` (grid lines).
        fov_degrees, view_range
            Overrides of the level guard's field of view and view range (world units); ``math.inf``
            means unlimited, the grid's diagonal (what the commands use with ``--los bresenham`` and
            no ``--view-range``, the grid solvers' rule). The scene's ``level`` carries them.
        space, walls_in_space
            A :class:`pymunk.Space` of the caller's to build the world in; see :class:`~guardsim.world.World`.

        Examples
        --------
        >>> from guardsim.level import parse_level
        >>> level = parse_level({"outer": [[0, 0], [30, 0], [30, 40], [0, 40]]})
        >>> Scene.from_level(level, line_of_sight="bresenham", view_range=math.inf).cone.view_range
        50.0
        """
        guard = level.guard
        if fov_degrees is not None:
            guard = dataclasses.replace(guard, fov_degrees=fov_degrees)
        if view_range is not None:
            if math.isinf(view_range):
                rows, cols = level.grid_shape()
                view_range = math.hypot(rows, cols) * level.cell_size
            guard = dataclasses.replace(guard, view_range=view_range)
        if guard is not level.guard:
            level = dataclasses.replace(level, guard=guard)
        world = World(level, space=space, walls_in_space=walls_in_space)
        grid = build_grid(level, world)
        cone = VisionCone.from_guard(level.guard, level.cell_size, grid_shape=grid.shape)
        return cls(level, world, grid, cone, LineOfSight(line_of_sight))

    @staticmethod
    def vision_options(
        line_of_sight: LineOfSight | str = LineOfSight.PYMUNK,
        fov_degrees: float | None = None,
        view_range: float | None = None,
    ) -> dict[str, Any]:
        """The commands' vision options as :meth:`from_level` keywords: with the Bresenham rule and no
        ``view_range``, the range is unlimited (the grid solvers' rule); :meth:`from_level` itself keeps
        the level guard's range unless told otherwise.

        >>> Scene.vision_options("bresenham")
        {'line_of_sight': 'bresenham', 'fov_degrees': None, 'view_range': inf}
        """
        if view_range is None and LineOfSight(line_of_sight) is LineOfSight.BRESENHAM:
            view_range = math.inf
        return {"line_of_sight": line_of_sight, "fov_degrees": fov_degrees, "view_range": view_range}

    def vision_record(self) -> dict[str, Any]:
        """The vision this scene sees by, as the JSON outputs record it so that a page can be drawn again:
        ``los``, ``fov`` and ``view_range`` (``null`` when unlimited). :meth:`recorded_vision` reads it back."""
        reach = self.cone.view_range
        return {
            "los": self.rule.value,
            "fov": self.cone.fov_degrees,
            "view_range": None if math.isinf(reach) else reach,
        }

    @staticmethod
    def recorded_vision(data: Mapping[str, Any]) -> dict[str, Any]:
        """The :meth:`from_level` keywords of the vision ``data`` records (:meth:`vision_record`); none when it
        records none (the level's own vision).

        >>> Scene.recorded_vision({"los": "bresenham", "fov": 90.0, "view_range": None})
        {'line_of_sight': 'bresenham', 'fov_degrees': 90.0, 'view_range': inf}
        """
        if "los" not in data:
            return {}
        reach = data["view_range"]
        return {
            "line_of_sight": data["los"],
            "fov_degrees": data["fov"],
            "view_range": math.inf if reach is None else float(reach),
        }

    @property
    def line_of_sight(self) -> LineOfSight:
        """The line-of-sight rule (the same as :attr:`rule`)."""
        return self.rule

    def view_table(self) -> ViewTable:
        """The sight table: which cells each guard state sees (:func:`guardsim.vision.table.view_table`),
        built on first use and shared."""
        from guardsim.vision.table import view_table

        return view_table(self.grid, self.vision())

    def vision(self, *, reference: bool = False) -> VisionFunction:
        """The vision to use: the shared cache by default, the per-cell-ray reference on request.

        Both give the same cells for every state (tested on every state of the shipped levels).
        """
        return self.reference_vision() if reference else self.vision_cache

    def reference_vision(self) -> VisionFunction:
        """The reference vision: one pymunk ray (or Bresenham line) per cell in the cone, every tick."""
        if self.line_of_sight is LineOfSight.BRESENHAM:
            from guardsim.vision.bresenham import bresenham_visible

            def see_on_grid(col: int, row: int, heading: int) -> np.ndarray:
                return bresenham_visible(self.grid.traversable, col, row, self.cone.offsets[heading])

            return see_on_grid

        def see(col: int, row: int, heading: int) -> np.ndarray:
            return visible_cells(self.world, self.grid, self.cone, col, row, heading)

        return see
