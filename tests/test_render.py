"""The renderer, judged by decoding what it writes: frame counts and sizes, colours where the trace says
unseen or seen, a cone that never shows a wall or what lies behind one, the caption outside the play area,
one colour per guard, byte-identical GIFs, and every edge case giving a valid GIF."""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from guardsim import load_level
from guardsim.cli import main
from guardsim.errors import LimitError
from guardsim.level import parse_level
from guardsim.render import (
    COLOURS,
    PALETTE,
    FrameDrawer,
    GifOptions,
    Index,
    encode_gif,
    frame_ticks,
    palette_rgb,
    render_frame,
    render_preview,
    write_gif,
)
from guardsim.render.layout import PLAY_PAD
from guardsim.render.palette import guard_index, trail_index
from guardsim.trace import Trace
from guardsim.world import World
from tests.common import SPLIT_ROOMS, scene_from, write_level

SQUARE = Path("levels/square.json")


def play_trace(tmp_path: Path, level: Path, *options: str) -> Trace:
    """The trace of ``guardsim play LEVEL OPTIONS``."""
    out = tmp_path / "trace.json"
    result = CliRunner().invoke(main, ["play", str(level), "--trace", str(out), *options])
    assert result.exit_code == 0, result.output
    return Trace.from_data(json.loads(out.read_text()))


def decode(data: bytes | Path) -> np.ndarray:
    """Every frame of a GIF as RGB."""
    return iio.imread(data, index=None, extension=".gif")


def colour(name: str) -> tuple[int, int, int]:
    return COLOURS[name]


def play_pixel(drawer: FrameDrawer, col, row):
    """``(y, x)`` in the whole frame of a point given in cells."""
    layout = drawer.layout
    return (
        (layout.top + PLAY_PAD + np.asarray(row) * layout.scale).astype(int),
        (layout.left + PLAY_PAD + np.asarray(col) * layout.scale).astype(int),
    )


def hand_trace(level_data: dict, path: list[tuple[int, int]], headings: list[int], **changes) -> tuple:
    """A level and a trace written by hand: every traversable cell a goal cell, none seen."""
    level = parse_level(level_data)
    scene = scene_from(level_data)
    traversable = scene.grid.traversable
    rows, cols = scene.grid.shape
    fields = dict(
        level=level.name,
        planner="by-hand",
        seed=0,
        cell_size=level.cell_size,
        origin=scene.grid.origin,
        shape=(rows, cols),
        path=tuple(path),
        headings=tuple(headings),
        unseen_percent=tuple(100.0 for _ in path),
        outcome="step_limit",
        reachable=int(traversable.sum()),
        unreachable=0,
        first_seen=np.full((rows, cols), -1),
        goal=traversable.copy(),
        traversable=traversable.copy(),
    )
    fields.update(changes)
    return level, Trace(**fields)


@pytest.fixture(scope="module")
def square(tmp_path_factory) -> tuple:
    level = load_level(SQUARE)
    return level, play_trace(tmp_path_factory.mktemp("square"), SQUARE)


@pytest.mark.parametrize(
    ("steps", "options", "expected"),
    [
        (10, GifOptions(stride=1), list(range(11))),
        (10, GifOptions(stride=4), [0, 4, 8, 10]),
        (8, GifOptions(stride=4), [0, 4, 8]),
        (999, GifOptions(max_frames=100), [*range(0, 999, 11), 999]),
        (5, GifOptions(max_frames=1), [5]),
        (0, GifOptions(), [0]),
    ],
    ids=["every-tick", "stride-keeps-last", "stride-lands-on-last", "auto-stride", "one-frame", "no-steps"],
)
def test_frame_ticks(steps: int, options: GifOptions, expected: list[int]) -> None:
    """Frames every stride ticks from 0, the last tick always included, the count under max_frames."""
    ticks = frame_ticks(steps, options)
    assert ticks == expected
    assert len(ticks) <= options.max_frames


