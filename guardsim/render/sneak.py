"""A sneak as an animated GIF: the patrol's frames, with the intruder's trail and position drawn on top,
coloured by its state, and each guard's awareness meter as a bar over the guard."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence

import numpy as np
from PIL import Image, ImageDraw

from guardsim.detection.model import meter_state
from guardsim.errors import ArgumentError
from guardsim.files.output import atomic_path
from guardsim.level import Level
from guardsim.render.frames import FrameDrawer
from guardsim.render.gif import GifOptions, GifStream, frame_ticks
from guardsim.render.layout import MIN_GUARD_RADIUS, wrap_caption
from guardsim.render.palette import DARK_ALPHA, Index, guard_index
from guardsim.trace import Trace

__all__ = [
    "CAMERA_INDEX",
    "STATE_INDEX",
    "SneakFrames",
    "camera_overlay",
    "meter_bar_box",
    "write_sneak_gif",
]

#: The intruder's colour: a guard colour no team of up to five guards uses.
_INTRUDER = guard_index(5)

#: A camera, its cone and the frame of its meter bar: guard colour 4 (magenta), as the preview's cameras.
CAMERA_INDEX = guard_index(4)
#: 4 x 4 ordered dither: a floor pixel is shaded dark where its threshold is below its cell's darkness.
_BAYER = np.array([[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]]) / 16.0
#: Floor entries (under the cone's tint or not) the dark may shade; walls, guards and text never.
_FLOOR = (Index.FREE, Index.UNSEEN, Index.TIGHT, Index.CONE_BASE + Index.FREE, Index.CONE_BASE + Index.UNSEEN)

#: Palette entries of the intruder's states (its disc) and of a meter bar's fill: white while unseen, the
#: walls' grey in view, orange (guard colour 4) suspicious, red (guard colour 1) detected. The viewer's
#: page uses the same colours (:data:`guardsim.viewer.layers.STATE_COLOURS`).
STATE_INDEX: dict[str, int] = {
    "unseen": int(Index.WHITE),
    "in view": int(Index.WALL),
    "suspicious": guard_index(3),
    "detected": guard_index(0),
}


def meter_bar_box(x: float, y: float, radius: float) -> tuple[int, int, int, int]:
    """The meter bar over a guard drawn at ``(x, y)`` with ``radius`` (pixels): ``(left, top, width,
    height)`` of its frame, one pixel of outline round a white inside filled from the left by the level
    (``round(level * (width - 2))`` pixels). The viewer's page draws it the same way."""
    half = round(radius) + 1
    height = max(5, round(0.6 * radius))
    return round(x) - half, round(y - radius) - 4 - height, 2 * half, height


