"""The viewer layers of a patrol and of a sneak, from their results (``guardsim patrol`` / ``sneak --html``).

Downstream of :mod:`guardsim.patrol` and :mod:`guardsim.sneak`: they never import the viewer.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.detection import NEVER_DETECTED, DetectionModel, GuardDetection, path_states
from guardsim.detection.watch import LevelWatch
from guardsim.errors import GuardsimError
from guardsim.grid import CoverageGrid
from guardsim.patrol.export import waypoints
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import seen_timeline
from guardsim.sneak import SneakResult
from guardsim.viewer.layers import DEFAULT_LAPS, IdlenessMap, Intruder, LapViews, Overlays, SafeSpot, WatchLayers
from guardsim.vision.table import ViewTable

__all__ = [
    "PATROL_LAYERS",
    "SNEAK_LAYERS",
    "patrol_overlays",
    "patrol_routes",
    "safe_spots",
    "sneak_overlays",
    "watch_layers",
]

#: Layers a patrol page opens with: the worst-gap heat map under the guards, their loops and cones.
PATROL_LAYERS = ("idleness", "route", "trail", "cone")
#: Layers a sneak page opens with: the hiding-spot heat map, the loops, the cones, the intruder, the
#: guards' awareness meters and the safe spots.
SNEAK_LAYERS = ("idleness", "route", "cone", "intruder", "meters", "safe")


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
    watch: LevelWatch | None = None,
) -> Overlays:
    """The page layers of ``patrol`` on ``grid`` (with ``watch``, the level's cameras and light too).

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
        layers=PATROL_LAYERS if watch is None else (*PATROL_LAYERS, "light", "cameras"),
        watch=watch_layers(watch, grid),
    )


def safe_spots(grid: CoverageGrid, result: SneakResult, points: Sequence[tuple[float, float]]) -> list[SafeSpot]:
    """The safe spots at ``points`` (world units), each checked as ``check --safe`` checks it under the
    sneak's rule: never seen during the lap, or (``--undetected``) a player standing there never detected.

    Raises
    ------
    GuardsimError
        When a point lies outside the grid.
    """
    spots = []
    for point in points:
        cell = grid.cell_of(point)
        if cell is None:
            raise GuardsimError(f"safe spot {point[0]:g},{point[1]:g} lies outside the level")
        flat = grid.flat(*cell)
        if result.undetected:
            lasts = int(result.time_to_detection[flat])
            holds = lasts == NEVER_DETECTED
            label = "never detected" if holds else ("no floor" if lasts < 0 else f"detected after {lasts} ticks")
        else:
            holds = int(result.sight.seen_counts()[flat]) == 0
            label = "never seen" if holds else f"seen {result.exposure[flat]:.0%} of the lap"
        spots.append(SafeSpot(cell, holds, label))
    return spots


def sneak_overlays(
    patrol: Patrol,
    grid: CoverageGrid,
    result: SneakResult,
    *,
    source: tuple[float, float] | None = None,
    target: tuple[float, float] | None = None,
    detection: GuardDetection | None = None,
    safe: Sequence[tuple[float, float]] = (),
    watch: LevelWatch | None = None,
) -> Overlays:
    """The page layers of a sneak check: the lap, the hiding spots, the exposure and time-to-detection
    maps, the loops, the intruder with the guards' awareness meters and its state, and the safe spots at
    the points ``safe``.

    The page's tick 0 is the lap's tick 0 (pair it with the patrol's trace from lap tick 0); the intruder
    enters at its ``start_tick`` and the timeline spans the laps its walk needs. ``detection`` gives the
    suspicious level of the intruder's states (default: the model's default).
    """
    path = result.path
    windows = result.hiding.reshape(grid.shape).astype(float)
    never = (windows == result.period) & grid.traversable
    windows[windows < 0] = np.nan
    heat = IdlenessMap(windows, unit="ticks", label="longest unseen window", never=never)
    exposure = np.where(grid.traversable, result.exposure.reshape(grid.shape), np.nan)
    lasts = result.time_to_detection.reshape(grid.shape)
    detection_time = IdlenessMap(
        np.where(lasts >= 0, lasts, np.nan).astype(float),
        unit="ticks",
        label="time to detection",
        never=lasts == NEVER_DETECTED,
        never_text="never detected",
    )
    suspicious = (detection.model if detection is not None else DetectionModel()).suspicious
    intruder = None
    laps = 1
    guards = result.sight.watchers - result.sight.cameras
    camera_meters = None
    if path is not None:
        cells = [int(cell) for cell in path.cells]
        in_view = [result.sight.seen_at(path.start_tick + tick, cell) for tick, cell in enumerate(cells)]
        grade = result.grade
        intruder = Intruder(
            [grid.unflat(cell) for cell in cells],
            path.start_tick,
            in_view=in_view,
            source=source,
            target=target,
            label="intruder" if path.found else "intruder (closest call)",
            meters=None if grade is None else grade.meters[:, :guards],
            states=() if grade is None else path_states(grade.meters, grade.in_view, grade.detected_at, suspicious),
            suspicious=suspicious,
            detected_at=None if grade is None else grade.detected_at,
        )
        laps = -(-(path.start_tick + len(cells)) // result.period)
        if grade is not None and result.sight.cameras:
            camera_meters = grade.meters[:, guards:]
    layers = watch_layers(watch, grid, camera_meters)
    return Overlays(
        idleness=heat,
        laps=LapViews(result.period, result.seen, laps=laps),
        routes=patrol_routes(patrol, grid),
        intruder=intruder,
        exposure=IdlenessMap(exposure, unit="of the lap in view", label="exposure", top=1.0),
        detection_time=detection_time,
        safe=safe_spots(grid, result, safe),
        layers=SNEAK_LAYERS if layers is None else (*SNEAK_LAYERS, "light", "cameras"),
        watch=layers,
    )


def watch_layers(watch: LevelWatch | None, grid: CoverageGrid, meters: np.ndarray | None = None) -> WatchLayers | None:
    """The page's light and cameras layers of ``watch`` (``None`` when it has neither), with the cameras'
    ``meters`` over an intruder's path."""
    if watch is None or not (watch.cameras or watch.dark):
        return None
    return WatchLayers(
        light=watch.light.reshape(grid.shape) if watch.dark else None,
        cameras=[
            (sight.camera.position, sight.headings, sight.camera.fov_degrees, sight.view_range)
            for sight in watch.cameras
        ],
        meters=meters,
    )
