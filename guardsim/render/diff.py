"""The picture of ``guardsim diff``: the level before and after an edit, side by side, and their difference.

Before and after: walls grey, floor white shading to red with the share of the lap some guard sees it,
floor never watched (safe spots) green, floor the guards do not reach lilac, the guards' routes in their
colours, each pair's best path (blue: an undetected way through; orange: the closest call, detected).
The difference panel (when the grids line up): floor added green, removed purple, exposure up red and
down blue, safe spots lost yellow and gained teal.
"""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from guardsim.design.analysis import Analysis
from guardsim.design.diff import LevelDiff
from guardsim.grid import cell_of_state
from guardsim.render.palette import COLOURS, GUARD_COLOURS
from guardsim.render.text import font

__all__ = ["DIFF_COLOURS", "diff_picture", "panel_geometry"]

#: The colours the pictures add to the palette's.
DIFF_COLOURS: dict[str, tuple[int, int, int]] = {
    "watched": (214, 40, 40),
    "safe": (150, 214, 160),
    "added": (60, 170, 80),
    "removed": (140, 84, 162),
    "less": (40, 90, 220),
    "safe_lost": (255, 196, 40),
    "safe_gained": (0, 150, 150),
    "found": (40, 90, 220),
    "detected": (240, 140, 20),
}

#: Height of the caption above each panel, and the gap between panels, in pixels.
CAPTION, GAP = 18, 8


def _mix(a: tuple[int, int, int], b: tuple[int, int, int], t: np.ndarray) -> np.ndarray:
    t = np.clip(t, 0.0, 1.0)[..., None]
    return np.rint(np.asarray(a) + t * (np.asarray(b) - np.asarray(a))).astype(np.uint8)


def _cells(analysis: Analysis) -> np.ndarray:
    grid = analysis.scene.grid
    floor = grid.traversable.ravel()
    out = np.empty((grid.size, 3), dtype=np.uint8)
    out[:] = COLOURS["wall"]
    out[floor] = COLOURS["unreachable"]
    patrolled = analysis.goal & floor
    out[patrolled] = _mix(COLOURS["free"], DIFF_COLOURS["watched"], analysis.exposure[patrolled])
    out[analysis.safe] = DIFF_COLOURS["safe"]
    return out.reshape(*grid.shape, 3)


def _difference(found: LevelDiff) -> np.ndarray:
    a, b = found.old, found.new
    shape = b.scene.grid.shape
    floor_a, floor_b = a.scene.grid.traversable.ravel(), b.scene.grid.traversable.ravel()
    out = np.empty((floor_b.size, 3), dtype=np.uint8)
    out[:] = COLOURS["wall"]
    change = np.asarray(found.exposure_change).ravel()
    both = floor_a & floor_b
    up = both & (change >= 0)
    out[up] = _mix(COLOURS["free"], DIFF_COLOURS["watched"], 3 * change[up])
    down = both & (change < 0)
    out[down] = _mix(COLOURS["free"], DIFF_COLOURS["less"], -3 * change[down])
    out[floor_b & ~floor_a] = DIFF_COLOURS["added"]
    out[floor_a & ~floor_b] = DIFF_COLOURS["removed"]
    out[a.safe & ~b.safe] = DIFF_COLOURS["safe_lost"]
    out[b.safe & ~a.safe] = DIFF_COLOURS["safe_gained"]
    return out.reshape(*shape, 3)


def panel_geometry(found: LevelDiff) -> tuple[int, list[tuple[int, int]]]:
    """Pixels per cell and the top-left corner of each panel's grid (before, after, difference)."""
    rows, cols = (max(a, b) for a, b in zip(found.old.scene.grid.shape, found.new.scene.grid.shape))
    scale = max(2, min(12, 480 // max(rows, cols)))
    panels = 3 if found.aligned else 2
    return scale, [(GAP + k * (cols * scale + GAP), CAPTION + GAP) for k in range(panels)]


def _overlay(draw: ImageDraw.ImageDraw, analysis: Analysis, left: int, top: int, scale: int) -> None:
    cols = analysis.scene.grid.shape[1]

    def centre(cell: int) -> tuple[float, float]:
        return left + (cell % cols + 0.5) * scale, top + (cell // cols + 0.5) * scale

    for guard, states in enumerate(analysis.patrol.states):
        cells = np.asarray(cell_of_state(states))
        colour = COLOURS["guard"] if guard == 0 else GUARD_COLOURS[(guard - 1) % len(GUARD_COLOURS)]
        if np.unique(cells).size > 1:
            draw.line([centre(int(c)) for c in cells] + [centre(int(cells[0]))], fill=colour, width=max(1, scale // 3))
        x, y = centre(int(cells[0]))
        draw.rectangle([x - scale / 2, y - scale / 2, x + scale / 2, y + scale / 2], fill=colour)
    for pair in analysis.pairs:
        path = None if pair.sneak is None else pair.sneak.path
        if path is not None and path.cells.size > 1:
            colour = DIFF_COLOURS["found"] if pair.sneak is not None and pair.sneak.found else DIFF_COLOURS["detected"]
            draw.line([centre(int(c)) for c in path.cells], fill=colour, width=max(1, scale // 2))


def diff_picture(found: LevelDiff) -> np.ndarray:
    """``uint8 (height, width, 3)``: before, after and (when the grids line up) their difference."""
    scale, corners = panel_geometry(found)
    rows, cols = (max(a, b) for a, b in zip(found.old.scene.grid.shape, found.new.scene.grid.shape))
    width = corners[-1][0] + cols * scale + GAP
    height = CAPTION + 2 * GAP + rows * scale
    canvas = np.full((height, width, 3), COLOURS["white"], dtype=np.uint8)
    panels = [_cells(found.old), _cells(found.new)] + ([_difference(found)] if found.aligned else [])
    for (left, top), cells in zip(corners, panels):
        block = np.repeat(np.repeat(cells, scale, axis=0), scale, axis=1)
        canvas[top : top + block.shape[0], left : left + block.shape[1]] = block
    image = Image.fromarray(canvas)
    draw = ImageDraw.Draw(image)
    for analysis, (left, top) in zip((found.old, found.new), corners):
        _overlay(draw, analysis, left, top, scale)
    captions = [f"before: score {found.old_report.score}", f"after: score {found.new_report.score}", "difference"]
    for caption, (left, _top) in zip(captions, corners):
        draw.text((left, 3), caption, fill=COLOURS["outline"], font=font(13))
    return np.asarray(image)
