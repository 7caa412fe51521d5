"""Images: dark pixels are walls and light pixels free, decoded back through the grid."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from guardsim import load_level
from guardsim.cli import main
from guardsim.errors import LevelError
from guardsim.simulation import Scene
from tests.common import import_map


def write_png(folder: Path, pixels: np.ndarray, name: str = "level.png", mode: str | None = None) -> Path:
    path = folder / name
    Image.fromarray(pixels.astype(np.uint8), mode=mode).save(path)
    return path


def room_with_pocket() -> np.ndarray:
    """A 16 x 12 grey image: white floor, a black pillar, and a black ring around a white pocket."""
    pixels = np.full((12, 16), 255, dtype=np.uint8)
    pixels[2:4, 2:6] = 0
    pixels[5:10, 8:14] = 20
    pixels[6:9, 9:13] = 240
    pixels[7, 10] = 0
    return pixels


def test_round_trip_light_pixels_are_exactly_the_traversable_cells(tmp_path: Path) -> None:
    """At cell size 1 each light pixel is a traversable cell and each dark one is not, pocket included."""
    pixels = room_with_pocket()
    imported = import_map(write_png(tmp_path, pixels))
    grid = Scene.from_level(imported.level).grid
    assert np.array_equal(grid.traversable, pixels >= 128)
    assert imported.map_size == (16, 12)
    assert "cut 1 enclosing wall open" in imported.summary()


@pytest.mark.parametrize(("threshold", "walls"), [(128, True), (50, False)])
def test_threshold_decides_what_is_dark(tmp_path: Path, threshold: int, walls: bool) -> None:
    """Grey 100 is a wall under threshold 128 and floor under threshold 50."""
    pixels = np.full((4, 4), 255, dtype=np.uint8)
    pixels[1:3, 1:3] = 100
    level = import_map(write_png(tmp_path, pixels), threshold=threshold).level
    assert bool(level.holes) == walls


def test_colour_and_transparency(tmp_path: Path) -> None:
    """Colour images are read by brightness; transparent pixels count as light, whatever their colour."""
    rgba = np.zeros((3, 4, 4), dtype=np.uint8)
    rgba[..., 3] = 255
    rgba[:, :, :3] = 255
    rgba[1, 1] = (10, 10, 200, 255)  # dark blue: wall
    rgba[1, 2] = (0, 0, 0, 0)  # fully transparent black: free
    level = import_map(write_png(tmp_path, rgba, mode="RGBA")).level
    traversable = Scene.from_level(level).grid.traversable
    assert traversable.sum() == 11
    assert not traversable[1, 1] and traversable[1, 2]


def test_not_an_image_is_one_error(tmp_path: Path) -> None:
    """A .png that is not an image is a LevelError naming the file."""
    path = tmp_path / "fake.png"
    path.write_text("not an image", encoding="utf-8")
    with pytest.raises(LevelError, match=f"{path}: not an image"):
        import_map(path)


def test_image_over_the_cell_limit(tmp_path: Path) -> None:
    """An image with more pixels than --max-cells is refused before it is decoded in full."""
    path = write_png(tmp_path, np.full((20, 30), 255))
    with pytest.raises(LevelError, match="600 pixels is over the limit of 500 cells"):
        import_map(path, max_cells=500)


def test_all_dark_image_has_no_free_area(tmp_path: Path) -> None:
    """An image with no light pixel cannot be a level."""
    with pytest.raises(LevelError, match="no free area"):
        import_map(write_png(tmp_path, np.zeros((3, 3))))


def test_import_command_threshold_option(tmp_path: Path) -> None:
    """`guardsim import level.png --threshold 50 --cell-size 0.5` passes both through."""
    pixels = np.full((4, 6), 255, dtype=np.uint8)
    pixels[:, 3] = 30
    source = write_png(tmp_path, pixels)
    out = tmp_path / "level.json"
    result = CliRunner().invoke(
        main, ["import", str(source), "--out", str(out), "--threshold", "50", "--cell-size", "0.5"]
    )
    assert result.exit_code == 0, result.output
    assert "image 6 x 4 -> 12 x 8 grid (cell size 0.5)" in result.stdout
    assert load_level(out).holes == (((3.0, 0.0), (3.0, 4.0), (4.0, 4.0), (4.0, 0.0)),)
