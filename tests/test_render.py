"""The renderer: GIFs decoded back, frame counts and sizes, colours of unseen and seen cells, previews."""

from __future__ import annotations

import io
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from PIL import Image

from guardsim.errors import LimitError
from guardsim.level import load_level
from guardsim.planners import RippleFront
from guardsim.render import COLOURS, GifOptions, encode_gif, frame_ticks, render_frame, render_preview
from guardsim.simulation import Scene, choose_start, run_episode
from tests.common import SPLIT_ROOMS, scene_from


def episode(scene: Scene):
    """The RippleFront episode from the level's start."""
    level = scene.level
    cell, heading = choose_start(scene, rng=np.random.default_rng(0), point=level.guard.start, heading="right")
    return run_episode(scene, RippleFront(), cell, heading)


@pytest.fixture(scope="module")
def square() -> tuple[Scene, object]:
    scene = Scene.from_level(load_level(Path("levels/square.json")))
    return scene, episode(scene)


def pixel_at_cell(frame: np.ndarray, col: int, row: int, scale: int) -> tuple[int, ...]:
    """The colour at a cell's top-left inner pixel (away from the centre, where the guard and text go)."""
    return tuple(int(v) for v in frame[row * scale + 1, col * scale + 1])


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
    """The GIF decodes to one frame per tick drawn, 480 x 480 pixels for a 60 x 60 grid."""
    scene, trace = square
    options = GifOptions(max_frames=50)
    data = encode_gif(scene.level, trace, options)
    frames = iio.imread(data, index=None, extension=".gif")
    assert frames.shape[0] == len(frame_ticks(trace.steps, options))
    assert frames.shape[1:3] == (480, 480)
    assert len(data) < 3_000_000


def test_gif_holds_the_last_frame_and_loops(square) -> None:
    """Every frame lasts frame_ms except the last, held for hold_ms; the GIF loops forever."""
    scene, trace = square
    data = encode_gif(scene.level, trace, GifOptions(max_frames=20, frame_ms=50, hold_ms=1500))
    image = Image.open(io.BytesIO(data))
    durations = []
    for index in range(image.n_frames):
        image.seek(index)
        durations.append(image.info["duration"])
    assert durations[:-1] == [50] * (len(durations) - 1)
    assert durations[-1] == 1500
    assert image.info.get("loop") == 0


def test_first_frame_dark_where_unseen_last_frame_clear(square) -> None:
    """In the first decoded frame the far corner is unseen-dark; in the last it is clear; walls are light."""
    scene, trace = square
    frames = iio.imread(encode_gif(scene.level, trace, GifOptions(max_frames=10)), index=None, extension=".gif")
    scale = 8
    assert pixel_at_cell(frames[0], 55, 55, scale) == COLOURS["unseen"]
    assert pixel_at_cell(frames[-1], 55, 55, scale) == COLOURS["free"]
    assert pixel_at_cell(frames[0], 25, 25, scale) == COLOURS["wall"]  # inside the pillar
    assert pixel_at_cell(frames[-1], 25, 25, scale) == COLOURS["wall"]


def test_guard_is_drawn_at_its_cell(square) -> None:
    """The guard's red disc is at the centre of its cell in the frame."""
    scene, trace = square
    frame = render_frame(scene.level, trace, 0)
    col, row = trace.path[0]
    assert tuple(int(v) for v in frame[row * 8 + 4, col * 8 + 4]) == COLOURS["guard"]


def test_unreachable_cells_are_drawn_distinctly() -> None:
    """Cells the guard can never reach are purple, not dark, in every frame."""
    scene = scene_from(SPLIT_ROOMS)
    trace = episode(scene)
    frame = render_frame(scene.level, trace, 0)
    scale = 480 // 6
    assert pixel_at_cell(frame, 5, 2, scale) == COLOURS["unreachable"]


def test_percentage_text_is_in_the_middle(square) -> None:
    """The unseen percentage is written in white with a dark outline around the frame's centre."""
    scene, trace = square
    frame = render_frame(scene.level, trace, 0)
    middle = frame[220:260, 100:380]
    white = np.all(middle == COLOURS["text"], axis=-1)
    assert white.sum() > 200
    corner = frame[460:480, 0:60]
    assert not np.all(corner == COLOURS["text"], axis=-1).any()


def test_preview_marks_reachable_and_unreachable() -> None:
    """The preview tints reachable cells green and the sealed room purple, with rulers around."""
    scene = scene_from(SPLIT_ROOMS)
    grid = scene.grid
    image = render_preview(scene.level, grid.traversable, grid.component(0, 0), grid.origin, size=600)
    margin, scale = 36, 100
    assert tuple(int(v) for v in image[margin + 2, margin + 2]) == COLOURS["reachable"]
    assert tuple(int(v) for v in image[margin + 2, margin + 5 * scale + 2]) == COLOURS["unreachable"]
    assert image.shape == (3 * scale + 2 * margin, 6 * scale + 2 * margin, 3)
