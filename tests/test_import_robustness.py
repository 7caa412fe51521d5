"""The importer's share of the fuzzing campaign (issue 16): each input that once gave a traceback, a hang,
a memory blow-up or a silent wrong answer now gives one located line on stderr and exit status 2.

Every case runs through the CLI (``guardsim import``, and ``validate``/``play`` where they differ) and
checks the rule the campaign checks: exit 2, exactly one stderr line, naming the file and the fault.
Limits must trip before the expensive work; how long that takes is measured by
``benchmarks/import_maps.py --robustness``, not asserted here.
"""

from __future__ import annotations

import base64
import io
import json
import os
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.errors import LevelError
from tests.common import load_any


def one_error_line(args: list[str], *fragments: str) -> str:
    """Run the CLI; assert exit 2 and exactly one `guardsim: error:` line holding every fragment."""
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = result.stderr.splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("guardsim: error: ")
    assert "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    return lines[0]


def imported_error(tmp_path: Path, name: str, content: str | bytes, *fragments: str) -> str:
    path = tmp_path / name
    path.write_bytes(content.encode("utf-8") if isinstance(content, str) else content)
    return one_error_line(["import", str(path), "--out", str(tmp_path / "out.json")], str(path), *fragments)


def tmx(layers: str, width: int = 4, height: int = 4, tile: int = 16) -> str:
    return (
        f'<?xml version="1.0"?>\n<map version="1.10" orientation="orthogonal" width="{width}" height="{height}" '
        f'tilewidth="{tile}" tileheight="{tile}" infinite="0">\n'
        ' <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2"/>\n'
        f"{layers}</map>\n"
    )


def csv_layer(name: str, gids: list[int], width: int, height: int) -> str:
    return f' <layer name="{name}" width="{width}" height="{height}"><data encoding="csv">{",".join(map(str, gids))}</data></layer>\n'


def zlib_layer(name: str, gids: np.ndarray, width: int, height: int) -> str:
    data = base64.b64encode(zlib.compress(np.asarray(gids, dtype="<u4").tobytes(), 9)).decode("ascii")
    return (
        f' <layer name="{name}" width="{width}" height="{height}">'
        f'<data encoding="base64" compression="zlib">{data}</data></layer>\n'
    )


FLOOR_4X4 = csv_layer("Ground", [1] * 16, 4, 4)


# -- Moving AI header numbers --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("header", "fragments"),
    [
        ("height ³\nwidth 2", ("line 2", "height must be a positive whole number", "'³'")),
        ("height 2\nwidth 9999999999999", ("9999999999999 x 2", "over the limit of 1000000", "--max-cells")),
        ("height 1\nwidth 1000000000000", ("1000000000000 x 1", "--max-cells")),
        ("height 1\nwidth " + "9" * 40, ("line 3", "far over the limit", "--max-cells")),
    ],
    ids=["superscript-digit", "width-13-digits", "width-10-to-the-12", "width-40-digits"],
)
def test_moving_ai_header_numbers_are_one_located_line(tmp_path: Path, header: str, fragments: tuple[str, ...]) -> None:
    imported_error(tmp_path, "m.map", f"type octile\n{header}\nmap\n..\n..\n", *fragments)


# -- Malformed numbers in Tiled maps -------------------------------------------------------------------


def test_tiled_json_with_a_5001_digit_integer(tmp_path: Path) -> None:
    text = '{"orientation": "orthogonal",\n "tilewidth": ' + "7" * 5001 + ', "tileheight": 8, "layers": []}'
    imported_error(tmp_path, "m.json", text, "line 2 column 15", "5001 digits")


