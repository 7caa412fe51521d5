"""``patrol --tiled-out`` maps opened by real Tiled (Debian's ``tiled``, headless).

Tiled re-saves each exported map as JSON (``tiled --export-map json``); the route layer must survive
with its points, headings, times and waits equal to route.json's, and the re-saved map must import
into the same level.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from guardsim.cli import main
from tests.common import write_level

TILED = shutil.which("tiled")
needs_tiled = pytest.mark.skipif(TILED is None, reason="Debian's tiled is not installed (.ci/run installs it)")

CORRIDOR: dict[str, Any] = {
    "name": "corridor",
    "outer": [[0, 0], [3, 0], [3, 1], [8, 1], [8, 0], [11, 0], [11, 3], [8, 3], [8, 2], [3, 2], [3, 3], [0, 3]],
    "holes": [[[9, 1.2], [10, 1.2], [10, 1.8], [9, 1.8]]],
    "guard": {"start": [0.5, 0.5], "heading": "right", "radius": 0.3},
}

# A 10 x 6 room drawn with tiles (gid 2 is a wall by its `collision` property) and a pillar.
SOURCE_TMX = """<?xml version="1.0" encoding="UTF-8"?>
<map version="1.8" orientation="orthogonal" renderorder="right-down" width="10" height="6" tilewidth="16"
 tileheight="16" infinite="0" nextlayerid="2" nextobjectid="1">
 <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2">
  <tile id="1"><properties><property name="collision" type="bool" value="true"/></properties></tile>
 </tileset>
 <layer id="1" name="Ground" width="10" height="6">
  <data encoding="csv">
2,2,2,2,2,2,2,2,2,2,
2,1,1,1,1,1,1,1,1,2,
2,1,1,1,1,1,1,1,1,2,
2,1,1,1,1,2,1,1,1,2,
2,1,1,1,1,2,1,1,1,2,
2,2,2,2,2,2,2,2,2,2
</data>
 </layer>
</map>
"""


def _resave(tmp_path: Path, exported: Path) -> dict[str, Any]:
    """``exported`` opened and saved as JSON by real Tiled."""
    again = exported.with_name(exported.stem + "-tiled.json")
    runtime = tmp_path / "runtime"
    runtime.mkdir(mode=0o700, exist_ok=True)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(tmp_path), XDG_RUNTIME_DIR=str(runtime))
    assert TILED is not None
    done = subprocess.run(
        [TILED, "--export-map", "json", str(exported), str(again)], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    data: dict[str, Any] = json.loads(again.read_text())
    return data


def _route_layer(data: dict[str, Any]) -> list[dict[str, Any]]:
    [layer] = [layer for layer in data["layers"] if layer["name"] == "guardsim"]
    objects: list[dict[str, Any]] = layer["objects"]
    return objects


def _check_routes(
    objects: list[dict[str, Any]], route: dict[str, Any], pixels: float, origin: tuple[float, float]
) -> None:
    """Tiled's copy of the route layer says what route.json says: points, headings, times and waits."""
    lines = [item for item in objects if item["type"] == "guardsim_route"]
    assert len(lines) == len(route["guards"])
    for number, (line, guard) in enumerate(zip(lines, route["guards"])):
        points = guard["waypoints"]
        expected = [v for p in points for v in ((p["x"] - origin[0]) * pixels, (p["y"] - origin[1]) * pixels)]
        got = [v for p in line["polyline"] for v in (p["x"], p["y"])][: len(expected)]
        assert got == pytest.approx(expected)
        properties = {item["name"]: item["value"] for item in line["properties"]}
        assert properties["guard"] == number + 1
        headings = [float(v) for v in properties["headings"].split()][: len(points)]
        times = [float(v) for v in properties["times"].split()][: len(points)]
        assert headings == [p["heading"] for p in points] and times == pytest.approx([p["time"] for p in points])
        assert properties["loop_mode"] == guard["loop_mode"] and properties["phase"] == guard["phase"]
        waits = [(here, here["wait"]) for here in points if here["wait"] > 0]
        marks = [
            item for item in objects if item["type"] == "guardsim_wait" and item["properties"][0]["value"] == number + 1
        ]
        assert len(marks) == len(waits)
        for mark, (here, seconds) in zip(marks, waits):
            values = {item["name"]: item["value"] for item in mark["properties"]}
            assert values["wait"] == pytest.approx(seconds) and values["facing"] == here["heading"]
            assert (mark["x"], mark["y"]) == pytest.approx(
                ((here["x"] - origin[0]) * pixels, (here["y"] - origin[1]) * pixels)
            )


