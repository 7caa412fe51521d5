"""The one palette every picture is drawn in: one colour per meaning.

Every picture guardsim draws takes its colours from here: the GIF frames (:mod:`~guardsim.render.frames`),
the designer's preview (``guardsim render``), the Gymnasium ``rgb_array`` (:mod:`guardsim.envs.rgb`) and
the HTML viewer's cell colours (its page reads :data:`COLOURS`). What each name means:

=============  =====================================================================================
``wall``       a wall (slate grey), with an ``outline`` (near black) where it meets the floor
``unseen``     floor the guard can reach and has not seen yet (dark navy)
``free``       floor seen (near white); in the preview, floor with nothing to say about it
``tight``      floor in a cell too tight for the guard's circle to stand in: never a goal (sand)
``unreachable`` floor the guard fits on but cannot reach from its start (purple, hatched)
``cone``       what a guard sees now (a yellow tint)
``guard``      the first guard (red); the others take :data:`GUARD_COLOURS` in turn
``reachable``  preview only: floor reachable from the start (pale green)
=============  =====================================================================================

:data:`HEAT_RAMP` is the ramp for a per-cell number such as the tick a cell was first seen; it runs
from pale cyan through blue to deep violet, away from the cone's yellow, so the cone stays visible over it.

Frames are arrays of palette indices, not RGB: the GIF writer never quantises, every frame of every GIF
shares the same global colour table, and equal inputs give byte-identical files. Translucent effects (the
cone's tint, the trail's fading, antialiased caption text) are precomputed blends with their own entries.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "COLOURS",
    "GUARD_COLOURS",
    "HEAT_RAMP",
    "PALETTE",
    "TRAIL_LEVELS",
    "WATCH_COLOURS",
    "Index",
    "guard_index",
    "palette_rgb",
    "text_index",
    "trail_index",
]

#: Named colours, as RGB.
COLOURS: dict[str, tuple[int, int, int]] = {
    "wall": (118, 122, 134),
    "free": (250, 250, 246),
    "unseen": (30, 34, 62),
    "tight": (226, 204, 150),
    "unreachable": (196, 150, 212),
    "hatch": (140, 84, 162),
    "outline": (24, 26, 32),
    "cone": (255, 196, 40),
    "bar": (28, 30, 38),
    "text": (246, 246, 246),
    "white": (255, 255, 255),
    # Preview-only colours (guardsim render), kept for the level designer's preview.
    "reachable": (206, 236, 210),
    "grid": (222, 224, 228),
    "ruler": (90, 90, 100),
    "guard": (214, 40, 40),
}

#: Cameras and light (apart from :data:`COLOURS`, whose entries the viewer pages carry): a camera and its
#: swing (magenta, away from the guards' red and the cone's yellow), and the dark that shades unlit floor
#: (deep blue; at most :data:`DARK_ALPHA` of it, so the floor still reads).
WATCH_COLOURS: dict[str, tuple[int, int, int]] = {
    "camera": (190, 30, 150),
    "dark": (16, 20, 52),
}
#: The strongest shade of dark over floor with no light at all.
DARK_ALPHA = 0.7

#: One colour per guard of a team, in order; a ninth guard takes the first colour again. Chosen to stand
#: apart from each other and from the floor, the unseen dark, the walls and the cone's yellow.
GUARD_COLOURS: tuple[tuple[int, int, int], ...] = (
    (214, 40, 40),
    (0, 104, 200),
    (0, 150, 90),
    (230, 110, 0),
    (200, 40, 160),
    (0, 170, 190),
    (120, 80, 30),
    (90, 90, 90),
)

#: Stops ``(fraction, RGB)`` of a heat map over the floor (early/low to late/high): pale cyan, blue, deep
#: violet. None is near the cone's yellow, so a yellow cone tinted over any of them stays visible.
HEAT_RAMP: tuple[tuple[float, tuple[int, int, int]], ...] = (
    (0.0, (200, 240, 244)),
    (0.5, (60, 130, 200)),
    (1.0, (60, 24, 110)),
)

#: Opacities of the trail over the floor, newest first: recent steps strong, old steps faint.
TRAIL_LEVELS: tuple[float, ...] = (1.0, 0.72, 0.5, 0.34, 0.22)

#: Strength of the cone's tint over what lies under it.
CONE_ALPHA = 0.42
#: Antialiasing levels of caption text over the bar.
TEXT_LEVELS = 8


class Index:
    """Palette indices of the fixed entries."""

    WALL = 0
    FREE = 1
    UNSEEN = 2
    UNREACHABLE = 3
    HATCH = 4
    OUTLINE = 5
    BAR = 6
    WHITE = 7
    CONE_BASE = 8
    """``CONE_BASE + i`` is base entry ``i`` (``FREE`` .. ``HATCH``) under the cone's tint."""
    TEXT_BASE = 16
    """``TEXT_BASE + k``: caption text at coverage ``k / (TEXT_LEVELS - 1)`` over the bar."""
    GUARD_BASE = 32
    """Each guard colour takes eight entries: the trail levels, then the solid colour, then a dark one."""
    TIGHT = 24
    """Floor in a cell too tight for the guard to stand in (never a goal)."""
    TIGHT_CONE = 25
    """``TIGHT`` under the cone's tint."""
    TRANSPARENT = 255
    """Never drawn: marks the pixels a GIF frame leaves as they were in the previous frame."""


