"""Walls, floor and spawns from what real maps use (issue 12): small maps that mark them the ways real
games do, the overrides, the warnings, --strict, templates and tile collision shapes, and every command
taking a map directly."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.errors import LevelError
from guardsim.importers.tiled_roles import words
from guardsim.render.palette import COLOURS
from tests.common import import_map, load_any

TILESET = """ <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="8" columns="4">{tiles}</tileset>
"""


def tmx(body: str, *, width: int = 6, height: int = 6, tiles: str = "") -> str:
    return (
        f'<?xml version="1.0"?>\n<map version="1.10" orientation="orthogonal" width="{width}" height="{height}" '
        f'tilewidth="16" tileheight="16" infinite="0">\n{TILESET.format(tiles=tiles)}{body}</map>\n'
    )


def layer(name: str, rows: list[str], extra: str = "") -> str:
    """A tile layer from rows of characters: a digit is that gid, '.' is empty."""
    gids = [0 if char == "." else int(char) for row in rows for char in row]
    return (
        f' <layer name="{name}" width="{len(rows[0])}" height="{len(rows)}"{extra}>'
        f'<data encoding="csv">{",".join(map(str, gids))}</data></layer>\n'
    )


ROOM = ["111111", "111111", "111111", "111111", "111111", "111111"]
BORDER = ["222222", "2....2", "2....2", "2....2", "2....2", "222222"]


def write(folder: Path, text: str, name: str = "map.tmx") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def free_cells(path: Path, **options: object) -> set[tuple[int, int]]:
    level = import_map(path, **options).level  # type: ignore[arg-type]
    free = level.free_area()
    min_x, min_y, max_x, max_y = (int(v) for v in level.bounds)
    return {
        (col, row)
        for col in range(min_x, max_x)
        for row in range(min_y, max_y)
        if free.contains(shapely.Point(col + 0.5, row + 0.5))
    }


INSIDE = {(col, row) for col in range(1, 5) for row in range(1, 5)}


@pytest.mark.parametrize("name", ["Walls", "base_wall", "Collision", "SOLID stuff", "obstacles", "Blocked"])
def test_a_tile_layer_named_like_walls_is_walls(tmp_path: Path, name: str) -> None:
    path = write(tmp_path, tmx(layer("Ground", ROOM) + layer(name, BORDER)))
    assert free_cells(path) == INSIDE
    assert f"every tile of '{name}'" in import_map(path).summary()


def test_wall_words_are_whole_words() -> None:
    assert "wall" in words("base_wall") and "walls" in words("Walls2")
    assert not words("Wallpaper") & {"wall", "walls"}


def test_a_layer_named_walls_is_never_the_floor_even_when_it_comes_first(tmp_path: Path) -> None:
    """perspective_walls.tmx: the first tile layer is 'Walls'; the floor is the next one."""
    path = write(tmp_path, tmx(layer("Walls", BORDER) + layer("Tiles", ROOM)))
    assert free_cells(path) == INSIDE
    assert "floor from 'Tiles'" in import_map(path).summary()


@pytest.mark.parametrize(
    "tile",
    [
        '<tile id="1" type="wall"/>',
        '<tile id="1" class="Solid"/>',
        '<tile id="1"><properties><property name="collides" type="bool" value="true"/></properties></tile>',
        '<tile id="1"><properties><property name="isWall" type="bool" value="true"/></properties></tile>',
    ],
    ids=["type-wall", "class-solid", "collides", "camel-case-property"],
)
def test_tiles_whose_class_or_property_says_wall(tmp_path: Path, tile: str) -> None:
    path = write(tmp_path, tmx(layer("Ground", ROOM) + layer("Things", BORDER), tiles=tile))
    assert free_cells(path) == INSIDE
    assert "collision-marked tile" in import_map(path).summary()


def test_tile_collision_shapes_are_used_not_the_whole_tile(tmp_path: Path) -> None:
    shape = (
        '<tile id="1"><objectgroup draworder="index">'
        '<object id="1" x="0" y="0" width="16" height="8"/></objectgroup></tile>'
    )
    things = ["......", ".2....", "......", "......", "......", "......"]
    path = write(tmp_path, tmx(layer("Ground", ROOM) + layer("Things", things), tiles=shape))
    imported = import_map(path)
    free = imported.level.free_area()
    assert not free.contains(shapely.Point(1.5, 1.25)) and free.contains(shapely.Point(1.5, 1.75))
    assert "1 tile collision shape" in imported.summary()


def test_object_layers_and_objects_whose_class_says_wall(tmp_path: Path) -> None:
    objects = (
        ' <objectgroup name="Stuff"><object id="1" type="wall" x="0" y="0" width="96" height="16"/>'
        '<object id="2" name="chest" x="32" y="32" width="16" height="16"/></objectgroup>\n'
        ' <objectgroup name="Collisions"><object id="3" x="0" y="80" width="96" height="16"/></objectgroup>\n'
    )
    cells = free_cells(write(tmp_path, tmx(layer("Ground", ROOM) + objects)))
    assert cells == {(col, row) for col in range(6) for row in range(1, 5)}


def test_a_mixed_obstacle_layer_keeps_only_its_walls(tmp_path: Path) -> None:
    """pygame_tutorials: 'Obstacles' holds objects named wall and others named zombie, player."""
    objects = (
        ' <objectgroup name="Obstacles"><object id="1" name="wall" x="0" y="0" width="96" height="16"/>'
        '<object id="2" name="zombie" x="32" y="32" width="16" height="16"/></objectgroup>\n'
    )
    cells = free_cells(write(tmp_path, tmx(layer("Ground", ROOM) + objects)))
    assert (2, 2) in cells and (2, 0) not in cells


def test_a_dungeon_on_a_blank_canvas_is_the_dungeon_and_its_spawns_are_used(tmp_path: Path) -> None:
    """Inside-out: floor tiles in the middle of empty void, spawns as points in a 'Spawn' layer."""
    dungeon = ["......", ".1111.", ".1111.", ".1....", ".1....", "......"]
    spawns = ' <objectgroup name="Spawn"><object id="1" x="24" y="24"><point/></object></objectgroup>\n'
    path = write(tmp_path, tmx(layer("Tiles", dungeon) + spawns))
    imported = import_map(path)
    assert free_cells(path) == {(1, 1), (2, 1), (3, 1), (4, 1), (1, 2), (2, 2), (3, 2), (4, 2), (1, 3), (1, 4)}
    assert imported.level.guard.start == (1.5, 1.5)
    assert "1 guard spawn from 1 objects in 'Spawn'" in imported.summary()


def test_a_painted_void_behind_walls_is_not_floor(tmp_path: Path) -> None:
    """Lost-In-The-Dark: tile 3 paints everything outside the room, and walls line the room."""
    painted = ["333333", "322223", "322223", "322223", "333333", "333333"]
    walls = (
        ' <objectgroup name="walls"><object id="1" x="16" y="16" width="64" height="4"/>'
        '<object id="2" x="16" y="60" width="64" height="4"/><object id="3" x="16" y="16" width="4" height="48"/>'
        '<object id="4" x="76" y="16" width="4" height="48"/></objectgroup>\n'
    )
    path = write(tmp_path, tmx(layer("Tile Layer 1", painted) + walls))
    cells = free_cells(path)
    assert cells == {(col, row) for col in range(1, 5) for row in range(1, 4)}
    assert "tile 3 fills the edge" in import_map(path).summary()


def test_grass_to_the_map_edge_without_walls_between_stays_floor(tmp_path: Path) -> None:
    town = ["111111", "122221", "122221", "111111", "111111", "111111"]
    house = ' <objectgroup name="Collisions"><object id="1" x="80" y="80" width="16" height="16"/></objectgroup>\n'
    cells = free_cells(write(tmp_path, tmx(layer("Tile Layer 1", town) + house)))
    assert (0, 0) in cells and len(cells) == 35


def test_overrides_name_the_layers_and_tiles(tmp_path: Path) -> None:
    rows = ["444444", "4....4", "4....4", "4....4", "4....4", "444444"]
    path = write(tmp_path, tmx(layer("Base", ROOM) + layer("Deco", rows) + layer("Top", BORDER)))
    assert free_cells(path, wall_layers=["Deco"]) == INSIDE
    assert free_cells(path, wall_tiles=[4]) == INSIDE
    with pytest.raises(LevelError, match="no free area"):
        import_map(path, floor_layers=["Deco"], wall_layers=["Top"])


def test_no_walls_is_a_warning_and_a_spawn_tile_that_matches_nothing_too(tmp_path: Path) -> None:
    path = write(tmp_path, tmx(layer("Ground", ROOM)))
    imported = import_map(path, spawn_tiles=[99999])
    assert any(warning.startswith("no walls found") and "--wall-layer" in warning for warning in imported.warnings)
    assert any("--spawn-tile 99999 matches no tile" in warning for warning in imported.warnings)


def test_a_free_area_in_many_small_parts_is_a_warning(tmp_path: Path) -> None:
    split = ["1.1.1.", "1.1.1.", "1.1.1.", "1.1.1.", "1.1.1.", "1.1.1."]
    imported = import_map(write(tmp_path, tmx(layer("Ground", split) + layer("Walls", ["2....."] + ["......"] * 5))))
    assert any("separate parts" in warning for warning in imported.warnings)


def test_templates_are_read_in_tmx_and_json(tmp_path: Path) -> None:
    (tmp_path / "block.tx").write_text(
        '<?xml version="1.0"?>\n<template><object name="block" type="wall" width="96" height="16"/></template>\n',
        encoding="utf-8",
    )
    path = write(
        tmp_path,
        tmx(
            layer("Ground", ROOM)
            + ' <objectgroup name="Things"><object id="4" template="block.tx" x="0" y="0"/></objectgroup>\n'
        ),
    )
    assert (0, 0) not in free_cells(path) and (0, 1) in free_cells(path)
    (tmp_path / "block.tj").write_text(
        json.dumps(
            {
                "type": "template",
                "object": {"name": "block", "type": "wall", "width": 96, "height": 16, "rotation": 0, "visible": True},
            }
        ),
        encoding="utf-8",
    )
    data = {
        "type": "map",
        "orientation": "orthogonal",
        "tilewidth": 16,
        "tileheight": 16,
        "width": 6,
        "height": 6,
        "tilesets": [],
        "layers": [
            {"type": "tilelayer", "name": "Ground", "width": 6, "height": 6, "data": [1] * 36},
            {"type": "objectgroup", "name": "Things", "objects": [{"id": 4, "template": "block.tj", "x": 0, "y": 80}]},
        ],
    }
    cells = free_cells(write(tmp_path, json.dumps(data), "map.json"))
    assert (0, 5) not in cells and (0, 0) in cells


# -- The CLI: every command takes a map, --strict ------------------------------------------------------


@pytest.fixture
def open_map(tmp_path: Path) -> Path:
    """A map with no walls at all: it imports, with a warning."""
    return write(tmp_path, tmx(layer("Ground", ROOM)), "open.tmx")


@pytest.fixture
def walled_map(tmp_path: Path) -> Path:
    return write(tmp_path, tmx(layer("Ground", ROOM) + layer("Walls", BORDER)), "room.tmx")


def test_import_strict_fails_on_warnings_with_status_1_and_writes_nothing(tmp_path: Path, open_map: Path) -> None:
    out = tmp_path / "level.json"
    relaxed = CliRunner().invoke(main, ["import", str(open_map), "--out", str(out)])
    assert relaxed.exit_code == 0 and "guardsim: warning:" in relaxed.stderr and out.exists()
    out.unlink()
    strict = CliRunner().invoke(main, ["import", str(open_map), "--out", str(out), "--strict"])
    assert strict.exit_code == 1 and not out.exists()
    assert strict.stderr.splitlines()[-1].startswith("guardsim: error:") and "--strict" in strict.stderr


def test_validate_takes_a_map_and_strict_fails_on_its_warnings(open_map: Path, walled_map: Path) -> None:
    result = CliRunner().invoke(main, ["validate", str(walled_map)])
    assert result.exit_code == 0, result.output
    assert f"{walled_map}: ok" in result.stdout and "Tiled map" in result.stderr
    assert CliRunner().invoke(main, ["validate", str(open_map)]).exit_code == 0
    assert CliRunner().invoke(main, ["validate", str(open_map), "--strict"]).exit_code == 1


def test_play_and_render_take_maps_and_their_import_options(tmp_path: Path, walled_map: Path) -> None:
    """The map is played as imported: the trace's grid is the map's, its walk stays inside the walls and
    sees all 16 inside cells; the GIF has a frame a tick; the preview's walls are where the map has them."""
    import imageio.v3 as iio

    gif, png, trace_path = tmp_path / "out.gif", tmp_path / "out.png", tmp_path / "t.json"
    played = CliRunner().invoke(main, ["play", str(walled_map), "--gif", str(gif), "--trace", str(trace_path)])
    assert played.exit_code == 0, played.output
    trace = json.loads(trace_path.read_text(encoding="utf-8"))
    assert trace["shape"] == [6, 6] and trace["reachable"] == 16 and trace["outcome"] == "covered"
    traversable = {(col, row) for row, line in enumerate(trace["traversable"]) for col, on in enumerate(line) if on}
    assert traversable == INSIDE
    assert {tuple(cell) for cell in trace["path"]} <= INSIDE
    frames = iio.imread(gif, index=None)
    assert frames.shape[0] == trace["steps"] + 1
    rendered = CliRunner().invoke(main, ["render", str(walled_map), "--png", str(png), "--wall-layer", "Walls"])
    assert rendered.exit_code == 0, rendered.output
    assert "6 x 6 cells, 16 traversable, 16 reachable, 0 unreachable" in rendered.stdout
    image = iio.imread(png)[:, :, :3]
    reachable = np.all(image == COLOURS["reachable"], axis=2).sum()
    walls = np.all(image == COLOURS["wall"], axis=2).sum()
    # 16 of the 36 cells are reachable floor (less the grid lines), the 20 round them wall.
    assert 0.5 * walls < reachable < walls


