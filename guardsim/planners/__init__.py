"""Planners: guard behaviours chosen by name."""

from __future__ import annotations

from collections.abc import Callable

from guardsim.planners.base import STAY, EpisodeSetup, GuardState, Planner, VisionFunction
from guardsim.planners.frontier import Frontier
from guardsim.planners.random_walk import RandomWalk
from guardsim.planners.ripplefront import RippleFront, ripple_sweep
from guardsim.planners.ripplefront_exact import RippleFrontExact
from guardsim.planners.sweep import Sweep
from guardsim.planners.tour import Tour

__all__ = [
    "PLANNERS",
    "STAY",
    "EpisodeSetup",
    "Frontier",
    "GuardState",
    "Planner",
    "RandomWalk",
    "RippleFront",
    "RippleFrontExact",
    "Sweep",
    "Tour",
    "VisionFunction",
    "make_planner",
    "ripple_sweep",
]

#: Planner factories by the name used on the command line.
PLANNERS: dict[str, Callable[..., Planner]] = {
    "ripplefront": RippleFront,
    "ripplefront-exact": RippleFrontExact,
    "frontier": Frontier,
    "random-walk": RandomWalk,
    "sweep": Sweep,
    "tour": Tour,
}


def make_planner(name: str, **options: object) -> Planner:
    """A fresh planner by name; an unknown name raises :class:`~guardsim.errors.PlannerError` (a
    ``KeyError`` too) listing the known ones."""
    try:
        factory = PLANNERS[name]
    except KeyError:
        from guardsim.errors import PlannerError

        raise PlannerError(f"unknown planner {name!r}; known: {', '.join(PLANNERS)}") from None
    return factory(**options)