def _blend(top: tuple[int, int, int], under: tuple[int, int, int], alpha: float) -> tuple[int, int, int]:
    return tuple(round(alpha * t + (1 - alpha) * u) for t, u in zip(top, under))  # type: ignore[return-value]


def _build() -> list[tuple[int, int, int]]:
    entries = [(0, 0, 0)] * 256
    for name, index in (
        ("wall", Index.WALL),
        ("free", Index.FREE),
        ("unseen", Index.UNSEEN),
        ("unreachable", Index.UNREACHABLE),
        ("hatch", Index.HATCH),
        ("outline", Index.OUTLINE),
        ("bar", Index.BAR),
        ("white", Index.WHITE),
        ("tight", Index.TIGHT),
    ):
        entries[index] = COLOURS[name]
    for base in range(Index.WALL, Index.HATCH + 1):
        entries[Index.CONE_BASE + base] = _blend(COLOURS["cone"], entries[base], CONE_ALPHA)
    entries[Index.TIGHT_CONE] = _blend(COLOURS["cone"], COLOURS["tight"], CONE_ALPHA)
    for level in range(TEXT_LEVELS):
        entries[Index.TEXT_BASE + level] = _blend(COLOURS["text"], COLOURS["bar"], level / (TEXT_LEVELS - 1))
    for guard, colour in enumerate(GUARD_COLOURS):
        base = Index.GUARD_BASE + 8 * guard
        for level, alpha in enumerate(TRAIL_LEVELS):
            entries[base + level] = _blend(colour, COLOURS["free"], alpha)
        entries[base + 6] = colour
        entries[base + 7] = _blend(colour, (0, 0, 0), 0.55)
    return entries


PALETTE: tuple[tuple[int, int, int], ...] = tuple(_build())


def palette_rgb() -> np.ndarray:
    """The palette as a ``uint8 (256, 3)`` array: ``palette_rgb()[frame]`` turns indices into RGB."""
    return np.asarray(PALETTE, dtype=np.uint8)


def guard_index(guard: int, *, dark: bool = False) -> int:
    """The solid (or dark) colour of guard ``guard``."""
    return Index.GUARD_BASE + 8 * (guard % len(GUARD_COLOURS)) + (7 if dark else 6)


def trail_index(guard: int, level: int) -> int:
    """Guard ``guard``'s trail at fading level ``level`` (0 newest)."""
    return Index.GUARD_BASE + 8 * (guard % len(GUARD_COLOURS)) + level


def text_index(coverage: np.ndarray) -> np.ndarray:
    """Palette indices of antialiased text, from an ``uint8`` coverage mask (0 bar, 255 full text)."""
    return (Index.TEXT_BASE + (coverage.astype(np.uint16) * (TEXT_LEVELS - 1) + 127) // 255).astype(np.uint8)
