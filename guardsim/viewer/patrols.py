"""The viewer layers of a patrol and of a sneak, from their results (``guardsim patrol`` / ``sneak --html``).

Downstream of :mod:`guardsim.patrol` and :mod:`guardsim.sneak`: they never import the viewer.
"""

from __future__ import annotations

import numpy as np

from guardsim.grid import CoverageGrid
from guardsim.patrol.export import waypoints
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import seen_timeline
from guardsim.sneak import SneakResult
from guardsim.viewer.layers import DEFAULT_LAPS, IdlenessMap, Intruder, LapViews, Overlays
from guardsim.vision.table import ViewTable

__all__ = ["PATROL_LAYERS", "SNEAK_LAYERS", "patrol_overlays", "patrol_routes", "sneak_overlays"]

#: Layers a patrol page opens with: the worst-gap heat map under the guards, their loops and cones.
PATROL_LAYERS = ("idleness", "route", "trail", "cone")
#: Layers a sneak page opens with: the hiding-spot heat map, the loops, the cones and the intruder.
SNEAK_LAYERS = ("idleness", "route", "cone", "intruder")


def patrol_routes(patrol: Patrol, grid: CoverageGrid) -> list[list[tuple[float, float]]]:
    """Each guard's loop as world points: the route.json waypoints (straight runs merged)."""
    return [[(point["x"], point["y"]) for point in waypoints(patrol, grid, guard)] for guard in range(patrol.guards)]


def patrol_overlays(
    patrol: Patrol,
    grid: CoverageGrid,
    table: ViewTable,
    *,
    idleness: np.ndarray | None = None,
    never: np.ndarray | None = None,
    unit: str = "ticks",
    laps: int = DEFAULT_LAPS,
) -> Overlays:
    """The page layers of ``patrol`` on ``grid``.

    Parameters
    ----------
    idleness
        ``float (rows, cols)``: each cell's worst gap (patrol.json's ``idleness``, NaN for its nulls), in
        ``unit``.
    never
        ``bool (rows, cols)``: goal cells the patrol never sees.
    laps
        Laps the timeline spans by default. A patrol that does not repeat has no laps and no loops: its
        page is the walked stretch with the heat map.
    """
    heat = None if idleness is None else IdlenessMap(idleness, unit=unit, label="worst gap", never=never)
    if patrol.period is None:
        return Overlays(idleness=heat, layers=PATROL_LAYERS)
    return Overlays(
        idleness=heat,
        laps=LapViews(patrol.period, seen_timeline(table, patrol.states, grid.size), laps=laps),
        routes=patrol_routes(patrol, grid),
        layers=PATROL_LAYERS,
    )


def sneak_overlays(
    patrol: Patrol,
    grid: CoverageGrid,
    result: SneakResult,
    *,
    source: tuple[float, float] | None = None,
    target: tuple[float, float] | None = None,
) -> Overlays:
    """The page layers of a sneak check: the lap, the hiding spots, the loops and the intruder.

    The page's tick 0 is the lap's tick 0 (pair it with the patrol's trace from lap tick 0); the intruder
    enters at its ``start_tick`` and the timeline spans the laps its walk needs.
    """
    path = result.path
    windows = result.hiding.reshape(grid.shape).astype(float)
    never = (windows == result.period) & grid.traversable
    windows[windows < 0] = np.nan
    heat = IdlenessMap(windows, unit="ticks", label="longest unseen window", never=never)
    intruder = None
    laps = 1
    if path is not None:
        cells = [int(cell) for cell in path.cells]
        in_view = [bool(result.seen[(path.start_tick + tick) % result.period, cell]) for tick, cell in enumerate(cells)]
        intruder = Intruder(
            [grid.unflat(cell) for cell in cells],
            path.start_tick,
            in_view=in_view,
            source=source,
            target=target,
            label="intruder" if path.found else "intruder (closest call)",
        )
        laps = -(-(path.start_tick + len(cells)) // result.period)
    return Overlays(
        idleness=heat,
        laps=LapViews(result.period, result.seen, laps=laps),
        routes=patrol_routes(patrol, grid),
        intruder=intruder,
        layers=SNEAK_LAYERS,
    )
