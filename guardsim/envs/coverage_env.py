"""``guardsim/Coverage-v0``: one guard, moved by the agent, until it has seen every cell it can reach."""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from guardsim.envs.actions import ACTIONS
from guardsim.envs.observations import observation_space
from guardsim.envs.rgb import TightCells, rgb_frame
from guardsim.envs.task import CoverageTask, LevelSource
from guardsim.errors import ArgumentError
from guardsim.simulation import Simulation
from guardsim.vision.rules import LineOfSight

__all__ = ["CoverageEnv"]


class CoverageEnv(gymnasium.Env[dict[str, Any], np.int64]):
    """A Gymnasium environment: one guard covers a guardsim level, one heading move per step.

    Made with ``gymnasium.make("guardsim/Coverage-v0", level=...)`` after ``import guardsim.envs``.
    See docs/envs.md for the spaces, the reward, the seeding rule and the reset options.

    Parameters
    ----------
    level
        A level file, a :class:`~guardsim.level.Level`, or a :class:`~guardsim.scene.Scene`.
    max_steps
        Step limit (the episode is truncated there); the simulation's default (10 per traversable
        cell, at least 100) when ``None``.
    step_cost
        What a step costs, in goal cells.
    normalize
        Divide the reward by the number of goal cells, so that seeing the whole goal is worth 1.
    crop
        Observe a ``(2 crop + 1)``-cell square around the guard instead of the whole grid.
    line_of_sight
        ``"pymunk"`` or ``"bresenham"`` (see :class:`~guardsim.vision.LineOfSight`).
    render_mode
        ``None`` or ``"rgb_array"``.
    cell_pixels
        Side of a cell in the ``rgb_array`` frames.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 10}  # noqa: RUF012 (Gymnasium's class attribute)

    def __init__(
        self,
        level: LevelSource,
        *,
        max_steps: int | None = None,
        step_cost: float = 1.0,
        normalize: bool = True,
        crop: int | None = None,
        line_of_sight: LineOfSight | str = LineOfSight.PYMUNK,
        render_mode: str | None = None,
        cell_pixels: int = 8,
    ) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ArgumentError(f"render_mode {render_mode!r} is not one of {self.metadata['render_modes']}")
        self.task = CoverageTask(
            level, max_steps=max_steps, step_cost=step_cost, normalize=normalize, crop=crop, line_of_sight=line_of_sight
        )
        self.action_space = spaces.Discrete(len(ACTIONS))
        self.observation_space = observation_space(self.task.scene.grid.shape, crop)
        self.render_mode = render_mode
        self.cell_pixels = cell_pixels
        self._tight = TightCells()

    @property
    def simulation(self) -> Simulation:
        """The guardsim simulation underneath: its state, and its :meth:`~Simulation.trace` for a GIF."""
        return self.task.simulation

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, Any], dict[str, Any]]:
        """Start an episode: episode 0 of batch ``seed``, or the batch's next episode (see docs/envs.md).

        ``options``: ``{"episode": k}`` runs episode k of the batch; ``{"start": (col, row)}`` starts there
        facing right, ``{"heading": h}`` facing ``h`` (with or without ``start``).
        """
        super().reset(seed=seed)
        task_options = dict(options or {})
        if "start" in task_options:
            task_options["starts"] = [task_options.pop("start")]
        if "heading" in task_options:
            task_options["headings"] = [task_options.pop("heading")]
        self.task.start(self.np_random, seed, task_options)
        return self.task.observation(0), self.task.info(0)

    def step(self, action: np.int64 | int) -> tuple[dict[str, Any], float, bool, bool, dict[str, Any]]:
        """Move the guard by ``action`` (0 stay, 1 right, 2 down, 3 left, 4 up) and let it look."""
        if not self.action_space.contains(action):
            raise ArgumentError(f"action {action!r} is not in {self.action_space}")
        reward = self.task.advance([int(action)])
        return self.task.observation(0), reward, self.task.terminated, self.task.truncated, self.task.info(0)

    def action_masks(self) -> np.ndarray:
        """``int8 (5,)``: which actions move the guard now (``info["action_mask"]``; sb3-contrib's name)."""
        return self.task.info(0)["action_mask"]

    def render(self) -> np.ndarray | None:
        """An ``rgb_array`` frame of the grid, or ``None`` without a render mode."""
        if self.render_mode != "rgb_array":
            return None
        simulation = self.task.simulation
        return rgb_frame(simulation, self.cell_pixels, tight=self._tight.of(simulation.scene))
