"""The coverage task both environments wrap: a team of agent-driven guards on one scene, its start rule and reward.

Starts follow guardsim's own rule, so an agent can be compared with the planners on the same episodes:
after ``reset(seed=s)`` the first episode starts as ``guardsim play LEVEL --seed s --episode 0`` and the
k-th reset after it (without a seed) as ``--episode k``, which are the episodes of ``guardsim bench
--seed s``. A reset with no seed ever given draws the batch seed from the environment's generator.

The reward of a tick is the number of goal cells first seen at that tick (by any guard) minus
``step_cost``, divided by the number of goal cells when ``normalize`` is on (the default): seeing the
whole goal is then worth 1 on any level, and a step costs ``step_cost`` cells' worth of it.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from guardsim.envs.actions import AgentPlanner, action_mask
from guardsim.envs.observations import observe
from guardsim.errors import ArgumentError
from guardsim.importers import load_level
from guardsim.level import Level
from guardsim.scene import Scene
from guardsim.simulation import Simulation
from guardsim.starts import check_headings
from guardsim.vision.rules import LineOfSight

__all__ = ["RESET_OPTIONS", "CoverageTask", "LevelSource", "scene_of"]

#: What a level argument may be: a level file, a parsed level, or a scene built from one.
LevelSource = str | os.PathLike[str] | Level | Scene

#: The keys ``reset(options=...)`` reads.
RESET_OPTIONS = ("episode", "starts", "headings")


def scene_of(level: LevelSource, line_of_sight: LineOfSight | str = LineOfSight.PYMUNK) -> Scene:
    """The scene of a level file, a :class:`~guardsim.level.Level`, or a :class:`~guardsim.scene.Scene` as it is."""
    if isinstance(level, Scene):
        return level
    if not isinstance(level, Level):
        level = load_level(level)
    return Scene.from_level(level, line_of_sight=line_of_sight)


class CoverageTask:
    """A :class:`~guardsim.simulation.Simulation` of ``guards`` guards whose moves an agent chooses.

    Parameters are those of the environments (see :class:`~guardsim.envs.CoverageEnv`).
    """

    def __init__(
        self,
        level: LevelSource,
        *,
        guards: int = 1,
        max_steps: int | None = None,
        step_cost: float = 1.0,
        normalize: bool = True,
        crop: int | None = None,
        line_of_sight: LineOfSight | str = LineOfSight.PYMUNK,
    ) -> None:
        if guards < 1:
            raise ArgumentError(f"a team needs at least one guard, not {guards}")
        if crop is not None and crop < 0:
            raise ArgumentError(f"crop must be a non-negative number of cells, not {crop}")
        self.scene = scene_of(level, line_of_sight)
        self.planners = [AgentPlanner() for _ in range(guards)]
        self.simulation = Simulation(self.scene, self.planners, max_steps=max_steps)
        self.step_cost = float(step_cost)
        self.normalize = normalize
        self.crop = crop
        self.batch_seed: int | None = None
        """The seed of the batch whose episodes the resets walk through."""
        self.episode = 0
        """The episode of that batch now running."""
        self.newly_seen = 0
        self._goal_cells = 1

    @property
    def guards(self) -> int:
        """Team size."""
        return len(self.planners)

    def start(self, rng: np.random.Generator, seed: int | None, options: Mapping[str, Any] | None) -> None:
        """Start the next episode: episode 0 of batch ``seed`` when given, else the batch's next episode.

        ``options`` may give ``episode`` (run that episode of the batch instead; later resets go on from
        it), ``starts`` (``(col, row)`` cells, one per guard) and ``headings`` (heading numbers, one per
        guard: 0 right with ``starts``, else the episode's drawn headings, by default). Other keys are
        ignored with a warning.
        """
        options = dict(options or {})
        unknown = sorted(set(options) - set(RESET_OPTIONS))
        if unknown:
            warnings.warn(f"guardsim.envs: reset options {unknown} ignored; known: {list(RESET_OPTIONS)}", stacklevel=3)
        if seed is not None:
            self.batch_seed, self.episode = int(seed), 0
        elif self.batch_seed is None:
            self.batch_seed, self.episode = int(rng.integers(2**32)), 0
        else:
            self.episode += 1
        if options.get("episode") is not None:
            self.episode = int(options["episode"])
            if self.episode < 0:
                raise ArgumentError(f"episode must be 0 or more, not {self.episode}")
        starts, headings = options.get("starts"), options.get("headings")
        facing = check_headings(headings, self.guards)
        if starts is not None:
            cells = [(int(col), int(row)) for col, row in starts]
            self.simulation.reset(seed=self.batch_seed, starts=cells, headings=facing or [0] * len(cells))
        else:
            self.simulation.reset(seed=self.batch_seed, episode=self.episode, headings=facing)
        self.newly_seen = int(self.simulation.goal.sum()) - self.simulation.unseen
        self._goal_cells = max(1, int(self.simulation.goal.sum()))

    def advance(self, actions: Sequence[int]) -> float:
        """Move every guard by its action for one tick; the tick's reward (0 once the episode is over)."""
        simulation = self.simulation
        if len(actions) != self.guards:
            raise ArgumentError(f"{len(actions)} actions for {self.guards} guards")
        for planner, action in zip(self.planners, actions):
            planner.choose(int(action))
        if simulation.done:
            self.newly_seen = 0
            return 0.0
        unseen = simulation.unseen
        simulation.step()
        self.newly_seen = unseen - simulation.unseen
        reward = self.newly_seen - self.step_cost
        return reward / self._goal_cells if self.normalize else float(reward)

    @property
    def terminated(self) -> bool:
        """Every goal cell is seen."""
        return self.simulation.outcome == "covered"

    @property
    def truncated(self) -> bool:
        """The step limit is reached."""
        return self.simulation.outcome == "step_limit"

    def observation(self, guard: int) -> dict[str, Any]:
        """Guard ``guard``'s observation (see :mod:`guardsim.envs.observations`)."""
        return observe(self.simulation, guard, self.crop)

    def info(self, guard: int) -> dict[str, Any]:
        """What a learner may log or mask with; new objects on every call."""
        simulation = self.simulation
        cell = simulation.cells[guard]
        return {
            "action_mask": action_mask(self.scene.grid, self.scene.grid.flat(*cell)),
            "cell": cell,
            "tick": simulation.tick,
            "newly_seen": self.newly_seen,
            "coverage": simulation.coverage,
            "outcome": simulation.outcome,
            "episode": self.episode,
        }
