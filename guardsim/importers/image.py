"""Images (PNG) into levels: dark pixels are walls, light pixels free, one pixel per world unit.

Transparent pixels count as light (the image is laid on white first), so walls painted on a
transparent layer work. The outer ring is the image's bounds; blocked pixels become holes exactly as
blocked cells of a Moving AI map do.
"""

from __future__ import annotations

import io
import os
import warnings

import numpy as np

from guardsim.errors import LevelError
from guardsim.importers.imported import ImportedLevel, level_from_blocked_cells, read_source_bytes
from guardsim.importers.source import display_name, excerpt
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES

__all__ = ["DEFAULT_THRESHOLD", "import_image", "read_image"]

#: Pixels darker than this (0-255 grey level) are walls.
DEFAULT_THRESHOLD = 128


def read_image(
    data: bytes, *, source: str = "<image>", threshold: int = DEFAULT_THRESHOLD, max_pixels: int
) -> np.ndarray:
    """The wall pixels of an image as ``bool (height, width)``: grey level below ``threshold``.

    Examples
    --------
    >>> from PIL import Image
    >>> buffer = io.BytesIO()
    >>> Image.fromarray(np.array([[0, 255], [200, 90]], dtype=np.uint8)).save(buffer, format="PNG")
    >>> read_image(buffer.getvalue(), max_pixels=10).astype(int).tolist()
    [[1, 0], [0, 1]]
    """
    from PIL import Image, UnidentifiedImageError

    if not 0 <= threshold <= 256:
        raise LevelError(f"{source}: threshold must be between 0 and 256, not {threshold}")
    try:
        with warnings.catch_warnings():
            # The size check below replaces Pillow's own bomb warning, which would print a second line.
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            image: Image.Image = Image.open(io.BytesIO(data))
        width, height = image.size
        if width * height > max_pixels:
            raise LevelError(
                f"{source}: {width} x {height} = {width * height} pixels is over the limit of {max_pixels} cells "
                "(scale the image down or raise --max-cells)"
            )
        image.load()
    except UnidentifiedImageError:
        raise LevelError(f"{source}: not an image Pillow can read") from None
    except (OSError, SyntaxError, ValueError, Image.DecompressionBombError) as error:
        raise LevelError(f"{source}: broken image: {excerpt(str(error), 80)}") from None
    if image.mode in ("RGBA", "LA", "PA") or (image.mode == "P" and "transparency" in image.info):
        rgba = image.convert("RGBA")
        white = Image.new("RGBA", rgba.size, (255, 255, 255, 255))
        image = Image.alpha_composite(white, rgba)
    grey = np.asarray(image.convert("L"))
    return grey < threshold


def import_image(
    path: str | os.PathLike[str],
    *,
    cell_size: float = 1.0,
    threshold: int = DEFAULT_THRESHOLD,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Convert an image to a level: pixels darker than ``threshold`` are walls."""
    source = display_name(path)
    blocked = read_image(
        read_source_bytes(path, max_file_bytes), source=source, threshold=threshold, max_pixels=max_cells
    )
    level, report = level_from_blocked_cells(
        blocked, source=source, cell_size=cell_size, max_cells=max_cells, max_vertices=max_vertices
    )
    height, width = blocked.shape
    changes = (f"{int(blocked.sum())} wall pixels (threshold {threshold})", report.describe("wall pixel runs"))
    return ImportedLevel(level, "image", (width, height), changes)
