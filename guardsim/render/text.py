"""Caption text for frames: antialiased coverage masks, set from cached glyphs.

Laying out a caption line with Pillow costs about as much as drawing the rest of a frame; the caption
changes every frame but only in a few digits, so each character is rendered once and the lines are set
by pasting the cached glyphs at their advance widths (kerning is not applied; the built-in font has none
worth noticing at caption sizes).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from PIL import Image, ImageDraw, ImageFont

__all__ = ["Typesetter", "font"]


@lru_cache(maxsize=8)
def font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """Pillow's built-in font at ``size`` pixels (the fixed bitmap font if Pillow lacks FreeType)."""
    try:
        return ImageFont.load_default(size=size)
    except (TypeError, ImportError, OSError):
        return ImageFont.load_default()


class Typesetter:
    """Sets lines of text in one font into ``uint8`` coverage masks (0 empty, 255 fully inked).

    Examples
    --------
    >>> setter = Typesetter(12)
    >>> mask = setter.mask((120, 20), [((2, 2), "tick 12")])
    >>> mask.shape, bool(mask.any()), bool(mask[:, 100:].any())
    ((20, 120), True, False)
    """

    def __init__(self, size: int) -> None:
        self.font = font(size)
        self.height = size + math.ceil(size / 2)
        self._glyphs: dict[str, tuple[np.ndarray, float]] = {}

    def _glyph(self, char: str) -> tuple[np.ndarray, float]:
        glyph = self._glyphs.get(char)
        if glyph is None:
            advance = float(self.font.getlength(char))
            image = Image.new("L", (math.ceil(advance) + 4, self.height), 0)
            ImageDraw.Draw(image).text((0, 0), char, fill=255, font=self.font)
            glyph = (np.asarray(image).copy(), advance)
            self._glyphs[char] = glyph
        return glyph

    def width(self, text: str) -> float:
        """Advance width of ``text`` in pixels."""
        return sum(self._glyph(char)[1] for char in text)

    def mask(self, size: tuple[int, int], lines: list[tuple[tuple[int, int], str]]) -> np.ndarray:
        """Coverage of ``lines`` (each ``((x, y), text)``, top-left) in a ``(height, width)`` mask of ``size``."""
        width, height = size
        mask = np.zeros((height, width), dtype=np.uint8)
        for (x, y), text in lines:
            pen = float(x)
            for char in text:
                glyph, advance = self._glyph(char)
                left = round(pen)
                pen += advance
                if char == " " or left >= width:
                    continue
                g_height, g_width = glyph.shape
                bottom, right = min(height, y + g_height), min(width, left + g_width)
                if bottom <= y or right <= left:
                    continue
                region = mask[y:bottom, left:right]
                np.maximum(region, glyph[: bottom - y, : right - left], out=region)
        return mask
