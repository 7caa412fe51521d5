"""Comparing a key frame with its reference, and drawing the diff image of a level that differs."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["DiffRow", "Tolerance", "compare_frames", "diff_image"]

_HIGHLIGHT = (255, 0, 255)

#: One row of the diff image: its label, the reference frame and the current frame.
DiffRow = tuple[str, np.ndarray, np.ndarray]


@dataclass(frozen=True)
class Tolerance:
    """How far a decoded key frame may drift from its reference and still match.

    The defaults absorb anti-aliasing changes in the percentage text between Pillow or FreeType
    versions (the text's edge pixels are about 0.5 % of a 240-pixel frame). What the guard did is
    compared exactly through the trace, so the frames need not catch a one-cell change (16 pixels).
    """

    channel: int = 32
    """A pixel differs when one of its channels differs by more than this (0-255)."""
    fraction: float = 0.005
    """A frame differs when more than this fraction of its pixels differ."""


def compare_frames(reference: np.ndarray, current: np.ndarray, tolerance: Tolerance) -> tuple[float, int]:
    """The fraction of pixels differing by more than ``tolerance.channel``, and the largest difference.

    Examples
    --------
    >>> a = np.zeros((10, 10, 3), dtype=np.uint8)
    >>> b = a.copy()
    >>> b[0, :4] = (40, 0, 0)
    >>> b[1, 0] = (10, 0, 0)
    >>> compare_frames(a, b, Tolerance(channel=32))
    (0.04, 40)
    """
    if reference.shape != current.shape:
        return 1.0, 255
    delta = _channel_delta(reference, current)
    return float((delta > tolerance.channel).mean()), int(delta.max(initial=0))


def _channel_delta(reference: np.ndarray, current: np.ndarray) -> np.ndarray:
    difference = np.abs(reference.astype(np.int16) - current.astype(np.int16))
    return difference.max(axis=2) if difference.ndim == 3 else difference


def diff_image(rows: list[DiffRow], tolerance: Tolerance) -> np.ndarray:
    """Rows of reference | current | difference (the reference greyed, differing pixels magenta).

    Parameters
    ----------
    rows
        One row per frame shown: its label, the reference frame and the current frame.
    tolerance
        Pixels whose channels differ by more than ``tolerance.channel`` are highlighted.

    Returns
    -------
    numpy.ndarray
        The image as RGB ``uint8``, a caption line above each row.
    """
    from PIL import Image, ImageDraw, ImageFont

    font = ImageFont.load_default()
    gap, label_height = 4, 14
    strips: list[tuple[str, np.ndarray | None]] = [("reference | current | pixels that differ (magenta)", None)]
    for label, reference, current in rows:
        height = max(reference.shape[0], current.shape[0])
        width = max(reference.shape[1], current.shape[1])
        old, new = _padded(reference, height, width), _padded(current, height, width)
        grey = (old.mean(axis=2, keepdims=True) * 0.35 + 160).astype(np.uint8).repeat(3, axis=2)
        grey[_channel_delta(old, new) > tolerance.channel] = _HIGHLIGHT
        spacer = np.full((height, gap, 3), 255, dtype=np.uint8)
        strips.append((label, np.concatenate([old, spacer, new, spacer, grey], axis=1)))
    width = max(strip.shape[1] for _, strip in strips if strip is not None)
    pieces = []
    for label, strip in strips:
        caption = Image.new("RGB", (width, label_height), (255, 255, 255))
        ImageDraw.Draw(caption).text((2, 1), label, fill=(0, 0, 0), font=font)
        pieces.append(np.asarray(caption))
        if strip is not None:
            pieces.append(_padded(strip, strip.shape[0] + gap, width))
    return np.concatenate(pieces, axis=0)


def _padded(image: np.ndarray, height: int, width: int) -> np.ndarray:
    """``image`` as RGB on a white canvas of ``height`` x ``width``."""
    rgb = image[..., :3] if image.ndim == 3 else np.repeat(image[..., None], 3, axis=2)
    canvas = np.full((height, width, 3), 255, dtype=np.uint8)
    canvas[: rgb.shape[0], : rgb.shape[1]] = rgb
    return canvas
