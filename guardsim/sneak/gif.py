"""The sneak as an animated GIF: the patrol's frames, with the intruder's trail and position drawn on top."""

from __future__ import annotations

import os

import numpy as np
from PIL import Image, ImageDraw

from guardsim.level import Level
from guardsim.output import atomic_path
from guardsim.render.frames import FrameDrawer
from guardsim.render.gif import GifOptions, GifStream, frame_ticks
from guardsim.render.palette import Index, guard_index
from guardsim.trace import Trace

__all__ = ["SneakFrames", "write_sneak_gif"]

#: The intruder's colour: a guard colour no team of up to five guards uses.
_INTRUDER = guard_index(5)


class SneakFrames(FrameDrawer):
    """The patrol's frames over the sneak's ticks, captioned with both clocks: the sneak's tick (the
    frame's) and the lap tick it falls on, ``(lap_start + tick) % period``, as sneak.json and the page
    count them. Without ``period`` the caption is the plain one."""

    def __init__(self, level: Level, trace: Trace, *, size: int, lap_start: int = 0, period: int | None = None) -> None:
        super().__init__(level, trace, size=size)
        self.lap_start = lap_start
        self.period = period

    def caption(self, tick: int) -> tuple[str, str]:
        first, second = super().caption(tick)
        if self.period is None:
            return first, second
        plain = f"  |  tick {tick} / {self.trace.steps}"
        lap = (self.lap_start + tick) % self.period
        both = f"  |  sneak tick {tick} / {self.trace.steps} \u00b7 lap tick {lap} / {self.period}"
        return first.replace(plain, both, 1), second


def write_sneak_gif(
    path: str | os.PathLike[str],
    level: Level,
    trace: Trace,
    intruder: list[tuple[int, int]],
    *,
    seen_ticks: set[int] | frozenset[int] = frozenset(),
    options: GifOptions | None = None,
    lap_start: int = 0,
    period: int | None = None,
) -> int:
    """Write the guards of ``trace`` with the intruder walking ``intruder`` (one cell per tick of the
    trace): its trail in the cyan of guard colour 6 (teams of up to five keep their own colours), itself a
    white disc ringed in that colour, filled black at ticks in ``seen_ticks`` (a closest call's).

    With ``period`` (the patrol's lap) the caption also gives the lap tick: the trace's tick 0 is lap tick
    ``lap_start`` (the sneak's start tick)."""
    options = options or GifOptions()
    drawer = SneakFrames(level, trace, size=options.size, lap_start=lap_start, period=period)
    layout = drawer.layout
    ticks = frame_ticks(trace.steps, options)
    radius = max(2.0, layout.scale * 0.45)
    with atomic_path(path) as temporary, open(temporary, "wb") as file:
        stream = GifStream(file)
        for number, tick in enumerate(ticks):
            frame = drawer.frame(tick)
            image = Image.frombytes("P", (frame.shape[1], frame.shape[0]), np.ascontiguousarray(frame).tobytes())
            draw = ImageDraw.Draw(image)
            shown = intruder[: min(tick, len(intruder) - 1) + 1]
            points = [_pixel(drawer, cell) for cell in shown]
            if len(points) > 1:
                draw.line(points, fill=_INTRUDER, width=max(2, layout.scale // 2))
            x, y = points[-1]
            fill = int(Index.WALL) if tick in seen_ticks else int(Index.WHITE)
            draw.ellipse([x - radius, y - radius, x + radius, y + radius], fill=fill, outline=_INTRUDER, width=2)
            last = number == len(ticks) - 1
            stream.add(np.asarray(image), max(options.frame_ms, options.hold_ms) if last else options.frame_ms)
        stream.close()
    return len(ticks)


def _pixel(drawer: FrameDrawer, cell: tuple[int, int]) -> tuple[float, float]:
    x, y = drawer.cell_centre(cell)
    return x + drawer.layout.left, y + drawer.layout.top
