"""Episodes as animated GIFs, streamed: each frame is encoded and written as soon as it is drawn.

Every frame uses the one fixed palette (:mod:`guardsim.render.palette`), written once as the GIF's global
colour table, so nothing is quantised. After the first frame only the rectangle that changed since the
previous frame is encoded (GIF frames are composed over the previous one), which keeps files small and
encoding fast. Pillow's GIF encoder does the LZW compression, one frame at a time.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import BinaryIO

import numpy as np
from PIL import GifImagePlugin, Image

from guardsim.errors import ArgumentError
from guardsim.files.output import atomic_path
from guardsim.level import Level
from guardsim.render.frames import FrameDrawer
from guardsim.render.palette import PALETTE, Index
from guardsim.render.timeline import GifOptions, frame_durations, frame_ticks
from guardsim.trace import Trace

__all__ = ["GifStream", "encode_gif", "write_gif"]

_PALETTE_BYTES = bytes(channel for colour in PALETTE for channel in colour)


def _palette_image(frame: np.ndarray) -> Image.Image:
    image = Image.frombytes("P", (frame.shape[1], frame.shape[0]), np.ascontiguousarray(frame).tobytes())
    image.putpalette(_PALETTE_BYTES)
    return image


class GifStream:
    """Writes palette-index frames to a binary file as an animated GIF that loops forever.

    Call :meth:`add` once per frame and :meth:`close` at the end; only the previous frame is kept.
    """

    def __init__(self, file: BinaryIO) -> None:
        self.file = file
        self.previous: np.ndarray | None = None

    def add(self, frame: np.ndarray, duration_ms: int) -> None:
        """Append ``frame`` (``uint8 (height, width)`` palette indices) shown for ``duration_ms``."""
        if self.previous is None:
            header, _ = GifImagePlugin.getheader(_palette_image(frame), None, {"loop": 0, "optimize": False})
            self.file.write(b"".join(header))
            box = (0, 0, frame.shape[1], frame.shape[0])
        else:
            if frame.shape != self.previous.shape:
                raise ArgumentError(f"frame shape {frame.shape} differs from the first frame's {self.previous.shape}")
            changed = frame != self.previous
            rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
            # An unchanged frame still needs an image: one pixel, redrawn as it was.
            box = (0, 0, 1, 1) if not rows.size else (int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1)
        x0, y0, x1, y1 = box
        part = frame[y0:y1, x0:x1]
        extra = {}
        if self.previous is not None:
            # Pixels that did not change inside the rectangle are left transparent: long runs of one
            # index, which LZW packs into few codes.
            part = np.where(part == self.previous[y0:y1, x0:x1], Index.TRANSPARENT, part).astype(np.uint8)
            extra["transparency"] = Index.TRANSPARENT
        image = _palette_image(part)
        self.file.write(b"".join(GifImagePlugin.getdata(image, (x0, y0), duration=duration_ms, disposal=1, **extra)))
        self.previous = frame

    def close(self) -> None:
        """Write the GIF trailer."""
        self.file.write(b";")


def _stream(level: Level, trace: Trace, options: GifOptions, file: BinaryIO) -> int:
    # Frames keep game time only when the trace has one (continuous motion records its tick rate).
    tick_hz = trace.tick_hz if trace.motion == "continuous" else None
    ticks = frame_ticks(trace.steps, options, tick_hz)
    speed_up = options.speed_up if tick_hz is not None else None
    drawer = FrameDrawer(level, trace, size=options.size, speed_up=speed_up)
    stream = GifStream(file)
    for tick, duration in zip(ticks, frame_durations(ticks, options, tick_hz), strict=True):
        stream.add(drawer.frame(tick), duration)
    stream.close()
    return len(ticks)


def write_gif(path: str | Path, level: Level, trace: Trace, options: GifOptions | None = None) -> int:
    """Write the episode to ``path`` as an animated GIF (atomically); return the number of frames."""
    with atomic_path(path) as temporary, open(temporary, "wb") as file:
        return _stream(level, trace, options or GifOptions(), file)


def encode_gif(level: Level, trace: Trace, options: GifOptions | None = None) -> bytes:
    """The episode as animated GIF bytes (loops forever; the last frame is held ``hold_ms``)."""
    buffer = io.BytesIO()
    _stream(level, trace, options or GifOptions(), buffer)
    return buffer.getvalue()
