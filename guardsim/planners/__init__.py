"""Planners: guard behaviours chosen by name."""

from __future__ import annotations

from collections.abc import Callable

from guardsim.planners.base import STAY, EpisodeSetup, GuardState, Planner, VisionFunction
from guardsim.planners.ripplefront import RippleFront, ripple_sweep

__all__ = [
    "PLANNERS",
    "STAY",
    "EpisodeSetup",
    "GuardState",
    "Planner",
    "RippleFront",
    "VisionFunction",
    "make_planner",
    "ripple_sweep",
]

#: Planner factories by the name used on the command line.
PLANNERS: dict[str, Callable[..., Planner]] = {"ripplefront": RippleFront}


def make_planner(name: str, **options: object) -> Planner:
    """A fresh planner by name; unknown names raise ``KeyError`` listing the known ones."""
    try:
        factory = PLANNERS[name]
    except KeyError:
        raise KeyError(f"unknown planner {name!r}; known: {', '.join(PLANNERS)}") from None
    return factory(**options)
