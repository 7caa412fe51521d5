"""What ``guardsim sneak`` writes: sneak.json, the hiding-spot heat map, the GIF and the viewer page."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from guardsim.detection import GuardDetection
from guardsim.detection.watch import LevelWatch
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.patrol.model import Patrol
from guardsim.patrol.replay import patrol_trace
from guardsim.scene import Scene
from guardsim.sneak import SneakResult
from guardsim.vision.table import ViewTable

__all__ = ["write_sneak_outputs"]


def write_sneak_outputs(
    folder: Path,
    scene: Scene,
    table: ViewTable,
    patrol: Patrol,
    result: SneakResult,
    data: dict[str, object],
    *,
    start: int,
    source: tuple[float, float],
    target: tuple[float, float],
    detection: GuardDetection,
    gif: bool = False,
    html: bool = False,
    safe: Sequence[tuple[float, float]] = (),
    watch: LevelWatch | None = None,
) -> tuple[list[str], list[str]]:
    """Write sneak.json (``data``, :func:`guardsim.sneak.sneak_data`) and hiding.png into ``folder``, and
    the GIF and the page when asked; the paths written and the warnings (what could not be drawn)."""
    level, grid = scene.level, scene.grid
    path = result.path
    assert path is not None
    written: list[str] = []
    warnings: list[str] = []
    write_text_atomic(folder / "sneak.json", json.dumps(data, separators=(",", ":")) + "\n")
    written.append(str(folder / "sneak.json"))
    try:
        from guardsim.patrol.heatmap import write_heat_map

        windows = result.hiding.reshape(grid.shape).astype(float)
        never = windows == result.period
        windows[windows < 0] = float("nan")
        cells = [grid.unflat(int(cell)) for cell in path.cells]
        label = "unseen path" if path.found else f"closest call ({path.ticks_in_view} ticks in view)"
        title = (
            f"{level.name}: hiding spots, longest unseen window per cell ({data['never_seen_cells']} never seen, black)"
        )
        write_heat_map(
            folder / "hiding.png",
            level,
            grid,
            windows,
            title=title,
            unit=f"ticks unseen in a row (lap {result.period})",
            never=never,
            marks=[(cells, "red", label)],
        )
        written.append(str(folder / "hiding.png"))
    except GuardsimError as error:
        warnings.append(f"hiding.png not written: {error}")
    if gif or html:
        trace = patrol_trace(
            scene,
            table,
            patrol,
            np.asarray(grid.component(*grid.unflat(start)).ravel()),
            start=path.start_tick,
            ticks=path.ticks,
            label="sneak",
        )
        cells = [grid.unflat(int(cell)) for cell in path.cells]
        grade = result.grade
        assert grade is not None
        if gif:
            from guardsim.sneak.gif import path_states, write_sneak_gif

            seen_at = {
                tick for tick, cell in enumerate(path.cells) if result.sight.seen_at(path.start_tick + tick, int(cell))
            }
            guards = grade.meters.shape[1] - result.sight.cameras
            write_sneak_gif(
                folder / "sneak.gif",
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
            written.append(str(folder / "sneak.gif"))
        if html:
            from guardsim.viewer import write_viewer
            from guardsim.viewer.patrols import sneak_overlays

            # The page runs in lap ticks from lap tick 0; the intruder enters at its start tick.
            lap = patrol_trace(scene, table, patrol, trace.goal.ravel(), start=0, ticks=patrol.ticks, label="sneak")
            overlays = sneak_overlays(
                patrol, grid, result, source=source, target=target, detection=detection, safe=safe, watch=watch
            )
            write_viewer(folder / "sneak.html", level, lap, overlays=overlays)
            written.append(str(folder / "sneak.html"))
    return written, warnings
