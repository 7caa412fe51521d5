"""``guardsim patrol`` as library calls: plan or read a patrol and score it, then write its files.

:func:`run_patrol` plans: it makes (or reads) the patrol and scores it, and writes nothing. The
:class:`PatrolRun` it returns holds patrol.json's contents and what a picture needs (the patrol, its view
table and goal, the idleness shown). :func:`write_patrol_files` writes patrol.json into the output
folder and the route files a :class:`PatrolJob` names (route.json, the Godot scene, the Tiled map;
cleaned routes with ``clean``); :func:`guardsim.pictures.write_patrol_pictures` draws the heat map, the
GIF and the page. The command parses options into a :class:`PatrolJob`, makes the three calls and prints
:meth:`PatrolRun.printed`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from guardsim.errors import GuardsimError
from guardsim.files.output import check_writable, write_text_atomic
from guardsim.importers.imported import counted
from guardsim.level import DEFAULT_MAX_FILE_BYTES
from guardsim.patrol.model import STRATEGIES, Patrol
from guardsim.patrol.scoring import NEVER, PatrolScore
from guardsim.scene import Scene

if TYPE_CHECKING:
    from guardsim.patrol.plan import Progress
    from guardsim.trace import Trace
    from guardsim.vision.table import ViewTable

__all__ = [
    "PatrolFiles",
    "PatrolJob",
    "PatrolRun",
    "ShownIdleness",
    "check_job",
    "idleness_text",
    "lap_trace",
    "run_patrol",
    "tiled_source_of",
    "write_patrol_files",
]


@dataclass(frozen=True)
class PatrolJob:
    """What ``guardsim patrol`` is asked for, beside the level (the command's options; docs/patrols.md)."""

    guards: int = 1
    strategy: str = "loop"
    planner: str = "auto"
    motion: str = "grid"
    seed: int = 0
    start: tuple[float, float] | None = None
    """Where the first guard starts (world units); the patrol watches the cells reachable from there."""
    laps: int = 10
    warmup_laps: int = 2
    compare: bool = False
    evaluate_path: str | None = None
    export_path: str | None = None
    speed: float | None = None
    tiled_out: str | None = None
    tiled_source: str | None = None
    """The Tiled map the level came from (:func:`tiled_source_of`), for ``tiled_out`` and pixel sizes."""
    godot_out: str | None = None
    godot_version: int = 4
    clean: bool = False
    clean_tolerance: float = 0.1
    units: str = "world"
    axis: str = "y-down"
    pixels_per_unit: float | None = None
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES
    memory_bytes: int = 2 * 2**30
    """The memory budget: a level whose patrol would need more is refused before any work."""


class ShownIdleness(NamedTuple):
    """A patrol's idleness as reported: in ticks (grid motion) or seconds (continuous)."""

    unit: str
    """``"ticks"`` or ``"seconds"``."""
    worst: float | None
    """The worst idleness, ``None`` when a goal cell is never seen."""
    mean: float | None
    gaps: np.ndarray
    """``float (cells,)``: worst gap per cell, NaN outside the goal and where never seen."""
    never: np.ndarray
    """``bool (cells,)``: goal cells never seen."""
    never_seen: int

    @classmethod
    def ticks(cls, score: PatrolScore) -> ShownIdleness:
        return cls._of(score, "ticks", 1.0)

    @classmethod
    def seconds(cls, score: PatrolScore, tick_hz: float) -> ShownIdleness:
        return cls._of(score, "seconds", tick_hz)

    @classmethod
    def _of(cls, score: PatrolScore, unit: str, per_second: float) -> ShownIdleness:
        never = score.worst_gap == NEVER
        gaps = score.worst_gap.astype(float)
        gaps[score.worst_gap < 0] = math.nan
        scale = 1.0 / per_second
        worst = score.worst_idleness
        return cls(
            unit,
            None if worst is None else (worst if unit == "ticks" else round(worst * scale, 3)),
            None if score.mean_idleness is None else score.mean_idleness * scale,
            gaps * scale,
            never,
            score.never_seen,
        )


@dataclass
class PatrolRun:
    """What :func:`run_patrol` did, and what a picture of the patrol needs."""

    lines: list[str]
    """What the command prints before its summary: the comparison table."""
    summary: str
    """The summary line, without the files written."""
    patrol: Patrol
    """The patrol made (or read)."""
    table: ViewTable
    goal: np.ndarray
    """``bool (cells,)``: the cells the patrol must watch."""
    warmup: int
    """Ticks before the scored (and drawn) part begins."""
    shown: ShownIdleness
    what: str
    """What was scored: ``"loop patrol"``, ``"patrol.json evaluated"``."""
    speed: float
    """The guards' walking speed, world units per second: the route files' times."""
    notes: list[str] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)
    """patrol.json's contents."""

    def printed(self, files: PatrolFiles, pictures: Sequence[str] = ()) -> list[str]:
        """The lines the command prints: :attr:`lines`, the cleaned routes, the summary naming every file
        written (``files``, then ``pictures``), and the patrol's notes."""
        named = [*files.written, *pictures]
        return [
            *self.lines,
            *files.lines,
            f"{self.summary} -> {', '.join(named)}",
            *(f"  {note}" for note in self.notes),
        ]


