"""Reinforcement-learning environments on guardsim's simulation (the optional ``rl`` extra).

Importing this package registers ``guardsim/Coverage-v0`` with Gymnasium, one guard moved by the agent::

    import gymnasium
    import guardsim.envs

    env = gymnasium.make("guardsim/Coverage-v0", level="levels/square.json")
    observation, info = env.reset(seed=0)

and offers :func:`coverage_parallel_env`, a PettingZoo ``ParallelEnv`` for a team. See docs/envs.md.
"""

from __future__ import annotations

try:
    import gymnasium
    import pettingzoo  # noqa: F401 (checked here so the message is one)
except ImportError as error:
    raise ImportError(
        f"guardsim.envs needs gymnasium and pettingzoo ({error.name} is missing): install guardsim[rl]"
    ) from error

from guardsim.envs.actions import ACTIONS, AgentPlanner, action_mask
from guardsim.envs.coverage_env import CoverageEnv
from guardsim.envs.observations import CHANNELS
from guardsim.envs.parallel_env import CoverageParallelEnv, coverage_parallel_env

__all__ = [
    "ACTIONS",
    "CHANNELS",
    "ENV_ID",
    "AgentPlanner",
    "CoverageEnv",
    "CoverageParallelEnv",
    "action_mask",
    "coverage_parallel_env",
]

#: The Gymnasium id of :class:`CoverageEnv`.
ENV_ID = "guardsim/Coverage-v0"

if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="guardsim.envs.coverage_env:CoverageEnv")
