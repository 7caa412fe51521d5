"""Moving AI maps: the round trip on every real map, header variants, and one-line errors for bad files.

The real maps are the Moving AI benchmark maps in ``../shared/maps/movingai`` (see SOURCES.md there),
beside the repository as CI clones it. The small maps written here are our own.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from shapely.geometry import LinearRing, Polygon

from guardsim import load_level
from guardsim.cli import main
from guardsim.errors import LevelError
from guardsim.importers.movingai import import_movingai, read_movingai
from guardsim.simulation import Scene
from tests.common import import_map

MAPS_DIR = Path(__file__).resolve().parents[2] / "shared" / "maps" / "movingai"
MAPS = sorted(MAPS_DIR.glob("*.map"))
needs_maps = pytest.mark.skipif(not MAPS, reason=f"the shared Moving AI maps are not at {MAPS_DIR}")


def passable_cells(text: str) -> np.ndarray:
    """The map's passable cells, read naively and independently of the importer."""
    lines = text.splitlines()
    height = int(next(line.split()[1] for line in lines if line.startswith("height")))
    rows = lines[lines.index("map") + 1 :][:height]
    return np.array([[char in ".GS" for char in row] for row in rows])


def write_map(folder: Path, text: str, name: str = "tiny.map") -> Path:
    path = folder / name
    path.write_bytes(text.encode("utf-8"))
    return path


def has_collinear_vertex(ring: tuple[tuple[float, float], ...]) -> bool:
    """Whether some vertex lies on the straight line through its two neighbours."""
    for index, (x, y) in enumerate(ring):
        (ax, ay), (bx, by) = ring[index - 1], ring[(index + 1) % len(ring)]
        if (x - ax) * (by - y) - (y - ay) * (bx - x) == 0:
            return True
    return False


@needs_maps
@pytest.mark.parametrize("path", MAPS, ids=[path.stem for path in MAPS])
def test_round_trip_gives_back_exactly_the_passable_cells(tmp_path: Path, path: Path) -> None:
    """Imported at cell size 1, written, loaded and rasterised: traversable cells == the map's passable cells."""
    imported = import_map(path)
    out = tmp_path / "level.json"
    out.write_text(imported.to_json(), encoding="utf-8")
    level = load_level(out)
    grid = Scene.from_level(level).grid
    expected = passable_cells(path.read_text(encoding="utf-8"))
    assert grid.shape == expected.shape
    assert grid.origin == (0.0, 0.0)
    mismatched = np.argwhere(grid.traversable != expected)
    assert mismatched.size == 0, f"{len(mismatched)} cells differ, first (row, col) {mismatched[:3].tolist()}"
    for ring in level.holes:
        assert LinearRing(ring).is_simple
        assert Polygon(ring).area > 0
        assert not has_collinear_vertex(ring)


@needs_maps
def test_large_map_rings_stay_small() -> None:
    """Collinear edges are merged: a 512 x 512 map needs a few thousand vertices, not one per cell edge."""
    imported = import_movingai(MAPS_DIR / "AR0603SR.map")
    assert imported.map_size == (512, 512)
    assert imported.vertices < 5000
    assert "merged" in imported.summary() and "holes" in imported.summary()


def test_header_variants_are_read_by_name(tmp_path: Path) -> None:
    """Header lines in any order, `octile type`, no type line, CRLF and no final newline all read the same."""
    grid = "@.@\r\n...\r\nT.S"
    texts = [
        "type octile\nheight 3\nwidth 3\nmap\n" + grid.replace("\r\n", "\n") + "\n",
        "type octile\r\nheight 3\r\nwidth 3\r\nmap\r\n" + grid,
        "width 3\nheight 3\noctile type\nmap\n" + grid.replace("\r\n", "\n"),
        "height 3\nwidth 3\nmap\n" + grid.replace("\r\n", "\n") + "\n\n",
    ]
    expected = [[False, True, False], [True, True, True], [False, True, True]]
    for text in texts:
        assert read_movingai(text).tolist() == expected


@pytest.mark.parametrize("symbol", list(".GS"))
def test_passable_symbols(tmp_path: Path, symbol: str) -> None:
    """`.`, `G` and `S` are floor."""
    assert read_movingai(f"type octile\nheight 1\nwidth 2\nmap\n{symbol}@\n").tolist() == [[True, False]]


@pytest.mark.parametrize("symbol", list("@OTW"))
def test_blocked_symbols(tmp_path: Path, symbol: str) -> None:
    """`@`, `O`, `T` and `W` are walls."""
    assert read_movingai(f"type octile\nheight 1\nwidth 2\nmap\n{symbol}.\n").tolist() == [[False, True]]


def test_pocket_enclosed_by_walls_is_cut_open_and_kept(tmp_path: Path) -> None:
    """A ring of wall around a free pocket cannot be one hole; it is cut, and the pocket stays free."""
    text = "type octile\nheight 7\nwidth 7\nmap\n.......\n.@@@@@.\n.@...@.\n.@.@.@.\n.@...@.\n.@@@@@.\n.......\n"
    imported = import_movingai(write_map(tmp_path, text))
    assert "cut 1 enclosing wall open" in imported.summary()
    grid = Scene.from_level(imported.level).grid
    assert np.array_equal(grid.traversable, passable_cells(text))
    # The pocket is its own connected area: the cut did not open a way in.
    assert grid.component(0, 0).sum() == 24
    assert grid.component(2, 2).sum() == 8