@pytest.mark.parametrize("key", ["tileheight", "tilewidth", "tilecount", "firstgid"])
def test_tiled_json_tileset_numbers_that_are_not_numbers(tmp_path: Path, key: str) -> None:
    """Found by benchmarks/fuzz.py (20,000 cases): a tileset's tileheight given as a string was a traceback."""
    tileset = {"firstgid": 1, "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 4, "columns": 2}
    tileset[key] = "sixteen"
    text = json.dumps(
        {
            "type": "map", "orientation": "orthogonal", "width": 2, "height": 2, "tilewidth": 16, "tileheight": 16,
            "infinite": False, "tilesets": [tileset],
            "layers": [{"type": "tilelayer", "name": "Ground", "width": 2, "height": 2, "data": [1, 1, 1, 1]}],
        }
    )  # fmt: skip
    imported_error(tmp_path, "m.json", text, "tilesets[0]", key, "must be a number")


@pytest.mark.parametrize(
    ("value", "why"),
    [("1e308", "must be a number of at most 1e+09"), ("-1e308", "at most 1e+09"), ("1e999", "must be a finite number")],
    ids=["1e308", "minus-1e308", "1e999"],
)
def test_huge_objects_in_tmx(tmp_path: Path, value: str, why: str) -> None:
    walls = f' <objectgroup name="Walls"><object id="5" x="0" y="0" width="{value}" height="{value}"/></objectgroup>\n'
    imported_error(tmp_path, "m.tmx", tmx(FLOOR_4X4 + walls), "layer 'Walls' object 5 width", why)


def test_huge_objects_in_tiled_json(tmp_path: Path) -> None:
    text = (
        '{"orientation": "orthogonal", "tilewidth": 16, "tileheight": 16, "width": 1, "height": 1, "layers": ['
        '{"type": "tilelayer", "name": "Ground", "width": 1, "height": 1, "data": [1]},'
        '{"type": "objectgroup", "name": "Walls", "objects": [{"id": 2, "x": 1e308, "y": 0, "width": 1e308, "height": 4}]}]}'
    )
    imported_error(
        tmp_path, "m.json", text, "layers[1] ('Walls').objects object 2 x", "must be a number of at most 1e+09"
    )


def test_nan_in_tmx_and_in_tiled_json(tmp_path: Path) -> None:
    walls = ' <objectgroup name="Walls"><object id="5" x="nan" y="0" width="4" height="4"/></objectgroup>\n'
    imported_error(tmp_path, "m.tmx", tmx(FLOOR_4X4 + walls), "object 5 x", "finite number", "nan")
    text = '{"orientation": "orthogonal", "tilewidth": NaN, "tileheight": 16, "layers": []}'
    imported_error(tmp_path, "m.json", text, "line 1 column 44", "NaN is not a JSON number")


def test_base64_layer_data_given_as_a_json_list(tmp_path: Path) -> None:
    text = (
        '{"orientation": "orthogonal", "tilewidth": 16, "tileheight": 16, "layers": ['
        '{"type": "tilelayer", "name": "Ground", "width": 2, "height": 1, "encoding": "base64", "data": [1, 1]}]}'
    )
    imported_error(tmp_path, "m.json", text, "layers[0] ('Ground').data", "base64 tile data must be a string")


def test_tmx_with_3000_nested_groups(tmp_path: Path) -> None:
    nested = "<group name='g'>" * 3000 + FLOOR_4X4 + "</group>" * 3000
    imported_error(tmp_path, "m.tmx", tmx(nested), "XML nested over the limit of 60 elements")


def test_hex_encoding_is_refused(tmp_path: Path) -> None:
    layer = ' <layer name="Ground" width="4" height="3"><data encoding="hex">111111111111</data></layer>\n'
    imported_error(tmp_path, "m.tmx", tmx(layer), "layer 'Ground'", "encoding hex is not one Tiled writes")


def test_walls_over_the_whole_floor_are_refused(tmp_path: Path) -> None:
    walls = ' <objectgroup name="Walls"><object id="1" x="0" y="0" width="64" height="64"/></objectgroup>\n'
    imported_error(tmp_path, "m.tmx", tmx(FLOOR_4X4 + walls), "no free area")
    wall_tiles = csv_layer("Walls", [1] * 16, 4, 4)
    imported_error(tmp_path, "m.tmx", tmx(FLOOR_4X4 + wall_tiles), "no free area")


# -- Size limits before the expensive work -------------------------------------------------------------


def png_bytes(pixels: np.ndarray) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(pixels).save(buffer, format="PNG")
    return buffer.getvalue()


def test_a_1000_by_1000_noise_png_trips_the_vertex_limit(tmp_path: Path) -> None:
    noise = np.random.default_rng(0).integers(0, 2, size=(1000, 1000), dtype=np.uint8) * 255
    imported_error(tmp_path, "noise.png", png_bytes(noise), "1000 x 1000", "vertices", "--max-vertices")


def test_a_1000_by_1000_checkerboard_tmx_trips_the_vertex_limit(tmp_path: Path) -> None:
    rows, cols = np.indices((1000, 1000))
    board = ((rows + cols) % 2).ravel()
    text = tmx(zlib_layer("Ground", board, 1000, 1000), 1000, 1000)
    assert len(text) < 40_000
    imported_error(tmp_path, "board.tmx", text, "vertices", "--max-vertices")


def test_a_2048_by_2048_tmx_trips_the_cell_limit(tmp_path: Path) -> None:
    text = tmx(zlib_layer("Ground", np.ones(2048 * 2048, dtype=np.uint32), 2048, 2048), 2048, 2048)
    imported_error(tmp_path, "big.tmx", text, "2048 x 2048 = 4194304 tiles", "--max-cells")


def test_a_png_past_pillows_bomb_size_gives_one_line_and_no_warning(tmp_path: Path) -> None:
    """A header declaring 10000 x 10000 pixels: Pillow warns of a decompression bomb; only our line shows."""
    header = struct.pack(">IIBBBBB", 10000, 10000, 8, 0, 0, 0, 0)

    def png_chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    data = b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", header) + png_chunk(b"IDAT", zlib.compress(b"\0" * 64))
    data += png_chunk(b"IEND", b"")
    imported_error(tmp_path, "bomb.png", data, "10000 x 10000", "--max-cells")


# -- Special files and the byte cap --------------------------------------------------------------------


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
@pytest.mark.parametrize("suffix", [".map", ".png", ".tmx", ".json"])
def test_dev_zero_is_refused_as_not_a_regular_file(tmp_path: Path, suffix: str) -> None:
    link = tmp_path / f"zero{suffix}"
    link.symlink_to("/dev/zero")
    one_error_line(["import", str(link), "--out", str(tmp_path / "o.json")], str(link), "not a regular file")
    # validate lists each level's problem on stdout and ends with one line on stderr.
    result = CliRunner().invoke(main, ["validate", str(link)])
    assert result.exit_code == 2 and len(result.stderr.splitlines()) == 1
    assert str(link) in result.stdout and "not a regular file" in result.stdout


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.tmx"
    os.mkfifo(fifo)
    one_error_line(["import", str(fifo), "--out", str(tmp_path / "o.json")], str(fifo), "not a regular file")
    one_error_line(["play", str(fifo)], str(fifo), "not a regular file")


def test_the_byte_cap_counts_bytes_read_not_the_reported_size(tmp_path: Path) -> None:
    """/proc files report size 0 and hold more; the cap must still hold."""
    status = Path("/proc/self/status")
    if not status.is_file():
        pytest.skip("no /proc")
    with pytest.raises(LevelError, match="over the limit of 16 bytes"):
        load_any(status, max_file_bytes=16)
    path = tmp_path / "m.map"
    path.write_text("type octile\nheight 1\nwidth 1\nmap\n.\n", encoding="utf-8")
    one_error_line(
        ["import", str(path), "--out", str(tmp_path / "o.json"), "--max-file-bytes", "10"], "--max-file-bytes"
    )


def test_a_newline_in_the_file_name_keeps_the_error_on_one_line(tmp_path: Path) -> None:
    path = tmp_path / "two\nlines.map"
    path.write_text("type octile\nheight x\n", encoding="utf-8")
    line = one_error_line(["import", str(path), "--out", str(tmp_path / "o.json")], "two\\nlines.map")
    assert "\n" not in line


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_dev_zero_in_a_real_process(tmp_path: Path) -> None:
    link = tmp_path / "zero.tmx"
    link.symlink_to("/dev/zero")
    result = subprocess.run(
        [sys.executable, "-m", "guardsim.cli", "play", str(link)], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and "not a regular file" in lines[0], result.stderr
