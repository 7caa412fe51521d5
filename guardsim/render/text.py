"""Caption text for frames: antialiased coverage masks, set from cached words.

Laying out a caption line with Pillow costs about as much as drawing the rest of a frame; the caption
changes every frame but only in a few numbers, so each word is rendered once (by Pillow, kerning and
all) and lines are set by pasting cached words at their advance widths, a space apart.
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

    #: Words kept rendered; a caption uses a few dozen, most of them in every frame.
    CACHE_WORDS = 4096

    def __init__(self, size: int) -> None:
        self.font = font(size)
        self.height = size + math.ceil(size / 2)
        self.space = float(self.font.getlength(" "))
        self._words: dict[str, tuple[np.ndarray, float]] = {}

    def _word(self, word: str) -> tuple[np.ndarray, float]:
        cached = self._words.get(word)
        if cached is None:
            advance = float(self.font.getlength(word))
            image = Image.new("L", (math.ceil(advance) + 4, self.height), 0)
            ImageDraw.Draw(image).text((0, 0), word, fill=255, font=self.font)
            cached = (np.asarray(image).copy(), advance)
            if len(self._words) >= self.CACHE_WORDS:
                self._words.clear()
            self._words[word] = cached
        return cached

    def width(self, text: str) -> float:
        """Advance width of ``text`` in pixels."""
        words = text.split(" ")
        pieces = [piece for word in words for piece in (word if any(c.isdigit() for c in word) else [word]) if word]
        return sum(self._word(piece)[1] for piece in pieces) + self.space * (len(words) - 1)

    def mask(self, size: tuple[int, int], lines: list[tuple[tuple[int, int], str]]) -> np.ndarray:
        """Coverage of ``lines`` (each ``((x, y), text)``, top-left) in a ``(height, width)`` mask of ``size``."""
        width, height = size
        mask = np.zeros((height, width), dtype=np.uint8)
        for (x, y), text in lines:
            pen = float(x)
            for word in text.split(" "):
                # Numbers change from frame to frame: set them a character at a time, from a few cached
                # glyphs, instead of rendering every new number.
                for piece in (word if any(c.isdigit() for c in word) else [word]) if word else ():
                    glyphs, advance = self._word(piece)
                    left = round(pen)
                    bottom, right = min(height, y + glyphs.shape[0]), min(width, left + glyphs.shape[1])
                    if bottom > y and right > left:
                        region = mask[y:bottom, left:right]
                        np.maximum(region, glyphs[: bottom - y, : right - left], out=region)
                    pen += advance
                pen += self.space
        return mask
