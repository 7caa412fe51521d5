"""An alert episode as an animated GIF: the sneak GIF's guards, meters, intruder, cameras and light,
plus each guard's state as a letter over it (``H`` while it investigates a noise it heard), the contaminated set as dots,
the last known position as a cross and each noise as a ring of its radius where and when it is made.

The caption gives the tick and game time, each guard's state, the intruder's and the search area's size;
the legend names the intruder, the state letters, the meter bar, the dots, the cross and the ring."""

from __future__ import annotations

import os

import numpy as np
from PIL import ImageDraw

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.recorded import RecordedEpisode
from guardsim.alert.trace import guard_trace
from guardsim.detection import grid_tick_seconds, intruder_state
from guardsim.render.layout import MIN_GUARD_RADIUS
from guardsim.render.palette import Index, guard_index
from guardsim.render.sneak import SneakFrames, write_sneak_gif
from guardsim.render.text import font
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable

__all__ = [
    "ALERT_LEGEND",
    "CONTAMINATED_INDEX",
    "HEARD_LETTER",
    "LAST_KNOWN_INDEX",
    "LETTER_SIZE",
    "STATE_LETTERS",
    "write_alert_gif",
]

#: The letter drawn over a guard in each state.
STATE_LETTERS = {"patrol": "P", "suspicious": "?", "investigate": "I", "chase": "!", "search": "S", "return": "R"}

#: The letter over a guard investigating a noise it heard.
HEARD_LETTER = "H"

#: Font size of the state letters, in pixels: a capital stands about 14 pixels tall.
LETTER_SIZE = 20

#: The alert frame's legend, ``(swatch kind, label)`` (:func:`~guardsim.render.legend.draw_legend`).
ALERT_LEGEND: list[tuple[str, str]] = [
    ("wall", "wall"),
    ("unseen", "not yet seen"),
    ("seen", "seen"),
    ("cone", "sees now"),
    ("guard", "guards"),
    ("intruder", "intruder (fill: its state)"),
    ("meter", "awareness meter"),
    ("contaminated", "search area (may hide there)"),
    ("last_known", "last known position"),
    ("noise", "noise"),
    ("letter", "P patrol"),
    ("letter", "? suspicious"),
    ("letter", "I investigate"),
    ("letter", "H heard a noise"),
    ("letter", "! chase"),
    ("letter", "S search"),
    ("letter", "R return"),
]

#: Contaminated cells: dots in the third guard colour (green). The viewer page draws them alike.
CONTAMINATED_INDEX = guard_index(2)
#: The last known cell: a cross in the first guard colour (red).
LAST_KNOWN_INDEX = guard_index(0)


def write_alert_gif(
    path: str | os.PathLike[str],
    scene: Scene,
    table: ViewTable,
    episode: AlertEpisode | RecordedEpisode,
    *,
    suspicious: float,
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

    seconds = grid_tick_seconds(scene.level)
    guards = len(record["guard_states"][0])
    team = f"{guards} guards" if guards > 1 else "1 guard"
    heard_at = record.get("heard", [])

    def captions(tick: int) -> tuple[str, str]:
        step = min(tick, len(record["guard_states"]) - 1)
        words = []
        for guard, state in enumerate(record["guard_states"][step]):
            heard = bool(heard_at and heard_at[step][guard])
            words.append(f"{guard + 1} {'heard a noise' if heard else state}")
        first = (
            f"{scene.level.name}  |  tick {tick} / {trace.steps} ({tick * seconds:.1f} s)  |  "
            f"{episode.search.name} search, {team}"
        )
        area = len(record["contaminated_cells"][step])
        second = f"guards: {', '.join(words)}  |  intruder {states[step]}  |  search area {area} {'cell' if area == 1 else 'cells'}"
        return first, second

    letters = font(LETTER_SIZE)

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
            # Beside the disc, level with the meter bar over it: left of it near the right edge, right of it
            # elsewhere. Set twice a pixel apart, so a stem reads bold while the gap in "!" stays open, in a white
            # halo that keeps it legible over cones, dots and the dark.
            advance = letters.getlength(letter) + 1
            right = x > layout.left + layout.play[0] - 2 * radius - advance - 8
            side = x - radius - 5 - advance if right else x + radius + 5
            for shift in (0, 1):
                draw.text((side + shift, y - radius), letter, font=letters, anchor="lm", fill=int(Index.WHITE),
                          stroke_width=2, stroke_fill=int(Index.WHITE))  # fmt: skip
            for shift in (0, 1):
                draw.text((side + shift, y - radius), letter, fill=int(Index.OUTLINE), font=letters, anchor="lm")

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
        captions=captions,
        legend=ALERT_LEGEND,
    )
