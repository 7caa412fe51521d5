"""The legend bar under every frame and every preview: a swatch and a word for each thing drawn."""

from __future__ import annotations

from collections.abc import Sequence

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
#: Width of the meter bar's swatch.
_METER = 16


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
    elif kind == "letter":
        return 0
    elif kind == "intruder":
        draw.ellipse(box, fill=Index.WHITE, outline=guard_index(5), width=2)
    elif kind == "meter":
        # As over a guard: an outlined white bar filled from the left by the meter's level.
        draw.rectangle((x, y + 3, x + _METER - 1, y + 8), fill=Index.WHITE, outline=Index.OUTLINE)
        draw.rectangle((x + 1, y + 4, x + _METER // 2, y + 7), fill=guard_index(3))
        return _METER
    elif kind == "contaminated":
        for dx, dy in ((1, 1), (7, 1), (4, 7), (10, 7)):
            draw.rectangle((x + dx - 1, y + dy, x + dx + 1, y + dy + 2), fill=guard_index(2))
    elif kind == "last_known":
        draw.line((x + 1, y + 1, x + _SWATCH - 1, y + _SWATCH - 1), fill=guard_index(0), width=2)
        draw.line((x + 1, y + _SWATCH - 1, x + _SWATCH - 1, y + 1), fill=guard_index(0), width=2)
    elif kind == "noise":
        draw.ellipse(box, fill=Index.FREE, outline=Index.OUTLINE, width=2)
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


def _swatch_width(kind: str, guards: int) -> int:
    widths = {"trail": 3 * len(TRAIL_LEVELS), "guard": _SWATCH + 4 * (min(guards, _SHOWN_GUARDS) - 1)}
    return widths.get(kind, {"letter": 0, "meter": _METER}.get(kind, _SWATCH))


def draw_legend(
    width: int,
    *,
    guards: int,
    unreachable: bool,
    tight: bool = False,
    items: Sequence[tuple[str, str]] | None = None,
) -> np.ndarray:
    """The legend, ``uint8 (height, width)`` palette indices, its items wrapped to ``width``.

    ``items`` (``(swatch kind, label)`` pairs) replaces the coverage legend's: besides its kinds
    (``wall``, ``unseen``, ``seen``, ``cone``, ``trail``, ``start``, ``guard``) a swatch may be
    ``intruder`` (a white disc ringed in guard colour 6), ``meter`` (a half-full meter bar),
    ``contaminated`` (green dots), ``last_known`` (a red cross), ``noise`` (a ring) or ``letter`` (none:
    the label says it all, as ``"! chase"``).
    """
    setter = Typesetter(12)
    items = _items(guards, unreachable, tight) if items is None else list(items)
    swatch_widths = [_swatch_width(kind, guards) for kind, _ in items]
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
