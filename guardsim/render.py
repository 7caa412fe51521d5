"""Headless drawing: episode frames as an animated GIF, and level previews as PNG.

Frames follow the RippleFront paper's figure: unseen cells dark, walls light, seen cells clear over the
level drawing, the guard and its vision cone on top and the percentage of area still unseen in the
middle. Cell colours are composed with numpy; Pillow draws only the vector overlays.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import imageio.v3 as iio
import numpy as np
import shapely
from PIL import Image, ImageDraw, ImageFont

from guardsim.errors import LimitError
from guardsim.level import Level
from guardsim.trace import Trace

__all__ = [
    "COLOURS",
    "DEFAULT_MAX_FRAMES",
    "GifOptions",
    "draw_cone_overlay",
    "encode_gif",
    "frame_ticks",
    "render_frame",
    "render_preview",
]

#: The palette, as RGB.
COLOURS = {
    "wall": (200, 202, 208),
    "free": (252, 252, 250),
    "unseen": (38, 40, 56),
    "unreachable": (122, 62, 142),
    "blocked": (236, 222, 196),
    "reachable": (206, 236, 210),
    "grid": (222, 224, 228),
    "path": (70, 130, 220),
    "guard": (214, 40, 40),
    "cone": (240, 150, 0),
    "text": (255, 255, 255),
    "text_outline": (0, 0, 0),
    "ruler": (90, 90, 100),
}

#: Frames in a GIF unless the caller asks for more; the stride grows to stay under it.
DEFAULT_MAX_FRAMES = 200
#: Hard ceiling on frames, whatever the options, to keep GIFs bounded.
FRAME_CEILING = 5000
#: Longest side of a frame in pixels, before rounding to whole pixels per cell.
DEFAULT_FRAME_SIZE = 480


@dataclass(frozen=True)
class GifOptions:
    """How an episode becomes a GIF."""

    stride: int | None = None
    """Ticks between frames; ``None`` picks the smallest stride that keeps under ``max_frames``."""
    frame_ms: int = 60
    """Duration of each frame in milliseconds."""
    hold_ms: int = 2000
    """Duration of the last frame, so the final coverage stays on screen."""
    max_frames: int = DEFAULT_MAX_FRAMES
    """Most frames the GIF may have."""
    size: int = DEFAULT_FRAME_SIZE
    """Longest side of a frame in pixels (approximate: cells are whole pixels)."""


def pixels_per_cell(shape: tuple[int, int], size: int) -> int:
    """Whole pixels per cell so that the longer side is about ``size`` pixels (at least 1)."""
    return max(1, size // max(shape))


def frame_ticks(steps: int, options: GifOptions) -> list[int]:
    """The ticks drawn: every ``stride``-th from 0, and always the last.

    Raises
    ------
    LimitError
        If an explicit stride would exceed ``max_frames``.
    """
    if options.max_frames < 1 or options.max_frames > FRAME_CEILING:
        raise LimitError(f"--max-frames must be from 1 to {FRAME_CEILING} (the GIF ceiling), not {options.max_frames}")
    if options.max_frames == 1:
        return [steps]
    if options.stride is None:
        # The last tick is always added, so leave room for it.
        stride = max(1, math.ceil(steps / (options.max_frames - 1)))
    else:
        if options.stride < 1:
            raise LimitError(f"frame stride must be at least 1, not {options.stride}")
        stride = options.stride
    ticks = list(range(0, steps + 1, stride))
    if ticks[-1] != steps:
        ticks.append(steps)
    if len(ticks) > options.max_frames:
        raise LimitError(
            f"{len(ticks)} frames at stride {stride} is over the limit of {options.max_frames} "
            "(raise --stride or --max-frames)"
        )
    return ticks


@lru_cache(maxsize=8)
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    try:
        return ImageFont.load_default(size=size)
    except (TypeError, ImportError, OSError):
        # Pillow built without FreeType has only the fixed bitmap font.
        return ImageFont.load_default()


def _level_drawing(level: Level, origin: tuple[float, float], shape: tuple[int, int], scale: int) -> Image.Image:
    """Walls light, free area clear, at ``scale`` pixels per cell."""
    rows, cols = shape
    image = Image.new("RGB", (cols * scale, rows * scale), COLOURS["wall"])
    draw = ImageDraw.Draw(image)
    pixels_per_unit = scale / level.cell_size

    def to_pixels(ring: tuple[tuple[float, float], ...]) -> list[tuple[float, float]]:
        return [((x - origin[0]) * pixels_per_unit, (y - origin[1]) * pixels_per_unit) for x, y in ring]

    draw.polygon(to_pixels(level.outer), fill=COLOURS["free"])
    for hole in level.holes:
        draw.polygon(to_pixels(hole), fill=COLOURS["wall"])
    return image


def _paint_cells(base: np.ndarray, cells: np.ndarray, colour: tuple[int, int, int], scale: int) -> None:
    """Paint every cell where ``cells`` is true with ``colour``, in place."""
    mask = np.repeat(np.repeat(cells, scale, axis=0), scale, axis=1)
    base[mask] = colour


def _text_centred(draw: ImageDraw.ImageDraw, centre: tuple[float, float], text: str, size: int) -> None:
    font = _font(size)
    draw.text(
        centre,
        text,
        fill=COLOURS["text"],
        font=font,
        anchor="mm",
        stroke_width=max(1, size // 10),
        stroke_fill=COLOURS["text_outline"],
    )


def _draw_guard(
    draw: ImageDraw.ImageDraw,
    level: Level,
    cell: tuple[int, int],
    heading: int,
    scale: int,
) -> None:
    centre = ((cell[0] + 0.5) * scale, (cell[1] + 0.5) * scale)
    # Past twice the grid's longer side the cone's arc is off the image; Pillow's time grows with the radius.
    reach = min(level.guard.view_range / level.cell_size, 2 * max(level.grid_shape())) * scale
    half = level.guard.fov_degrees / 2
    box = [centre[0] - reach, centre[1] - reach, centre[0] + reach, centre[1] + reach]
    width = max(1, scale // 4)
    if level.guard.fov_degrees >= 360:
        draw.ellipse(box, outline=COLOURS["cone"], width=width)
    else:
        # Pillow's angles run clockwise from +x on screen, like our headings with y down.
        draw.pieslice(box, 90 * heading - half, 90 * heading + half, outline=COLOURS["cone"], width=width)
    radius = max(2.0, max(level.guard.radius / level.cell_size, 0.35) * scale)
    draw.ellipse(
        [centre[0] - radius, centre[1] - radius, centre[0] + radius, centre[1] + radius], fill=COLOURS["guard"]
    )


def render_frame(level: Level, trace: Trace, tick: int, *, size: int = DEFAULT_FRAME_SIZE) -> np.ndarray:
    """The frame at ``tick`` as an ``uint8 (height, width, 3)`` array."""
    scale = pixels_per_cell(trace.shape, size)
    base = np.asarray(_level_drawing(level, trace.origin, trace.shape, scale)).copy()
    return _compose(base, level, trace, tick, scale)


def _compose(base: np.ndarray, level: Level, trace: Trace, tick: int, scale: int) -> np.ndarray:
    unseen = trace.goal & ((trace.first_seen < 0) | (trace.first_seen > tick))
    frame = base.copy()
    _paint_cells(frame, unseen, COLOURS["unseen"], scale)
    _paint_cells(frame, trace.traversable & ~trace.goal, COLOURS["unreachable"], scale)
    image = Image.fromarray(frame)
    draw = ImageDraw.Draw(image)
    team = list(zip(trace.team_paths(), trace.team_headings()))
    for path, _ in team:
        walked = [((c + 0.5) * scale, (r + 0.5) * scale) for c, r in path[: tick + 1]]
        if len(walked) > 1:
            draw.line(walked, fill=COLOURS["path"], width=max(1, scale // 4))
    for path, headings in team:
        _draw_guard(draw, level, path[tick], headings[tick], scale)
    percent = trace.unseen_percent[tick]
    _text_centred(draw, (image.width / 2, image.height / 2), f"{percent:.1f}% unseen", max(12, image.width // 12))
    return np.asarray(image)


def encode_gif(level: Level, trace: Trace, options: GifOptions | None = None) -> bytes:
    """The episode as animated GIF bytes (loops forever; the last frame is held ``hold_ms``)."""
    options = options or GifOptions()
    ticks = frame_ticks(trace.steps, options)
    scale = pixels_per_cell(trace.shape, options.size)
    base = np.asarray(_level_drawing(level, trace.origin, trace.shape, scale)).copy()
    frames = np.stack([_compose(base, level, trace, tick, scale) for tick in ticks])
    durations = [options.frame_ms] * len(ticks)
    durations[-1] = max(options.frame_ms, options.hold_ms)
    return iio.imwrite("<bytes>", frames, extension=".gif", duration=durations, loop=0)


def render_preview(
    level: Level,
    traversable: np.ndarray,
    reachable: np.ndarray,
    origin: tuple[float, float],
    *,
    start: tuple[int, int] | None = None,
    size: int = 640,
) -> np.ndarray:
    """A level designer's preview: walls, grid, reachable and unreachable cells, the start.

    Traversable cells reachable from the start are tinted green, other traversable cells purple, and
    free-area cells where the guard does not fit are tinted sand.
    """
    shape = traversable.shape
    scale = max(2, pixels_per_cell(shape, size))
    drawing = np.asarray(_level_drawing(level, origin, shape, scale)).copy()
    rows, cols = shape
    centre_x = origin[0] + (np.arange(cols) + 0.5) * level.cell_size
    centre_y = origin[1] + (np.arange(rows) + 0.5) * level.cell_size
    free = shapely.contains_xy(level.free_area(), *np.meshgrid(centre_x, centre_y))
    _paint_cells(drawing, free & ~traversable, COLOURS["blocked"], scale)
    _paint_cells(drawing, reachable, COLOURS["reachable"], scale)
    _paint_cells(drawing, traversable & ~reachable, COLOURS["unreachable"], scale)
    image = Image.fromarray(drawing)
    draw = ImageDraw.Draw(image)
    if scale >= 4:
        for col in range(shape[1] + 1):
            draw.line([(col * scale, 0), (col * scale, image.height)], fill=COLOURS["grid"])
        for row in range(shape[0] + 1):
            draw.line([(0, row * scale), (image.width, row * scale)], fill=COLOURS["grid"])
    pixels_per_unit = scale / level.cell_size
    for ring in (level.outer, *level.holes):
        points = [((x - origin[0]) * pixels_per_unit, (y - origin[1]) * pixels_per_unit) for x, y in ring]
        draw.line([*points, points[0]], fill=COLOURS["ruler"], width=1)
    if start is not None:
        centre = ((start[0] + 0.5) * scale, (start[1] + 0.5) * scale)
        radius = max(2, scale // 2)
        draw.ellipse(
            [centre[0] - radius, centre[1] - radius, centre[0] + radius, centre[1] + radius], fill=COLOURS["guard"]
        )
    return np.asarray(_with_rulers(image, level, origin, scale))


def _with_rulers(image: Image.Image, level: Level, origin: tuple[float, float], scale: int) -> Image.Image:
    """Add a margin with world-coordinate ticks along the top and left edges."""
    margin = 36
    framed = Image.new("RGB", (image.width + 2 * margin, image.height + 2 * margin), (255, 255, 255))
    framed.paste(image, (margin, margin))
    draw = ImageDraw.Draw(framed)
    font = _font(10)
    cols, rows = image.width // scale, image.height // scale
    step = _ruler_step(max(cols, rows) * level.cell_size)
    pixels_per_unit = scale / level.cell_size
    value = math.ceil(origin[0] / step) * step
    while (value - origin[0]) * pixels_per_unit <= image.width:
        x = margin + (value - origin[0]) * pixels_per_unit
        draw.line([(x, margin - 6), (x, margin)], fill=COLOURS["ruler"])
        draw.text((x, margin - 8), f"{value:g}", fill=COLOURS["ruler"], font=font, anchor="mb")
        value += step
    value = math.ceil(origin[1] / step) * step
    while (value - origin[1]) * pixels_per_unit <= image.height:
        y = margin + (value - origin[1]) * pixels_per_unit
        draw.line([(margin - 6, y), (margin, y)], fill=COLOURS["ruler"])
        draw.text((margin - 8, y), f"{value:g}", fill=COLOURS["ruler"], font=font, anchor="rm")
        value += step
    return framed


def _ruler_step(extent: float) -> float:
    """A round tick spacing giving about ten ticks over ``extent``."""
    raw = max(extent / 10, 1e-9)
    power = 10 ** math.floor(math.log10(raw))
    for multiple in (1, 2, 5, 10):
        if raw <= multiple * power:
            return multiple * power
    return 10 * power


def draw_cone_overlay(
    preview: np.ndarray,
    level: Level,
    shape: tuple[int, int],
    seen: np.ndarray,
    cell: tuple[int, int],
    heading: int,
    *,
    size: int = 640,
) -> np.ndarray:
    """A copy of a :func:`render_preview` image showing what a guard at ``cell`` facing ``heading`` sees.

    The ``bool (rows, cols)`` ``seen`` cells are tinted with the cone's colour, and the cone's outline and
    the guard are drawn on top. ``shape`` and ``size`` must be the ones the preview was drawn with.
    """
    rows, cols = shape
    scale = max(2, pixels_per_cell(shape, size))
    # render_preview frames the cells in an equal margin on every side (the rulers).
    margin = (preview.shape[1] - cols * scale) // 2
    framed = preview.copy()
    cells = framed[margin : margin + rows * scale, margin : margin + cols * scale]
    tint = np.repeat(np.repeat(seen, scale, axis=0), scale, axis=1)
    cells[tint] = (cells[tint] * 0.45 + np.asarray(COLOURS["cone"]) * 0.55).astype(np.uint8)
    image = Image.fromarray(np.ascontiguousarray(cells))
    _draw_guard(ImageDraw.Draw(image), level, cell, heading, scale)
    framed[margin : margin + rows * scale, margin : margin + cols * scale] = np.asarray(image)
    return framed
