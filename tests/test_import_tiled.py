"""Tiled maps: the sneaktime samples land with walls and floor where the maps' own layers put them, and
small maps written here exercise rotation, offsets, groups, chunks, encodings, properties, snapping,
boundaries, spawns and the errors.

The samples are three levels of the MIT-licensed stealth game sneaktime in ``../shared/maps/tiled``
(see SOURCES.md and LICENSE-sneaktime.txt there).
"""

from __future__ import annotations

import base64
import json
import re
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import shapely
from click.testing import CliRunner
from shapely.geometry import Polygon

from guardsim import load_level
from guardsim.cli import main
from guardsim.errors import LevelError
from guardsim.importers import import_tiled
from guardsim.level import level_to_data, parse_level
from guardsim.motion import run_episode
from guardsim.planners import RippleFront
from guardsim.simulation import Scene, choose_start
from tests.common import import_map

TILED_DIR = Path(__file__).resolve().parents[2] / "shared" / "maps" / "tiled"
SAMPLES = sorted(TILED_DIR.glob("sneaktime_*.json"))
needs_samples = pytest.mark.skipif(not SAMPLES, reason=f"the shared Tiled maps are not at {TILED_DIR}")
#: The sneaktime Spawners layer marks guards with tile 50 and the boss with 51 (see SOURCES.md).
GUARD_TILES = (50, 51)


