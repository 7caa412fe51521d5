"""The sneak check of a level's scene as ``guardsim sneak`` runs it: the patrol checked, the view table,
the level's detection model, its cameras and light, then :func:`~guardsim.sneak.sneak_check`."""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

if TYPE_CHECKING:
    from guardsim.detection import GuardDetection
    from guardsim.detection.watch import LevelWatch
    from guardsim.patrol.model import Patrol
    from guardsim.scene import Scene
    from guardsim.sneak import SneakResult
    from guardsim.vision.table import ViewTable

__all__ = [
    "SneakRun",
    "gait_runs",
    "run_sneak",
    "sneak_endpoints",
    "sneak_header",
    "sneak_summary",
]


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
    return {
        **scene.vision_record(),
        "detection": dataclasses.asdict(detection.model),
        "intruder": dataclasses.asdict(scene.level.intruder),
        "max_lap": max_lap,
    }


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

    patrol.require_repeating_grid(patrol_name, "sneak")
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


def sneak_endpoints(
    scene: Scene,
    source: tuple[float, float] | None,
    target: tuple[float, float],
    *,
    level_name: str = "level",
    say: Callable[[str], None] | None = None,
) -> tuple[tuple[float, float], int, int]:
    """The entry point (``source``, default the level's first player start, told to ``say``) and the
    flat floor cells of it and ``target`` (world units); a point off the floor, a level without a player
    start when none is given (named ``level_name``) and a goal that cannot be reached at all are each a
    :class:`~guardsim.errors.GuardsimError` line."""
    from guardsim.errors import GuardsimError

    level, grid = scene.level, scene.grid
    if source is None:
        if not level.player_starts:
            raise GuardsimError(f"{level_name}: the level marks no player start: give --from X,Y")
        source = level.player_starts[0]
        if say is not None:
            say(f"from the level's player start ({source[0]:g}, {source[1]:g})")
    start, goal = grid.floor_cell(source, "--from"), grid.floor_cell(target, "--to")
    if grid.component_labels[start] != grid.component_labels[goal]:
        raise GuardsimError(
            f"--to {target[0]:g},{target[1]:g} cannot be reached from --from {source[0]:g},{source[1]:g} at all"
        )
    return source, start, goal


def sneak_summary(result: SneakResult, *, undetected: bool = False, unheard: bool = False) -> str:
    """The answer in one line: the path (or the closest call), then its grade and the slack."""
    path, grade = result.path, result.grade
    assert path is not None and grade is not None
    rule = ("undetected" if undetected else "unseen") + (", unheard" if unheard else "")
    if path.found:
        answer = f"sneaks: {rule} from tick {path.start_tick} of the lap, {path.ticks} ticks"
    else:
        heard = f" and heard {path.steps_heard} times" if unheard else ""
        answer = (
            f"caught: no {rule} path; the closest call is seen for {path.ticks_in_view} ticks{heard} "
            f"({path.ticks} ticks long)"
        )
    peaks = grade.peak_by_guard
    guards = len(peaks) - result.sight.cameras
    peak = ", ".join(f"{value:.2f}" for value in peaks[:guards])
    if result.sight.cameras:
        peak += "; by camera: " + ", ".join(f"{value:.2f}" for value in peaks[guards:])
    graded = (
        f"detected: {'yes, at tick ' + str(grade.detected_at) if grade.detected else 'no'}; "
        f"peak awareness {grade.peak:.2f} (by guard: {peak}); risk {grade.risk:.2f}; "
        f"slack {result.slack}/{result.period} entry ticks"
    )
    return f"{answer}; {graded}"


def gait_runs(gaits: tuple[str, ...], sneak_ticks: int) -> str:
    """A path's gaits per tick as runs in order: ``walk x2, sneak x5 (2 ticks each), wait 3 ticks``."""
    runs: list[str] = []
    for gait, ticks in ((gait, len(list(run))) for gait, run in itertools.groupby(gaits)):
        if gait == "wait":
            runs.append(f"wait {ticks} tick{'s' if ticks != 1 else ''}")
        elif gait == "sneak":
            runs.append(f"sneak x{ticks // sneak_ticks} ({sneak_ticks} tick{'s' if sneak_ticks != 1 else ''} each)")
        else:
            runs.append(f"walk x{ticks}")
    return ", ".join(runs) if runs else "none (it enters at its goal)"
