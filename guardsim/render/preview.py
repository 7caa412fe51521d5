"""Level previews for designers (``guardsim render``): walls, grid, reachable and unreachable cells, cells
too tight to stand in, rulers, a legend, and optionally what a guard sees from one spot. Colours are the
frames' (:mod:`~guardsim.render.palette`): one colour per meaning in every picture.

Cell colours are composed with numpy; Pillow draws only the vector overlays.
"""

from __future__ import annotations

import math

import numpy as np
from PIL import Image, ImageDraw

from guardsim.level import Level
from guardsim.render.cells import tight_cells
from guardsim.render.layout import grow_mask
from guardsim.render.legend import draw_rgb_legend
from guardsim.render.palette import COLOURS, GUARD_COLOURS, WATCH_COLOURS
from guardsim.render.sight import SightCaster
from guardsim.render.text import font
from guardsim.render.timeline import cell_pixels
from guardsim.world import World

__all__ = ["draw_cone_overlay", "preview_scale", "render_preview", "tight_cells", "with_legend"]


#: Longest side of a small level's preview in pixels, before rounding to whole pixels per cell.
PREVIEW_SIZE = 640


def preview_scale(shape: tuple[int, int], size: int | None) -> int:
    """Pixels per cell of a preview of a grid of ``shape`` (at least 2): ``size`` on the longest side, else
    about :data:`PREVIEW_SIZE` but at least 6 pixels a cell up to 1600 pixels, as the GIF frames."""
    return max(2, cell_pixels(shape, size, base=PREVIEW_SIZE))


def _level_drawing(level: Level, origin: tuple[float, float], shape: tuple[int, int], scale: int) -> Image.Image:
    """Walls, free area clear, at ``scale`` pixels per cell."""
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


def _paint_cells(
    base: np.ndarray, cells: np.ndarray, colour: tuple[int, int, int], scale: int, *, hatch: bool = False
) -> None:
    """Paint every cell where ``cells`` is true with ``colour`` (hatched as in the frames), in place."""
    mask = np.repeat(np.repeat(cells, scale, axis=0), scale, axis=1)
    base[mask] = colour
    if hatch:
        rows, cols = np.indices(mask.shape)
        base[mask & ((rows + cols) % 6 == 0)] = COLOURS["hatch"]