def sample_layers(path: Path) -> tuple[set[tuple[int, int]], list[Polygon]]:
    """The floor tiles of 'Tile Layer 1' and the wall polygons (in tiles), read straight from the JSON."""
    data = json.loads(path.read_text(encoding="utf-8"))
    floor: set[tuple[int, int]] = set()
    walls: list[Polygon] = []
    for layer in data["layers"]:
        if layer["name"] == "Tile Layer 1":
            for chunk in layer["chunks"]:
                for index, gid in enumerate(chunk["data"]):
                    if gid:
                        floor.add((chunk["x"] + index % chunk["width"], chunk["y"] + index // chunk["width"]))
        if layer["name"].startswith("Walls"):
            for item in layer["objects"]:
                walls.append(Polygon([((item["x"] + p["x"]) / 64, (item["y"] + p["y"]) / 64) for p in item["polygon"]]))
    return floor, walls


@needs_samples
@pytest.mark.parametrize("path", SAMPLES, ids=[path.stem for path in SAMPLES])
def test_sample_walls_and_floor_are_where_the_map_puts_them(path: Path) -> None:
    """Each tile is free exactly when the map's floor layer has it and no wall polygon covers its centre.

    Tiles whose centre lies within 0.05 tiles of a wall polygon's edge are skipped: there the answer
    depends on snapping a hand-placed vertex, which is the point of snapping.
    """
    floor, walls = sample_layers(path)
    level = import_map(path, spawn_tiles=GUARD_TILES).level
    free = level.free_area()
    walls_union = shapely.union_all(walls)
    min_x, min_y, max_x, max_y = (int(v) for v in level.bounds)
    checked = {"floor": 0, "wall": 0}
    for col in range(min_x - 1, max_x + 1):
        for row in range(min_y - 1, max_y + 1):
            centre = shapely.Point(col + 0.5, row + 0.5)
            if walls_union.boundary.distance(centre) < 0.05:
                continue
            expected_free = (col, row) in floor and not walls_union.contains(centre)
            assert free.contains(centre) == expected_free, (col, row)
            checked["floor" if expected_free else "wall"] += 1
    assert checked["floor"] > 150 and checked["wall"] > 100


@needs_samples
@pytest.mark.parametrize("path", SAMPLES, ids=[path.stem for path in SAMPLES])
def test_tmx_and_json_give_the_same_level(path: Path) -> None:
    """The TMX file and its JSON export import to identical levels."""
    from_json = import_map(path, spawn_tiles=GUARD_TILES).level
    from_tmx = import_map(path.with_suffix(".tmx"), spawn_tiles=GUARD_TILES).level
    assert level_to_data(from_json) == level_to_data(from_tmx)


@needs_samples
def test_sample_guard_spawns_become_starts() -> None:
    """tilemap1's three guard tiles (id 50) become starts at their tile centres; the first is guard.start."""
    imported = import_map(TILED_DIR / "sneaktime_tilemap1.json", spawn_tiles=(50,))
    assert imported.level.starts == ((10.5, 9.5), (17.5, 11.5), (9.5, 17.5))
    assert imported.level.guard.start == (10.5, 9.5)
    assert "3 guard spawns" in imported.summary()
    assert "snapped" in imported.summary() and "merged" in imported.summary()


@needs_samples
@pytest.mark.parametrize("path", SAMPLES, ids=[path.stem for path in SAMPLES])
def test_sample_plays_to_full_coverage_from_every_spawn(path: Path) -> None:
    """Every spawn is a usable start, and RippleFront covers all reachable cells from the first."""
    level = import_map(path, spawn_tiles=GUARD_TILES).level
    scene = Scene.from_level(level)
    for point in level.starts:
        choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
    cell, heading = choose_start(scene, rng=np.random.default_rng(0), point=level.starts[0])
    trace = run_episode(scene, RippleFront(), starts=[cell], headings=[heading])
    assert trace.outcome == "covered"
    assert trace.unreachable == 0


TMX_ROTATED = """<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" renderorder="right-down" width="6" height="4"
     tilewidth="16" tileheight="16" infinite="0">
 <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="4" columns="2">
  <tile id="1"><properties><property name="collision" type="bool" value="true"/></properties></tile>
  <tile id="2" type="guard"/>
 </tileset>
 <layer id="1" name="Ground" width="6" height="4">
  <data encoding="csv">
1,1,1,1,1,1,
1,1,1,1,1,1,
1,1,1,2,1,1,
1,1,1,1,1,1
</data>
 </layer>
 <layer id="2" name="Markers" width="6" height="4">
  <data encoding="csv">
0,0,0,0,0,0,
0,0,0,0,3,0,
0,0,0,0,0,0,
0,0,0,0,0,0
</data>
 </layer>
 <group id="3" name="Building" offsetx="16" offsety="0">
  <objectgroup id="4" name="Walls" offsety="16">
   <object id="1" x="16" y="0" width="16" height="32" rotation="90"/>
   <object id="2" x="80" y="32" width="16" height="16">
    <properties><property name="collision" type="bool" value="false"/></properties>
   </object>
  </objectgroup>
 </group>
</map>
"""


def tiles_mask(rows: int, cols: int, walls: list[tuple[int, int]]) -> np.ndarray:
    mask = np.ones((rows, cols), dtype=bool)
    for col, row in walls:
        mask[row, col] = False
    return mask


def test_rotation_group_and_layer_offsets_collision_tiles_and_spawn_tiles(tmp_path: Path) -> None:
    """A 90-degree rotated rectangle in an offset layer inside an offset group lands on tiles (0,1)-(1,1);
    a tile with the collision property is a wall; `collision: false` opts an object out; a tile of class
    guard is a spawn."""
    path = tmp_path / "rotated.tmx"
    path.write_text(TMX_ROTATED, encoding="utf-8")
    imported = import_map(path)
    level = imported.level
    assert level.bounds == (0.0, 0.0, 6.0, 4.0)
    grid = Scene.from_level(level).grid
    assert np.array_equal(grid.traversable, tiles_mask(4, 6, [(0, 1), (1, 1), (3, 2)]))
    assert level.starts == ((4.5, 1.5),)
    assert "floor from 'Ground' (named floor or ground)" in imported.summary()


def chunk_data(gids: list[int]) -> str:
    """Tile ids as Tiled's base64 zlib chunk data."""
    return base64.b64encode(zlib.compress(np.asarray(gids, dtype="<u4").tobytes())).decode("ascii")


def json_map(**changes: Any) -> dict[str, Any]:
    """An infinite 32-pixel-tile JSON map: floor chunk at x -16..-1 (4 rows), a wall block, a guard point."""
    floor = [0] * (16 * 16)
    for row in range(4):
        for col in range(10, 16):
            floor[row * 16 + col] = 1
    data: dict[str, Any] = {
        "type": "map",
        "orientation": "orthogonal",
        "infinite": True,
        "tilewidth": 32,
        "tileheight": 32,
        "tilesets": [{"firstgid": 1, "name": "t", "tiles": []}],
        "layers": [
            {
                "type": "tilelayer",
                "name": "Base",
                "properties": [{"name": "floor", "type": "bool", "value": True}],
                "encoding": "base64",
                "compression": "zlib",
                "chunks": [{"x": -16, "y": 0, "width": 16, "height": 16, "data": chunk_data(floor)}],
            },
            {
                "type": "objectgroup",
                "name": "Blockers",
                "properties": [{"name": "collision", "type": "bool", "value": True}],
                "objects": [{"id": 1, "x": -128, "y": 32, "width": 64, "height": 32, "rotation": 0}],
            },
            {
                "type": "objectgroup",
                "name": "People",
                "objects": [{"id": 2, "type": "guard", "point": True, "x": -176, "y": 16}],
            },
        ],
    }
    data.update(changes)
    return data


def write_json(folder: Path, data: Any, name: str = "map.json") -> Path:
    path = folder / name
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def test_infinite_base64_zlib_chunks_at_negative_coordinates(tmp_path: Path) -> None:
    """Chunks at negative x keep their place: the floor is tiles -6..-1, the block covers (-4,1) and (-3,1)."""
    imported = import_map(write_json(tmp_path, json_map()))
    level = imported.level
    assert level.bounds == (-6.0, 0.0, 0.0, 4.0)
    grid = Scene.from_level(level).grid
    assert np.array_equal(grid.traversable, tiles_mask(4, 6, [(2, 1), (3, 1)]))
    assert level.starts == ((-5.5, 0.5),)
    assert level.guard.start == (-5.5, 0.5)


def test_snapping_closes_hand_placed_gaps(tmp_path: Path) -> None:
    """Wall vertices a pixel off the grid are snapped onto it and counted."""
    data = json_map()
    data["layers"][1]["objects"] = [{"id": 1, "x": -129, "y": 33, "width": 65.5, "height": 30, "rotation": 0}]
    imported = import_map(write_json(tmp_path, data))
    assert "snapped 4 vertices" in imported.summary()
    assert [[-4, 1], [-4, 2], [-2, 2], [-2, 1]] in [[list(p) for p in hole] for hole in imported.level.holes]


def test_overlapping_and_self_touching_walls_are_merged_and_split(tmp_path: Path) -> None:
    """Overlapping rectangles merge into one hole; a polygon touching itself at a vertex is split."""
    data = json_map()
    data["layers"][1]["objects"] = [
        {"id": 1, "x": -160, "y": 32, "width": 64, "height": 32},
        {"id": 2, "x": -128, "y": 32, "width": 64, "height": 32},
        {
            "id": 3,
            "x": -64,
            "y": 0,
            "polygon": [
                {"x": x * 32, "y": y * 32} for x, y in [(0, 1), (1, 1), (1, 2), (2, 2), (2, 3), (1, 3), (1, 2), (0, 2)]
            ],
        },
    ]
    imported = import_map(write_json(tmp_path, data))
    assert "split 1 self-touching ring" in imported.summary()
    parse_level(level_to_data(imported.level))
    grid = Scene.from_level(imported.level).grid
    assert np.array_equal(grid.traversable, tiles_mask(4, 6, [(1, 1), (2, 1), (3, 1), (4, 1), (5, 2)]))


def test_boundary_object_replaces_the_floor(tmp_path: Path) -> None:
    """With a boundary object the free area is the boundary (an L here) minus the walls; tiles are ignored."""
    data = json_map()
    boundary = [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)]
    data["layers"].append(
        {
            "type": "objectgroup",
            "name": "Outline",
            "objects": [
                {
                    "id": 9,
                    "x": 0,
                    "y": 0,
                    "class": "boundary",
                    "polygon": [{"x": x * 32, "y": y * 32} for x, y in boundary],
                }
            ],
        }
    )
    data["layers"][1]["objects"] = []
    data["layers"][2]["objects"] = []
    imported = import_map(write_json(tmp_path, data))
    assert imported.level.bounds == (0.0, 0.0, 4.0, 3.0)
    assert shapely.equals(imported.level.free_area(), Polygon(boundary))
    assert "free area from 1 boundary object" in imported.summary()


def test_spawn_in_a_wall_is_dropped_and_reported(tmp_path: Path) -> None:
    """A guard marked inside a wall does not become a start; the summary says so."""
    data = json_map()
    data["layers"][2]["objects"][0].update(x=-112, y=48)
    imported = import_map(write_json(tmp_path, data))
    assert imported.level.starts == ()
    assert "dropped spawn (-3.5, 1.5): not on the free area" in imported.summary()


BAD_TILED = {
    "broken-xml": (
        "map.tmx",
        '<?xml version="1.0"?>\n<map orientation="orthogonal">\n <layer>\n</map>\n',
        "line 4, column 2",
    ),
    "not-a-map-xml": ("map.tmx", "<tileset/>", "a tileset, not a map"),
    "isometric": ("map.tmx", '<map orientation="isometric" tilewidth="1" tileheight="1"/>', "'isometric'"),
    "json-syntax": ("map.json", '{"orientation": "orthogonal",\n "layers": [}', "line 2 column"),
    "bad-tile-count": (
        "map.tmx",
        '<map orientation="orthogonal" tilewidth="8" tileheight="8"><layer name="F" width="2" height="2">'
        '<data encoding="csv">1,1,1</data></layer></map>',
        "layer 'F': tile data has 3 tiles, expected 4",
    ),
    "zstd": (
        "map.json",
        json.dumps(
            {
                "orientation": "orthogonal",
                "tilewidth": 8,
                "tileheight": 8,
                "layers": [
                    {
                        "type": "tilelayer",
                        "name": "F",
                        "width": 1,
                        "height": 1,
                        "encoding": "base64",
                        "compression": "zstd",
                        "data": "AA==",
                    }
                ],
            }
        ),
        "zstd compression is not supported",
    ),
    "template": (
        "map.tmx",
        '<map orientation="orthogonal" tilewidth="8" tileheight="8"><objectgroup name="W">'
        '<object id="7" template="wall.tx" x="0" y="0"/></objectgroup></map>',
        "layer 'W' object 7: template wall.tx not found",
    ),
    "bad-polygon-point": (
        "map.tmx",
        '<map orientation="orthogonal" tilewidth="8" tileheight="8"><objectgroup name="W">'
        '<object id="3" x="0" y="0"><polygon points="0,0 8,x 8,8"/></object></objectgroup></map>',
        "layer 'W' object 3 polygon: point 2 is '8,x', not two numbers",
    ),
    "malformed-polygon-points": (
        "map.tmx",
        '<map orientation="orthogonal" tilewidth="8" tileheight="8"><objectgroup name="W">'
        '<object id="4" x="0" y="0"><polygon points="0,0 16,0,5 3,3"/></object></objectgroup></map>',
        "layer 'W' object 4 polygon: point 2 is '16,0,5', not x,y",
    ),
    "nan-polyline-point": (
        "map.tmx",
        '<map orientation="orthogonal" tilewidth="8" tileheight="8"><objectgroup name="W">'
        '<object id="5" x="0" y="0"><polyline points="0,0 nan,1"/></object></objectgroup></map>',
        "layer 'W' object 5 polyline: point 2 is 'nan,1', not two finite numbers",
    ),
    "no-floor": (
        "map.json",
        json.dumps({"orientation": "orthogonal", "tilewidth": 8, "tileheight": 8, "layers": []}),
        "no floor",
    ),
}


@pytest.mark.parametrize("case", list(BAD_TILED))
def test_bad_tiled_map_is_one_error_naming_file_and_place(tmp_path: Path, case: str) -> None:
    """Each malformed map raises a LevelError naming the file and the line, layer or object at fault."""
    name, text, fragment = BAD_TILED[case]
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LevelError) as caught:
        import_map(path)
    assert str(caught.value).startswith(f"{path}: ")
    assert fragment in str(caught.value)


