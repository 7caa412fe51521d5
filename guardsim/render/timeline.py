"""Which ticks of an episode become frames, and how long each is shown: no drawing library needed."""

from __future__ import annotations

import math
from dataclasses import dataclass

from guardsim.errors import LimitError

__all__ = ["DEFAULT_FRAME_SIZE", "DEFAULT_MAX_FRAMES", "FRAME_CEILING", "GifOptions", "frame_ticks"]

#: Longest side of the play area in pixels, before rounding to whole pixels per cell.
DEFAULT_FRAME_SIZE = 480
#: Frames in a GIF unless the caller asks for more; the stride grows to stay under it.
DEFAULT_MAX_FRAMES = 200
#: Hard ceiling on frames, whatever the options, to keep GIFs bounded.
FRAME_CEILING = 5000


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
    size: int = DEFAULT_FRAME_SIZE
    """Longest side of the play area in pixels (approximate: cells are whole pixels)."""


def frame_ticks(steps: int, options: GifOptions) -> list[int]:
    """The ticks drawn: every ``stride``-th from 0, and always the last.

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
    else:
        if options.stride < 1:
            raise LimitError(f"frame stride must be at least 1, not {options.stride}")
        stride = options.stride
    ticks = list(range(0, steps + 1, stride))
    if ticks[-1] != steps:
        ticks.append(steps)
    if len(ticks) > options.max_frames:
        raise LimitError(
            f"{len(ticks)} frames at stride {stride} is over the limit of {options.max_frames} "
            "(raise --stride or --max-frames)"
        )
    return ticks