def test_bench_and_regress_take_maps(tmp_path: Path, walled_map: Path) -> None:
    """bench runs its episodes on the imported map (starts inside the walls, all 16 cells reachable);
    regress stores the map's references, passes on the same map and fails once a wall tile is added."""
    import csv

    benched = CliRunner().invoke(main, ["bench", str(walled_map), "--episodes", "2", "--out", str(tmp_path / "b")])
    assert benched.exit_code == 0, benched.output
    with (tmp_path / "b" / "results.csv").open(encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    assert [row["episode"] for row in rows] == ["0", "1"]
    for row in rows:
        assert row["level_file"] == str(walled_map) and row["reachable"] == "16" and row["outcome"] == "covered"
        assert (int(row["start_col"]), int(row["start_row"])) in INSIDE
    renders = tmp_path / "renders"
    updated = CliRunner().invoke(main, ["regress", str(walled_map), "--renders", str(renders), "--update"])
    assert updated.exit_code == 0, updated.output
    assert "references written" in updated.stdout
    again = CliRunner().invoke(main, ["regress", str(walled_map), "--renders", str(renders)])
    assert again.exit_code == 0, again.output
    assert "room.tmx: ok" in again.stdout
    pillar = ["222222", "2....2", "2.2..2", "2....2", "2....2", "222222"]
    write(tmp_path, tmx(layer("Ground", ROOM) + layer("Walls", pillar)), "room.tmx")
    changed = CliRunner().invoke(main, ["regress", str(walled_map), "--renders", str(renders)])
    assert changed.exit_code == 1, changed.output


def test_a_tiled_json_is_told_from_a_guardsim_level_by_content(tmp_path: Path) -> None:
    tiled = {
        "type": "map",
        "orientation": "orthogonal",
        "tilewidth": 16,
        "tileheight": 16,
        "width": 2,
        "height": 1,
        "layers": [{"type": "tilelayer", "name": "Ground", "width": 2, "height": 1, "data": [1, 1]}],
    }
    level, imported = load_any(write(tmp_path, json.dumps(tiled), "tiled.json"))
    assert imported is not None and level.bounds == (0.0, 0.0, 2.0, 1.0)
    plain = {"outer": [[0, 0], [3, 0], [3, 3], [0, 3]]}
    level, imported = load_any(write(tmp_path, json.dumps(plain), "level.json"))
    assert imported is None and level.bounds == (0.0, 0.0, 3.0, 3.0)


def test_a_resized_template_instance_keeps_its_own_size_and_the_templates_properties(tmp_path: Path) -> None:
    """Tiled stores what the instance changed; the instance wins, the rest comes from the template."""
    (tmp_path / "block.tx").write_text(
        '<?xml version="1.0"?>\n<template><object name="block" type="crate" width="96" height="16">'
        '<properties><property name="collision" type="bool" value="true"/></properties></object></template>\n',
        encoding="utf-8",
    )
    objects = ' <objectgroup name="Things"><object id="4" template="block.tx" x="0" y="0" width="32"/></objectgroup>\n'
    cells = free_cells(write(tmp_path, tmx(layer("Ground", ROOM) + objects)))
    assert (0, 0) not in cells and (1, 0) not in cells and (2, 0) in cells and (0, 1) in cells
    (tmp_path / "block.tj").write_text(
        json.dumps(
            {
                "type": "template",
                "object": {
                    "name": "block",
                    "type": "crate",
                    "width": 96,
                    "height": 16,
                    "rotation": 0,
                    "visible": True,
                    "properties": [{"name": "collision", "type": "bool", "value": True}],
                },
            }
        ),
        encoding="utf-8",
    )
    data = {
        "type": "map",
        "orientation": "orthogonal",
        "tilewidth": 16,
        "tileheight": 16,
        "width": 6,
        "height": 6,
        "tilesets": [],
        "layers": [
            {"type": "tilelayer", "name": "Ground", "width": 6, "height": 6, "data": [1] * 36},
            {
                "type": "objectgroup",
                "name": "Things",
                "objects": [{"id": 4, "template": "block.tj", "x": 0, "y": 0, "width": 32}],
            },
        ],
    }
    cells = free_cells(write(tmp_path, json.dumps(data), "map.json"))
    assert (0, 0) not in cells and (1, 0) not in cells and (2, 0) in cells


def test_a_tile_template_counts_its_tile_in_the_maps_tilesets(tmp_path: Path) -> None:
    """A template's tile id is relative to the template's own tileset; the map loads that tileset at 5."""
    (tmp_path / "t.tsx").write_text(
        '<?xml version="1.0"?>\n<tileset name="t" tilewidth="16" tileheight="16" tilecount="4" columns="2">'
        '<tile id="1"><properties><property name="collision" type="bool" value="true"/></properties></tile>'
        "</tileset>\n",
        encoding="utf-8",
    )
    (tmp_path / "crate.tx").write_text(
        '<?xml version="1.0"?>\n<template><tileset firstgid="1" source="t.tsx"/>'
        '<object name="crate" gid="2" width="16" height="16"/></template>\n',
        encoding="utf-8",
    )
    text = tmx(
        layer("Ground", ROOM)
        + ' <objectgroup name="Things"><object id="9" template="crate.tx" x="32" y="48"/></objectgroup>\n'
    )
    text = text.replace("</tileset>\n", '</tileset>\n <tileset firstgid="5" source="t.tsx"/>\n', 1)
    cells = free_cells(write(tmp_path, text))
    # Tile objects hang from their bottom-left corner: (32, 48) is the bottom-left of cell (2, 2).
    assert (2, 2) not in cells and len(cells) == 35


def test_guardsims_own_route_layer_is_neither_walls_nor_spawns(tmp_path: Path) -> None:
    """`patrol --tiled-out` writes routes as polylines in a layer 'guardsim' (class guardsim_route); even
    inside a group whose name says guards, re-importing must not make walls or spawns of them."""
    route = (
        '<object id="{id}" name="route 0" type="guardsim_route" x="24" y="24">'
        '<polyline points="0,0 48,0 48,48 0,48 0,0"/></object>'
    )
    body = (
        layer("Ground", ROOM)
        + layer("Walls", BORDER)
        + f' <group name="Guards"><objectgroup name="guardsim">{route.format(id=1)}</objectgroup>'
        + f'<objectgroup name="patrol">{route.format(id=2)}</objectgroup></group>\n'
    )
    path = write(tmp_path, tmx(body, tiles='<tile id="1" type="wall"/>'))
    imported = import_map(path)
    assert free_cells(path) == INSIDE
    assert imported.level.guard.start is None
    assert "spawns from" not in imported.summary()
