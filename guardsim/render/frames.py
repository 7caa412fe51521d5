"""Episode frames: the level, what is still unseen, each guard's cone, trail, start and body, a caption bar
and a legend, drawn from the trace as arrays of indices into the fixed palette.

Frames are drawn in tick order by one :class:`FrameDrawer`, which keeps what does not change (the level,
the legend, the unreachable cells) and updates the rest incrementally: cells newly seen since the last
frame are repainted, trail segments walked since then are added to a layer that stores, per pixel, the
tick it was last walked, and only the cones are recomputed. The trail fades in whole blocks of ticks, so
between two block boundaries a frame differs from the previous one only near the guards and in the
caption, which keeps the GIF's per-frame rectangles small.

Under continuous motion the trace records the body's pose at every physics tick; the guard and its cone
are drawn at the pose and the trail is the polyline through the poses (a diagonal walked as a diagonal),
rather than the band between the centres of the cells the body passed through.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from PIL import Image, ImageDraw

from guardsim.errors import ArgumentError
from guardsim.level import Level
from guardsim.render.cells import tight_cells
from guardsim.render.layout import (
    CAPTION_LINE,
    CAPTION_SIZE,
    MIN_FRAME_WIDTH,
    MIN_GUARD_RADIUS,
    PLAY_PAD,
    Layout,
    VisionSettings,
    draw_guard,
    grow_mask,
    grown_box,
    wrap_caption,
)
from guardsim.render.legend import draw_legend
from guardsim.render.palette import Index, guard_index, palette_rgb, text_index, trail_index
from guardsim.render.sight import SightCaster
from guardsim.render.text import Typesetter
from guardsim.render.timeline import DEFAULT_FRAME_SIZE, cell_pixels
from guardsim.trace import Trace
from guardsim.world import World

__all__ = ["DEFAULT_FRAME_SIZE", "FrameDrawer", "cell_pixels", "render_frame"]

#: The trail fades over about this many blocks of ticks per episode.
TRAIL_BLOCKS = 24
#: Age in blocks at which the trail steps down to each fainter level.
_TRAIL_AGES = np.asarray([1, 2, 4, 8])


class FrameDrawer:
    """Draws an episode's frames; fastest when asked for ticks in increasing order.

    Parameters
    ----------
    level
        The level the trace was played on (its walls and outline are drawn; its guard is used only when
        the trace does not record the vision simulated).
    trace
        The episode.
    size
        Longest side of the play area in pixels (approximate: cells are whole pixels); ``None`` chooses
        it from the level's size (:func:`~guardsim.render.timeline.cell_pixels`: at least 6 pixels a
        cell up to 1600 pixels a side).
    speed_up
        Under continuous motion, game seconds per second of animation, named in the caption (``None``:
        not named, as when a frame is drawn alone).
    """

    def __init__(self, level: Level, trace: Trace, *, size: int | None = None, speed_up: float | None = None) -> None:
        self.level = level
        self.trace = trace
        self.vision = VisionSettings.of(level, trace)
        self.sight = SightCaster(World(level))
        self.paths = trace.team_paths()
        self.headings = trace.team_headings()
        self.guards = len(self.paths)
        rows, cols = trace.shape
        scale = cell_pixels(trace.shape, size)
        self.pixels_per_unit = scale / trace.cell_size
        self.speed_up = speed_up
        self.caption_setter = Typesetter(CAPTION_SIZE)
        play = (cols * scale + 2 * PLAY_PAD, rows * scale + 2 * PLAY_PAD)
        width = max(MIN_FRAME_WIDTH, play[0])
        self.tight = tight_cells(level, trace.traversable, trace.origin)
        legend = draw_legend(
            width,
            guards=self.guards,
            unreachable=bool(trace.unreachable),
            tight=bool(self.tight.any()),
            items=self._legend_items(),
        )
        # The caption bar holds as many lines as the longest caption wraps to (the first and last ticks'
        # have the widest numbers); a subclass that rewrites the caption gets a spare line.
        self.caption_width = width - 16
        lines = max(len(wrap_caption(FrameDrawer.caption(self, tick), self.caption_setter, self.caption_width))
                    for tick in (0, trace.steps))  # fmt: skip
        if type(self).caption is not FrameDrawer.caption:
            lines += 1
        lines = self._caption_rows(lines)
        top = lines * CAPTION_LINE + 8
        self.layout = Layout(scale, play, (width - play[0]) // 2, top, legend.shape[0], width)
        self.template = np.full((self.layout.height, width), Index.BAR, dtype=np.uint8)
        self.template[self.layout.height - legend.shape[0] :] = legend
        self.static = self._draw_level()
        self.free = self.static == Index.FREE
        # Cells in first-seen order, to repaint only those newly seen between two frames.
        flat = np.flatnonzero(trace.goal & (trace.first_seen >= 0))
        ticks = trace.first_seen.ravel()[flat]
        order = np.argsort(ticks, kind="stable")
        self._seen_cells, self._seen_ticks = flat[order], ticks[order]
        self.trail_block = max(1, math.ceil(trace.steps / TRAIL_BLOCKS))
        self.trail_width = max(1, round(scale / 3))
        # Pose points in the coordinates Pillow draws in (pixel centres on whole numbers), for the trail.
        self._pose_points: np.ndarray | None = None
        self.guard_poses: np.ndarray | None = None
        """``float (guards, ticks + 1, 3)``: each guard's ``x, y, facing degrees`` at every tick, for a team
        whose bodies move freely (an alert episode in continuous motion); the trace's cells otherwise."""
        if trace.poses is not None and self.guards == 1:
            self._pose_points = np.column_stack(self.to_pixels((trace.poses[:, 1], trace.poses[:, 2]))) - 0.5
        self._reset()

    def _legend_items(self) -> list[tuple[str, str]] | None:
        """The legend's ``(swatch kind, label)`` items (:func:`~guardsim.render.legend.draw_legend`);
        ``None``: the coverage legend."""
        return None

    def _caption_rows(self, lines: int) -> int:
        """Caption lines the bar holds, given the ``lines`` the plain caption needs."""
        return lines

    # -- static parts ------------------------------------------------------------------------------

    def to_pixels(self, point: tuple[Any, Any]) -> tuple[Any, Any]:
        """A world point (or arrays of coordinates) in play-area pixels."""
        origin = self.trace.origin
        return (
            PLAY_PAD + (point[0] - origin[0]) * self.pixels_per_unit,
            PLAY_PAD + (point[1] - origin[1]) * self.pixels_per_unit,
        )

    def cell_centre(self, cell: tuple[int, int]) -> tuple[float, float]:
        """A cell's centre in play-area pixels."""
        scale = self.layout.scale
        return (PLAY_PAD + (cell[0] + 0.5) * scale, PLAY_PAD + (cell[1] + 0.5) * scale)

    def _upscale(self, cells: np.ndarray) -> np.ndarray:
        scale = self.layout.scale
        return np.pad(np.repeat(np.repeat(cells, scale, axis=0), scale, axis=1), PLAY_PAD)

    def _floor(self, shape: tuple[int, int]) -> np.ndarray:
        """The level's floor (outer ring minus holes) rasterised: ``uint8`` ``FREE`` on ``WALL``."""
        image = Image.new("L", (shape[1], shape[0]), Index.WALL)
        draw = ImageDraw.Draw(image)
        draw.polygon([self.to_pixels(p) for p in self.level.outer], fill=Index.FREE)
        for hole in self.level.holes:
            draw.polygon([self.to_pixels(p) for p in hole], fill=Index.WALL)
        return np.asarray(image).copy()

    def _draw_level(self) -> np.ndarray:
        """Walls, floor, unreachable cells hatched, cells too tight to stand in, and an outline where a
        wall meets the floor (not where two wall pieces touch, as where an importer cut a wall open)."""
        play = self.layout.play
        static = self._floor((play[1], play[0]))
        floor = static == Index.FREE
        unreachable = self._upscale(self.trace.traversable & ~self.trace.goal) & floor
        rows, cols = np.indices(static.shape)
        static[unreachable] = Index.UNREACHABLE
        static[unreachable & ((rows + cols) % 6 == 0)] = Index.HATCH
        static[self._upscale(self.tight) & floor] = Index.TIGHT
        image = Image.new("L", play, 0)
        draw = ImageDraw.Draw(image)
        width = 2 if self.layout.scale >= 4 else 1
        for ring in (self.level.outer, *self.level.holes):
            points = [self.to_pixels(p) for p in ring]
            draw.line([*points, points[0]], fill=1, width=width)
        outline = (np.asarray(image) > 0) & grow_mask(floor, width)
        static[outline] = Index.OUTLINE
        return static

    # -- what changes with the tick ---------------------------------------------------------------

    def _reset(self) -> None:
        self._tick = 0
        unseen = self.trace.goal & ((self.trace.first_seen < 0) | (self.trace.first_seen > 0))
        self._background = np.where(self._upscale(unseen) & self.free, Index.UNSEEN, self.static).astype(np.uint8)
        self._walked = np.full(self.static.shape, -1, dtype=np.int64)
        self._trail = np.zeros(self.static.shape, dtype=np.uint8)
        self._trail_box: tuple[int, int, int, int] | None = None
        self._current: tuple[int, int, np.ndarray] | None = None

    def _trail_level(self, walked: np.ndarray | int, tick: int) -> np.ndarray:
        age = tick // self.trail_block - np.asarray(walked) // self.guards // self.trail_block
        return np.searchsorted(_TRAIL_AGES, age, side="right")

    def _trail_colour(self, walked: np.ndarray, tick: int) -> np.ndarray:
        guard = walked % self.guards % 8
        return (Index.GUARD_BASE + 8 * guard + self._trail_level(walked, tick)).astype(np.uint8)

    def _segment_box(self, a: tuple[int, int], b: tuple[int, int]) -> tuple[int, int, int, int]:
        """The band of trail pixels between two cells' centres: ``(x0, y0, x1, y1)``, ends exclusive."""
        scale, width = self.layout.scale, self.trail_width
        inset = PLAY_PAD + (scale - width) // 2
        xa, ya, xb, yb = a[0] * scale + inset, a[1] * scale + inset, b[0] * scale + inset, b[1] * scale + inset
        return min(xa, xb), min(ya, yb), max(xa, xb) + width, max(ya, yb) + width

    def _advance(self, tick: int) -> None:
        """Bring the background and the trail layers from the current tick to ``tick``."""
        if tick < self._tick:
            self._reset()
        start, stop = np.searchsorted(self._seen_ticks, [self._tick, tick], side="right")
        if stop > start:
            cols, scale = self.trace.shape[1], self.layout.scale
            cells = self._seen_cells[start:stop]
            offsets = PLAY_PAD + np.arange(scale)
            rows = ((cells // cols) * scale)[:, None, None] + offsets[None, :, None]
            columns = ((cells % cols) * scale)[:, None, None] + offsets[None, None, :]
            self._background[rows, columns] = self.static[rows, columns]
        walk = self._walk_cells if self._pose_points is None else self._walk_poses
        box = walk(self._tick, tick, self._trail_box)
        self._trail_box = box
        if box is not None and tick // self.trail_block != self._tick // self.trail_block:
            x0, y0, x1, y1 = box
            walked = self._walked[y0:y1, x0:x1]
            drawn = walked >= 0
            self._trail[y0:y1, x0:x1][drawn] = self._trail_colour(walked[drawn], tick)
        self._tick = tick

    def _walk_cells(
        self, start: int, tick: int, box: tuple[int, int, int, int] | None
    ) -> tuple[int, int, int, int] | None:
        """Add the bands between the cell centres of ticks ``start`` to ``tick`` to the trail layers;
        returns the box of trail pixels grown to hold them."""
        for step in range(start + 1, tick + 1):
            for guard, path in enumerate(self.paths):
                if path[step - 1] == path[step]:
                    continue
                x0, y0, x1, y1 = self._segment_box(path[step - 1], path[step])
                code = step * self.guards + guard
                self._walked[y0:y1, x0:x1] = code
                self._trail[y0:y1, x0:x1] = self._trail_colour(np.asarray(code), tick)
                box = grown_box(box, (x0, y0, x1, y1))
        return box

    def _walk_poses(
        self, start: int, tick: int, box: tuple[int, int, int, int] | None
    ) -> tuple[int, int, int, int] | None:
        """Add the polyline through the poses of the blocks finished between ticks ``start`` and ``tick``
        to the trail layers, and draw the block ``tick`` is in (from its first step) as the current piece.

        A trail pixel needs only the fading block of its last walk, so each block is one Pillow polyline,
        drawn whole once the guard has left it; the block being walked is redrawn from its start at every
        frame. So a frame is the same whichever frames were drawn before it.
        """
        block = self.trail_block
        for number in range(start // block, tick // block):
            piece = self._polyline(number * block, (number + 1) * block - 1)
            if piece is not None:
                x0, y0, mask = piece
                x1, y1 = x0 + mask.shape[1], y0 + mask.shape[0]
                code = number * block * self.guards
                self._walked[y0:y1, x0:x1][mask] = code
                self._trail[y0:y1, x0:x1][mask] = self._trail_colour(np.asarray(code), tick)
                box = grown_box(box, (x0, y0, x1, y1))
        self._current = self._polyline(tick // block * block, tick)
        return box

    def _polyline(self, first: int, last: int) -> tuple[int, int, np.ndarray] | None:
        """The trail pixels of steps ``first`` to ``last`` (each from the pose before it to its own): the
        corner ``(x0, y0)`` of a box and a ``bool`` mask over it; ``None`` if the guard did not move."""
        points = self._pose_points
        if points is None or last < 1:
            return None
        run = points[max(0, first - 1) : last + 1]
        moved = np.any(run[1:] != run[:-1], axis=1)
        if not moved.any():
            return None
        run = run[np.concatenate([[True], moved])]
        reach = self.trail_width / 2 + 2
        width, height = self.layout.play
        x0, y0 = max(0, math.floor(run[:, 0].min() - reach)), max(0, math.floor(run[:, 1].min() - reach))
        x1 = min(width, math.ceil(run[:, 0].max() + reach) + 1)
        y1 = min(height, math.ceil(run[:, 1].max() + reach) + 1)
        if x1 <= x0 or y1 <= y0:
            return None
        image = Image.new("L", (x1 - x0, y1 - y0), 0)
        line = [(x - x0, y - y0) for x, y in run.tolist()]
        ImageDraw.Draw(image).line(line, fill=1, width=self.trail_width, joint="curve")
        return x0, y0, np.asarray(image) > 0

    def pose(self, guard: int, tick: int) -> tuple[tuple[float, float], float]:
        """Where guard ``guard`` is at ``tick`` (a world point) and where it faces (degrees, clockwise on
        screen from +x): the recorded pose under continuous motion, else its cell's centre and heading."""
        if self.guard_poses is not None:
            x, y, facing = (float(v) for v in self.guard_poses[guard, min(tick, self.guard_poses.shape[1] - 1)])
            return (x, y), facing
        poses = getattr(self.trace, "poses", None)
        if poses is not None and guard == 0:
            _, x, y, facing = (float(v) for v in poses[tick])
            return (x, y), facing
        cell = self.paths[guard][tick]
        origin, size = self.trace.origin, self.trace.cell_size
        centre = (origin[0] + (cell[0] + 0.5) * size, origin[1] + (cell[1] + 0.5) * size)
        return centre, 90.0 * self.headings[guard][tick]

    def cone_polygon(self, guard: int, tick: int) -> list[tuple[float, float]]:
        """What guard ``guard`` sees at ``tick``, as a ring of play-area pixel points."""
        eye, heading = self.pose(guard, tick)
        ring = self.sight.polygon(eye, heading, self.vision.fov_degrees, self.vision.view_range)
        return [self.to_pixels(point) for point in ring]

    @staticmethod
    def _tint_cone(play: np.ndarray, ring: list[tuple[float, float]]) -> None:
        height, width = play.shape
        xs, ys = [p[0] for p in ring], [p[1] for p in ring]
        x0, y0 = max(0, math.floor(min(xs))), max(0, math.floor(min(ys)))
        x1, y1 = min(width, math.ceil(max(xs)) + 1), min(height, math.ceil(max(ys)) + 1)
        if x1 <= x0 or y1 <= y0:
            return
        mask_image = Image.new("L", (x1 - x0, y1 - y0), 0)
        ImageDraw.Draw(mask_image).polygon([(x - x0, y - y0) for x, y in ring], fill=1)
        region = play[y0:y1, x0:x1]
        # Only floor entries are tinted: never walls or outlines, nor a cone another guard already tinted.
        inside = np.asarray(mask_image) > 0
        mask = inside & (region >= Index.FREE) & (region <= Index.HATCH)
        region[mask] += Index.CONE_BASE
        region[inside & (region == Index.TIGHT)] = Index.TIGHT_CONE

    def _paint_trail(self, play: np.ndarray) -> None:
        if self._trail_box is not None:
            x0, y0, x1, y1 = self._trail_box
            trail = self._trail[y0:y1, x0:x1]
            drawn = trail > 0
            play[y0:y1, x0:x1][drawn] = trail[drawn]
        if self._current is not None:
            x0, y0, mask = self._current
            play[y0 : y0 + mask.shape[0], x0 : x0 + mask.shape[1]][mask] = trail_index(0, 0)

    def _draw_markers(self, play: np.ndarray, tick: int, rings: list[list[tuple[float, float]]]) -> np.ndarray:
        image = Image.fromarray(play)
        draw = ImageDraw.Draw(image)
        radius = max(MIN_GUARD_RADIUS, 0.45 * self.layout.scale)
        for guard, path in enumerate(self.paths):
            x, y = self.cell_centre(path[0])
            half = max(radius + 2, 0.5 * self.layout.scale)
            draw.rectangle((x - half, y - half, x + half, y + half), outline=guard_index(guard), width=2)
        for guard, ring in enumerate(rings):
            draw.line([*ring, ring[0]], fill=guard_index(guard), width=1)
        # Guards sharing a cell are spread round its centre so that each stays visible.
        sharing: dict[tuple[float, float], list[tuple[int, float]]] = {}
        for guard in range(self.guards):
            point, heading = self.pose(guard, tick)
            sharing.setdefault(point, []).append((guard, heading))
        for point, guards in sharing.items():
            cx, cy = self.to_pixels(point)
            for place, (guard, heading) in enumerate(guards):
                angle = 2 * math.pi * place / len(guards) - math.pi / 2
                spread = 0.9 * radius if len(guards) > 1 else 0.0
                centre = (cx + spread * math.cos(angle), cy + spread * math.sin(angle))
                draw_guard(draw, centre, heading, radius, guard)
        return np.asarray(image)

    def caption(self, tick: int) -> tuple[str, str]:
        """The two caption lines at ``tick`` (before wrapping to the frame's width)."""
        trace = self.trace
        team = f"{self.guards} guards" if self.guards > 1 else "1 guard"
        tick_hz = getattr(trace, "tick_hz", None)
        pace = ""
        if tick_hz and self.speed_up is not None:
            pace = ", real time" if self.speed_up == 1 else f", {self.speed_up:g}x"
        clock = f" ({tick / tick_hz:.1f} s{pace})" if tick_hz else ""
        first = f"{trace.level}  |  tick {tick} / {trace.steps}{clock}  |  {trace.planner}, {team}"
        second = f"{trace.unseen_percent[tick]:.1f}% of {trace.reachable} reachable cells unseen"
        if trace.unreachable:
            second += f"  |  {trace.unreachable} unreachable cells (not counted)"
        return first, second

    def frame(self, tick: int) -> np.ndarray:
        """The frame at ``tick`` as a ``uint8 (height, width)`` array of palette indices."""
        if not 0 <= tick <= self.trace.steps:
            raise ArgumentError(f"tick {tick} is outside the episode (0 to {self.trace.steps})")
        self._advance(tick)
        play = self._background.copy()
        rings = [self.cone_polygon(guard, tick) for guard in range(self.guards)]
        for ring in rings:
            self._tint_cone(play, ring)
        self._paint_trail(play)
        play = self._draw_markers(play, tick, rings)
        layout = self.layout
        canvas = self.template.copy()
        canvas[layout.top : layout.top + layout.play[1], layout.left : layout.left + layout.play[0]] = play
        lines = wrap_caption(self.caption(tick), self.caption_setter, self.caption_width)
        coverage = self.caption_setter.mask(
            (layout.width, layout.top), [((8, 4 + k * CAPTION_LINE), line) for k, line in enumerate(lines)]
        )
        inked = coverage > 0
        canvas[: layout.top][inked] = text_index(coverage[inked])
        return canvas


def render_frame(level: Level, trace: Trace, tick: int, *, size: int | None = None) -> np.ndarray:
    """The frame at ``tick`` as an RGB ``uint8 (height, width, 3)`` array."""
    return palette_rgb()[FrameDrawer(level, trace, size=size).frame(tick)]
