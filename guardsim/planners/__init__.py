"""Planners: guard behaviours chosen by name."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from guardsim.planners.base import STAY, EpisodeSetup, GuardState, Planner, VisionFunction
from guardsim.planners.frontier import Frontier
from guardsim.planners.random_walk import RandomWalk
from guardsim.planners.ripplefront import RippleFront, ripple_sweep
from guardsim.planners.ripplefront_exact import RippleFrontExact
from guardsim.planners.sweep import Sweep
from guardsim.planners.tour import Tour

__all__ = [
    "FIELD_PLANNERS",
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
    "plain_loop_pays",
    "planner_options",
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


#: Planners that keep a distance field a trace can record (``Simulation(record_field=True)``).
FIELD_PLANNERS = frozenset({"ripplefront", "ripplefront-exact"})


def planner_options(name: str, **given: Any) -> dict[str, Any]:
    """The options among ``given`` that planner ``name`` takes (its factory's keyword arguments), so that
    a command can offer one set of options to every planner.

    >>> planner_options("ripplefront", sweeps_per_tick=2), planner_options("sweep", sweeps_per_tick=2)
    ({'sweeps_per_tick': 2}, {})
    """
    import inspect

    if name not in PLANNERS:
        make_planner(name)  # raises PlannerError, one line naming the known planners
    accepted = inspect.signature(PLANNERS[name]).parameters
    return {key: value for key, value in given.items() if key in accepted}


def plain_loop_pays(name: str, guards: int, traversable_cells: int) -> bool:
    """Whether one episode is quicker on the plain loop than on the compiled tick (which gives the same
    trace): a lone RippleFront guard on a small level while the compiled tick is not built yet."""
    if name != "ripplefront" or guards != 1:
        return False
    from guardsim.planners.ripplefront_compiled import COLD_START_CELLS, is_compiled

    return not is_compiled() and traversable_cells <= COLD_START_CELLS
