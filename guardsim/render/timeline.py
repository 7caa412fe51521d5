"""Which ticks of an episode become frames, and how long each is shown: no drawing library needed."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

from guardsim.errors import LimitError

__all__ = [
    "DEFAULT_FRAME_SIZE",
    "DEFAULT_MAX_FRAMES",
    "FRAME_CEILING",
    "MAX_FRAME_SIDE",
    "MIN_CELL_PIXELS",
    "MIN_FRAME_MS",
    "GifOptions",
    "cell_pixels",
    "frame_durations",
    "frame_ticks",
]

#: Longest side of the play area in pixels, before rounding to whole pixels per cell, for a small level.
DEFAULT_FRAME_SIZE = 480
#: Fewest pixels per cell by default: a real map (130 x 90 cells) drawn in 480 pixels is 3 per cell, too
#: few to read a cell, a trail or a cone's edge.
MIN_CELL_PIXELS = 6
#: Longest side of the play area that the default size grows to, for big maps (past 266 cells a side the
#: default gives fewer than ``MIN_CELL_PIXELS``).
MAX_FRAME_SIDE = 1600
#: Frames in a GIF unless the caller asks for more; the stride grows to stay under it.
DEFAULT_MAX_FRAMES = 200
#: Hard ceiling on frames, whatever the options, to keep GIFs bounded.
FRAME_CEILING = 5000
#: Shortest frame a timed GIF shows: browsers play a GIF frame of less than 20 ms for 100 ms.
MIN_FRAME_MS = 20


@dataclass(frozen=True)
class GifOptions:
    """How an episode becomes a GIF."""

    stride: int | None = None
    """Ticks between frames; ``None`` picks the smallest stride that keeps under ``max_frames``."""
    frame_ms: int = 60
    """Duration of each frame in milliseconds."""
    hold_ms: int = 2000
    """Duration of the last frame, so the final coverage stays on screen."""
    max_frames: int = DEFAULT_MAX_FRAMES
    """Most frames the GIF may have."""
    size: int | None = None
    """Longest side of the play area in pixels (approximate: cells are whole pixels); ``None`` chooses
    it from the level (:func:`cell_pixels`)."""
    speed_up: float | None = None
    """Continuous motion: game seconds per second of GIF (1 is real time). Each frame is then shown for
    the game time to the next frame divided by this, and frames are at least ``frame_ms`` apart; ``None``
    shows each frame ``frame_ms``."""


def cell_pixels(shape: tuple[int, int], size: int | None = None, *, base: int = DEFAULT_FRAME_SIZE) -> int:
    """Whole pixels per cell for a grid of ``shape`` ``(rows, cols)``.

    With ``size``, the longest side is about ``size`` pixels (at least 1 per cell). Without it, the
    longest side is about ``base`` pixels (:data:`DEFAULT_FRAME_SIZE` for the GIF frames), but never
    fewer than :data:`MIN_CELL_PIXELS` per cell unless that would pass :data:`MAX_FRAME_SIDE`.

    Examples
    --------
    >>> cell_pixels((60, 60)), cell_pixels((90, 130)), cell_pixels((512, 512)), cell_pixels((90, 130), 260)
    (8, 6, 3, 2)
    """
    longest = max(shape)
    if size is not None:
        return max(1, size // longest)
    return max(1, min(max(MIN_CELL_PIXELS, base // longest), MAX_FRAME_SIDE // longest))


def frame_ticks(steps: int, options: GifOptions, tick_hz: float | None = None) -> list[int]:
    """The ticks drawn: every ``stride``-th from 0, and always the last.

    With ``options.speed_up`` and the trace's ``tick_hz`` (continuous motion), the stride chosen also
    keeps frames at least ``frame_ms`` (and :data:`MIN_FRAME_MS`) of animation apart.

    Raises
    ------
    LimitError
        If an explicit stride would exceed ``max_frames``.
    """
    if options.max_frames < 1 or options.max_frames > FRAME_CEILING:
        raise LimitError(f"--max-frames must be from 1 to {FRAME_CEILING} (the GIF ceiling), not {options.max_frames}")
    if options.max_frames == 1:
        return [steps]
    if options.stride is None:
        # The last tick is always added, so leave room for it.
        stride = max(1, math.ceil(steps / (options.max_frames - 1)))
        if options.speed_up is not None and tick_hz is not None:
            shortest = max(options.frame_ms, MIN_FRAME_MS) / 1000
            stride = max(stride, math.ceil(shortest * tick_hz * options.speed_up - 1e-9))
    else:
        if options.stride < 1:
            raise LimitError(f"frame stride must be at least 1, not {options.stride}")
        stride = options.stride
    ticks = list(range(0, steps + 1, stride))
    if ticks[-1] != steps:
        timed = options.speed_up is not None and tick_hz is not None
        # A timed GIF cannot show a frame for less than a stride: the last replaces the one before it.
        if timed and len(ticks) > 1:
            ticks[-1] = steps
        else:
            ticks.append(steps)
    if len(ticks) > options.max_frames:
        raise LimitError(
            f"{len(ticks)} frames at stride {stride} is over the limit of {options.max_frames} "
            "(raise --stride or --max-frames)"
        )
    return ticks


def frame_durations(ticks: list[int], options: GifOptions, tick_hz: float | None = None) -> list[int]:
    """How long each frame of ``ticks`` is shown, in milliseconds (multiples of 10: GIF counts hundredths).

    Without ``options.speed_up`` (or a tick rate) each frame is shown ``frame_ms``. With them, frame k is
    shown from its tick's game time divided by the speed-up to the next one's, rounded to hundredths on
    the running clock, so the animation keeps game time however the stride divides it. The last frame
    is held at least ``hold_ms``.

    Examples
    --------
    >>> frame_durations([0, 1, 2, 3], GifOptions(speed_up=1.0, hold_ms=0), tick_hz=30)
    [30, 40, 30, 30]
    >>> frame_durations([0, 5, 7], GifOptions(frame_ms=60, hold_ms=2000))
    [60, 60, 2000]
    """
    if options.speed_up is None or tick_hz is None:
        durations = [options.frame_ms] * len(ticks)
    else:
        starts = [round(100 * tick / tick_hz / options.speed_up) for tick in ticks]
        durations = [10 * (after - before) for before, after in itertools.pairwise(starts)]
        durations.append(max(durations[-1:] or [options.frame_ms]))
    durations[-1] = max(durations[-1], options.hold_ms)
    return durations