class PatrolFiles(NamedTuple):
    """What :func:`write_patrol_files` wrote."""

    written: list[str]
    """The paths written, patrol.json first."""
    warnings: list[str]
    """What was assumed (pixels per unit, tile sizes) for want of a record of it."""
    lines: list[str]
    """One line per route cleaned, as the command prints it."""


def lap_trace(scene: Scene, run: PatrolRun) -> Trace:
    """The trace a picture of ``run`` shows: one lap from the end of the warm-up (a repeating patrol),
    else a twelfth of the walk, at least one tick."""
    from guardsim.patrol.replay import patrol_trace

    chosen = run.patrol
    ticks = (
        chosen.ticks if chosen.period is not None else min(chosen.ticks - run.warmup - 1, max(1, chosen.ticks // 12))
    )
    return patrol_trace(
        scene, run.table, chosen, run.goal, start=run.warmup, ticks=ticks, label=f"patrol {chosen.strategy}"
    )


def check_job(job: PatrolJob) -> None:
    """Refuse what cannot be done before any work: continuous motion walks loops only (made or read)."""
    if job.motion == "continuous" and job.evaluate_path is None:
        if job.strategy != "loop":
            raise GuardsimError(
                f"--motion continuous is not yet supported for patrol strategy {job.strategy} (only loop and --evaluate)"
            )
        if job.compare:
            raise GuardsimError(
                "--compare is not yet supported with --motion continuous (the walked strategies are grid-only)"
            )
    if job.tiled_out:
        from guardsim.patrol.tiled_export import check_tiled_formats

        # A level drawn by hand has no source map: a fresh map is written (any Tiled format).
        check_tiled_formats(job.tiled_source or job.tiled_out, job.tiled_out)


def tiled_source_of(level_path: str, tiled_source: str | None) -> str | None:
    """The Tiled map a level came from: ``tiled_source``, else ``level_path`` itself when it is a Tiled map."""
    if tiled_source is not None:
        return tiled_source
    suffix = Path(level_path).suffix.lower()
    if suffix in (".tmx", ".tmj"):
        return level_path
    if suffix == ".json":
        try:
            head = Path(level_path).read_bytes()[:65536]
        except OSError:
            return None
        if b'"orientation"' in head and b'"outer"' not in head:
            return level_path
    return None


def run_patrol(scene: Scene, job: PatrolJob, *, progress: Progress | None = None) -> PatrolRun:
    """Make (or read and score) the patrol of ``scene`` that ``job`` asks for; ``progress(what, done,
    total)`` hears of each stage. Writes and draws nothing (:func:`write_patrol_files` and
    :func:`guardsim.pictures.write_patrol_pictures` do, from the run)."""
    tell: Progress = progress or _silent
    from guardsim.patrol import patrol_data, patrol_setup, plan_loop, plan_patrol, read_patrol, score_patrol

    level = scene.level
    guards, strategy, planner, motion, seed = job.guards, job.strategy, job.planner, job.motion, job.seed
    laps, warmup_laps, compare, evaluate_path = job.laps, job.warmup_laps, job.compare, job.evaluate_path
    lines: list[str] = []
    tell("view table", 0, 0)
    from guardsim.patrol.plan import check_patrol_memory

    check_patrol_memory(scene, job.memory_bytes)
    setup = patrol_setup(scene, guards, seed=seed, start=job.start)
    extra: dict[str, object] = {}
    if evaluate_path is not None:
        chosen = read_patrol(evaluate_path, scene.grid, level=scene.level.name)
        if chosen.motion == "continuous":
            motion = "continuous"
        score = score_patrol(setup.table, chosen, setup.goal, warmup=0)
        warmup = 0
        what = f"{Path(evaluate_path).name} evaluated"
    else:
        loop_plan, team_scores = plan_loop(setup, guards, planner=planner, progress=tell)
        lap = loop_plan.patrol.ticks
        if strategy == "loop":
            plan = loop_plan
        else:
            tell(f"{strategy} patrol", 0, 0)
            plan = plan_patrol(setup, strategy, laps=laps, warmup_laps=warmup_laps, lap=lap)
        chosen, score, warmup = plan
        what = f"{strategy} patrol"
        if strategy != "loop":
            extra["warmup_ticks"] = warmup
        if compare:
            rows = [("loop", loop_plan.score, loop_plan.patrol.period)]
            for other in STRATEGIES[1:]:
                tell(f"{other} patrol to compare", 0, 0)
                result = (
                    plan
                    if other == strategy
                    else plan_patrol(setup, other, laps=laps, warmup_laps=warmup_laps, lap=lap)
                )
                rows.append((other, result.score, None))
            lines.append(f"{'strategy':<12} {'worst':>8} {'mean':>9} {'period':>7}")
            for name, row_score, period in rows:
                worst = "never" if row_score.worst_idleness is None else str(row_score.worst_idleness)
                mean = "-" if row_score.mean_idleness is None else f"{row_score.mean_idleness:.1f}"
                lines.append(f"{name:<12} {worst:>8} {mean:>9} {period if period is not None else '-':>7}")
            extra["compare"] = {
                name: {"worst_idleness": row_score.worst_idleness, "mean_idleness": row_score.mean_idleness}
                for name, row_score, _ in rows
            }
        if guards > 1 and strategy == "loop":
            extra["team_compare"] = {
                name: {"worst_idleness": team_score.worst_idleness, "mean_idleness": team_score.mean_idleness}
                for name, team_score in team_scores.items()
            }
    from guardsim.motion import GuardMotion

    walk = GuardMotion.of_guard(level.guard, move_speed=job.speed)
    shown = ShownIdleness.ticks(score)
    if motion == "continuous":
        if chosen.period is None:
            raise GuardsimError("--motion continuous walks repeating patrols; this one has period null")
        from guardsim.patrol.continuous import continuous_patrol

        walked = continuous_patrol(scene, chosen, setup.goal, walk)
        shown = ShownIdleness.seconds(walked.score, walk.tick_hz)
        extra.update(
            {
                "period_seconds": round(walked.period_seconds, 4),
                "physics_ticks_per_lap": walked.period,
                "tick_hz": walk.tick_hz,
                "move_speed": walk.move_speed,
                "turn_speed": walk.turn_speed,
                "grid_worst_idleness": score.worst_idleness,
                "ticks_scored": walked.period,
            }
        )
    data = patrol_data(chosen, score, scene.grid, level=level.name, motion=motion, extra=extra)
    data.update(
        worst_idleness=shown.worst,
        mean_idleness=None if shown.mean is None else round(shown.mean, 3),
        idleness=[
            [None if math.isnan(v) else (round(v, 3) if shown.unit == "seconds" else int(v)) for v in row]
            for row in shown.gaps.reshape(scene.grid.shape).tolist()
        ],
        idleness_unit=shown.unit,
        never_seen=shown.never_seen,
    )
    team = f", {chosen.guards} guards" if chosen.guards > 1 else ""
    if chosen.team:
        team += f" ({chosen.team})"
    period_text = f", period {chosen.period} ticks" if chosen.period is not None else ""
    if motion == "continuous":
        period_text = f", continuous lap {data['period_seconds']:.1f} s"
    worst = (
        f"never seen: {shown.never_seen} cells"
        if shown.worst is None
        else f"worst idleness {idleness_text(shown.worst)} {shown.unit}"
    )
    summary = f"{level.name}: {what}{team}{period_text}, {worst}, mean {idleness_text(shown.mean)}"
    return PatrolRun(
        lines,
        summary,
        chosen,
        setup.table,
        setup.goal,
        warmup,
        shown,
        what,
        walk.move_speed,
        list(chosen.notes),
        data,
    )


def write_patrol_files(
    scene: Scene, folder: Path, run: PatrolRun, job: PatrolJob, *, progress: Progress | None = None
) -> PatrolFiles:
    """Write ``run``'s patrol.json into ``folder`` and the route files ``job`` names (route.json, the
    Godot scene, the Tiled map; routes cleaned first with ``job.clean``). Outputs named outside the folder
    are checked before anything is written."""
    tell: Progress = progress or _silent
    level, chosen, speed = scene.level, run.patrol, run.speed
    export_path, tiled_out, tiled_source, godot_out = job.export_path, job.tiled_out, job.tiled_source, job.godot_out
    units, axis, pixels_per_unit, max_file_bytes = job.units, job.axis, job.pixels_per_unit, job.max_file_bytes
    # A bad output found after patrol.json is written would leave it written and the command failed.
    for named in (export_path, tiled_out, godot_out):
        if named is not None:
            check_writable(named)
    lines: list[str] = []
    warnings: list[str] = []
    tell("writing", 0, 0)
    written = [str(folder / "patrol.json")]
    write_text_atomic(folder / "patrol.json", json.dumps(run.data, separators=(",", ":")) + "\n")
    routes = None
    if job.clean and (export_path or godot_out or tiled_out):
        from guardsim.patrol.cleaning import clean_routes
        from guardsim.patrol.export import guard_routes

        routes, reports = clean_routes(
            scene, guard_routes(chosen, scene.grid, speed=speed), run.goal, speed=speed, tolerance=job.clean_tolerance
        )
        for number, report in enumerate(reports, start=1):
            if report is not None:
                lines.append(
                    f"  route {number} cleaned: {report.waypoints_before} -> {report.waypoints_after} waypoints "
                    f"({counted(report.jogs, 'jog')}, {counted(report.spurs, 'spur')} taken out), worst idleness "
                    f"{idleness_text(report.worst_before)} -> {idleness_text(report.worst_after)} s replayed"
                )
    if export_path or godot_out:
        pixels = _pixels_per_unit(pixels_per_unit, tiled_source, level.tile_pixels, max_file_bytes)
        if pixels_per_unit is None and tiled_source is None and level.tile_pixels is None:
            # Only where pixels are written: the Godot scene, and an export in pixels.
            assumed = [str(out) for out in (godot_out, export_path if units == "pixels" else None) if out]
            if assumed:
                warnings.append(
                    f"{', '.join(assumed)}: {pixels[0]:g} pixels per world unit assumed ({level.source} records no "
                    "tile_pixels); give --pixels-per-unit N, or --tiled-source MAP for the tiles of its Tiled map"
                )
    if export_path:
        from guardsim.patrol.export import RouteFrame, route_data

        frame = RouteFrame(units, axis, pixels, scene.grid.cell_size)
        route = route_data(chosen, scene.grid, level=level.name, speed=speed, frame=frame, routes=routes)
        write_text_atomic(export_path, json.dumps(route, indent=1) + "\n")
        written.append(export_path)
    if godot_out:
        from guardsim.patrol.godot import godot_scene

        text = godot_scene(
            chosen,
            scene.grid,
            level=level.name,
            speed=speed,
            pixels_per_unit=pixels,
            version=job.godot_version,
            routes=routes,
        )
        write_text_atomic(godot_out, text)
        written.append(godot_out)
    if tiled_out:
        from guardsim.files.output import atomic_path
        from guardsim.files.reading import read_limited_bytes
        from guardsim.patrol.tiled_export import tiled_with_routes
        from guardsim.patrol.tiled_fresh import DEFAULT_TILE_PIXELS, tiled_from_level

        if tiled_source is None:
            tile: int | tuple[int, int] = level.tile_pixels or DEFAULT_TILE_PIXELS
            if level.tile_pixels is None:
                warnings.append(
                    f"{tiled_out}: {tile}-pixel tiles assumed ({level.source} records no tile_pixels); for the "
                    "tiles of the Tiled map it came from, give --tiled-source MAP (or import the map again)"
                )
            copy = tiled_from_level(level, tiled_out, chosen, scene.grid, speed=speed, routes=routes, tile_pixels=tile)
        else:
            source_bytes = read_limited_bytes(tiled_source, max_file_bytes=max_file_bytes, kind="Tiled map")
            copy = tiled_with_routes(
                tiled_source, tiled_out, chosen, scene.grid, speed=speed, source_bytes=source_bytes, routes=routes
            )
        with atomic_path(tiled_out) as temporary:
            temporary.write_bytes(copy)
        written.append(tiled_out)
    return PatrolFiles(written, warnings, lines)


def _silent(_what: str, _done: int, _total: int) -> None:
    return None


def _pixels_per_unit(
    chosen: float | None, tiled_source: str | None, tile_pixels: tuple[int, int] | None, max_file_bytes: int
) -> tuple[float, float]:
    """Pixels per world unit along x and y: as chosen, else the Tiled map's tile size, else the one the
    level records (:attr:`~guardsim.level.Level.tile_pixels`), else 32."""
    if chosen is not None:
        return chosen, chosen
    if tiled_source is not None:
        from guardsim.files.reading import read_limited_bytes
        from guardsim.patrol.tiled_export import map_tile_size

        return map_tile_size(
            tiled_source, read_limited_bytes(tiled_source, max_file_bytes=max_file_bytes, kind="Tiled map")
        )
    if tile_pixels is not None:
        return float(tile_pixels[0]), float(tile_pixels[1])
    from guardsim.patrol.godot import DEFAULT_PIXELS_PER_UNIT

    return DEFAULT_PIXELS_PER_UNIT, DEFAULT_PIXELS_PER_UNIT


def idleness_text(value: float | None) -> str:
    """An idleness as printed: ``-`` for none, an int as it is, else one decimal."""
    if value is None:
        return "-"
    return str(value) if isinstance(value, int) else f"{value:.1f}"
