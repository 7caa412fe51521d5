"""Reading a level file within limits: its bytes and its JSON (``guardsim.load_level`` then parses it)."""

from __future__ import annotations

import os
from typing import Any

from guardsim.errors import LevelError
from guardsim.files.reading import DEFAULT_MAX_DEPTH, display_path, parse_json, read_text_file
from guardsim.files.reading import read_limited_bytes as _read_bytes
from guardsim.level.limits import DEFAULT_MAX_FILE_BYTES

__all__ = ["read_level_json", "read_limited_bytes"]


def read_limited_bytes(path: str | os.PathLike[str], *, max_file_bytes: int, kind: str = "level file") -> bytes:
    """A regular file's bytes, every way of failing (missing, a folder, a FIFO or device, unreadable, too
    large) a one-line :class:`LevelError` naming the file; ``kind`` names what a folder is not (``level
    file``, ``map``). See :func:`guardsim.files.reading.read_limited_bytes`."""
    return _read_bytes(path, max_file_bytes=max_file_bytes, kind=kind, error=LevelError)


def read_level_json(
    path: str | os.PathLike[str],
    *,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    max_depth: int = DEFAULT_MAX_DEPTH,
) -> Any:
    """Read a JSON file, turning every way it can fail into a :class:`LevelError`.

    ``NaN`` and ``Infinity`` are decoded (as Python's json module does) so that the level check can say
    which coordinate or setting holds one; nesting deeper than ``max_depth`` is refused before decoding.
    """
    text = read_text_file(path, max_file_bytes=max_file_bytes, error=LevelError)
    return parse_json(text, source=display_path(path), max_depth=max_depth, error=LevelError, allow_non_finite=True)