def test_a_level_file_named_like_a_map_loads_as_a_level_and_the_tiled_reader_refuses_it(tmp_path: Path) -> None:
    path = tmp_path / "map.json"
    path.write_text('{"outer": [[0, 0], [4, 0], [4, 4], [0, 4]]}', encoding="utf-8")
    records: list[object] = []
    assert load_level(path, report=records.append).outer == ((0, 0), (4, 0), (4, 4), (0, 4)) and records == []
    with pytest.raises(LevelError, match=f"^{re.escape(str(path))}: .*not a Tiled JSON map"):
        import_tiled(path)


def test_missing_external_tileset_is_a_note_not_an_error(tmp_path: Path) -> None:
    """A tileset file that is not there only costs its tile properties, and the summary says so."""
    data = json_map(tilesets=[{"firstgid": 1, "source": "gone.tsx"}])
    imported = import_map(write_json(tmp_path, data))
    assert "tileset gone.tsx not found" in imported.summary()


def test_import_command_with_spawn_tiles(tmp_path: Path) -> None:
    """`guardsim import map.tmx --spawn-tile 4` marks tile id 4 as a guard spawn."""
    path = tmp_path / "rotated.tmx"
    path.write_text(TMX_ROTATED.replace('<tile id="2" type="guard"/>', ""), encoding="utf-8")
    out = tmp_path / "level.json"
    result = CliRunner().invoke(main, ["import", str(path), "--out", str(out), "--spawn-tile", "3"])
    assert result.exit_code == 0, result.output
    assert "1 guard spawn" in result.stdout
    assert json.loads(out.read_text())["starts"] == [[4.5, 1.5]]


