"""Everything that watches a level's floor besides its guards: the cameras and the light, on one lap.

:func:`level_watch` computes, once per scene, the light of every cell and each camera's swing and gains.
:func:`lap_gains` joins them to a patrol: the joint lap is the least common multiple of the patrol's
lap and every camera's period in ticks (over :data:`MAX_JOINT_LAP` ticks it is a one-line
:class:`~guardsim.errors.LimitError` naming the limit to raise), the patrol repeated over it, and the
gains of every watcher (the guards first, then the cameras) at every tick of it. A level fully lit with
no camera gives the patrol's own lap and exactly the gains it always had.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from guardsim.detection.cameras import CameraSight, camera_gains, camera_sight, camera_ticks
from guardsim.detection.exposure import PatrolGains
from guardsim.detection.light import light_values, scene_sight
from guardsim.detection.model import AwarenessMeter, DetectionModel, GuardDetection
from guardsim.detection.sight import LapSight, lap_sight, patrol_gains
from guardsim.errors import ArgumentError, LimitError
from guardsim.grid import CoverageGrid
from guardsim.kernels.meter import DETECTED
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable

__all__ = [
    "MAX_GAIN_ENTRIES",
    "MAX_JOINT_LAP",
    "CameraAlarms",
    "LevelWatch",
    "joint_lap",
    "lap_gains",
    "lap_sight_of",
    "level_watch",
]

#: Longest joint lap (patrol lap and camera swings), in ticks, before the exact checks refuse a level.
MAX_JOINT_LAP = 10_000
#: Most (tick, cell) gains one camera's swing may hold (8 bytes each): as many as the sneak search's nodes.
MAX_GAIN_ENTRIES = 20_000_000


class LevelWatch(NamedTuple):
    """A level's light and cameras on its grid, for one tick length."""

    light: np.ndarray
    """``float64 (cells,)``: each cell's light (all 1 on a fully lit level)."""
    cameras: tuple[CameraSight, ...]
    """Each camera's swing and sight."""
    gains: tuple[np.ndarray, ...]
    """Each camera's ``float64 (ticks, cells)`` gains over its own swing (empty when not computed)."""
    notes: tuple[str, ...]
    """One line per camera whose period was rounded to whole ticks."""
    source: str = ""
    """The level's file, named by the errors about its cameras."""

    @property
    def periods(self) -> tuple[int, ...]:
        """Each camera's period in ticks."""
        return tuple(sight.ticks for sight in self.cameras)

    @property
    def dark(self) -> bool:
        """Whether some cell is less than fully lit."""
        return bool((self.light < 1.0).any())


def level_watch(scene: Scene, dt: float, *, max_lap: int = MAX_JOINT_LAP, gains: bool = True) -> LevelWatch:
    """The light and cameras of ``scene``'s level with ticks of ``dt`` seconds; ``gains=False`` leaves the
    cameras' gains out (pictures and game-time alarms read only their sight).

    Raises
    ------
    LimitError
        When a camera's swing alone is over ``max_lap`` ticks (no joint lap could hold it), or its gains
        over :data:`MAX_GAIN_ENTRIES` (swing ticks times cells).
    """
    level = scene.level
    sight = scene_sight(scene)
    light = light_values(level, sight) if sight is not None else np.ones(scene.grid.size, dtype=np.float64)
    light = light.astype(np.float64)
    cameras = []
    tables: list[np.ndarray] = []
    notes = []
    for index, camera in enumerate(level.cameras):
        assert sight is not None  # scene_sight gives one whenever the level has a camera
        try:
            ticks, _ = camera_ticks(camera, dt, name=f"cameras[{index}]")
        except LimitError as error:
            raise LimitError(f"{level.source}: {error}") from None
        if ticks > max_lap:
            raise LimitError(
                f"{level.source}: cameras[{index}]'s swing is {ticks} ticks, over the limit of {max_lap} for the joint lap "
                "(raise it with --max-lap)"
            )
        if gains and ticks * scene.grid.size > MAX_GAIN_ENTRIES:
            raise LimitError(
                f"{level.source}: cameras[{index}]'s swing of {ticks} ticks over {scene.grid.size} cells is over "
                f"{MAX_GAIN_ENTRIES} (tick, cell) gains: shorten its swing or use a larger cell_size"
            )
        watch = camera_sight(camera, level.guard, sight, dt, name=f"cameras[{index}]")
        cameras.append(watch)
        if gains:
            tables.append(camera_gains(watch, light, dt, scene.grid.size))
        if watch.note:
            notes.append(watch.note)
    return LevelWatch(light, tuple(cameras), tuple(tables), tuple(notes), level.source)


