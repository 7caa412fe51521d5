"""Pictures that read on real maps (issue 25, item 4), judged by decoding what is written: one colour per
meaning in the GIF, the preview and the ``rgb_array``; frames big enough to read a cell; captions wrapped,
not cut; a legend on ``guardsim render``; no line where two wall pieces touch."""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.level import parse_level
from guardsim.render import COLOURS, GUARD_COLOURS, PALETTE, FrameDrawer, Index
from guardsim.render.layout import PLAY_PAD, wrap_caption
from guardsim.render.palette import HEAT_RAMP
from guardsim.render.preview import with_legend
from guardsim.render.text import Typesetter
from guardsim.render.timeline import MAX_FRAME_SIDE, MIN_CELL_PIXELS, cell_pixels
from guardsim.simulation import Simulation
from tests.common import SPLIT_ROOMS, scene_from, write_level

#: A 6 x 4 room where the guard (radius 0.6) cannot stand in the ring of cells along the walls.
TIGHT_ROOM: dict[str, Any] = {
    "name": "tight room",
    "outer": [[0, 0], [6, 0], [6, 4], [0, 4]],
    "guard": {"radius": 0.6, "start": [2.5, 1.5], "heading": "right"},
}

#: One wall cut in two along x = 6 (as an importer cuts a wall enclosing a pocket): two holes touching
#: along an edge, so the line x = 6 between y = 2 and y = 6 has wall on both sides.
CUT_WALL: dict[str, Any] = {
    "name": "cut wall",
    "outer": [[0, 0], [12, 0], [12, 8], [0, 8]],
    "holes": [[[3, 2], [6, 2], [6, 6], [3, 6]], [[6, 2], [9, 2], [9, 6], [6, 6]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}


def rgb(frame: np.ndarray, y: int, x: int) -> tuple[int, int, int]:
    r, g, b = (int(v) for v in frame[y, x, :3])
    return r, g, b


def drawer_for(level_data: dict[str, Any], **options: Any) -> FrameDrawer:
    simulation = Simulation(scene_from(level_data), "ripplefront", max_steps=30)
    simulation.reset(seed=0)
    return FrameDrawer(parse_level(level_data), simulation.run(), **options)


def cell_centre(drawer: FrameDrawer, col: float, row: float) -> tuple[int, int]:
    """``(y, x)`` in the whole frame of the centre of cell ``(col, row)``."""
    layout = drawer.layout
    return (
        int(layout.top + PLAY_PAD + (row + 0.5) * layout.scale),
        int(layout.left + PLAY_PAD + (col + 0.5) * layout.scale),
    )


def test_each_meaning_has_its_own_colour() -> None:
    meanings = ["wall", "unseen", "free", "tight", "unreachable", "cone", "outline", "reachable"]
    colours = [COLOURS[name] for name in meanings] + [GUARD_COLOURS[0]]
    assert len(set(colours)) == len(colours)
    assert PALETTE[Index.TIGHT] == COLOURS["tight"]


def test_the_cone_stays_visible_over_the_heat_ramp() -> None:
    """No heat-map colour is near the cone's yellow, and the cone's tint over every stop moves it visibly."""
    cone = np.asarray(COLOURS["cone"], dtype=float)
    for _, stop in HEAT_RAMP:
        heat = np.asarray(stop, dtype=float)
        assert np.abs(heat - cone).sum() > 150
        tinted = 0.42 * cone + 0.58 * heat
        assert np.abs(tinted - heat).sum() > 100


def test_tight_cells_have_their_own_colour_in_every_frame(tmp_path: Path) -> None:
    """The ring of cells too tight to stand in is the palette's tight colour, not the seen floor's, at the
    first tick and at the last; the legend names it."""
    gif = tmp_path / "tight.gif"
    result = CliRunner().invoke(main, ["play", str(write_level(tmp_path, TIGHT_ROOM)), "--gif", str(gif)])
    assert result.exit_code == 0, result.output
    frames = iio.imread(gif, index=None, extension=".gif")
    drawer = drawer_for(TIGHT_ROOM)
    assert drawer.tight.astype(int).tolist() == [[1] * 6, [1, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 1], [1] * 6]
    scale = drawer.layout.scale
    tight = {COLOURS["tight"], PALETTE[Index.TIGHT_CONE]}
    for frame in (frames[0], frames[-1]):
        for col, row in [(0, 0), (5, 3), (0, 2)]:
            y, x = cell_centre(drawer, col, row)
            cell = frame[y - scale // 4 : y + scale // 4, x - scale // 4 : x + scale // 4, :3].reshape(-1, 3)
            # The cone's outline or the start marker may cross a cell; most of it is the tight colour.
            assert sum(tuple(int(v) for v in pixel) in tight for pixel in cell) > 0.8 * len(cell)
        legend = frame[drawer.layout.height - drawer.layout.legend :].reshape(-1, frame.shape[2])[:, :3]
        assert (legend == COLOURS["tight"]).all(axis=1).sum() > 50
    # The traversable middle is floor seen at the end, never tight.
    assert rgb(frames[-1], *cell_centre(drawer, 2, 2)) != COLOURS["tight"]


def test_the_viewer_page_uses_the_same_heat_ramp_and_tight_colour() -> None:
    """The page's first-seen ramp is the palette's, and its tight cells are the frames' tight cells."""
    from guardsim.viewer.page import page_data

    scene = scene_from(TIGHT_ROOM)
    simulation = Simulation(scene)
    simulation.reset(seed=0)
    trace = simulation.run()
    data = page_data(scene.level, trace)
    assert data["heat_ramp"] == [[fraction, list(colour)] for fraction, colour in HEAT_RAMP]
    assert data["colours"]["tight"] == "#" + "".join(f"{v:02x}" for v in COLOURS["tight"])
    kinds = np.frombuffer(base64.b64decode(data["kinds"]), dtype=np.uint8).reshape(4, 6)
    assert (kinds == 3).astype(int).tolist() == drawer_for(TIGHT_ROOM).tight.astype(int).tolist()
    assert data["tight"] == 16


def test_frame_keeps_six_pixels_a_cell_on_a_real_sized_map(tmp_path: Path) -> None:
    """A 130 x 90 map: at least 6 pixels a cell by default; --size sets the long side."""
    level = {"name": "wide", "outer": [[0, 0], [130, 0], [130, 90], [0, 90]], "guard": {"start": [1.5, 1.5]}}
    path = write_level(tmp_path, level)
    sizes = {}
    for name, options in {"default": [], "small": ["--size", "390"], "big": ["--size", "1300"]}.items():
        gif = tmp_path / f"{name}.gif"
        result = CliRunner().invoke(main, ["play", str(path), "--max-steps", "2", "--gif", str(gif), *options])
        assert result.exit_code == 0, result.output
        sizes[name] = iio.imread(gif, index=0, extension=".gif").shape[1]
    assert sizes == {
        "default": 130 * MIN_CELL_PIXELS + 2 * PLAY_PAD,
        "small": 400,  # 130 * 3 + 2 * PLAY_PAD, widened to the narrowest frame (the caption's room)
        "big": 130 * 10 + 2 * PLAY_PAD,
    }


@pytest.mark.parametrize(
    ("shape", "expected"), [((10, 10), 48), ((60, 60), 8), ((90, 130), 6), ((512, 512), 3), ((2000, 100), 1)]
)
def test_default_cell_pixels_stay_readable_up_to_the_cap(shape: tuple[int, int], expected: int) -> None:
    scale = cell_pixels(shape)
    assert scale == expected
    assert scale * max(shape) <= max(MAX_FRAME_SIDE, max(shape))


def test_long_captions_wrap_inside_the_frame() -> None:
    """A long level name and an unreachable count: the caption bar grows by lines, and no caption text
    runs into the bar's right margin (where a cut caption ended)."""
    data = dict(SPLIT_ROOMS, name="a level with a rather long name taken from a real map " * 2)
    drawer = drawer_for(data)
    layout = drawer.layout
    lines = wrap_caption(drawer.caption(0), drawer.caption_setter, drawer.caption_width)
    assert len(lines) >= 3 and " ".join(lines).replace("  |  ", " ").count("(not counted)") == 1
    assert layout.top == len(lines) * 17 + 8
    frame = drawer.frame(0)
    bar = frame[: layout.top]
    assert (bar[:, -8:] == Index.BAR).all()
    inked_rows = np.flatnonzero((bar != Index.BAR).any(axis=1))
    assert inked_rows.max() > 2 * 17 + 4  # the third line is drawn


def test_wrap_breaks_between_parts_then_words() -> None:
    setter = Typesetter(13)
    caption = ["level  |  tick 3 / 10  |  ripplefront, 1 guard", "9.0% of 20 cells unseen  |  3 unreachable cells"]
    assert wrap_caption(caption, setter, 1000) == caption
    narrow = wrap_caption(caption, setter, 150)
    assert " ".join(narrow).replace("  |  ", " ").split() == " ".join(caption).replace("  |  ", " ").split()
    assert all(setter.width(line) <= 150 for line in narrow)


def test_seams_between_touching_wall_pieces_are_not_drawn() -> None:
    """Where two holes touch (x = 6) the frame shows wall, not the outline; their outer edges keep it."""
    drawer = drawer_for(CUT_WALL)
    frame = drawer.frame(0)
    layout = drawer.layout
    y = layout.top + PLAY_PAD + 4 * layout.scale
    seam = layout.left + PLAY_PAD + 6 * layout.scale
    assert (frame[y, seam - 2 : seam + 3] == Index.WALL).all()
    edge = layout.left + PLAY_PAD + 3 * layout.scale
    assert (frame[y, edge - 1 : edge + 1] == Index.OUTLINE).any()


def test_render_has_a_legend_and_no_seams(tmp_path: Path) -> None:
    """guardsim render: the cells as before, a legend bar below naming what is drawn, no seam line."""
    png = tmp_path / "cut.png"
    path = write_level(tmp_path, CUT_WALL)
    result = CliRunner().invoke(main, ["render", str(path), "--png", str(png), "--size", "480"])
    assert result.exit_code == 0, result.output
    image = iio.imread(png)
    scale, margin = 40, 36
    body = margin + 8 * scale + margin
    assert image.shape[0] > body + 10
    legend = image[body:].reshape(-1, 3)
    for name in ("bar", "wall", "reachable"):
        assert (legend == COLOURS[name]).all(axis=1).sum() > 20, name
    assert (legend == GUARD_COLOURS[0]).all(axis=1).sum() > 20
    seam_x, y = margin + 6 * scale, margin + 4 * scale
    assert {rgb(image, y, x) for x in range(seam_x - 2, seam_x + 3)} == {COLOURS["wall"]}


def test_preview_legend_names_what_is_there() -> None:
    preview = np.full((50, 400, 3), 255, dtype=np.uint8)
    plain, full = with_legend(preview), with_legend(preview, unreachable=True, tight=True, cone=True, start=True)
    for name in ("unreachable", "tight"):
        assert not (plain[50:] == COLOURS[name]).all(axis=2).any()
        assert (full[50:] == COLOURS[name]).all(axis=2).sum() > 20


def test_rgb_array_uses_the_gif_palette() -> None:
    """The Gymnasium picture: walls, unseen floor, tight cells and the guard in the GIF's colours."""
    gymnasium = pytest.importorskip("gymnasium")
    pytest.importorskip("pettingzoo")
    import guardsim.envs  # noqa: F401  (registers the environments)

    level = parse_level(
        dict(TIGHT_ROOM, outer=[[0, 0], [8, 0], [8, 4], [0, 4]], holes=[[[6, 0], [8, 0], [8, 4], [6, 4]]])
    )
    env = gymnasium.make("guardsim/Coverage-v0", level=level, render_mode="rgb_array", cell_pixels=2).unwrapped
    env.reset(seed=0)
    frame = env.render()
    assert frame is not None
    colours = {rgb(frame, 2 * row, 2 * col) for row in range(4) for col in range(8)}
    assert {COLOURS["wall"], COLOURS["tight"], GUARD_COLOURS[0]} <= colours
    assert rgb(frame, 0, 2 * 7) == COLOURS["wall"]
    assert rgb(frame, 0, 0) == COLOURS["tight"]


def test_check_names_where_the_unreachable_cells_are(tmp_path: Path) -> None:
    """`guardsim check --no-unreachable` says how many cells and where (the hatched room of the pictures):
    a cell centre inside each of the largest unreachable areas, in world units."""
    from guardsim.validate.checks import CheckRules, run_checks

    result = run_checks(scene_from(SPLIT_ROOMS), CheckRules(no_unreachable=True))[0]
    assert not result.holds
    assert "9 cells" in result.message and result.message.endswith(": 9 around (4.5, 1.5)")
    run = CliRunner().invoke(main, ["check", str(write_level(tmp_path, SPLIT_ROOMS)), "--no-unreachable"])
    assert "9 around (4.5, 1.5)" in run.output


def test_render_keeps_six_pixels_a_cell_on_a_real_sized_map(tmp_path: Path) -> None:
    """guardsim render on a 130 x 90 map: 6 pixels a cell (it was 4), and --size still sets the long side."""
    level = {"name": "wide", "outer": [[0, 0], [130, 0], [130, 90], [0, 90]], "guard": {"start": [1.5, 1.5]}}
    path = write_level(tmp_path, level)
    widths = {}
    for name, options in {"default": [], "sized": ["--size", "260"]}.items():
        png = tmp_path / f"{name}.png"
        result = CliRunner().invoke(main, ["render", str(path), "--png", str(png), *options])
        assert result.exit_code == 0, result.output
        widths[name] = iio.imread(png).shape[1]
    assert widths == {"default": 130 * 6 + 2 * 36, "sized": 130 * 2 + 2 * 36}