@needs_tiled
@pytest.mark.parametrize("suffix", [".tmx", ".tmj"])
def test_a_hand_made_level_exports_a_map_that_real_tiled_opens_with_its_route(tmp_path: Path, suffix: str) -> None:
    from tests.common import import_map

    level = write_level(tmp_path, CORRIDOR)
    exported, route_path = tmp_path / f"fresh{suffix}", tmp_path / "route.json"
    args = ["patrol", str(level), "--out", str(tmp_path / "o"), "--guards", "2", "--strategy", "staleness"]
    result = CliRunner().invoke(main, [*args, "--laps", "1", "--tiled-out", str(exported), "--export", str(route_path)])
    assert result.exit_code == 0, result.output
    data = _resave(tmp_path, exported)
    properties = {item["name"]: item["value"] for item in data["properties"]}
    assert properties["guardsim_level"] == "corridor" and properties["guardsim_origin"] == "-1,-1"
    _check_routes(_route_layer(data), json.loads(route_path.read_text()), 32, (-1.0, -1.0))
    # Tiled's own save imports into the level drawn, moved by the map's border.
    resaved = tmp_path / "resaved.json"
    resaved.write_text(json.dumps(data))
    imported = import_map(resaved)
    assert imported.warnings == ()
    assert imported.level.free_area().area == pytest.approx(3 * 3 * 2 + 5 * 1 - 0.6)  # type: ignore[attr-defined]


def test_a_level_with_no_tile_size_says_which_it_assumed(tmp_path: Path) -> None:
    """A level that records no map tile size gets 32-pixel tiles, and one warning line saying so and
    how to give the map's own."""
    level = write_level(tmp_path, CORRIDOR)
    exported = tmp_path / "fresh.tmx"
    result = CliRunner().invoke(
        main, ["patrol", str(level), "--out", str(tmp_path / "o"), "--tiled-out", str(exported)]
    )
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines() == [
        f"guardsim: warning: {exported}: 32-pixel tiles assumed ({level} records no tile_pixels); for the tiles "
        "of the Tiled map it came from, give --tiled-source MAP (or import the map again)"
    ]
    assert 'tilewidth="32" tileheight="32"' in exported.read_text()


@needs_tiled
def test_a_level_imported_from_a_64_pixel_map_exports_64_pixel_tiles(tmp_path: Path) -> None:
    """`guardsim import` records the map's tile size in the level (tile_pixels); `patrol --tiled-out`
    without --tiled-source writes tiles of that size, with no warning, and real Tiled reads the routes
    at 64 pixels a world unit."""
    source = tmp_path / "map.tmx"
    source.write_text(SOURCE_TMX.replace('"16"', '"64"'), encoding="utf-8")
    level = tmp_path / "level.json"
    imported = CliRunner().invoke(main, ["import", str(source), "--out", str(level)])
    assert imported.exit_code == 0, imported.output
    assert json.loads(level.read_text())["tile_pixels"] == [64, 64]
    exported, route_path = tmp_path / "fresh.tmx", tmp_path / "route.json"
    args = [
        "patrol",
        str(level),
        "--out",
        str(tmp_path / "o"),
        "--tiled-out",
        str(exported),
        "--export",
        str(route_path),
    ]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert result.stderr == ""
    data = _resave(tmp_path, exported)
    assert (data["tilewidth"], data["tileheight"]) == (64, 64)
    properties = {item["name"]: item["value"] for item in data["properties"]}
    origin = tuple(float(value) for value in properties["guardsim_origin"].split(","))
    _check_routes(_route_layer(data), json.loads(route_path.read_text()), 64, origin)  # type: ignore[arg-type]


@needs_tiled
def test_a_tiled_copy_opens_in_real_tiled_with_its_route_and_imports_as_the_source(tmp_path: Path) -> None:
    from guardsim.level import level_to_data
    from tests.common import import_map

    source = tmp_path / "map.tmx"
    source.write_text(SOURCE_TMX, encoding="utf-8")
    copy, route_path = tmp_path / "routed.tmx", tmp_path / "route.json"
    args = ["patrol", str(source), "--out", str(tmp_path / "o"), "--tiled-out", str(copy), "--export", str(route_path)]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    data = _resave(tmp_path, copy)
    assert [layer["name"] for layer in data["layers"]] == ["Ground", "guardsim"]
    _check_routes(_route_layer(data), json.loads(route_path.read_text()), 16, (0.0, 0.0))
    resaved = tmp_path / "resaved.json"
    resaved.write_text(json.dumps(data))
    again, plain = (level_to_data(import_map(path).level) for path in (resaved, source))
    again.pop("name"), plain.pop("name")
    assert again == plain
