"""The sneak check of a level's scene as ``guardsim sneak`` runs it: the patrol checked, the view table,
the level's detection model, its cameras and light, then :func:`~guardsim.sneak.sneak_check`."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

from guardsim.errors import PatrolError

if TYPE_CHECKING:
    from guardsim.detection import GuardDetection
    from guardsim.detection.watch import LevelWatch
    from guardsim.patrol.model import Patrol
    from guardsim.scene import Scene
    from guardsim.sneak import SneakResult
    from guardsim.vision.table import ViewTable

__all__ = ["SneakRun", "check_sneak_patrol", "run_sneak", "sneak_header"]


class SneakRun(NamedTuple):
    """What :func:`run_sneak` did: the answer and what its pictures need."""

    result: SneakResult
    patrol: Patrol
    """The patrol over the joint lap the search ran on (the patrol itself without cameras)."""
    table: ViewTable
    detection: GuardDetection
    watch: LevelWatch | None
    """The level's cameras and light; ``None`` on a fully lit level without cameras."""
    notes: tuple[str, ...]
    """What the cameras' lap had to leave out or round (say them as warnings)."""


def sneak_header(scene: Scene, detection: GuardDetection, max_lap: int | None) -> dict[str, Any]:
    """What sneak.json records of how the check ran, so that it can be run again exactly (``guardsim view``
    does, for the page): the vision (``los``, ``fov``, ``view_range``, ``null`` when unlimited), the
    detection keys, the intruder's keys and the joint lap's limit (``null``: the default)."""
    reach = scene.cone.view_range
    return {
        "los": scene.rule.value,
        "fov": scene.cone.fov_degrees,
        "view_range": None if math.isinf(reach) else reach,
        "detection": dataclasses.asdict(detection.model),
        "intruder": dataclasses.asdict(scene.level.intruder),
        "max_lap": max_lap,
    }


def check_sneak_patrol(patrol: Patrol, patrol_name: str = "patrol") -> None:
    """Refuse a patrol the sneak check cannot search under (a :class:`~guardsim.errors.PatrolError` naming
    ``patrol_name``): it must repeat, in grid motion."""
    if patrol.motion != "grid":
        raise PatrolError(
            f"{patrol_name}: motion is {patrol.motion!r}: the sneak check runs on grid-motion patrols (ticks) only"
        )
    if patrol.period is None:
        raise PatrolError(f"{patrol_name}: period is null: the sneak check needs a repeating patrol")


def run_sneak(
    scene: Scene,
    patrol: Patrol,
    start: int,
    goal: int,
    *,
    undetected: bool = False,
    unheard: bool = False,
    max_lap: int | None = None,
    patrol_name: str = "patrol",
    progress: Callable[[str, int, int], None] | None = None,
) -> SneakRun:
    """Search ``scene`` for a path from flat cell ``start`` to ``goal`` unseen by ``patrol`` (``undetected``:
    no guard's meter fills; ``unheard``: nor hears a step, under the level's intruder keys) under the
    level's detection keys, cameras and light, over a joint lap of at
    most ``max_lap`` ticks (default :data:`~guardsim.detection.watch.MAX_JOINT_LAP`). A patrol that is
    not a repeating grid-motion one is a :class:`~guardsim.errors.PatrolError` naming ``patrol_name``."""
    from guardsim.detection import GuardDetection
    from guardsim.detection.watch import MAX_JOINT_LAP, level_watch
    from guardsim.sneak import sneak_check
    from guardsim.vision.table import view_table

    check_sneak_patrol(patrol, patrol_name)
    level, grid = scene.level, scene.grid
    table = view_table(grid, scene.vision())
    detection = GuardDetection.of_level(level)
    limit = MAX_JOINT_LAP if max_lap is None else max_lap
    watch = level_watch(scene, detection.dt, max_lap=limit) if level.cameras or not level.lit else None
    if progress is not None:
        rule = ("undetected" if undetected else "unseen") + (", unheard" if unheard else "")
        progress(f"searching for an {rule} path", 0, 0)
    result = sneak_check(
        grid, table, patrol, start, goal, detection=detection, undetected=undetected, watch=watch, max_lap=limit,
        unheard=unheard, intruder=level.intruder,
    )  # fmt: skip
    lap = patrol if result.lap is None else result.lap
    return SneakRun(result, lap, table, detection, watch, () if watch is None else tuple(watch.notes))
