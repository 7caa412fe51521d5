"""The simulation loop: guards, their vision and their planners, tick by tick until the level is seen.

- :mod:`~guardsim.simulation.loop`: :class:`Simulation`, the one episode loop (reset, step, trace);
- :mod:`~guardsim.simulation.reads`: what a game reads from it (positions, seen cells, who sees a point).
"""

from __future__ import annotations

from guardsim.scene import Scene
from guardsim.simulation.loop import Simulation, default_max_steps
from guardsim.starts import choose_start, episode_generator, team_starts

__all__ = [
    "Scene",
    "Simulation",
    "choose_start",
    "default_max_steps",
    "episode_generator",
    "team_starts",
]
