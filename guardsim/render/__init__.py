"""Headless drawing, every picture but the page: episode frames and animated GIFs drawn from the trace, level
previews, heat maps and figures as PNG.

- :mod:`~guardsim.render.palette`: the one fixed palette frames are drawn in.
- :mod:`~guardsim.render.sight`: what a guard sees, as a visibility polygon from pymunk ray casts.
- :mod:`~guardsim.render.text` and :mod:`~guardsim.render.legend`: caption text and the legend bar.
- :mod:`~guardsim.render.frames`: one episode frame as palette indices.
- :mod:`~guardsim.render.layout`: a frame's layout and the pieces every picture shares (caption wrapping, the guard's body).
- :mod:`~guardsim.render.timeline`: which ticks become frames (no drawing library needed).
- :mod:`~guardsim.render.gif`: frames streamed into an animated GIF.
- :mod:`~guardsim.render.preview`: the level designer's preview (``guardsim render``).
- :mod:`~guardsim.render.sneak` and :mod:`~guardsim.render.alert`: the sneak and alert GIFs.
- :mod:`~guardsim.render.heatmap` and :mod:`~guardsim.render.plots`: heat maps and figures (matplotlib).

Names are loaded from their module when first used, so that reading :data:`DEFAULT_MAX_FRAMES` (a
command-line default) does not import Pillow. See ``docs/rendering.md``.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from guardsim.render.frames import FrameDrawer, render_frame
    from guardsim.render.gif import GifStream, encode_gif, write_gif
    from guardsim.render.layout import pixels_per_cell
    from guardsim.render.palette import COLOURS, GUARD_COLOURS, PALETTE, Index, palette_rgb
    from guardsim.render.preview import draw_cone_overlay, render_preview
    from guardsim.render.sight import SightCaster
    from guardsim.render.timeline import DEFAULT_FRAME_SIZE, DEFAULT_MAX_FRAMES, FRAME_CEILING, GifOptions, frame_ticks

#: Public name -> the module that defines it.
_HOMES = {
    "COLOURS": "palette",
    "GUARD_COLOURS": "palette",
    "PALETTE": "palette",
    "Index": "palette",
    "palette_rgb": "palette",
    "SightCaster": "sight",
    "FrameDrawer": "frames",
    "pixels_per_cell": "layout",
    "render_frame": "frames",
    "DEFAULT_FRAME_SIZE": "timeline",
    "DEFAULT_MAX_FRAMES": "timeline",
    "FRAME_CEILING": "timeline",
    "GifOptions": "timeline",
    "frame_ticks": "timeline",
    "GifStream": "gif",
    "encode_gif": "gif",
    "write_gif": "gif",
    "draw_cone_overlay": "preview",
    "render_preview": "preview",
}

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


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module 'guardsim.render' has no attribute {name!r}")
    return getattr(importlib.import_module(f"guardsim.render.{home}"), name)


def __dir__() -> list[str]:
    return __all__
