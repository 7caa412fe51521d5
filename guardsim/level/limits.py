"""The default size limits of a level; each is a keyword of the loader that a caller may raise.

Each limit is set so that the work it allows finishes in seconds on a laptop; ``docs/robustness.md``
gives the figures. A message about a limit names its keyword (``max_cells``), which the command line
turns into its option.
"""

from __future__ import annotations

__all__ = ["DEFAULT_MAX_CELLS", "DEFAULT_MAX_FILE_BYTES", "DEFAULT_MAX_VERTICES"]

#: Largest grid (rows x cols) a level may produce unless the caller raises the cap.
DEFAULT_MAX_CELLS = 1_000_000
#: Largest number of vertices over all rings.
DEFAULT_MAX_VERTICES = 100_000
#: Largest level file read.
DEFAULT_MAX_FILE_BYTES = 16 * 1024 * 1024