def test_diagonal_walls_touch_only_at_a_corner(tmp_path: Path) -> None:
    """Blocked cells meeting corner to corner become separate holes touching at a point, which loads."""
    text = "type octile\nheight 4\nwidth 4\nmap\n....\n.@..\n..@.\n....\n"
    imported = import_movingai(write_map(tmp_path, text))
    assert len(imported.level.holes) == 2
    assert np.array_equal(Scene.from_level(imported.level).grid.traversable, passable_cells(text))


def test_cell_size_sets_the_grid_not_the_world(tmp_path: Path) -> None:
    """--cell-size 0.5 keeps one map cell per world unit and doubles the grid's resolution."""
    imported = import_map(write_map(tmp_path, "type octile\nheight 2\nwidth 3\nmap\n.@.\n...\n"), cell_size=0.5)
    assert imported.level.bounds == (0.0, 0.0, 3.0, 2.0)
    assert imported.level.grid_shape() == (4, 6)


BAD_MAPS = {
    "no-map-line": ("type octile\nheight 1\nwidth 1\n.\n", "line 4: unexpected header line"),
    "missing-width": ("type octile\nheight 1\nmap\n.\n", "no width line"),
    "width-not-number": ("type octile\nheight 1\nwidth x\nmap\n.\n", "line 3: width must be a positive whole number"),
    "hex-map": ("type hex\nheight 1\nwidth 1\nmap\n.\n", "line 1: map type 'hex'"),
    "short-row": ("type octile\nheight 2\nwidth 3\nmap\n...\n..\n", "line 6: row has 2 characters, the width is 3"),
    "too-few-rows": ("type octile\nheight 3\nwidth 1\nmap\n.\n.\n", "line 7: the map ends after 2 of 3 rows"),
    "too-many-rows": ("type octile\nheight 1\nwidth 1\nmap\n.\n.\n", "line 6: more rows than the height 1"),
    "unknown-terrain": ("type octile\nheight 1\nwidth 3\nmap\n.#.\n", "line 5 column 2: unknown terrain '#'"),
    "all-blocked": ("type octile\nheight 1\nwidth 2\nmap\n@T\n", "no free area"),
    "empty": ("", "no 'map' line"),
}


@pytest.mark.parametrize("case", list(BAD_MAPS))
def test_bad_map_is_a_level_error_naming_file_and_line(tmp_path: Path, case: str) -> None:
    """Each malformed map raises LevelError with the file and the line at fault."""
    text, fragment = BAD_MAPS[case]
    path = write_map(tmp_path, text)
    with pytest.raises(LevelError) as caught:
        import_map(path)
    assert str(caught.value).startswith(f"{path}: ")
    assert fragment in str(caught.value)


def test_binary_file_is_a_level_error(tmp_path: Path) -> None:
    """Bytes that are not UTF-8 text are reported, not decoded into garbage."""
    path = tmp_path / "binary.map"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\xff\xfe")
    with pytest.raises(LevelError, match="not a text file"):
        import_map(path)


def test_import_command_writes_level_and_prints_one_line(tmp_path: Path) -> None:
    """`guardsim import x.map --out level.json` writes a loadable level and prints one summary line."""
    source = write_map(tmp_path, "type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n")
    out = tmp_path / "level.json"
    result = CliRunner().invoke(main, ["import", str(source), "--out", str(out)])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert len(lines) == 1
    assert str(source) in lines[0] and "4 x 3 grid" in lines[0] and "1 holes" in lines[0] and str(out) in lines[0]
    level = load_level(out)
    assert level.holes == (((1.0, 1.0), (1.0, 2.0), (3.0, 2.0), (3.0, 1.0)),)
    assert json.loads(out.read_text())["outer"] == [[0, 0], [4, 0], [4, 3], [0, 3]]


@pytest.mark.parametrize(
    ("name", "text", "fragment"),
    [
        ("level.txt", "hello", "unknown map type '.txt'"),
        ("bad.map", "type octile\nheight 1\nwidth 2\nmap\n.\n", "line 5"),
        ("missing.map", None, "no such file"),
    ],
    ids=["unknown-type", "malformed", "missing"],
)
def test_import_command_errors_are_one_line(tmp_path: Path, name: str, text: str | None, fragment: str) -> None:
    """Unknown file types, malformed maps and missing files: one `guardsim: error:` line, exit 2, no output file."""
    source = tmp_path / name
    if text is not None:
        source.write_text(text, encoding="utf-8")
    out = tmp_path / "level.json"
    result = CliRunner().invoke(main, ["import", str(source), "--out", str(out)])
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("guardsim: error: ") and str(source) in lines[0]
    assert fragment in lines[0]
    assert not out.exists()


def test_import_command_in_a_subprocess(tmp_path: Path) -> None:
    """The real entry point imports a map and the level it writes validates."""
    source = write_map(tmp_path, "type octile\nheight 3\nwidth 3\nmap\n...\n.T.\n...\n")
    out = tmp_path / "level.json"
    command = [sys.executable, "-c", "from guardsim.cli import main; main()"]
    done = subprocess.run([*command, "import", str(source), "--out", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    checked = subprocess.run([*command, "validate", str(out)], capture_output=True, text=True)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert f"{out}: ok" in checked.stdout
