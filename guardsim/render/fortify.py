"""The picture of a fortified level (``guardsim fortify``): every watcher with its cone or swing, the
counterexample paths the loop found, crossed out, and any way still through.

Drawn over the designer's preview (:func:`~guardsim.render.preview.render_preview`): the level's cameras,
old and added, with their swings (:func:`~guardsim.render.watchers.draw_cameras`); each added post as a
guard dot ringed by its view range (it turns through all four headings); each counterexample as a grey
line with a dark cross at its middle; a way still through as a red line; entries as green squares and goals
as gold diamonds.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from PIL import Image, ImageDraw

from guardsim.level import Level
from guardsim.render.legend import draw_rgb_legend
from guardsim.render.palette import COLOURS, GUARD_COLOURS, WATCH_COLOURS
from guardsim.render.preview import preview_scale, render_preview
from guardsim.render.watchers import draw_cameras

__all__ = ["FORTIFY_COLOURS", "fortify_picture"]

#: Colours of the fortify picture's own marks.
FORTIFY_COLOURS: dict[str, tuple[int, int, int]] = {
    "counterexample": (120, 120, 128),
    "cross": (40, 40, 48),
    "through": (220, 30, 30),
    "entry": (20, 150, 60),
    "goal": (220, 170, 0),
    "post": GUARD_COLOURS[1],
}

Point = tuple[float, float]


def fortify_picture(
    level: Level,
    traversable: np.ndarray,
    origin: tuple[float, float],
    *,
    posts: Sequence[Point],
    counterexamples: Sequence[Sequence[Point]],
    ways_through: Sequence[Sequence[Point]],
    pairs: Sequence[tuple[Point, Point]],
    size: int | None = None,
) -> np.ndarray:
    """``uint8 (height, width, 3)``: ``level`` (with its cameras) and the marks above, every position in
    world units; a legend below."""
    shape = traversable.shape
    scale = preview_scale(shape, size)
    preview = render_preview(level, traversable, traversable, origin, size=size)
    rows, cols = shape
    margin = (preview.shape[1] - cols * scale) // 2
    framed = preview.copy()
    cells = framed[margin : margin + rows * scale, margin : margin + cols * scale]
    cells = draw_cameras(cells, level, origin, scale)
    image = Image.fromarray(np.ascontiguousarray(cells))
    draw = ImageDraw.Draw(image)
    per_unit = scale / level.cell_size
    width = max(1, scale // 4)

    def pixel(point: Point) -> tuple[float, float]:
        return ((point[0] - origin[0]) * per_unit, (point[1] - origin[1]) * per_unit)

    for path in counterexamples:
        points = [pixel(p) for p in path]
        if len(points) > 1:
            draw.line(points, fill=FORTIFY_COLOURS["counterexample"], width=width)
        x, y = points[len(points) // 2]
        arm = max(3.0, 0.8 * scale)
        cross = FORTIFY_COLOURS["cross"]
        draw.line((x - arm, y - arm, x + arm, y + arm), fill=cross, width=width + 1)
        draw.line((x - arm, y + arm, x + arm, y - arm), fill=cross, width=width + 1)
    for path in ways_through:
        points = [pixel(p) for p in path]
        if len(points) > 1:
            draw.line(points, fill=FORTIFY_COLOURS["through"], width=width + 1)
    reach = level.guard.view_range * per_unit
    for post in posts:
        x, y = pixel(post)
        draw.ellipse((x - reach, y - reach, x + reach, y + reach), outline=FORTIFY_COLOURS["post"], width=width)
        radius = max(3.0, 0.45 * scale)
        draw.ellipse(
            (x - radius, y - radius, x + radius, y + radius), fill=FORTIFY_COLOURS["post"], outline=COLOURS["outline"]
        )
    for entry, goal in pairs:
        x, y = pixel(entry)
        half = max(3.0, 0.45 * scale)
        draw.rectangle(
            (x - half, y - half, x + half, y + half), fill=FORTIFY_COLOURS["entry"], outline=COLOURS["outline"]
        )
        x, y = pixel(goal)
        draw.polygon(
            [(x, y - half), (x + half, y), (x, y + half), (x - half, y)],
            fill=FORTIFY_COLOURS["goal"],
            outline=COLOURS["outline"],
        )
    framed[margin : margin + rows * scale, margin : margin + cols * scale] = np.asarray(image)
    items = [
        (COLOURS["wall"], "wall"),
        (WATCH_COLOURS["camera"], "camera and its swing"),
        (FORTIFY_COLOURS["post"], "post and its view range"),
        (FORTIFY_COLOURS["entry"], "entry"),
        (FORTIFY_COLOURS["goal"], "goal"),
        (FORTIFY_COLOURS["counterexample"], "way through found, crossed out"),
    ]
    if ways_through:
        items.append((FORTIFY_COLOURS["through"], "way still through"))
    return np.concatenate([framed, draw_rgb_legend(framed.shape[1], items)])
