"""The legend bar under every frame and every preview: a swatch and a word for each thing drawn."""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from guardsim.render.palette import COLOURS, TRAIL_LEVELS, Index, guard_index, text_index, trail_index
from guardsim.render.text import Typesetter

__all__ = ["draw_legend", "draw_rgb_legend"]

_ROW_HEIGHT = 18
_PAD = 8
_SWATCH = 11
#: Team members shown in the guard swatch; the label gives the count.
_SHOWN_GUARDS = 4


def _items(guards: int, unreachable: bool, tight: bool) -> list[tuple[str, str]]:
    items = [("wall", "wall"), ("unseen", "unseen"), ("seen", "seen")]
    if unreachable:
        items.append(("unreachable", "unreachable"))
    if tight:
        items.append(("tight", "too tight to stand in"))
    items += [("cone", "sees now"), ("trail", "trail (faint = older)"), ("start", "start")]
    items.append(("guard", f"guards ({guards})" if guards > 1 else "guard"))
    return items


def _swatch(draw: ImageDraw.ImageDraw, kind: str, x: int, y: int, guards: int) -> int:
    """Draw the swatch for ``kind`` at ``(x, y)``; return its width."""
    box = (x, y, x + _SWATCH, y + _SWATCH)
    plain = {"wall": Index.WALL, "unseen": Index.UNSEEN, "seen": Index.FREE, "tight": Index.TIGHT}
    if kind in plain:
        draw.rectangle(box, fill=plain[kind], outline=Index.WHITE)
    elif kind == "unreachable":
        draw.rectangle(box, fill=Index.UNREACHABLE, outline=Index.WHITE)
        draw.line((x + 1, y + _SWATCH - 1, x + _SWATCH - 1, y + 1), fill=Index.HATCH, width=2)
    elif kind == "cone":
        draw.rectangle(box, fill=Index.CONE_BASE + Index.FREE, outline=guard_index(0))
    elif kind == "trail":
        # Oldest (faintest) on the left, newest on the right: the way the guard went.
        for step in range(len(TRAIL_LEVELS)):
            left = x + 3 * step
            draw.rectangle((left, y + 4, left + 2, y + 7), fill=trail_index(0, len(TRAIL_LEVELS) - 1 - step))
        return 3 * len(TRAIL_LEVELS)
    elif kind == "start":
        draw.rectangle(box, outline=guard_index(0), width=2)
    else:
        shown = min(guards, _SHOWN_GUARDS)
        for guard in range(shown):
            draw.ellipse(
                (x + 4 * guard, y, x + 4 * guard + _SWATCH, y + _SWATCH), fill=guard_index(guard), outline=Index.OUTLINE
            )
        return _SWATCH + 4 * (shown - 1)
    return _SWATCH


def _rows(setter: Typesetter, labels: list[str], swatches: list[int], width: int) -> list[tuple[int, int]]:
    """Where each item goes, ``(x, row)``: left to right, wrapped to ``width``."""
    positions: list[tuple[int, int]] = []
    x, row = _PAD, 0
    for label, swatch in zip(labels, swatches):
        needed = swatch + 5 + round(setter.width(label)) + 10
        if x + needed > width - _PAD and x > _PAD:
            x, row = _PAD, row + 1
        positions.append((x, row))
        x += needed
    return positions


def draw_legend(width: int, *, guards: int, unreachable: bool, tight: bool = False) -> np.ndarray:
    """The legend, ``uint8 (height, width)`` palette indices, its items wrapped to ``width``."""
    setter = Typesetter(12)
    items = _items(guards, unreachable, tight)
    swatch_widths = [
        3 * len(TRAIL_LEVELS)
        if kind == "trail"
        else _SWATCH + 4 * (min(guards, _SHOWN_GUARDS) - 1)
        if kind == "guard"
        else _SWATCH
        for kind, _ in items
    ]
    positions = _rows(setter, [label for _, label in items], swatch_widths, width)
    height = (positions[-1][1] + 1) * _ROW_HEIGHT + 8
    image = Image.new("L", (width, height), Index.BAR)
    draw = ImageDraw.Draw(image)
    lines = []
    for (kind, label), (x, row) in zip(items, positions):
        y = 4 + row * _ROW_HEIGHT + 3
        swatch = _swatch(draw, kind, x, y, guards)
        lines.append(((x + swatch + 5, y - 2), label))
    legend = np.asarray(image).copy()
    coverage = setter.mask((width, height), lines)
    inked = coverage > 0
    legend[inked] = text_index(coverage[inked])
    return legend


def draw_rgb_legend(width: int, items: list[tuple[tuple[int, int, int], str]]) -> np.ndarray:
    """A legend of plain swatches, ``uint8 (height, width, 3)`` RGB, in the frames' bar and text colours.

    Examples
    --------
    >>> legend = draw_rgb_legend(200, [(COLOURS["wall"], "wall"), (COLOURS["tight"], "too tight")])
    >>> legend.shape[1], legend[0, 0].tolist() == list(COLOURS["bar"])
    (200, True)
    """
    setter = Typesetter(12)
    positions = _rows(setter, [label for _, label in items], [_SWATCH] * len(items), width)
    height = (positions[-1][1] + 1) * _ROW_HEIGHT + 8 if items else 0
    image = Image.new("RGB", (width, height), COLOURS["bar"])
    draw = ImageDraw.Draw(image)
    lines = []
    for (colour, label), (x, row) in zip(items, positions):
        y = 4 + row * _ROW_HEIGHT + 3
        draw.rectangle((x, y, x + _SWATCH, y + _SWATCH), fill=colour, outline=COLOURS["white"])
        lines.append(((x + _SWATCH + 5, y - 2), label))
    alpha = setter.mask((width, height), lines)[..., None] / 255.0
    blended = np.asarray(image) * (1 - alpha) + np.asarray(COLOURS["text"]) * alpha
    return np.rint(blended).astype(np.uint8)