def _draw_guard(
    draw: ImageDraw.ImageDraw,
    level: Level,
    origin: tuple[float, float],
    cell: tuple[int, int],
    heading: int,
    scale: int,
) -> None:
    """The guard and the outline of what it sees (its cone clipped by the walls)."""
    centre = ((cell[0] + 0.5) * scale, (cell[1] + 0.5) * scale)
    pixels_per_unit = scale / level.cell_size
    eye = (origin[0] + (cell[0] + 0.5) * level.cell_size, origin[1] + (cell[1] + 0.5) * level.cell_size)
    ring = SightCaster(World(level)).polygon(eye, 90.0 * heading, level.guard.fov_degrees, level.guard.view_range)
    points = [((x - origin[0]) * pixels_per_unit, (y - origin[1]) * pixels_per_unit) for x, y in ring]
    draw.line([*points, points[0]], fill=COLOURS["cone"], width=max(1, scale // 4))
    radius = max(2.0, max(level.guard.radius / level.cell_size, 0.35) * scale)
    draw.ellipse(
        [centre[0] - radius, centre[1] - radius, centre[0] + radius, centre[1] + radius], fill=COLOURS["guard"]
    )


def render_preview(
    level: Level,
    traversable: np.ndarray,
    reachable: np.ndarray,
    origin: tuple[float, float],
    *,
    start: tuple[int, int] | None = None,
    size: int | None = None,
) -> np.ndarray:
    """A level designer's preview: walls, grid, reachable and unreachable cells, the start.

    Traversable cells reachable from the start are tinted green, other traversable cells purple and
    hatched, and free-area cells where the guard does not fit are sand (the frames' ``tight``). Walls
    are outlined only where they meet the floor. ``size`` is the longest side of the cells in pixels
    (``None``: :func:`preview_scale`). Add the legend with :func:`with_legend`.
    """
    shape = traversable.shape
    scale = preview_scale(shape, size)
    drawing = np.asarray(_level_drawing(level, origin, shape, scale)).copy()
    floor = (drawing == np.asarray(COLOURS["free"], dtype=np.uint8)).all(axis=2)
    _paint_cells(drawing, tight_cells(level, traversable, origin), COLOURS["tight"], scale)
    _paint_cells(drawing, reachable, COLOURS["reachable"], scale)
    _paint_cells(drawing, traversable & ~reachable, COLOURS["unreachable"], scale, hatch=True)
    if scale >= 4:
        # Grid lines on the floor only: over the walls they would read as a texture.
        rows, cols = np.indices(floor.shape)
        drawing[floor & ((rows % scale == 0) | (cols % scale == 0))] = COLOURS["grid"]
    pixels_per_unit = scale / level.cell_size
    rings = Image.new("L", (drawing.shape[1], drawing.shape[0]), 0)
    ring_draw = ImageDraw.Draw(rings)
    for ring in (level.outer, *level.holes):
        points = [((x - origin[0]) * pixels_per_unit, (y - origin[1]) * pixels_per_unit) for x, y in ring]
        ring_draw.line([*points, points[0]], fill=1, width=1)
    # Where two wall pieces touch (a wall an importer cut open) there is wall on both sides: no line.
    outline = (np.asarray(rings) > 0) & grow_mask(floor, 1)
    drawing[outline] = COLOURS["outline"]
    image = Image.fromarray(drawing)
    draw = ImageDraw.Draw(image)
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
    ruler_font = font(10)
    cols, rows = image.width // scale, image.height // scale
    step = _ruler_step(max(cols, rows) * level.cell_size)
    pixels_per_unit = scale / level.cell_size
    value = math.ceil(origin[0] / step) * step
    while (value - origin[0]) * pixels_per_unit <= image.width:
        x = margin + (value - origin[0]) * pixels_per_unit
        draw.line([(x, margin - 6), (x, margin)], fill=COLOURS["ruler"])
        draw.text((x, margin - 8), f"{value:g}", fill=COLOURS["ruler"], font=ruler_font, anchor="mb")
        value += step
    value = math.ceil(origin[1] / step) * step
    while (value - origin[1]) * pixels_per_unit <= image.height:
        y = margin + (value - origin[1]) * pixels_per_unit
        draw.line([(margin - 6, y), (margin, y)], fill=COLOURS["ruler"])
        draw.text((margin - 8, y), f"{value:g}", fill=COLOURS["ruler"], font=ruler_font, anchor="rm")
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
    size: int | None = None,
) -> np.ndarray:
    """A copy of a :func:`render_preview` image showing what a guard at ``cell`` facing ``heading`` sees.

    The ``bool (rows, cols)`` ``seen`` cells are tinted with the cone's colour, and the cone's outline and
    the guard are drawn on top. ``shape`` and ``size`` must be the ones the preview was drawn with.
    """
    rows, cols = shape
    scale = preview_scale(shape, size)
    # render_preview frames the cells in an equal margin on every side (the rulers).
    margin = (preview.shape[1] - cols * scale) // 2
    framed = preview.copy()
    cells = framed[margin : margin + rows * scale, margin : margin + cols * scale]
    tint = np.repeat(np.repeat(seen, scale, axis=0), scale, axis=1)
    cells[tint] = (cells[tint] * 0.45 + np.asarray(COLOURS["cone"]) * 0.55).astype(np.uint8)
    image = Image.fromarray(np.ascontiguousarray(cells))
    _draw_guard(ImageDraw.Draw(image), level, level.bounds[:2], cell, heading, scale)
    framed[margin : margin + rows * scale, margin : margin + cols * scale] = np.asarray(image)
    return framed


def with_legend(
    preview: np.ndarray,
    *,
    unreachable: bool = False,
    tight: bool = False,
    start: bool = False,
    cone: bool = False,
    cameras: bool = False,
) -> np.ndarray:
    """``preview`` with a legend bar below it naming each colour drawn (as the GIF frames' legend does).

    Examples
    --------
    >>> preview = np.full((100, 300, 3), 255, dtype=np.uint8)
    >>> framed = with_legend(preview, tight=True)
    >>> framed.shape[0] > 100 and framed.shape[1] == 300, framed[-1, 0].tolist() == list(COLOURS["bar"])
    (True, True)
    """
    items = [(COLOURS["wall"], "wall"), (COLOURS["reachable"], "reachable floor")]
    if unreachable:
        items.append((COLOURS["unreachable"], "unreachable"))
    if tight:
        items.append((COLOURS["tight"], "too tight to stand in"))
    if cone:
        items.append((_cone_tint(COLOURS["reachable"]), "sees now"))
    if start:
        items.append((GUARD_COLOURS[0], "guard"))
    if cameras:
        items.append((WATCH_COLOURS["camera"], "camera and its swing"))
    legend = draw_rgb_legend(preview.shape[1], items)
    return np.concatenate([preview, legend])


def _cone_tint(colour: tuple[int, int, int]) -> tuple[int, int, int]:
    """``colour`` under the cone's tint, as :func:`draw_cone_overlay` blends it."""
    r, g, b = (np.asarray(colour) * 0.45 + np.asarray(COLOURS["cone"]) * 0.55).astype(np.uint8).tolist()
    return r, g, b
