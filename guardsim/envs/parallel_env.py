"""A PettingZoo ``ParallelEnv``: a team of guards, each moved by its own agent, covering one level together."""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from pettingzoo import ParallelEnv

from guardsim.envs.actions import ACTIONS
from guardsim.envs.observations import observation_space, state_planes, state_space
from guardsim.envs.rgb import TightCells, rgb_frame
from guardsim.envs.task import CoverageTask, LevelSource
from guardsim.errors import ArgumentError
from guardsim.simulation import Simulation
from guardsim.vision.rules import LineOfSight

__all__ = ["CoverageParallelEnv", "coverage_parallel_env"]


class CoverageParallelEnv(ParallelEnv):
    """Guards ``guard_0`` .. ``guard_{n-1}`` cover a level together; every guard moves at every step.

    The reward is the team's: each guard receives the goal cells first seen by anyone at that tick, minus
    one ``step_cost`` per tick (not per guard). Every agent terminates when the goal is covered and is
    truncated at the step limit, all at once. An agent missing from the actions stays. See
    :class:`~guardsim.envs.CoverageEnv` for the parameters and docs/envs.md for the spaces.
    """

    metadata: dict[str, Any] = {  # noqa: RUF012 (PettingZoo's class attribute)
        "name": "guardsim_coverage_v0",
        "render_modes": ["rgb_array"],
        "render_fps": 10,
        "is_parallelizable": True,
    }

    def __init__(
        self,
        level: LevelSource,
        *,
        guards: int = 2,
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
            level,
            guards=guards,
            max_steps=max_steps,
            step_cost=step_cost,
            normalize=normalize,
            crop=crop,
            line_of_sight=line_of_sight,
        )
        shape = self.task.scene.grid.shape
        self.possible_agents: list[str] = [f"guard_{number}" for number in range(guards)]
        self.agents: list[str] = []
        self.observation_spaces = {agent: observation_space(shape, crop) for agent in self.possible_agents}
        self.action_spaces = {agent: spaces.Discrete(len(ACTIONS)) for agent in self.possible_agents}
        self.state_space = state_space(shape)
        self.render_mode = render_mode
        self.cell_pixels = cell_pixels
        self._tight = TightCells()
        self._np_random: np.random.Generator | None = None

    @property
    def simulation(self) -> Simulation:
        """The guardsim simulation underneath."""
        return self.task.simulation

    @property
    def np_random(self) -> np.random.Generator:
        """The environment's generator (Gymnasium's seeding), made from the first reset's seed."""
        if self._np_random is None:
            self._np_random, _ = seeding.np_random()
        return self._np_random

    def observation_space(self, agent: str) -> spaces.Space[Any]:
        """The observation space of ``agent`` (the same object on every call, as PettingZoo requires)."""
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space[Any]:
        """The action space of ``agent``: ``Discrete(5)``, the same object on every call."""
        return self.action_spaces[agent]

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, dict[str, Any]], dict[str, dict[str, Any]]]:
        """Start an episode: episode 0 of batch ``seed``, or the batch's next one (see docs/envs.md).

        ``options``: ``{"episode": k}``, or ``{"starts": [(col, row), ...], "headings": [h, ...]}``.
        """
        if seed is not None:
            self._np_random, _ = seeding.np_random(seed)
        self.task.start(self.np_random, seed, options)
        self.agents = list(self.possible_agents)
        return (
            {agent: self.task.observation(number) for number, agent in enumerate(self.agents)},
            {agent: self.task.info(number) for number, agent in enumerate(self.agents)},
        )

    def step(
        self, actions: dict[str, int]
    ) -> tuple[
        dict[str, dict[str, Any]],
        dict[str, float],
        dict[str, bool],
        dict[str, bool],
        dict[str, dict[str, Any]],
    ]:
        """Move every guard by its action at once; one tick."""
        unknown = sorted(set(actions) - set(self.possible_agents))
        if unknown:
            raise ArgumentError(f"actions for unknown agents {unknown}; the agents are {self.possible_agents}")
        if not self.agents:
            return {}, {}, {}, {}, {}
        for agent, action in actions.items():
            if not self.action_spaces[agent].contains(action):
                raise ArgumentError(f"action {action!r} of {agent} is not in {self.action_spaces[agent]}")
        reward = self.task.advance([int(actions.get(agent, 0)) for agent in self.possible_agents])
        terminated, truncated = self.task.terminated, self.task.truncated
        agents = self.agents
        result = (
            {agent: self.task.observation(number) for number, agent in enumerate(agents)},
            dict.fromkeys(agents, reward),
            dict.fromkeys(agents, terminated),
            dict.fromkeys(agents, truncated),
            {agent: self.task.info(number) for number, agent in enumerate(agents)},
        )
        if terminated or truncated:
            self.agents = []
        return result

    def state(self) -> np.ndarray:
        """``uint8 (4, rows, cols)``: traversable, goal, seen, and every guard's cell (see ``state_space``)."""
        return state_planes(self.task.simulation)

    def render(self) -> np.ndarray | None:
        """An ``rgb_array`` frame of the grid, or ``None`` without a render mode."""
        if self.render_mode != "rgb_array":
            return None
        simulation = self.task.simulation
        return rgb_frame(simulation, self.cell_pixels, tight=self._tight.of(simulation.scene))

    def close(self) -> None:
        """Nothing to release."""


def coverage_parallel_env(level: LevelSource, *, guards: int = 2, **options: Any) -> CoverageParallelEnv:
    """A :class:`CoverageParallelEnv` of ``guards`` guards on ``level`` (PettingZoo's ``parallel_env()``)."""
    return CoverageParallelEnv(level, guards=guards, **options)