def test_gzip_base64_layer_reads_like_csv(tmp_path: Path) -> None:
    """The same floor stored as base64 gzip data gives the same level as CSV."""
    import gzip

    ground = np.ones(24, dtype="<u4")
    ground[2 * 6 + 3] = 2
    encoded = base64.b64encode(gzip.compress(ground.tobytes())).decode("ascii")
    csv_block = TMX_ROTATED[TMX_ROTATED.index('<layer id="1"') : TMX_ROTATED.index('<layer id="2"')]
    gzip_block = (
        '<layer id="1" name="Ground" width="6" height="4">\n'
        f'  <data encoding="base64" compression="gzip">{encoded}</data>\n </layer>\n '
    )
    csv_path, gzip_path = tmp_path / "csv.tmx", tmp_path / "gzip.tmx"
    csv_path.write_text(TMX_ROTATED, encoding="utf-8")
    gzip_path.write_text(TMX_ROTATED.replace(csv_block, gzip_block), encoding="utf-8")
    assert level_to_data(import_map(gzip_path).level)["holes"] == level_to_data(import_map(csv_path).level)["holes"]


def test_compressed_data_is_not_inflated_past_what_the_layer_needs(tmp_path: Path) -> None:
    """50 MB of zeros in 50 kB of zlib data, declared as a 2 x 2 layer, is an error, not 50 MB of memory."""
    bomb = base64.b64encode(zlib.compress(bytes(50_000_000), 9)).decode("ascii")
    data = {
        "orientation": "orthogonal",
        "tilewidth": 8,
        "tileheight": 8,
        "layers": [
            {
                "type": "tilelayer",
                "name": "F",
                "width": 2,
                "height": 2,
                "encoding": "base64",
                "compression": "zlib",
                "data": bomb,
            }
        ],
    }
    with pytest.raises(LevelError, match="tile data has 5 tiles, expected 4"):
        import_map(write_json(tmp_path, data))