class SneakFrames(FrameDrawer):
    """The patrol's frames over the sneak's ticks, captioned with both clocks: the sneak's tick (the
    frame's) and the lap tick it falls on, ``(lap_start + tick) % period``, as sneak.json and the page
    count them. Without ``period`` the caption is the plain one.

    ``captions(tick)`` gives each frame's two caption lines instead (the bar grows to hold the longest),
    and ``legend`` (``(swatch kind, label)`` pairs, :func:`~guardsim.render.legend.draw_legend`) replaces
    the coverage legend."""

    def __init__(
        self,
        level: Level,
        trace: Trace,
        *,
        size: int | None,
        lap_start: int = 0,
        period: int | None = None,
        captions: Callable[[int], tuple[str, str]] | None = None,
        legend: Sequence[tuple[str, str]] | None = None,
    ) -> None:
        # Read while the base class lays the frame out.
        self.captions = captions
        self.legend = None if legend is None else list(legend)
        super().__init__(level, trace, size=size)
        self.lap_start = lap_start
        self.period = period

    def _legend_items(self) -> list[tuple[str, str]] | None:
        return self.legend

    def _caption_rows(self, lines: int) -> int:
        if self.captions is None:
            return lines
        return max(
            lines,
            *(len(wrap_caption(self.captions(tick), self.caption_setter, self.caption_width))
              for tick in range(self.trace.steps + 1)),
        )  # fmt: skip

    def caption(self, tick: int) -> tuple[str, str]:
        if self.captions is not None:
            return self.captions(tick)
        first, second = super().caption(tick)
        if self.period is None:
            return first, second
        plain = f"  |  tick {tick} / {self.trace.steps}"
        lap = (self.lap_start + tick) % self.period
        both = f"  |  sneak tick {tick} / {self.trace.steps} \u00b7 lap tick {lap} / {self.period}"
        return first.replace(plain, both, 1), second

    def guard_centres(self, tick: int) -> list[tuple[float, float]]:
        """Where each guard's disc is drawn at ``tick``, in frame pixels (guards sharing a place are
        spread round it as the frames draw them)."""
        radius = max(MIN_GUARD_RADIUS, 0.45 * self.layout.scale)
        sharing: dict[tuple[float, float], list[int]] = {}
        for guard in range(self.guards):
            sharing.setdefault(self.pose(guard, tick)[0], []).append(guard)
        centres: list[tuple[float, float]] = [(0.0, 0.0)] * self.guards
        for point, team in sharing.items():
            cx, cy = self.to_pixels(point)
            spread = 0.9 * radius if len(team) > 1 else 0.0
            for place, guard in enumerate(team):
                angle = 2 * math.pi * place / len(team) - math.pi / 2
                centres[guard] = (
                    self.layout.left + cx + spread * math.cos(angle),
                    self.layout.top + cy + spread * math.sin(angle),
                )
        return centres


def _draw_meters(
    frame: np.ndarray,
    drawer: SneakFrames,
    tick: int,
    levels: np.ndarray,
    suspicious: float,
    centres: list[tuple[float, float]] | None = None,
    outline: int = int(Index.OUTLINE),
) -> None:
    """Each guard's meter bar at ``tick`` (or one per point of ``centres``), clipped to the play area, onto
    ``frame`` (palette indices)."""
    layout = drawer.layout
    radius = max(MIN_GUARD_RADIUS, 0.45 * layout.scale)
    top, bottom = layout.top, layout.top + layout.play[1]
    left, right = layout.left, layout.left + layout.play[0]
    for guard, (x, y) in enumerate(drawer.guard_centres(tick) if centres is None else centres):
        x0, y0, width, height = meter_bar_box(x, y, radius)
        bar = np.full((height, width), outline, dtype=np.uint8)
        bar[1:-1, 1:-1] = Index.WHITE
        level = float(levels[guard])
        filled = round(min(1.0, max(0.0, level)) * (width - 2))
        bar[1:-1, 1 : 1 + filled] = STATE_INDEX[meter_state(level, suspicious)]
        ya, yb, xa, xb = max(y0, top), min(y0 + height, bottom), max(x0, left), min(x0 + width, right)
        if ya < yb and xa < xb:
            frame[ya:yb, xa:xb] = bar[ya - y0 : yb - y0, xa - x0 : xb - x0]