def test_explicit_stride_over_frame_limit_is_refused() -> None:
    """A stride that would need more frames than allowed raises LimitError naming the options."""
    with pytest.raises(LimitError, match="--stride or --max-frames"):
        frame_ticks(1000, GifOptions(stride=1, max_frames=50))


def test_gif_decodes_with_expected_frames_and_size(square) -> None:
    """One decoded frame per tick drawn; the play area is 8 px per cell with bars above and below."""
    level, trace = square
    options = GifOptions(max_frames=50)
    data = encode_gif(level, trace, options)
    frames = decode(data)
    layout = FrameDrawer(level, trace).layout
    assert frames.shape[0] == len(frame_ticks(trace.steps, options))
    assert frames.shape[1:3] == (layout.height, layout.width)
    assert layout.scale == 8 and layout.play == (480 + 2 * PLAY_PAD, 480 + 2 * PLAY_PAD)
    assert layout.top > 20 and layout.legend > 10


def test_gif_holds_the_last_frame_and_loops(square) -> None:
    """Every frame lasts frame_ms except the last, held for hold_ms; the GIF loops forever."""
    level, trace = square
    data = encode_gif(level, trace, GifOptions(max_frames=20, frame_ms=50, hold_ms=1500))
    image = Image.open(io.BytesIO(data))
    durations = []
    for index in range(image.n_frames):
        image.seek(index)
        durations.append(image.info["duration"])
    assert durations[:-1] == [50] * (len(durations) - 1)
    assert durations[-1] == 1500
    assert image.info.get("loop") == 0


def test_every_frame_uses_only_the_fixed_palette(square) -> None:
    """Decoded pixels are palette colours only: nothing was quantised per frame."""
    level, trace = square
    frames = decode(encode_gif(level, trace, GifOptions(max_frames=12)))
    allowed = {tuple(c) for c in PALETTE}
    used = {tuple(int(v) for v in c) for c in np.unique(frames.reshape(-1, 3), axis=0)}
    assert used <= allowed


