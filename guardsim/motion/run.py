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


def play_episode(
    scene: Scene,
    planner: str = "ripplefront",
    *,
    seed: int = 0,
    episode: int | None = None,
    start: tuple[float, float] | None = None,
    heading: str | None = None,
    guards: int = 1,
    max_steps: int | None = None,
    sweeps_per_tick: int = 1,
    record_field: bool = False,
    reference: bool = False,
    motion: str | GuardMotion = "grid",
    max_seconds: float | None = None,
) -> Trace:
    """The episode ``guardsim play`` walks: the start and heading chosen as
    :func:`~guardsim.starts.episode_start` chooses them (``start`` a world point, ``heading`` a name), the
    other guards' starts drawn next from the same generator, which then feeds the planners.

    ``sweeps_per_tick`` reaches the planners that take it; ``record_field`` keeps the planner's field at
    every tick in the trace. A lone RippleFront guard on a small level walks the plain loop while the
    compiled tick is not built yet (the same trace, sooner). ``motion``: ``"grid"``, ``"continuous"`` (the
    level guard's speeds) or a :class:`~guardsim.motion.GuardMotion`.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [12, 0], [12, 3], [0, 3]]}))
    >>> play_episode(scene, start=(0.5, 1.5), heading="right").steps
    16
    """
    from guardsim.planners import plain_loop_pays, planner_options
    from guardsim.starts import episode_start, team_starts

    rng, cell, first_heading = episode_start(scene, seed=seed, episode=episode, point=start, heading=heading)
    options = planner_options(planner, sweeps_per_tick=sweeps_per_tick)
    cells, headings = team_starts(scene, (cell, first_heading), guards, rng=rng)
    if motion != "grid":
        return run_episode(
            scene, planner, seed=seed, starts=[cell], headings=[first_heading], rng=rng, max_steps=max_steps,
            motion=motion, max_seconds=max_seconds, reference=reference, **options,
        )  # fmt: skip
    # One small RippleFront episode runs faster on the plain loop than the compiler takes to build the
    # fast path on a fresh install; both give the same trace, so take whichever is quicker now.
    plain = reference or plain_loop_pays(planner, guards, int(scene.grid.traversable.sum()))
    simulation = Simulation(
        scene, planner, guards=guards, max_steps=max_steps, reference=plain, record_field=record_field, **options
    )
    simulation.reset(seed=seed, starts=cells, headings=headings, rng=rng)
    return simulation.run()


def play_summary(name: str, trace: Trace, seconds: float, written: Sequence[str] = ()) -> str:
    """``guardsim play``'s line about ``trace`` of level ``name``: outcome, steps (or time and distance in
    continuous motion), share seen, the ``seconds`` it took and the files ``written``."""
    from guardsim.motion.measures import summary_text

    seen_percent = 100.0 - trace.unseen_percent[-1]
    extra = f", {trace.unreachable} unreachable" if trace.unreachable else ""
    team = f" ({trace.guards} guards, {trace.total_moves} moves in all)" if trace.guards > 1 else ""
    moved = summary_text(trace)
    after, moved = (moved, "") if trace.motion == "continuous" else (f"{trace.steps} steps{team}", f", {moved}")
    return (
        f"{name}: {trace.outcome.replace('_', ' ')} after {after}, {seen_percent:.1f}% seen "
        f"({trace.reachable} reachable cells{extra}){moved}, {seconds:.2f} s"
        + (f" -> {', '.join(written)}" if written else "")
    )
