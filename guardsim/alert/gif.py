"""An alert episode as an animated GIF: the sneak GIF's guards, meters, intruder, cameras and light,
plus each guard's state as a letter over it (``H`` while it investigates a noise it heard), the contaminated set as dots,
the last known position as a cross and each noise as a ring of its radius where and when it is made."""

from __future__ import annotations

import os

import numpy as np
from PIL import ImageDraw

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.trace import guard_trace
from guardsim.detection import intruder_state
from guardsim.render.layout import MIN_GUARD_RADIUS
from guardsim.render.palette import Index, guard_index
from guardsim.scene import Scene
from guardsim.sneak.gif import SneakFrames, write_sneak_gif
from guardsim.vision.table import ViewTable

__all__ = ["CONTAMINATED_INDEX", "HEARD_LETTER", "LAST_KNOWN_INDEX", "STATE_LETTERS", "write_alert_gif"]

#: The letter drawn over a guard in each state.
STATE_LETTERS = {"patrol": "P", "suspicious": "?", "investigate": "I", "chase": "!", "search": "S", "return": "R"}

#: The letter over a guard investigating a noise it heard.
HEARD_LETTER = "H"

#: Contaminated cells: dots in the third guard colour (green). The viewer page draws them alike.
CONTAMINATED_INDEX = guard_index(2)
#: The last known cell: a cross in the first guard colour (red).
LAST_KNOWN_INDEX = guard_index(0)


def write_alert_gif(
    path: str | os.PathLike[str], scene: Scene, table: ViewTable, episode: AlertEpisode, *, suspicious: float
) -> int:
    """Write ``episode`` as a GIF; returns the number of frames."""
    grid = scene.grid
    trace = guard_trace(scene, table, episode)
    record = episode.record
    cells: list[tuple[int, int]] = []
    # Before a sneak enters it is drawn at its entry, where it waits; after it leaves, where it left.
    last = next((cell for cell in record["intruder"] if cell is not None), episode.intruder.cell)
    for cell in record["intruder"]:
        last = cell if cell is not None else last
        cells.append(grid.unflat(last))
    meters = np.asarray(record["awareness"], dtype=np.float64)
    detected_at = next((e.tick for e in episode.events if e.event == "detected"), None)
    states = [
        intruder_state(list(meters[t]), False, suspicious, detected_at is not None and t >= detected_at)
        for t in range(meters.shape[0])
    ]

    def overlay(draw: ImageDraw.ImageDraw, drawer: SneakFrames, tick: int) -> None:
        step = min(tick, len(record["cells"]) - 1)
        layout = drawer.layout
        dot = max(1.0, layout.scale / 5)
        for cell in record["contaminated_cells"][step].tolist():
            x, y = drawer.cell_centre(grid.unflat(cell))
            x, y = x + layout.left, y + layout.top
            draw.rectangle([x - dot, y - dot, x + dot, y + dot], fill=CONTAMINATED_INDEX)
        known = record["last_known"][step]
        if known >= 0:
            x, y = drawer.cell_centre(grid.unflat(known))
            x, y, arm = x + layout.left, y + layout.top, max(3.0, layout.scale * 0.6)
            draw.line([x - arm, y - arm, x + arm, y + arm], fill=LAST_KNOWN_INDEX, width=2)
            draw.line([x - arm, y + arm, x + arm, y - arm], fill=LAST_KNOWN_INDEX, width=2)
        for tick, cell, reach, _ in episode.noises:
            if tick == step:
                x, y = drawer.cell_centre(grid.unflat(cell))
                x, y, ring = x + layout.left, y + layout.top, reach / grid.cell_size * layout.scale
                draw.ellipse([x - ring, y - ring, x + ring, y + ring], outline=int(Index.OUTLINE), width=2)
        radius = max(MIN_GUARD_RADIUS, 0.45 * layout.scale)
        heard = record["heard"][step] if "heard" in record else []
        for guard, (x, y) in enumerate(drawer.guard_centres(step)):
            letter = STATE_LETTERS[record["guard_states"][step][guard]]
            if heard and heard[guard]:
                letter = HEARD_LETTER
            # Left of the meter bar near the right edge, right of it elsewhere.
            side = x - radius - 9 if x > layout.left + layout.play[0] - 3 * radius - 8 else x + radius + 2
            draw.text((side, y - radius - 13), letter, fill=int(Index.OUTLINE))

    # In continuous motion the guards are drawn, and look, from their bodies' poses at each tick.
    poses = np.asarray(record["poses"], dtype=np.float64) if "poses" in record else None
    # The level's cameras sweep on their own clock: the episode's tick t is their swing's tick phase + t.
    watch = episode.cameras.watch
    camera_meters = record.get("camera_awareness")
    return write_sneak_gif(
        path,
        scene.level,
        trace,
        cells,
        meters=meters,
        states=states,
        suspicious=suspicious,
        overlay=overlay,
        guard_poses=None if poses is None else poses.transpose(1, 0, 2),
        lap_start=episode.phase,
        light=None if watch is None or not watch.dark else watch.light.reshape(grid.shape),
        cameras=[
            (sight.camera.position, sight.headings, sight.camera.fov_degrees, sight.view_range)
            for sight in (() if watch is None else watch.cameras)
        ],
        camera_meters=None if not camera_meters else np.asarray(camera_meters, dtype=np.float64),
    )