def test_unseen_and_seen_cells_match_the_trace(square) -> None:
    """At each drawn tick, a goal cell's inner corner pixel is unseen-dark exactly when the trace says the
    cell is still unseen; only overlays (trail, cone outline, guard, start marker) may cover it."""
    level, trace = square
    drawer = FrameDrawer(level, trace)
    unseen_entries = {Index.UNSEEN, Index.CONE_BASE + Index.UNSEEN}
    for tick in (0, trace.steps // 3, trace.steps):
        frame = drawer.frame(tick)
        unseen = trace.goal & ((trace.first_seen < 0) | (trace.first_seen > tick))
        rows, cols = np.nonzero(trace.goal)
        ys, xs = play_pixel(drawer, cols, rows)
        pixels = frame[ys + 1, xs + 1]
        overlay = (pixels >= Index.GUARD_BASE) | (pixels == Index.OUTLINE)
        assert not np.isin(pixels[~unseen[rows, cols]], list(unseen_entries)).any()
        dark = np.isin(pixels[unseen[rows, cols]], list(unseen_entries)) | overlay[unseen[rows, cols]]
        assert dark.all(), tick
        assert overlay.mean() < 0.05
    y, x = play_pixel(drawer, 25, 25)
    assert drawer.frame(0)[y, x] == Index.WALL  # inside the pillar


def test_walls_seen_floor_and_unseen_are_clearly_different() -> None:
    """Wall, seen floor and unseen are far apart in colour (the old wall and floor differed by 50)."""
    names = ("wall", "free", "unseen", "unreachable")
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            assert sum(abs(p - q) for p, q in zip(colour(a), colour(b))) > 90, (a, b)


def test_guard_is_drawn_at_its_cell_at_a_readable_size(square) -> None:
    """The guard's disc, in its colour, covers its cell centre and is at least 7 px in radius."""
    level, trace = square
    drawer = FrameDrawer(level, trace)
    frame = drawer.frame(10)
    col, row = trace.path[10]
    y, x = play_pixel(drawer, col + 0.5, row + 0.5)
    heading = trace.headings[10]
    back = (-1, 0) if heading == 0 else (0, -1) if heading == 1 else (1, 0) if heading == 2 else (0, 1)
    for distance in (1, 3, 6):
        assert frame[y + distance * back[1], x + distance * back[0]] == guard_index(0), distance


def test_caption_is_in_a_bar_outside_the_play_area(square) -> None:
    """Caption text is drawn only in the bars; the play area holds no text colours."""
    level, trace = square
    drawer = FrameDrawer(level, trace)
    frame = drawer.frame(0)
    layout = drawer.layout
    text = (frame >= Index.TEXT_BASE + 2) & (frame < Index.GUARD_BASE)
    play = text[layout.top : layout.top + layout.play[1]]
    assert not play.any()
    assert text[: layout.top].sum() > 300
    first, second = drawer.caption(0)
    assert f"tick 0 / {trace.steps}" in first and trace.planner in first
    assert second.startswith(f"{trace.unseen_percent[0]:.1f}% of {trace.reachable} reachable cells unseen")


def test_unreachable_cells_are_hatched_and_counted_in_the_caption() -> None:
    """The sealed room is hatched purple, never unseen-dark, and the caption counts it separately."""
    scene = scene_from(SPLIT_ROOMS)
    start = scene.grid.cell_of((0.5, 0.5))
    goal = scene.grid.component(*start)
    level, trace = hand_trace(
        SPLIT_ROOMS, [start], [0], goal=goal, reachable=int(goal.sum()), unreachable=int((~goal).sum())
    )
    drawer = FrameDrawer(level, trace)
    frame = drawer.frame(0)
    y, x = play_pixel(drawer, 5, 2)
    block = frame[y + 1 : y + drawer.layout.scale - 1, x + 1 : x + drawer.layout.scale - 1]
    assert set(np.unique(block)) <= {Index.UNREACHABLE, Index.HATCH}
    assert (block == Index.HATCH).any()
    assert f"{trace.unreachable} unreachable cells" in drawer.caption(0)[1]


#: A room with a wall in front of the guard: what lies straight behind it is in range but hidden.
SHADOW_ROOM = {
    "name": "shadow room",
    "outer": [[0, 0], [24, 0], [24, 12], [0, 12]],
    "holes": [[[8, 4], [9, 4], [9, 8], [8, 8]]],
    "guard": {"view_range": 14, "fov_degrees": 120, "radius": 0.3},
}


def cone_pixels(drawer: FrameDrawer, frame: np.ndarray) -> np.ndarray:
    """``(y, x)`` in play-area pixels of every pixel tinted by a cone."""
    layout = drawer.layout
    play = frame[layout.top : layout.top + layout.play[1], layout.left : layout.left + layout.play[0]]
    tinted = (play >= Index.CONE_BASE) & (play <= Index.CONE_BASE + Index.HATCH)
    return np.argwhere(tinted)


def test_cone_shows_no_wall_and_nothing_behind_a_wall() -> None:
    """Decoded cone pixels are never wall and never hidden from the eye (a pixel's centre may sit within
    a pixel and a half of the edge of what is visible: that is the polygon's rasterisation)."""
    level, trace = hand_trace(SHADOW_ROOM, [(4, 6)], [0])
    drawer = FrameDrawer(level, trace)
    frame = decode(encode_gif(level, trace))[0]
    indices = drawer.frame(0)
    assert (palette_rgb()[indices] == frame).all()
    world = World(level)
    eye = (4.5, 6.5)
    unit = drawer.pixels_per_unit
    pixels = cone_pixels(drawer, indices)
    assert len(pixels) > 2000
    hidden = 0
    for y, x in pixels:
        point = ((x + 0.5 - PLAY_PAD) / unit, (y + 0.5 - PLAY_PAD) / unit)
        if world.line_of_sight(eye, point):
            continue
        near = [
            world.line_of_sight(eye, (point[0] + dx / unit, point[1] + dy / unit))
            for dx in (-1.5, 0, 1.5)
            for dy in (-1.5, 0, 1.5)
        ]
        assert any(near), (x, y)
        hidden += 1
    assert hidden < 0.02 * len(pixels)
    # The shadow straight behind the wall (x 9..18, y 5.5..7.5 in world units) holds no cone pixel.
    xs, ys = (pixels[:, 1] + 0.5 - PLAY_PAD) / unit, (pixels[:, 0] + 0.5 - PLAY_PAD) / unit
    assert not ((xs > 9.5) & (xs < 18) & (ys > 5.8) & (ys < 7.2)).any()
    # ... while the open floor above the wall, within range and angle, is tinted.
    assert ((xs > 12) & (xs < 14) & (ys > 1) & (ys < 2)).any()


def full_circle_radius(tmp_path: Path, *options: str) -> tuple[float, list[float]]:
    """Play square.json with a 360-degree, 3-unit guard; the cone's reach in the first decoded frame in
    cells, and the reach in each quadrant."""
    gif = tmp_path / "out.gif"
    result = CliRunner().invoke(
        main,
        ["play", str(SQUARE), "--fov", "360", "--view-range", "3", "--gif", str(gif), "--max-frames", "3", *options],
    )
    assert result.exit_code == 0, result.output
    trace = play_trace(tmp_path, SQUARE, "--fov", "360", "--view-range", "3", *options)
    assert trace.fov_degrees == 360 and trace.view_range == 3
    level = load_level(SQUARE)
    drawer = FrameDrawer(level, trace)
    frame = decode(gif)[0]
    index = drawer.frame(0)
    assert (palette_rgb()[index] == frame).all()
    pixels = cone_pixels(drawer, index)
    col, row = trace.path[0]
    centre = (PLAY_PAD + (col + 0.5) * 8, PLAY_PAD + (row + 0.5) * 8)
    dx, dy = pixels[:, 1] + 0.5 - centre[0], pixels[:, 0] + 0.5 - centre[1]
    distance = np.hypot(dx, dy) / 8
    angle = np.arctan2(dy, dx)
    quadrants = [
        float(distance[(angle >= a) & (angle < a + math.pi / 2)].max(initial=0))
        for a in (-math.pi, -math.pi / 2, 0, math.pi / 2)
    ]
    return float(distance.max()), quadrants


def test_fov_360_view_range_3_draws_a_3_unit_circle(tmp_path: Path) -> None:
    """`play square.json --fov 360 --view-range 3 --gif` draws the simulated 3-unit circle (not the level's
    8-unit, 90-degree cone): it reaches 3 units where the floor is open, and from the open middle of the
    room it reaches 3 units in every quadrant."""
    reach, quadrants = full_circle_radius(tmp_path)
    assert 2.8 < reach < 3.1
    reach, quadrants = full_circle_radius(tmp_path, "--start", "10.5,10.5")
    assert all(2.8 < q < 3.1 for q in quadrants), quadrants


def test_cone_falls_back_to_the_level_guard_for_old_traces(square) -> None:
    """A trace without recorded vision (written before it was recorded) is drawn with the level's guard."""
    level, trace = square
    fields = {name: getattr(trace, name) for name in trace.__dataclass_fields__}
    old = Trace(**{**fields, "view_range": None, "fov_degrees": None})
    drawer = FrameDrawer(level, old)
    assert (drawer.vision.view_range, drawer.vision.fov_degrees) == (level.guard.view_range, level.guard.fov_degrees)
    assert (drawer.frame(5) == FrameDrawer(level, trace).frame(5)).all() == (
        (trace.view_range, trace.fov_degrees) == (level.guard.view_range, level.guard.fov_degrees)
    )


def test_trail_is_strong_where_recent_and_faint_where_old(square) -> None:
    """At the last tick the newest step of the trail is drawn at full strength, the first step faintest."""
    level, trace = square
    drawer = FrameDrawer(level, trace)
    frame = drawer.frame(trace.steps)
    levels = {trail_index(0, k): k for k in range(5)}
    used = {levels[v] for v in np.unique(frame) if v in levels}
    assert 0 in used and 4 in used and len(used) >= 4
    assert trace.steps > 8 * drawer.trail_block


def test_start_marker_is_drawn(square) -> None:
    """A square outline in the guard's colour marks the start, also late in the episode."""
    level, trace = square
    drawer = FrameDrawer(level, trace)
    frame = drawer.frame(trace.steps)
    col, row = trace.path[0]
    y, x = play_pixel(drawer, col + 0.5, row + 0.5)
    ring = frame[y - 9 : y + 10, x - 9 : x + 10]
    assert (ring == guard_index(0)).sum() > 30


def test_gifs_are_byte_identical_for_the_same_inputs(square, tmp_path: Path) -> None:
    """Two encodings of one episode, and the file write_gif streams, are the same bytes."""
    level, trace = square
    options = GifOptions(max_frames=40)
    first = encode_gif(level, trace, options)
    assert first == encode_gif(level, trace, options)
    assert write_gif(tmp_path / "a.gif", level, trace, options) == len(frame_ticks(trace.steps, options))
    assert (tmp_path / "a.gif").read_bytes() == first


def test_frames_drawn_out_of_order_equal_frames_drawn_in_order(square) -> None:
    """Asking for an earlier tick resets the incremental state: the frame is the one drawn fresh."""
    level, trace = square
    drawer = FrameDrawer(level, trace)
    drawer.frame(trace.steps)
    again = drawer.frame(7)
    assert (again == FrameDrawer(level, trace).frame(7)).all()
    assert (palette_rgb()[again] == render_frame(level, trace, 7)).all()


# -- edge cases: each gives a valid GIF, checked by decoding it -----------------------------------------


def test_covered_at_step_zero_renders_one_frame(tmp_path: Path) -> None:
    """A 360-degree guard in a 3 x 3 room sees everything at step 0: a one-frame GIF, exit 0 (it used to
    crash with a TypeError in Pillow's writer)."""
    room = write_level(
        tmp_path,
        {
            "name": "closet",
            "outer": [[0, 0], [3, 0], [3, 3], [0, 3]],
            "guard": {"fov_degrees": 360, "start": [1.5, 1.5]},
        },
    )
    gif = tmp_path / "closet.gif"
    result = CliRunner().invoke(main, ["play", str(room), "--gif", str(gif)])
    assert result.exit_code == 0, result.output
    assert "after 0 steps" in result.output
    frames = decode(gif)
    assert frames.shape[0] == 1
    assert frames.shape[2] >= 400


def test_max_frames_one_draws_the_last_tick(tmp_path: Path, square) -> None:
    """--max-frames 1 gives one frame, the final coverage."""
    gif = tmp_path / "one.gif"
    result = CliRunner().invoke(main, ["play", str(SQUARE), "--gif", str(gif), "--max-frames", "1"])
    assert result.exit_code == 0, result.output
    frames = decode(gif)
    level, trace = square
    assert frames.shape[0] == 1
    assert (frames[0] == render_frame(level, trace, trace.steps)).all()


def test_single_tick_trace_renders(tmp_path: Path) -> None:
    """A trace of one tick (the start only) encodes to a single valid frame."""
    level, trace = hand_trace(SHADOW_ROOM, [(4, 6)], [0])
    frames = decode(encode_gif(level, trace))
    assert frames.shape[0] == 1


def test_team_sharing_a_cell_shows_every_guard_in_its_colour() -> None:
    """Two guards on one cell are both drawn, side by side, each in its own colour, with their trails."""
    path = [(3, 3), (4, 3), (5, 3), (5, 4)]
    other = [(5, 5), (5, 4), (5, 3), (5, 4)]
    level, trace = hand_trace(
        SHADOW_ROOM,
        path,
        [0, 0, 0, 1],
        guard_paths=(tuple(path), tuple(other)),
        guard_headings=((0, 0, 0, 1), (3, 3, 3, 1)),
    )
    drawer = FrameDrawer(level, trace)
    frame = drawer.frame(3)
    assert (frame == guard_index(0)).sum() > 50
    assert (frame == guard_index(1)).sum() > 50
    assert guard_index(0) != guard_index(1)
    frames = decode(encode_gif(level, trace, GifOptions(stride=1)))
    assert frames.shape[0] == 4
    assert "2 guards" in drawer.caption(0)[0]


def test_level_with_unreachable_room_renders_through_the_cli(tmp_path: Path) -> None:
    """play --gif on a level with a sealed room: a valid GIF whose last frame still shows the room."""
    level_path = write_level(tmp_path, SPLIT_ROOMS)
    gif = tmp_path / "split.gif"
    result = CliRunner().invoke(main, ["play", str(level_path), "--gif", str(gif)])
    assert result.exit_code == 0, result.output
    frames = decode(gif)
    assert frames.shape[0] >= 1
    last = frames[-1].reshape(-1, 3)
    assert (last == colour("unreachable")).all(axis=1).sum() > 1000


def test_preview_marks_reachable_and_unreachable() -> None:
    """The preview tints reachable cells green and the sealed room purple, with rulers around."""
    scene = scene_from(SPLIT_ROOMS)
    grid = scene.grid
    image = render_preview(scene.level, grid.traversable, grid.component(0, 0), grid.origin, size=600)
    margin, scale = 36, 100
    assert tuple(int(v) for v in image[margin + 2, margin + 2]) == COLOURS["reachable"]
    room = {
        tuple(int(v) for v in pixel) for pixel in image[margin + 2, margin + 5 * scale + 2 : margin + 5 * scale + 9]
    }
    assert room == {COLOURS["unreachable"], COLOURS["hatch"]}
    assert image.shape == (3 * scale + 2 * margin, 6 * scale + 2 * margin, 3)


def test_every_decoded_frame_is_the_frame_drawn(square) -> None:
    """Frames after the first carry only their changed rectangle, unchanged pixels transparent; decoded,
    each is exactly the whole frame drawn for its tick."""
    level, trace = square
    options = GifOptions(max_frames=30)
    frames = decode(encode_gif(level, trace, options))
    drawer = FrameDrawer(level, trace)
    for frame, tick in zip(frames, frame_ticks(trace.steps, options), strict=True):
        assert (frame == palette_rgb()[drawer.frame(tick)]).all(), tick


def test_continuous_motion_draws_the_recorded_pose_and_game_time() -> None:
    """Under continuous motion the guard and its cone are drawn at the recorded pose (between cell
    centres, at any angle) and the caption gives the game time from the tick rate."""
    level, trace = hand_trace(SHADOW_ROOM, [(4, 6), (4, 6)], [0, 0])
    fields = {name: getattr(trace, name) for name in trace.__dataclass_fields__}
    poses = np.asarray([[0.0, 4.5, 6.5, 0.0], [0.05, 4.9, 6.2, 45.0]])
    moving = Trace(**{**fields, "motion": "continuous", "tick_hz": 20.0, "poses": poses})
    drawer = FrameDrawer(level, moving)
    assert drawer.pose(0, 1) == ((4.9, 6.2), 45.0)
    assert "(0.1 s)" in drawer.caption(1)[0] or "(0.0 s)" in drawer.caption(1)[0]
    frame = drawer.frame(1)
    y, x = (int(v) for v in reversed(drawer.to_pixels((4.9, 6.2))))
    assert frame[drawer.layout.top + y, drawer.layout.left + x - 2] == guard_index(0)
    ring = drawer.cone_polygon(0, 1)
    assert ring[0] == drawer.to_pixels((4.9, 6.2))


# -- continuous motion: the trail through the poses, frames in game time ------------------------------

CONTINUOUS_SQUARE = Path("renders/square/seed0-continuous.trace.json")


def trail_mask(drawer: FrameDrawer, frame: np.ndarray) -> np.ndarray:
    """``bool`` over the play area: pixels in guard 0's faded trail colours, from RGB. The newest level is
    left out: it is the guard's own colour, also used by its disc, start marker and cone outline."""
    layout = drawer.layout
    play = frame[layout.top : layout.top + layout.play[1], layout.left : layout.left + layout.play[0]]
    colours = palette_rgb()[[trail_index(0, level) for level in range(1, 5)]]
    return (play[:, :, None, :] == colours[None, None]).all(axis=3).any(axis=2)


def pixel_centres(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Play-area coordinates of the centres of the pixels set in ``mask``."""
    rows, cols = np.nonzero(mask)
    return cols + 0.5, rows + 0.5


def colour_of(index: int) -> tuple[int, ...]:
    return tuple(int(v) for v in palette_rgb()[index])


def continuous_hand_trace(poses: np.ndarray, tick_hz: float = 10.0) -> tuple:
    """A continuous trace by hand on the shadow room: ``poses`` and the cells they lie in."""
    cells = [(int(x), int(y)) for _, x, y, _ in poses]
    level, trace = hand_trace(SHADOW_ROOM, cells, [0] * len(cells))
    fields = {name: getattr(trace, name) for name in trace.__dataclass_fields__}
    return level, Trace(**{**fields, "motion": "continuous", "tick_hz": tick_hz, "poses": poses})


def test_continuous_trail_is_the_diagonal_walked_not_the_cell_staircase() -> None:
    """A guard walking a string-pulled diagonal leaves its trail along the diagonal: every trail pixel of the
    decoded GIF lies within half the trail's width (and a pixel of rasterising) of the segment, and most lie
    off the bands between cell centres that a staircase through the same cells would draw. The guard then
    stands 200 ticks, so the whole trail has faded to colours of its own."""
    walk, steps = 40, 240
    t = np.minimum(np.arange(steps + 1) / walk, 1.0)
    start, end = np.array([1.5, 1.5]), np.array([6.5, 10.5])
    xy = start + t[:, None] * (end - start)
    heading = math.degrees(math.atan2(*(end - start)[::-1]))
    poses = np.column_stack([np.arange(steps + 1) / 10, xy, np.full(steps + 1, heading)])
    level, trace = continuous_hand_trace(poses)
    drawer = FrameDrawer(level, trace)
    frame = decode(encode_gif(level, trace, GifOptions(stride=walk)))[-1]
    xs, ys = pixel_centres(trail_mask(drawer, frame))
    assert xs.size > 100
    a, b = np.array(drawer.to_pixels(tuple(start))), np.array(drawer.to_pixels(tuple(end)))
    along = np.clip(((xs - a[0]) * (b - a)[0] + (ys - a[1]) * (b - a)[1]) / ((b - a) ** 2).sum(), 0, 1)
    distance = np.hypot(xs - (a[0] + along * (b - a)[0]), ys - (a[1] + along * (b - a)[1]))
    assert distance.max() <= drawer.trail_width / 2 + 1.5
    scale = drawer.layout.scale
    # Distance to the nearest line through cell centres (rows or columns): a staircase's bands stay
    # within half the trail's width of them, so none of its pixels would be this far off.
    off_row = np.abs((ys - PLAY_PAD) / scale % 1 - 0.5) * scale
    off_col = np.abs((xs - PLAY_PAD) / scale % 1 - 0.5) * scale
    assert (np.minimum(off_row, off_col) > drawer.trail_width / 2 + 1).mean() > 0.2


def test_continuous_trail_follows_the_recorded_poses_frame_by_frame() -> None:
    """The square's continuous reference episode, decoded frame by frame: the trail is the polyline through
    the poses up to the frame's tick, never ahead of the guard, and it covers that polyline (except where
    the guard's disc, the start marker or the cone outline is drawn over it)."""
    from shapely import LineString, Point, contains_xy

    level = load_level(SQUARE)
    trace = Trace.from_data(json.loads(CONTINUOUS_SQUARE.read_text(encoding="utf-8")))
    options = GifOptions(max_frames=12)
    frames = decode(encode_gif(level, trace, options))
    drawer = FrameDrawer(level, trace)
    points = np.column_stack(drawer.to_pixels((trace.poses[:, 1], trace.poses[:, 2])))
    half = drawer.trail_width / 2
    checked = 0
    for frame, tick in zip(frames, frame_ticks(trace.steps, options), strict=True):
        if tick < 2:
            continue
        walked = LineString(points[: tick + 1])
        mask = trail_mask(drawer, frame)
        xs, ys = pixel_centres(mask)
        assert contains_xy(walked.buffer(half + 1.5), xs, ys).all(), tick
        # Every pose point walked is under trail colour, or under a marker drawn on top of it.
        layout = drawer.layout
        play = frame[layout.top : layout.top + layout.play[1], layout.left : layout.left + layout.play[0]]
        guard_colour = palette_rgb()[guard_index(0)]
        marked = mask | (play == guard_colour).all(axis=2)
        eye = Point(points[tick]).buffer(2.5 * max(7, 0.45 * layout.scale))
        for x, y in points[: tick + 1 : 7]:
            if not eye.contains(Point(x, y)):
                assert marked[int(y), int(x)] or marked[int(y - 0.5), int(x - 0.5)], (tick, x, y)
        checked += 1
    assert checked >= 10


def test_speed_up_shows_frames_in_game_time(tmp_path: Path) -> None:
    """--speed-up 4: each frame is shown for the game time to the next frame over 4 (hundredths on the
    running clock, never under 20 ms), the caption says 4x, and the frames are the poses' frames."""
    trace_path = tmp_path / "walk.json"
    gif = tmp_path / "walk.gif"
    result = CliRunner().invoke(
        main,
        ["play", str(SQUARE), "--motion", "continuous", "--tick-hz", "10", "--max-seconds", "30",
         "--speed-up", "4", "--gif", str(gif), "--trace", str(trace_path)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    trace = Trace.from_data(json.loads(trace_path.read_text()))
    options = GifOptions(speed_up=4.0)
    ticks = frame_ticks(trace.steps, options, trace.tick_hz)
    assert ticks[1] == 3  # 60 ms of GIF at 4x is 0.24 s of game time: 3 ticks at 10 Hz
    with Image.open(gif) as image:
        durations = []
        for number in range(image.n_frames):
            image.seek(number)
            durations.append(image.info["duration"])
    assert len(durations) == len(ticks)
    assert min(durations) >= 20 and all(d % 10 == 0 for d in durations)
    clock = np.cumsum([0, *durations[:-1]])
    game = np.asarray(ticks) / trace.tick_hz / 4 * 1000
    assert np.abs(clock - game).max() <= 5
    drawer = FrameDrawer(load_level(SQUARE), trace, speed_up=4.0)
    assert "4x" in drawer.caption(ticks[1])[0]
    frames = decode(gif)
    layout = drawer.layout
    for index in (1, len(ticks) // 2, -1):
        # The guard's disc at the pose of the frame's tick (the trace's poses are rounded to 6 decimals,
        # so the frame drawn from it may differ from the GIF's by a pixel of rasterising here and there).
        (x, y), heading = drawer.pose(0, ticks[index])
        px, py = drawer.to_pixels((x, y))
        # Behind the centre, away from the white eye and the nose.
        px, py = px - 4 * math.cos(math.radians(heading)), py - 4 * math.sin(math.radians(heading))
        assert tuple(frames[index][layout.top + int(py), layout.left + int(px)]) == colour_of(guard_index(0))


def test_speed_up_needs_continuous_motion(tmp_path: Path) -> None:
    """Grid ticks have no game time: --speed-up with --motion grid is a usage error (exit 2)."""
    result = CliRunner().invoke(main, ["play", str(SQUARE), "--gif", str(tmp_path / "g.gif"), "--speed-up", "2"])
    assert result.exit_code == 2
    assert "--speed-up" in result.output and "--motion continuous" in result.output
