"""The one convenience beside :class:`~guardsim.simulation.Simulation`: an episode run to its end, on the
grid or in continuous motion (it lives here, downstream of both, so that the simulation never imports
the motion that plugs into it)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.motion.episode import ContinuousSimulation
from guardsim.motion.parameters import GuardMotion
from guardsim.planners.base import Planner
from guardsim.scene import Scene
from guardsim.simulation.loop import Simulation
from guardsim.trace import Trace
from guardsim.vision.rules import VisionFunction

__all__ = ["run_episode"]


def run_episode(
    scene: Scene,
    planner: str | Planner | Sequence[Planner] = "ripplefront",
    *,
    guards: int = 1,
    starts: Sequence[tuple[int, int]] | None = None,
    headings: Sequence[int] | None = None,
    seed: int | None = None,
    episode: int | None = None,
    rng: np.random.Generator | None = None,
    motion: str | GuardMotion | None = None,
    max_steps: int | None = None,
    max_seconds: float | None = None,
    vision: VisionFunction | None = None,
    reference: bool = False,
    **planner_options: Any,
) -> Trace:
    """One episode run to its end: the one convenience beside :class:`Simulation`.

    The arguments are those of :class:`Simulation` and its :meth:`~Simulation.reset`: a planner name
    (``guards`` fresh planners, made with ``planner_options``) or planner objects, one per guard; the
    starts as ``guardsim play --seed SEED --episode K`` draws them (``guardsim bench``'s episode ``K``),
    or ``starts`` (``(col, row)`` cells) facing ``headings``; ``rng`` (else one from ``seed``) feeds the
    planners. ``motion="continuous"`` (the level guard's speeds) or a
    :class:`~guardsim.motion.GuardMotion` walks one guard in continuous motion
    (:class:`~guardsim.motion.ContinuousSimulation`, limited by ``max_seconds``) instead of a grid step
    per tick.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [12, 0], [12, 3], [0, 3]]}))
    >>> run_episode(scene, starts=[(0, 1)], headings=[0]).steps
    16
    >>> run_episode(scene, "sweep", guards=2, seed=1, episode=0).guards
    2
    """
    if motion is None or motion == "grid":
        if max_seconds is not None:
            raise ArgumentError("max_seconds limits continuous motion; grid episodes take max_steps")
        simulation = Simulation(
            scene, planner, guards=guards, max_steps=max_steps, vision=vision, reference=reference, **planner_options
        )
        simulation.reset(seed=seed, episode=episode, starts=starts, headings=headings, rng=rng)
        return simulation.run()
    if not isinstance(planner, str) or guards != 1 or vision is not None:
        raise ArgumentError("continuous motion walks one guard with a planner name and the scene's own vision")
    if isinstance(motion, str) and motion != "continuous":
        raise ArgumentError(f"motion is 'grid', 'continuous' or a GuardMotion, not {motion!r}")
    continuous = ContinuousSimulation(
        scene,
        planner,
        motion=motion if isinstance(motion, GuardMotion) else None,
        max_seconds=max_seconds,
        max_steps=max_steps,
        reference=reference,
        **planner_options,
    )
    continuous.reset(seed=seed, episode=episode, starts=starts, headings=headings, rng=rng)
    return continuous.run()
