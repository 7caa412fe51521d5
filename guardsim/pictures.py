"""The pictures of ``guardsim patrol``, ``sneak`` and ``fortify``, drawn from what their computing step returned.

The computing packages draw nothing: :func:`guardsim.patrol.job.run_patrol` returns a
:class:`~guardsim.patrol.job.PatrolRun` and :func:`guardsim.sneak.sneak_check` a
:class:`~guardsim.sneak.SneakResult`; this module (downstream of :mod:`guardsim.render` and
:mod:`guardsim.viewer`) turns them into the heat map (PNG), the GIF and the viewer page, each at the path
it is given. A picture that cannot be drawn for want of an optional library is a warning, not an error.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from guardsim.errors import GuardsimError, TraceError

if TYPE_CHECKING:
    from guardsim.design.diff import LevelDiff
    from guardsim.design.fortify.loop import FortifyResult
    from guardsim.detection import GuardDetection
    from guardsim.detection.watch import LevelWatch
    from guardsim.level import Level
    from guardsim.patrol.job import PatrolRun
    from guardsim.patrol.model import Patrol
    from guardsim.render.timeline import GifOptions
    from guardsim.scene import Scene
    from guardsim.sneak import SneakResult
    from guardsim.trace import Trace
    from guardsim.vision.table import ViewTable

__all__ = [
    "Drawn",
    "write_diff_pictures",
    "write_fortify_picture",
    "write_patrol_pictures",
    "write_play_pictures",
    "write_sneak_json_page",
    "write_sneak_pictures",
]


class Drawn(NamedTuple):
    """What a ``write_*_pictures`` call drew."""

    written: list[str]
    """The paths written, in the order drawn."""
    warnings: list[str]
    """One line per picture that could not be drawn, and why."""


def write_patrol_pictures(
    scene: Scene,
    run: PatrolRun,
    *,
    heat_map: Path | None = None,
    gif: Path | None = None,
    html: Path | None = None,
) -> Drawn:
    """Draw ``run`` (:func:`~guardsim.patrol.job.run_patrol` on ``scene``): each cell's worst gap as a heat
    map PNG, one lap as a GIF, and the lap in the viewer page, each where a path is given."""
    level, grid, shown = scene.level, scene.grid, run.shown
    written: list[str] = []
    warnings: list[str] = []
    if heat_map is not None:
        from guardsim.patrol.job import idleness_text
        from guardsim.render.heatmap import write_heat_map

        title = (
            f"{level.name}: {run.what}, worst gap per cell "
            f"(worst {idleness_text(shown.worst)}, mean {idleness_text(shown.mean)} {shown.unit})"
        )
        try:
            write_heat_map(
                heat_map,
                level,
                grid,
                shown.gaps.reshape(grid.shape),
                title=title,
                unit=f"{shown.unit} unseen in a row",
                never=shown.never.reshape(grid.shape),
            )
            written.append(str(heat_map))
        except GuardsimError as error:
            warnings.append(f"{heat_map.name} not written: {error}")
    if gif is None and html is None:
        return Drawn(written, warnings)
    from guardsim.patrol.job import lap_trace

    trace = lap_trace(scene, run)
    if gif is not None:
        from guardsim.render.gif import write_gif

        write_gif(gif, level, trace)
        written.append(str(gif))
    if html is not None:
        from guardsim.viewer import write_viewer
        from guardsim.viewer.patrols import patrol_overlays

        overlays = patrol_overlays(
            run.patrol,
            grid,
            run.table,
            idleness=shown.gaps.reshape(grid.shape),
            never=shown.never.reshape(grid.shape),
            unit=shown.unit,
            watch=_level_watch(scene),
        )
        write_viewer(html, level, trace, overlays=overlays)
        written.append(str(html))
    return Drawn(written, warnings)


def write_sneak_pictures(
    scene: Scene,
    table: ViewTable,
    patrol: Patrol,
    result: SneakResult,
    *,
    start: int,
    source: tuple[float, float],
    target: tuple[float, float],
    detection: GuardDetection,
    never_seen: int,
    heat_map: Path | None = None,
    gif: Path | None = None,
    html: Path | None = None,
    safe: Sequence[tuple[float, float]] = (),
    watch: LevelWatch | None = None,
) -> Drawn:
    """Draw ``result`` (:func:`~guardsim.sneak.sneak_check` from flat cell ``start``): the hiding spots
    (each cell's longest unseen window, ``never_seen`` cells never seen) with the path as a heat map PNG,
    the guards and the intruder as a GIF, and the lap with the hiding spots and the intruder in the viewer
    page, each where a path is given."""
    from guardsim.patrol.replay import patrol_trace

    level, grid = scene.level, scene.grid
    path = result.path
    if path is None:
        raise GuardsimError("the sneak result holds no path to draw")
    written: list[str] = []
    warnings: list[str] = []
    cells = [grid.unflat(int(cell)) for cell in path.cells]
    if heat_map is not None:
        from guardsim.render.heatmap import write_heat_map

        windows = result.hiding.reshape(grid.shape).astype(float)
        never = windows == result.period
        windows[windows < 0] = float("nan")
        label = "unseen path" if path.found else f"closest call ({path.ticks_in_view} ticks in view)"
        title = f"{level.name}: hiding spots, longest unseen window per cell ({never_seen} never seen, black)"
        try:
            write_heat_map(
                heat_map,
                level,
                grid,
                windows,
                title=title,
                unit=f"ticks unseen in a row (lap {result.period})",
                never=never,
                marks=[(cells, "red", label)],
            )
            written.append(str(heat_map))
        except GuardsimError as error:
            warnings.append(f"{heat_map.name} not written: {error}")
    if gif is not None:
        from guardsim.detection import path_states
        from guardsim.render.sneak import write_sneak_gif

        trace = patrol_trace(
            scene,
            table,
            patrol,
            np.asarray(grid.component(*grid.unflat(start)).ravel()),
            start=path.start_tick,
            ticks=path.ticks,
            label="sneak",
        )
        grade = result.grade
        if grade is None:
            raise GuardsimError("the sneak result holds no graded path to draw")
        seen_at = {
            tick for tick, cell in enumerate(path.cells) if result.sight.seen_at(path.start_tick + tick, int(cell))
        }
        guards = grade.meters.shape[1] - result.sight.cameras
        write_sneak_gif(
            gif,
            level,
            trace,
            cells,
            seen_ticks=seen_at,
            lap_start=path.start_tick,
            period=result.period,
            meters=grade.meters[:, :guards],
            states=path_states(grade.meters, grade.in_view, grade.detected_at, detection.model.suspicious),
            suspicious=detection.model.suspicious,
            light=None if watch is None or not watch.dark else watch.light.reshape(grid.shape),
            cameras=[
                (sight.camera.position, sight.headings, sight.camera.fov_degrees, sight.view_range)
                for sight in (() if watch is None else watch.cameras)
            ],
            camera_meters=grade.meters[:, guards:] if result.sight.cameras else None,
        )
        written.append(str(gif))
    if html is not None:
        from guardsim.viewer import write_viewer
        from guardsim.viewer.patrols import sneak_overlays

        # The page runs in lap ticks from lap tick 0; the intruder enters at its start tick.
        goal = np.asarray(grid.component(*grid.unflat(start)).ravel())
        lap = patrol_trace(scene, table, patrol, goal, start=0, ticks=patrol.ticks, label="sneak")
        overlays = sneak_overlays(
            patrol, grid, result, source=source, target=target, detection=detection, safe=safe, watch=watch
        )
        write_viewer(html, level, lap, overlays=overlays)
        written.append(str(html))
    return Drawn(written, warnings)


def write_sneak_json_page(
    path: Path,
    level: Level,
    data: dict[str, Any],
    *,
    patrol_path: str | None = None,
    source: str = "sneak.json",
) -> SneakResult:
    """Write the viewer page of a saved sneak check (``data``, sneak.json read from ``source``) on
    ``level``: the check run again as it ran (its patrol, ``patrol_path`` or the one it records, its
    vision, detection keys and lap limit), so the page is the one ``sneak --html`` writes. A
    :class:`~guardsim.errors.TraceError` when the file is not a sneak check of this level, or when the
    check run again does not find its path (the level or the patrol changed since)."""
    import dataclasses

    from guardsim.patrol import read_patrol
    from guardsim.scene import Scene
    from guardsim.sneak.run import run_sneak

    try:
        cells = [(int(col), int(row)) for col, row in data["path"]]
        patrol_file = patrol_path if patrol_path is not None else str(data["patrol"])
        points = (float(data["from"][0]), float(data["from"][1])), (float(data["to"][0]), float(data["to"][1]))
        undetected = data["rule"] == "undetected"
        unheard = bool(data.get("unheard", False))
        hiding = data["longest_unseen"]
        shape = (len(hiding), len(hiding[0]))
    except (KeyError, TypeError, ValueError, IndexError) as error:
        raise TraceError(f"{source}: not a sneak check's sneak.json ({type(error).__name__}: {error})") from None
    if not cells:
        raise TraceError(f"{source}: the check found no path to draw")
    if "detection" in data:
        level = dataclasses.replace(level, guard=dataclasses.replace(level.guard, **data["detection"]))
    if "intruder" in data:
        level = dataclasses.replace(level, intruder=dataclasses.replace(level.intruder, **data["intruder"]))
    scene = Scene.from_level(level, **Scene.recorded_vision(data))
    grid = scene.grid
    rows, cols = grid.shape
    if shape != (rows, cols) or any(not (0 <= c < cols and 0 <= r < rows) for c, r in cells):
        raise TraceError(f"{source}: its grid is not the {rows} x {cols} grid of {level.source}")
    start, goal = grid.flat(*cells[0]), grid.flat(*cells[-1])
    patrol = read_patrol(patrol_file, grid, level=level.name)
    run = run_sneak(
        scene, patrol, start, goal, undetected=undetected, unheard=unheard, max_lap=data.get("max_lap"),
        patrol_name=patrol_file,
    )  # fmt: skip
    found = run.result.path
    if (
        found is None
        or [grid.unflat(int(cell)) for cell in found.cells] != cells
        or found.start_tick != data["start_tick"]
    ):
        raise TraceError(
            f"{source}: the check run again on {level.source} and {patrol_file} finds another path: the level or "
            "the patrol changed since"
        )
    write_sneak_pictures(
        scene, run.table, run.patrol, run.result, start=start, source=points[0], target=points[1],
        detection=run.detection, never_seen=int(data.get("never_seen_cells", 0)), html=path, watch=run.watch,
    )  # fmt: skip
    return run.result


def _level_watch(scene: Scene) -> LevelWatch | None:
    """The level's cameras and light for the page, ``None`` on a fully lit level without cameras."""
    from guardsim.detection import grid_tick_seconds
    from guardsim.detection.watch import level_watch

    if not scene.level.cameras and scene.level.lit:
        return None
    return level_watch(scene, grid_tick_seconds(scene.level), gains=False)


def write_fortify_picture(result: FortifyResult, picture: str) -> str:
    """Draw what :func:`guardsim.fortify` placed (each watcher with its cone or swing, the counterexamples
    crossed out, the ways still through) to the PNG ``picture``; returns its path."""
    from PIL import Image

    from guardsim.files.output import atomic_path
    from guardsim.render.fortify import fortify_picture

    grid = result.scene.grid
    document = result.document
    post_points = [tuple(w["position"]) for w in document["watchers"] if w["kind"] == "post"]
    image = fortify_picture(
        result.level, grid.traversable, grid.origin,
        posts=post_points,
        counterexamples=[[tuple(p) for p in c["path"]] for c in document["counterexamples"]],
        ways_through=[[tuple(p) for p in pair["way_through"]["path"]] for pair in document["pairs"] if not pair["sealed"]],
        pairs=[(tuple(pair["from"]), tuple(pair["to"])) for pair in document["pairs"]],
    )  # fmt: skip
    with atomic_path(picture) as temporary:
        Image.fromarray(np.ascontiguousarray(image)).save(temporary, format="PNG")
    return picture


def write_diff_pictures(
    found: LevelDiff, data: dict[str, Any], *, png: str | None, html: str | None, title: str
) -> list[str]:
    """The picture of what an edit changed (PNG, :func:`guardsim.render.diff.diff_picture`) and the page
    of both analyses with the table of changes (``data``: :func:`guardsim.design.diff_data`); the paths
    written."""
    from guardsim.files.output import atomic_path, write_text_atomic

    written: list[str] = []
    if png is not None:
        import imageio.v3 as iio

        from guardsim.render.diff import diff_picture

        with atomic_path(png) as temporary:
            iio.imwrite(temporary, diff_picture(found), extension=".png")
        written.append(png)
    if html is not None:
        from guardsim.viewer.serve import analysis_payload, diff_table, static_page

        payloads = [analysis_payload(found.old, data["old_report"]), analysis_payload(found.new, data["new_report"])]
        write_text_atomic(html, static_page(title, payloads, diff_table(data)))
        written.append(html)
    return written


def write_play_pictures(
    level: Level,
    trace: Trace,
    *,
    gif: str | None = None,
    html: str | None = None,
    gif_options: GifOptions | None = None,
    progress: Callable[[str, int, int], None] | None = None,
) -> list[str]:
    """Draw ``guardsim play``'s episode ``trace`` on ``level``: a GIF and the viewer page, each where a
    path is given; the paths written, in that order. ``progress`` hears each one begin."""
    report = progress or (lambda _what, _done, _total: None)
    written = []
    if gif:
        from guardsim.render.gif import write_gif

        report("writing the GIF", 0, 0)
        write_gif(gif, level, trace, gif_options)
        written.append(gif)
    if html:
        from guardsim.viewer import write_viewer

        report("writing the page", 0, 0)
        write_viewer(html, level, trace)
        written.append(html)
    return written