def joint_lap(period: int, watch: LevelWatch | None, *, max_lap: int = MAX_JOINT_LAP) -> int:
    """The least common multiple of the patrol's ``period`` and the cameras' periods.

    >>> joint_lap(12, None)
    12
    """
    lap = int(period)
    for ticks in () if watch is None else watch.periods:
        lap = math.lcm(lap, int(ticks))
    if lap > max_lap and watch is not None and watch.cameras:
        periods = ", ".join(str(ticks) for ticks in watch.periods)
        raise LimitError(
            f"{watch.source + ': ' if watch.source else ''}the joint lap of the patrol's {period} ticks and the cameras' swings ({periods} ticks) is {lap} ticks, "
            f"over the limit of {max_lap} (raise it with --max-lap)"
        )
    return lap


def lap_gains(
    grid: CoverageGrid,
    table: ViewTable,
    states: np.ndarray,
    detection: GuardDetection,
    watch: LevelWatch | None,
    *,
    max_lap: int = MAX_JOINT_LAP,
) -> tuple[PatrolGains, np.ndarray]:
    """The gains of every watcher over the joint lap, and the patrol's states repeated over it
    (``int64 (guards, joint lap)``). ``watch`` ``None`` is a fully lit level without cameras."""
    states, light, cameras = _joint(states, watch, max_lap)
    gains = patrol_gains(
        grid, table, states, detection.model, view_range=detection.view_range, dt=detection.dt,
        light=light, cameras=cameras,
    )  # fmt: skip
    return gains, states


def lap_sight_of(
    grid: CoverageGrid,
    table: ViewTable,
    states: np.ndarray,
    detection: GuardDetection,
    watch: LevelWatch | None,
    *,
    max_lap: int = MAX_JOINT_LAP,
) -> tuple[LapSight, np.ndarray]:
    """:func:`lap_gains` kept sparse (:class:`~guardsim.detection.sight.LapSight`): the same gains, without
    an array over every (watcher, lap tick, cell)."""
    states, light, cameras = _joint(states, watch, max_lap)
    sight = lap_sight(
        grid, table, states, detection.model, view_range=detection.view_range, dt=detection.dt,
        light=light, cameras=cameras,
    )  # fmt: skip
    return sight, states


def _joint(
    states: np.ndarray, watch: LevelWatch | None, max_lap: int
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """The states over the joint lap, the light (``None``: fully lit) and the cameras' gains over it."""
    states = np.asarray(states, dtype=np.int64)
    period = states.shape[1]
    lap = joint_lap(period, watch, max_lap=max_lap)
    if lap != period:
        states = states[:, np.arange(lap) % period]
    light = None if watch is None or not watch.dark else watch.light
    cameras = None
    if watch is not None and watch.cameras:
        if len(watch.gains) != len(watch.cameras):
            raise ArgumentError("lap_gains needs the cameras' gains: build the watch with level_watch(..., gains=True)")
        cameras = np.stack([gain[np.arange(lap) % gain.shape[0]] for gain in watch.gains])
    return states, light, cameras


class CameraAlarms:
    """The cameras' own meters in game time: :meth:`look` each tick; a camera whose meter fills raises
    the alarm.

    Examples
    --------
    >>> from guardsim import Scene, parse_level
    >>> scene = Scene.from_level(parse_level({"outer": [[0, 0], [6, 0], [6, 1], [0, 1]],
    ...     "cameras": [{"position": [0, 0.5], "detect_near": 1, "detect_far": 1}]}))
    >>> detection = GuardDetection.of_level(scene.level)
    >>> alarms = CameraAlarms(level_watch(scene, detection.dt), detection, guards=2)
    >>> [alarms.look(tick, scene.grid.flat(3, 0)) for tick in range(3)], alarms.levels()
    ([[], [2], []], [1.0])
    """

    def __init__(self, watch: LevelWatch | None, detection: GuardDetection, guards: int) -> None:
        self.watch = watch
        self.dt = detection.dt
        self.guards = guards
        model = detection.model
        self.meters = [
            AwarenessMeter(
                DetectionModel(sight.detect_near, sight.detect_far, model.forget, model.suspicious, dark_sight=0.0),
                sight.view_range,
            )
            for sight in (() if watch is None else watch.cameras)
        ]

    def look(self, tick: int, intruder: int) -> list[int]:
        """Update every camera's meter for the intruder in flat cell ``intruder`` (-1: not in the level) at
        tick ``tick`` of the cameras' swings; the watchers (``guards + camera``) whose meter filled now."""
        if self.watch is None:
            return []
        filled = []
        light = 1.0 if intruder < 0 else float(self.watch.light[intruder])
        for index, (sight, meter) in enumerate(zip(self.watch.cameras, self.meters, strict=True)):
            before = meter.level
            where = int(np.searchsorted(sight.cells, intruder)) if intruder >= 0 else 0
            seen = intruder >= 0 and where < sight.cells.size and int(sight.cells[where]) == intruder
            seen = seen and bool(sight.in_cone[tick % sight.ticks, where])
            distance = float(sight.distances[where]) if seen else 0.0
            meter.update(self.dt, seen, distance, light)
            if seen and meter.level >= DETECTED > before:
                filled.append(self.guards + index)
        return filled

    def levels(self) -> list[float]:
        """Each camera's meter."""
        return [meter.level for meter in self.meters]