def write_sneak_gif(
    path: str | os.PathLike[str],
    level: Level,
    trace: Trace,
    intruder: list[tuple[int, int]],
    *,
    seen_ticks: set[int] | frozenset[int] = frozenset(),
    options: GifOptions | None = None,
    lap_start: int = 0,
    period: int | None = None,
    meters: np.ndarray | None = None,
    states: Sequence[str] = (),
    suspicious: float = 0.5,
    overlay: Callable[[ImageDraw.ImageDraw, SneakFrames, int], None] | None = None,
    guard_poses: np.ndarray | None = None,
    light: np.ndarray | None = None,
    cameras: Sequence[tuple[tuple[float, float], np.ndarray, float, float]] = (),
    camera_meters: np.ndarray | None = None,
    captions: Callable[[int], tuple[str, str]] | None = None,
    legend: Sequence[tuple[str, str]] | None = None,
) -> int:
    """Write the guards of ``trace`` with the intruder walking ``intruder`` (one cell per tick of the
    trace): its trail in the cyan of guard colour 6 (teams of up to five keep their own colours), itself a
    disc ringed in that colour, filled by its state at each tick (``states``, one per tick, see
    :data:`STATE_INDEX`); without ``states``, white, and the walls' grey at ticks in ``seen_ticks`` (a
    closest call's).

    ``meters`` (``float (ticks + 1, guards)``, the path's :attr:`~guardsim.sneak.PathGrade.meters`) adds a
    bar over each guard filled by its awareness meter at the frame's tick, coloured by
    :func:`meter_state` at the ``suspicious`` level.

    With ``period`` (the patrol's lap) the caption also gives the lap tick: the trace's tick 0 is lap tick
    ``lap_start`` (the sneak's start tick). ``overlay(draw, drawer, tick)`` draws more on each frame (palette
    indices) before the intruder and the meters. ``guard_poses`` (``float (guards, ticks + 1, 3)``: ``x, y,
    facing degrees``) draws each guard and its cone where its body is rather than at its cell.

    ``light`` (``float (rows, cols)``, 0 to 1) shades the floor by an ordered dither of near black, denser
    the darker the cell (at most :data:`~guardsim.render.palette.DARK_ALPHA` of its pixels), so the floor
    still reads. ``cameras`` (each ``(position, headings per lap tick, fov degrees, range)``) draws each
    camera and its cone at the frame's lap tick, and ``camera_meters`` (``float (ticks + 1, cameras)``)
    its meter bar over it.

    ``captions(tick)`` (each frame's two caption lines) and ``legend`` (``(swatch kind, label)`` pairs)
    replace the patrol's caption and coverage legend (:class:`SneakFrames`)."""
    options = options or GifOptions()
    drawer = SneakFrames(
        level, trace, size=options.size, lap_start=lap_start, period=period, captions=captions, legend=legend
    )
    drawer.guard_poses = guard_poses
    layout = drawer.layout
    if meters is not None:
        meters = np.asarray(meters, dtype=np.float64)
        if meters.ndim != 2 or meters.shape[0] < len(intruder) or meters.shape[1] != drawer.guards:
            raise ArgumentError(
                f"meters has shape {meters.shape}, expected ({len(intruder)}, {drawer.guards}): a row per tick of "
                "the path, a column per guard"
            )
    if states and len(states) < len(intruder):
        raise ArgumentError(f"{len(states)} intruder states for {len(intruder)} ticks of path")
    ticks = frame_ticks(trace.steps, options)
    radius = max(2.0, layout.scale * 0.45)
    dark = None if light is None else _dark_pixels(drawer, light)
    play_area = np.zeros((layout.height, layout.width), dtype=bool)
    play_area[layout.top : layout.top + layout.play[1], layout.left : layout.left + layout.play[0]] = True
    with atomic_path(path) as temporary, open(temporary, "wb") as file:
        stream = GifStream(file)
        for number, tick in enumerate(ticks):
            frame = drawer.frame(tick)
            if dark is not None:
                frame = frame.copy()
                frame[dark & np.isin(frame, _FLOOR)] = Index.OUTLINE
            image = Image.frombytes("P", (frame.shape[1], frame.shape[0]), np.ascontiguousarray(frame).tobytes())
            draw = ImageDraw.Draw(image)
            if overlay is not None:
                overlay(draw, drawer, tick)
            camera_centres = camera_overlay(draw, drawer, tick, cameras, lap_start)
            if cameras:
                # A camera's cone reaches past the play area: the caption and the legend stay as they were.
                drawn = np.array(image)
                drawn[~play_area] = frame[~play_area]
                image = Image.frombytes("P", (drawn.shape[1], drawn.shape[0]), np.ascontiguousarray(drawn).tobytes())
                draw = ImageDraw.Draw(image)
            step = min(tick, len(intruder) - 1)
            points = [_pixel(drawer, cell) for cell in intruder[: step + 1]]
            if len(points) > 1:
                draw.line(points, fill=_INTRUDER, width=max(2, layout.scale // 2))
            x, y = points[-1]
            plain = int(Index.WALL) if tick in seen_ticks else int(Index.WHITE)
            fill = STATE_INDEX[states[step]] if states else plain
            draw.ellipse([x - radius, y - radius, x + radius, y + radius], fill=fill, outline=_INTRUDER, width=2)
            shown = np.array(image)
            if meters is not None:
                _draw_meters(shown, drawer, tick, meters[step], suspicious)
            if camera_meters is not None and camera_centres:
                # A camera on the top wall shows its bar below it, where the play area has room.
                lifted = [
                    (x, y if meter_bar_box(x, y, radius)[1] >= layout.top else y + 3 * radius + 8)
                    for x, y in camera_centres
                ]
                _draw_meters(shown, drawer, tick, camera_meters[step], suspicious, lifted, CAMERA_INDEX)
            last = number == len(ticks) - 1
            stream.add(shown, max(options.frame_ms, options.hold_ms) if last else options.frame_ms)
        stream.close()
    return len(ticks)


def _pixel(drawer: FrameDrawer, cell: tuple[int, int]) -> tuple[float, float]:
    x, y = drawer.cell_centre(cell)
    return x + drawer.layout.left, y + drawer.layout.top


def _dark_pixels(drawer: FrameDrawer, light: np.ndarray) -> np.ndarray:
    """``bool (frame height, frame width)``: the pixels the dark shades, by the ordered dither."""
    layout = drawer.layout
    height, width = layout.height, layout.width
    mask = np.zeros((height, width), dtype=bool)
    rows, cols = light.shape
    scale = layout.scale
    darkness = np.repeat(np.repeat((1.0 - np.clip(light, 0.0, 1.0)) * DARK_ALPHA, scale, axis=0), scale, axis=1)
    x0, y0 = drawer.to_pixels(drawer.trace.origin)
    top, left = layout.top + round(y0), layout.left + round(x0)
    ys, xs = np.indices(darkness.shape)
    area = mask[top : top + rows * scale, left : left + cols * scale]
    area[:] = (
        _BAYER[(ys + top) % 4, (xs + left) % 4][: area.shape[0], : area.shape[1]]
        < darkness[: area.shape[0], : area.shape[1]]
    )
    return mask


def camera_overlay(
    draw: ImageDraw.ImageDraw,
    drawer: FrameDrawer,
    tick: int,
    cameras: Sequence[tuple[tuple[float, float], np.ndarray, float, float]],
    lap_start: int = 0,
) -> list[tuple[float, float]]:
    """Each camera (``(position, headings per tick of its swing, fov degrees, range)``) and the outline of
    its cone at lap tick ``lap_start + tick``, in :data:`CAMERA_INDEX`; the frame pixels of the cameras."""
    layout = drawer.layout
    centres = []
    for position, headings, fov, reach in cameras:
        px, py = drawer.to_pixels(position)
        x, y = layout.left + px, layout.top + py
        heading = float(headings[(lap_start + tick) % len(headings)])
        r = reach * drawer.pixels_per_unit
        width = 2 if layout.scale >= 4 else 1
        if fov >= 360:
            draw.ellipse([x - r, y - r, x + r, y + r], outline=CAMERA_INDEX, width=width)
        else:
            draw.pieslice([x - r, y - r, x + r, y + r], heading - fov / 2, heading + fov / 2, outline=CAMERA_INDEX,
                          width=width)  # fmt: skip
        dot = max(3.0, 0.35 * layout.scale)
        draw.ellipse([x - dot, y - dot, x + dot, y + dot], fill=CAMERA_INDEX, outline=int(Index.OUTLINE))
        centres.append((x, y))
    return centres
