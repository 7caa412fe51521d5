"""A patrol for a game or an engine: waypoints in world coordinates (route.json).

route.json (``guardsim patrol --export``) lists each guard's waypoints: the points where its motion
changes (a turn, a stop, a start), straight runs merged, each with its arrival tick, its time in seconds
at ``speed`` world units per second, and the guard's heading there in degrees (0 along +x, 90 along +y,
y down as in Tiled). A wait is two waypoints at the same place. A repeating guard's last waypoint is
its first again, one period later. The Tiled object layer is :mod:`guardsim.patrol.tiled_export`.
"""

from __future__ import annotations

from typing import Any

from guardsim.grid import CoverageGrid
from guardsim.patrol.model import Patrol

__all__ = ["DEFAULT_SPEED", "route_data", "waypoints"]

#: World units per second a guard walks at unless told otherwise (a walking pace when a unit is a metre).
DEFAULT_SPEED = 2.0

def waypoints(patrol: Patrol, grid: CoverageGrid, guard: int, *, speed: float = DEFAULT_SPEED) -> list[dict[str, Any]]:
    """Guard ``guard``'s waypoints, straight runs merged (see the module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 3), dtype=bool), np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]]))
    >>> lap = Patrol(np.array([[0 * 4 + 2, 1 * 4 + 0, 2 * 4 + 0, 1 * 4 + 2]]), 4, "loop")
    >>> [(w["x"], w["tick"], w["heading"]) for w in waypoints(lap, grid, 0)]
    [(0.5, 0, 180.0), (2.5, 2, 0.0), (0.5, 4, 180.0)]
    """
    cells = patrol.cells(grid, guard)
    headings = patrol.headings(guard)
    if patrol.period is not None:
        cells.append(cells[0])
        headings.append(headings[0])
    seconds_per_tick = grid.cell_size / speed
    moves = [cells[index + 1] != cells[index] for index in range(len(cells) - 1)]
    kinds = [
        headings[index + 1] if moves[index] else -1 for index in range(len(moves))
    ]  # what each tick's move is: a heading, or -1 for standing
    kept = [0]
    for index in range(1, len(cells) - 1):
        if kinds[index - 1] != kinds[index]:
            kept.append(index)
    if len(cells) > 1:
        kept.append(len(cells) - 1)
    points = []
    for index in kept:
        x, y = grid.centre(*cells[index])
        points.append(
            {
                "x": round(x, 6),
                "y": round(y, 6),
                "tick": index,
                "time": round(index * seconds_per_tick, 6),
                "heading": float(90 * headings[index]),
            }
        )
    return points


def route_data(patrol: Patrol, grid: CoverageGrid, *, level: str, speed: float = DEFAULT_SPEED) -> dict[str, Any]:
    """The JSON-ready route.json of a patrol."""
    seconds_per_tick = grid.cell_size / speed
    return {
        "level": level,
        "units": "world",
        "speed": speed,
        "seconds_per_tick": seconds_per_tick,
        "period_ticks": patrol.period,
        "period_seconds": None if patrol.period is None else round(patrol.period * seconds_per_tick, 6),
        "repeats": patrol.period is not None,
        "guards": [{"waypoints": waypoints(patrol, grid, guard, speed=speed)} for guard in range(patrol.guards)],
    }
