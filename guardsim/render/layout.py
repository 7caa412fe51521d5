"""How a frame is laid out and the small drawing pieces every picture shares: pixels per cell, the
caption's wrapping, the guard's body, the vision settings drawn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from PIL import ImageDraw

from guardsim.level import GuardSpec, Level
from guardsim.render.palette import Index, guard_index
from guardsim.render.text import Typesetter
from guardsim.trace import Trace

__all__ = [
    "CAPTION_LINE",
    "CAPTION_SIZE",
    "MIN_FRAME_WIDTH",
    "MIN_GUARD_RADIUS",
    "PLAY_PAD",
    "Layout",
    "VisionSettings",
    "draw_guard",
    "grow_mask",
    "grown_box",
    "pixels_per_cell",
    "wrap_caption",
]

#: Narrowest frame: the caption and legend need this much room even for a small level.
MIN_FRAME_WIDTH = 400
#: The guard's disc is never smaller than this radius in pixels, whatever the cell size.
MIN_GUARD_RADIUS = 7
#: Wall-coloured margin round the grid, so the level's outer boundary is drawn on every side.
PLAY_PAD = 4
CAPTION_SIZE = 13
CAPTION_LINE = 17
#: Where a caption line may be broken first: between its ``|``-separated parts.
_CAPTION_SEPARATOR = "  |  "


def pixels_per_cell(shape: tuple[int, int], size: int) -> int:
    """Whole pixels per cell so that the longer side is about ``size`` pixels (at least 1)."""
    return max(1, size // max(shape))


@dataclass(frozen=True)
class VisionSettings:
    """The guard's vision as simulated: from the trace, or the level's guard for traces that lack it."""

    view_range: float
    fov_degrees: float

    @classmethod
    def of(cls, level: Level, trace: Trace) -> VisionSettings:
        """The trace's vision, else the level's guard's."""
        return cls.of_guard(level.guard, trace)

    @classmethod
    def of_guard(cls, guard: GuardSpec, trace: Trace) -> VisionSettings:
        """The trace's vision, else ``guard``'s."""
        return cls(
            view_range=guard.view_range if trace.view_range is None else trace.view_range,
            fov_degrees=guard.fov_degrees if trace.fov_degrees is None else trace.fov_degrees,
        )


@dataclass(frozen=True)
class Layout:
    """Where things go in a frame, in pixels."""

    scale: int
    """Pixels per cell."""
    play: tuple[int, int]
    """``(width, height)`` of the play area."""
    left: int
    """Left edge of the play area."""
    top: int
    """Height of the caption bar above the play area (also the play area's top edge)."""
    legend: int
    """Height of the legend bar below it."""
    width: int
    """Width of the whole frame."""

    @property
    def height(self) -> int:
        """Height of the whole frame."""
        return self.top + self.play[1] + self.legend


def grow_mask(mask: np.ndarray, reach: int) -> np.ndarray:
    """``mask`` grown by ``reach`` pixels in every direction (a square neighbourhood)."""
    grown = mask.copy()
    padded = np.pad(mask, reach)
    height, width = mask.shape
    for dy in range(2 * reach + 1):
        for dx in range(2 * reach + 1):
            grown |= padded[dy : dy + height, dx : dx + width]
    return grown


def wrap_caption(lines: tuple[str, ...] | list[str], setter: Typesetter, width: float) -> list[str]:
    """Caption ``lines`` wrapped to ``width`` pixels: broken between ``|``-separated parts first, then
    between words, never cut; a word wider than ``width`` stands alone on its line.

    Examples
    --------
    >>> setter = Typesetter(13)
    >>> wrap_caption(["a  |  b"], setter, 400)
    ['a  |  b']
    >>> wrap_caption(["1.0% of 2 cells unseen  |  321 unreachable cells (not counted)"], setter, 200)
    ['1.0% of 2 cells unseen', '321 unreachable cells (not', 'counted)']
    """
    wrapped: list[str] = []
    for line in lines:
        current = ""
        for part in line.split(_CAPTION_SEPARATOR):
            joined = f"{current}{_CAPTION_SEPARATOR}{part}" if current else part
            if setter.width(joined) <= width:
                current = joined
                continue
            if current:
                wrapped.append(current)
            current = ""
            for word in part.split(" "):
                joined = f"{current} {word}" if current else word
                if current and setter.width(joined) > width:
                    wrapped.append(current)
                    joined = word
                current = joined
        wrapped.append(current)
    return wrapped


def grown_box(box: tuple[int, int, int, int] | None, part: tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    """The smallest box ``(x0, y0, x1, y1)`` holding ``box`` (if any) and ``part``."""
    if box is None:
        return part
    return min(box[0], part[0]), min(box[1], part[1]), max(box[2], part[2]), max(box[3], part[3])


def draw_guard(
    draw: ImageDraw.ImageDraw, centre: tuple[float, float], heading_degrees: float, radius: float, guard: int
) -> None:
    """A disc in the guard's colour with a pointed nose towards its heading and a white eye."""
    angle = math.radians(heading_degrees)
    dx, dy = math.cos(angle), math.sin(angle)
    x, y = centre
    tip = (x + dx * radius * 1.9, y + dy * radius * 1.9)
    side = radius * 0.85
    draw.polygon(
        [tip, (x - dy * side, y + dx * side), (x + dy * side, y - dx * side)],
        fill=guard_index(guard),
        outline=Index.OUTLINE,
    )
    draw.ellipse((x - radius, y - radius, x + radius, y + radius), fill=guard_index(guard), outline=Index.OUTLINE)
    eye = (x + dx * radius * 0.35, y + dy * radius * 0.35)
    draw.ellipse((eye[0] - 1.5, eye[1] - 1.5, eye[0] + 1.5, eye[1] + 1.5), fill=Index.WHITE)
