"""Headless drawing: episode frames and animated GIFs drawn from the trace, and level previews as PNG.

- :mod:`~guardsim.render.palette`: the one fixed palette frames are drawn in.
- :mod:`~guardsim.render.sight`: what a guard sees, as a visibility polygon from pymunk ray casts.
- :mod:`~guardsim.render.frames`: one episode frame (level, unseen cells, cones, trails, guards, caption,
  legend) as palette indices.
- :mod:`~guardsim.render.gif`: frames streamed into an animated GIF.
- :mod:`~guardsim.render.preview`: the level designer's preview (``guardsim render``).

See ``docs/rendering.md``.
"""

from __future__ import annotations

from guardsim.render.frames import DEFAULT_FRAME_SIZE, FrameDrawer, pixels_per_cell, render_frame
from guardsim.render.gif import (
    DEFAULT_MAX_FRAMES,
    FRAME_CEILING,
    GifOptions,
    GifStream,
    encode_gif,
    frame_ticks,
    write_gif,
)
from guardsim.render.palette import COLOURS, GUARD_COLOURS, PALETTE, Index, palette_rgb
from guardsim.render.preview import draw_cone_overlay, render_preview
from guardsim.render.sight import SightCaster

__all__ = [
    "COLOURS",
    "DEFAULT_FRAME_SIZE",
    "DEFAULT_MAX_FRAMES",
    "FRAME_CEILING",
    "GUARD_COLOURS",
    "PALETTE",
    "FrameDrawer",
    "GifOptions",
    "GifStream",
    "Index",
    "SightCaster",
    "draw_cone_overlay",
    "encode_gif",
    "frame_ticks",
    "palette_rgb",
    "pixels_per_cell",
    "render_frame",
    "render_preview",
    "write_gif",
]