@pytest.fixture(scope="module")
def rotated_patrol(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The rotated map with no typed spawn tile, and a patrol planned on it."""
    folder = tmp_path_factory.mktemp("rotated")
    path = folder / "rotated.tmx"
    path.write_text(TMX_ROTATED.replace('<tile id="2" type="guard"/>', ""), encoding="utf-8")
    result = CliRunner().invoke(main, ["patrol", str(path), "--out", str(folder / "p")])
    assert result.exit_code == 0, result.output
    return path, folder / "p" / "patrol.json"


@pytest.mark.parametrize("command", ["patrol", "sneak", "alert", "check"])
def test_commands_that_take_a_map_take_the_import_options(
    tmp_path: Path, rotated_patrol: tuple[Path, Path], command: str
) -> None:
    """Every command that reads a level takes a map with the import options: ``--spawn-tile 3`` makes the
    marker tile a guard spawn (the import's summary says so), where the same run without it finds none."""
    path, patrol = rotated_patrol
    arguments = {
        "patrol": ["--out", str(tmp_path / "p")],
        "sneak": ["--patrol", str(patrol), "--from", "0.5,3.5", "--to", "5.5,3.5", "--out", str(tmp_path / "s")],
        "alert": ["--patrol", str(patrol), "--intruder", "still", "--from", "0.5,3.5", "--max-seconds", "2"],
        "check": ["--max-cover-steps", "100"],
    }[command]
    told = CliRunner().invoke(main, [command, str(path), *arguments, "--spawn-tile", "3"])
    assert told.exit_code == 0, told.output
    assert "1 guard spawn from 1 spawn tile (gids 3)" in told.stderr
    plain = CliRunner().invoke(main, [command, str(path), *arguments])
    assert plain.exit_code == 0, plain.output
    assert "0 guard spawns" in plain.stderr


def test_bounds_reads_a_map_with_its_spawn_tile(tmp_path: Path) -> None:
    """`guardsim bounds map.tmx --spawn-tile 3`: the import's summary names the spawn it was told of."""
    path = tmp_path / "rotated.tmx"
    path.write_text(TMX_ROTATED.replace('<tile id="2" type="guard"/>', ""), encoding="utf-8")
    result = CliRunner().invoke(main, ["bounds", str(path), "--spawn-tile", "3"])
    assert result.exit_code == 0, result.output
    assert "1 guard spawn" in result.stderr


def test_an_empty_tmx_is_not_valid_xml(tmp_path: Path) -> None:
    """An empty .tmx has no content to tell its format by: its name says XML, and the error says so."""
    path = tmp_path / "empty.tmx"
    path.write_bytes(b"")
    result = CliRunner().invoke(main, ["import", str(path), "--out", str(tmp_path / "x.json")])
    assert result.exit_code == 2
    assert "empty.tmx: not valid XML" in result.stderr and "JSON" not in result.stderr
