"""The default size limits of a level; each is a keyword of the loader that a caller may raise.

Each limit is set so that the work it allows finishes in seconds on a laptop; ``docs/robustness.md``
gives the figures. A message about a limit names its keyword (``max_cells``), which the command line
turns into its option.
"""

from __future__ import annotations

__all__ = ["DEFAULT_MAX_CELLS", "DEFAULT_MAX_FILE_BYTES", "DEFAULT_MAX_VERTICES", "MAX_SNEAK_TICKS", "MAX_TICK_HZ"]

#: Largest grid (rows x cols) a level may produce unless the caller raises the cap.
DEFAULT_MAX_CELLS = 1_000_000
#: Largest number of vertices over all rings.
DEFAULT_MAX_VERTICES = 100_000
#: Largest level file read.
DEFAULT_MAX_FILE_BYTES = 16 * 1024 * 1024
#: Most physics ticks per second (``guard.tick_hz`` and ``--tick-hz``): games step their physics 30 to
#: 240 times a second; past this a 20-second continuous episode is hours of stepping (100 000 Hz was
#: killed after a minute of silence), and below it every game's rate fits with room to spare.
MAX_TICK_HZ = 1000.0
#: Most ticks a sneaking step may take (the level's ``intruder.sneak_ticks`` and ``--sneak-ticks``): the
#: searches with gaits hold a layer per tick stood still.
MAX_SNEAK_TICKS = 1000
