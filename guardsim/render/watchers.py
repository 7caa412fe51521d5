"""Cameras and light in pictures: each camera's swing drawn as an arc, and the light as a shaded layer
with a colour bar (``guardsim render``, and the sneak pictures).

Darkness is a blend toward :data:`~guardsim.render.palette.WATCH_COLOURS` ``dark`` of at most
:data:`~guardsim.render.palette.DARK_ALPHA`, in proportion to ``1 - light``: unlit floor is dark, yet its
cells, walls and grid still read. A camera is a magenta dot; its swing is the arc its cone's edges sweep
(``heading ± (sweep + fov) / 2`` at its range), with the two ends of the swing as lines.
"""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from guardsim.level import Level
from guardsim.render.palette import COLOURS, DARK_ALPHA, WATCH_COLOURS
from guardsim.render.preview import preview_scale
from guardsim.render.text import Typesetter

__all__ = ["draw_cameras", "draw_watch_overlay", "light_bar", "shade_light"]


def shade_light(cells: np.ndarray, light: np.ndarray, scale: int) -> np.ndarray:
    """A copy of ``cells`` (``uint8 (rows * scale, cols * scale, 3)``, a picture of the grid at ``scale``
    pixels a cell) darkened where ``light`` (``float (rows, cols)``, 0 to 1) is below 1.

    >>> cells = np.full((2, 4, 3), 200, dtype=np.uint8)
    >>> shade_light(cells, np.array([[1.0, 0.0]]), 2)[0, :, 0].tolist()
    [200, 200, 71, 71]
    """
    shade = np.repeat(np.repeat((1.0 - np.clip(light, 0.0, 1.0)) * DARK_ALPHA, scale, axis=0), scale, axis=1)
    dark = np.asarray(WATCH_COLOURS["dark"], dtype=float)
    out = cells * (1.0 - shade[..., None]) + dark * shade[..., None]
    return np.rint(out).astype(np.uint8)


def draw_cameras(cells: np.ndarray, level: Level, origin: tuple[float, float], scale: int) -> np.ndarray:
    """A copy of ``cells`` (as :func:`shade_light`'s) with each camera and its swing drawn."""
    image = Image.fromarray(np.ascontiguousarray(cells))
    draw = ImageDraw.Draw(image)
    per_unit = scale / level.cell_size
    colour = WATCH_COLOURS["camera"]
    for camera in level.cameras:
        x = (camera.position[0] - origin[0]) * per_unit
        y = (camera.position[1] - origin[1]) * per_unit
        reach = (camera.view_range if camera.view_range is not None else level.guard.view_range) * per_unit
        low = camera.heading - camera.sweep / 2
        high = camera.heading + camera.sweep / 2
        box = (x - reach, y - reach, x + reach, y + reach)
        width = max(1, scale // 4)
        if camera.sweep + camera.fov_degrees >= 360:
            draw.ellipse(box, outline=colour, width=width)
        else:
            # PIL's angles run clockwise from +x with y down: the level's headings.
            draw.arc(box, low - camera.fov_degrees / 2, high + camera.fov_degrees / 2, fill=colour, width=width)
        for end in {low, high}:
            angle = np.radians(end)
            draw.line((x, y, x + reach * np.cos(angle), y + reach * np.sin(angle)), fill=colour, width=width)
        radius = max(3.0, 0.4 * scale)
        draw.ellipse((x - radius, y - radius, x + radius, y + radius), fill=colour, outline=COLOURS["outline"])
    return np.asarray(image)


def light_bar(width: int) -> np.ndarray:
    """``uint8 (height, width, 3)``: the light's colour bar, from dark (0) to full light (1), labelled.

    >>> bar = light_bar(300)
    >>> bar.shape[1], bar.shape[0] > 10
    (300, True)
    """
    setter = Typesetter(12)
    height = 34
    image = np.zeros((height, width, 3), dtype=np.float64)
    image[:] = COLOURS["bar"]
    left, right = 70, max(80, width - 40)
    ramp = np.linspace(0.0, 1.0, right - left)
    floor = np.asarray(COLOURS["free"], dtype=float)
    dark = np.asarray(WATCH_COLOURS["dark"], dtype=float)
    shade = ((1.0 - ramp) * DARK_ALPHA)[:, None]
    image[8:22, left:right] = (floor * (1 - shade) + dark * shade)[None, :, :]
    lines = [((6, 8), "light"), ((left - 12, 20), "0"), ((right + 4, 20), "1")]
    alpha = setter.mask((width, height), lines)[..., None] / 255.0
    blended = image * (1 - alpha) + np.asarray(COLOURS["text"]) * alpha
    return np.rint(blended).astype(np.uint8)


def draw_watch_overlay(
    preview: np.ndarray,
    level: Level,
    shape: tuple[int, int],
    light: np.ndarray | None,
    *,
    size: int | None = None,
) -> np.ndarray:
    """A copy of a :func:`~guardsim.render.render_preview` image with the light shaded (``light``:
    ``float (rows, cols)``, ``None`` for full light) and the cameras' swings drawn; ``shape`` and ``size``
    must be the ones the preview was drawn with."""
    rows, cols = shape
    scale = preview_scale(shape, size)
    margin = (preview.shape[1] - cols * scale) // 2
    framed = preview.copy()
    cells = framed[margin : margin + rows * scale, margin : margin + cols * scale]
    if light is not None:
        cells = shade_light(cells, light, scale)
    cells = draw_cameras(cells, level, level.bounds[:2], scale)
    framed[margin : margin + rows * scale, margin : margin + cols * scale] = cells
    return framed
