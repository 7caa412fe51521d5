"""Collision however real Tiled maps mark it (issue: Tiled conventions): properties of any type named like
collision, tile and object classes, --wall-property and --wall-class, tile objects and image tiles at
their real footprint (rotation, flips, size), flip bits in gids, tileset images without a size, player
starts kept apart from guard spawns, and a missing tileset named in the warning.

Every map here is written twice, as TMX and as Tiled JSON, from one description, and checked cell by
cell: the walls are exactly the cells marked.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import pytest
import shapely
from shapely.geometry.base import BaseGeometry

from guardsim.errors import LevelError
from guardsim.importers.tiled_roles import truth, wall_mark, words
from guardsim.level import Level
from tests.common import assert_one_line_error, import_map, load_any, run

SIZE = 8
"""Maps are SIZE x SIZE tiles of TILE pixels."""
TILE = 16
FORMATS = ["tmx", "json"]
H, V, D = 0x80000000, 0x40000000, 0x20000000
"""Tiled's flip bits in a stored gid: horizontal, vertical, diagonal."""


@dataclass
class Tile:
    """A tile a tileset says something about."""

    id: int
    kind: str = ""
    old_type: bool = False
    """Write the class as ``type`` (Tiled before 1.9)."""
    props: list[tuple[str, str, Any]] = field(default_factory=list)
    """``(name, type, value)``: type is ``bool``, ``int``, ``float`` or ``string``."""
    image: tuple[str, int | None, int | None] | None = None
    """``(source, width, height)`` of a tile of a collection of images (a size of None is left out)."""
    shapes: list[tuple[float, float, float, float]] = field(default_factory=list)
    """Collision rectangles ``(x, y, width, height)`` in the tile's pixels."""


@dataclass
class Tileset:
    firstgid: int
    name: str
    tiles: list[Tile] = field(default_factory=list)
    size: tuple[int, int] = (TILE, TILE)
    image: tuple[str, int | None, int | None] | None = ("atlas.png", 4 * TILE, 4 * TILE)
    """The tileset's single image; None for a collection of images."""
    source: str = ""
    """An external tileset file to refer to instead (not written here)."""


@dataclass
class Obj:
    id: int
    x: float
    y: float
    w: float | None = None
    h: float | None = None
    name: str = ""
    kind: str = ""
    old_type: bool = False
    gid: int | None = None
    rotation: float = 0.0
    props: list[tuple[str, str, Any]] = field(default_factory=list)
    point: bool = False


@dataclass
class TileLayer:
    name: str
    cells: dict[tuple[int, int], int]
    """(col, row) -> stored gid (flip bits included)."""
    encoding: str = "csv"
    """``csv`` or ``xml`` (TMX <tile gid> elements; JSON always writes a list)."""


@dataclass
class ObjectLayer:
    name: str
    objects: list[Obj]


GROUND = Tileset(1, "ground", image=("ground.png", TILE, TILE))
FLOOR = TileLayer("Ground", {(col, row): 1 for col in range(SIZE) for row in range(SIZE)})


def _value(kind: str, value: Any) -> str:
    return ("true" if value else "false") if kind == "bool" else str(value)


def _tmx_properties(props: list[tuple[str, str, Any]]) -> str:
    if not props:
        return ""
    items = "".join(
        f'<property name="{name}"'
        + ("" if kind == "string" else f' type="{kind}"')
        + f' value="{_value(kind, value)}"/>'
        for name, kind, value in props
    )
    return f"<properties>{items}</properties>"


def _json_properties(props: list[tuple[str, str, Any]]) -> list[dict[str, Any]]:
    return [{"name": name, "type": kind, "value": value} for name, kind, value in props]


def _tmx_image(image: tuple[str, int | None, int | None]) -> str:
    source, width, height = image
    size = "" if width is None else f' width="{width}" height="{height}"'
    return f'<image source="{source}"{size}/>'


def to_tmx(tilesets: list[Tileset], layers: list[TileLayer | ObjectLayer]) -> str:
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<map version="1.10" orientation="orthogonal" renderorder="right-down" width="{SIZE}" height="{SIZE}" '
        f'tilewidth="{TILE}" tileheight="{TILE}" infinite="0">',
    ]
    for tileset in tilesets:
        if tileset.source:
            out.append(f'<tileset firstgid="{tileset.firstgid}" source="{tileset.source}"/>')
            continue
        columns = 0 if tileset.image is None else 4
        out.append(
            f'<tileset firstgid="{tileset.firstgid}" name="{tileset.name}" tilewidth="{tileset.size[0]}" '
            f'tileheight="{tileset.size[1]}" tilecount="16" columns="{columns}">'
        )
        if tileset.image is not None:
            out.append(_tmx_image(tileset.image))
        for tile in tileset.tiles:
            kind = f' {"type" if tile.old_type else "class"}="{tile.kind}"' if tile.kind else ""
            body = _tmx_properties(tile.props)
            if tile.image is not None:
                body += _tmx_image(tile.image)
            if tile.shapes:
                body += '<objectgroup draworder="index">' + "".join(
                    f'<object id="{n + 1}" x="{x}" y="{y}" width="{w}" height="{h}"/>'
                    for n, (x, y, w, h) in enumerate(tile.shapes)
                )
                body += "</objectgroup>"
            out.append(f'<tile id="{tile.id}"{kind}>{body}</tile>')
        out.append("</tileset>")
    for number, layer in enumerate(layers, start=1):
        if isinstance(layer, TileLayer):
            gids = [layer.cells.get((col, row), 0) for row in range(SIZE) for col in range(SIZE)]
            out.append(f'<layer id="{number}" name="{layer.name}" width="{SIZE}" height="{SIZE}">')
            if layer.encoding == "xml":
                out.append("<data>" + "".join(f'<tile gid="{gid}"/>' if gid else "<tile/>" for gid in gids) + "</data>")
            else:
                out.append(f'<data encoding="csv">{",".join(map(str, gids))}</data>')
            out.append("</layer>")
        else:
            out.append(f'<objectgroup id="{number}" name="{layer.name}">')
            for item in layer.objects:
                attributes = f'id="{item.id}" x="{item.x}" y="{item.y}"'
                if item.name:
                    attributes += f' name="{item.name}"'
                if item.kind:
                    attributes += f' {"type" if item.old_type else "class"}="{item.kind}"'
                if item.gid is not None:
                    attributes += f' gid="{item.gid}"'
                if item.w is not None:
                    attributes += f' width="{item.w}" height="{item.h}"'
                if item.rotation:
                    attributes += f' rotation="{item.rotation}"'
                body = _tmx_properties(item.props) + ("<point/>" if item.point else "")
                out.append(f"<object {attributes}>{body}</object>")
            out.append("</objectgroup>")
    out.append("</map>")
    return "\n".join(out) + "\n"


def to_json(tilesets: list[Tileset], layers: list[TileLayer | ObjectLayer]) -> str:
    sets: list[dict[str, Any]] = []
    for tileset in tilesets:
        if tileset.source:
            sets.append({"firstgid": tileset.firstgid, "source": tileset.source})
            continue
        raw: dict[str, Any] = {
            "firstgid": tileset.firstgid,
            "name": tileset.name,
            "tilewidth": tileset.size[0],
            "tileheight": tileset.size[1],
            "tilecount": 16,
            "columns": 0 if tileset.image is None else 4,
            "margin": 0,
            "spacing": 0,
            "tiles": [],
        }
        if tileset.image is not None:
            raw["image"] = tileset.image[0]
            if tileset.image[1] is not None:
                raw["imagewidth"], raw["imageheight"] = tileset.image[1], tileset.image[2]
        for tile in tileset.tiles:
            entry: dict[str, Any] = {"id": tile.id}
            if tile.kind:
                entry["type" if tile.old_type else "class"] = tile.kind
            if tile.props:
                entry["properties"] = _json_properties(tile.props)
            if tile.image is not None:
                entry["image"] = tile.image[0]
                if tile.image[1] is not None:
                    entry["imagewidth"], entry["imageheight"] = tile.image[1], tile.image[2]
            if tile.shapes:
                entry["objectgroup"] = {
                    "type": "objectgroup",
                    "name": "",
                    "draworder": "index",
                    "objects": [
                        {"id": n + 1, "x": x, "y": y, "width": w, "height": h, "rotation": 0, "visible": True}
                        for n, (x, y, w, h) in enumerate(tile.shapes)
                    ],
                }
            raw["tiles"].append(entry)
        sets.append(raw)
    out_layers: list[dict[str, Any]] = []
    for number, layer in enumerate(layers, start=1):
        common = {"id": number, "name": layer.name, "opacity": 1, "visible": True, "x": 0, "y": 0}
        if isinstance(layer, TileLayer):
            gids = [layer.cells.get((col, row), 0) for row in range(SIZE) for col in range(SIZE)]
            out_layers.append({**common, "type": "tilelayer", "width": SIZE, "height": SIZE, "data": gids})
        else:
            objects = []
            for item in layer.objects:
                raw_object: dict[str, Any] = {
                    "id": item.id,
                    "name": item.name,
                    "x": item.x,
                    "y": item.y,
                    "width": item.w or 0,
                    "height": item.h or 0,
                    "rotation": item.rotation,
                    "visible": True,
                }
                if item.kind:
                    raw_object["type" if item.old_type else "class"] = item.kind
                if item.gid is not None:
                    raw_object["gid"] = item.gid
                if item.props:
                    raw_object["properties"] = _json_properties(item.props)
                if item.point:
                    raw_object["point"] = True
                objects.append(raw_object)
            out_layers.append({**common, "type": "objectgroup", "draworder": "topdown", "objects": objects})
    data = {
        "type": "map",
        "version": "1.10",
        "orientation": "orthogonal",
        "renderorder": "right-down",
        "width": SIZE,
        "height": SIZE,
        "tilewidth": TILE,
        "tileheight": TILE,
        "infinite": False,
        "tilesets": sets,
        "layers": out_layers,
    }
    return json.dumps(data)


def write(folder: Path, fmt: str, tilesets: list[Tileset], layers: list[TileLayer | ObjectLayer]) -> Path:
    path = folder / f"map.{fmt}"
    sets = [GROUND, *tilesets]
    path.write_text(to_tmx(sets, [FLOOR, *layers]) if fmt == "tmx" else to_json(sets, [FLOOR, *layers]))
    return path


def blocked_cells(level: Level) -> set[tuple[int, int]]:
    """The map's cells whose centre is not on the level's free area."""
    free = cast(BaseGeometry, level.free_area())
    return {
        (col, row)
        for col in range(SIZE)
        for row in range(SIZE)
        if not free.contains(shapely.Point(col + 0.5, row + 0.5))
    }


def wall_cells(path: Path, **options: Any) -> set[tuple[int, int]]:
    """The blocked cells of the map imported with ``options``."""
    return blocked_cells(import_map(path, **options).level)


def block(cols: range, rows: range) -> set[tuple[int, int]]:
    return {(col, row) for col in cols for row in rows}


# -- 1. collision properties of any type, on tiles and objects ------------------------------------------

MARKED = {(1, 1), (2, 1), (5, 4), (6, 6)}


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("name", "kind", "value", "wall"),
    [
        ("CollisionShape", "int", 1, True),
        ("IsBlocking", "bool", True, True),
        ("collides", "bool", True, True),
        ("collidable", "string", "yes", True),
        ("solid", "string", "1", True),
        ("Solid", "string", "TRUE", True),
        ("blocked", "float", 2.5, True),
        ("isWall", "bool", True, True),
        ("CollisionShape", "int", 0, False),
        ("IsBlocking", "bool", False, False),
        ("solid", "string", "no", False),
        ("solid", "string", "false", False),
        ("solid", "string", "", False),
        ("solid", "string", "granite", False),
        ("no_collision", "bool", True, False),
        ("wallpaper", "bool", True, False),
    ],
)
def test_a_tile_property_of_any_type_named_like_collision_marks_walls(
    tmp_path: Path, fmt: str, name: str, kind: str, value: Any, wall: bool
) -> None:
    things = Tileset(2, "things", [Tile(0, props=[(name, kind, value)])])
    path = write(tmp_path, fmt, [things], [TileLayer("Decor", dict.fromkeys(MARKED, 2))])
    assert wall_cells(path) == (MARKED if wall else set())


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("name", "kind", "value", "wall"),
    [
        ("CollisionShape", "int", 1, True),
        ("IsBlocking", "bool", True, True),
        ("collidable", "string", "true", True),
        ("solid", "int", 0, False),
        ("Blocking", "string", "no", False),
    ],
)
def test_an_object_property_of_any_type_named_like_collision_marks_it_a_wall(
    tmp_path: Path, fmt: str, name: str, kind: str, value: Any, wall: bool
) -> None:
    items = [Obj(1, 16, 32, 32, 16, name="crate", props=[(name, kind, value)]), Obj(2, 96, 96, 16, 16, name="rug")]
    path = write(tmp_path, fmt, [], [ObjectLayer("Things", items)])
    assert wall_cells(path) == ({(1, 2), (2, 2)} if wall else set())


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_tile_whose_own_property_opts_out_is_no_wall_even_in_a_wall_layer(tmp_path: Path, fmt: str) -> None:
    """As phaser-dungeon-crawler-ts draws its dungeons: a layer named 'Walls' whose decoration tiles say
    collides=false (the game collides only with collides=true)."""
    things = Tileset(2, "things", [Tile(0), Tile(1, props=[("collides", "bool", False)])])
    path = write(tmp_path, fmt, [things], [TileLayer("Walls", {(1, 1): 2, (2, 1): 3, (3, 1): 2})])
    assert wall_cells(path) == {(1, 1), (3, 1)}


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_object_with_a_property_named_for_the_player_is_the_player_start(tmp_path: Path, fmt: str) -> None:
    """As Lost-In-The-Dark marks its start: a point among the spawns with player_spawn = "player_spawn"."""
    items = [
        Obj(1, 24, 24, point=True, props=[("player_spawn", "string", "player_spawn")]),
        Obj(2, 72, 72, point=True, props=[("player", "bool", False)]),
    ]
    imported = import_map(write(tmp_path, fmt, [], [ObjectLayer("Spawn", items)]))
    assert imported.player_starts == ((1.5, 1.5),)
    assert [tuple(point) for point in imported.level.starts] == [(4.5, 4.5)]


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_floor_where_the_guard_fits_on_no_cell_is_said(tmp_path: Path, fmt: str) -> None:
    """As bevy_ecs_tiled's samples draw theirs: every tile carries a collision shape, leaving slivers."""
    slab = Tileset(2, "slab", [Tile(0, shapes=[(0.0, 0.0, float(TILE), TILE - 2.0)])])
    covered = {(col, row): 2 for col in range(SIZE) for row in range(SIZE)}
    # A level no guard can stand in is refused (every command would refuse it), saying why.
    with pytest.raises(LevelError, match="fits on no cell of the free area: every floor tile"):
        import_map(write(tmp_path, fmt, [slab], [FLOOR, TileLayer("Decor", covered)]))
    # A floor with room says nothing of the kind.
    roomy = import_map(write(tmp_path, fmt, [slab], [FLOOR, TileLayer("Decor", {(0, 0): 2})]))
    assert not [w for w in roomy.warnings if "fits on no cell" in w]


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_false_collision_property_opts_an_object_out_of_a_wall_layer(tmp_path: Path, fmt: str) -> None:
    items = [Obj(1, 16, 16, 16, 16), Obj(2, 64, 64, 16, 16, props=[("CollisionShape", "int", 0)])]
    path = write(tmp_path, fmt, [], [ObjectLayer("Collision", items)])
    assert wall_cells(path) == {(1, 1)}


def test_names_split_into_words_including_camel_case() -> None:
    assert words("CollisionShape") == {"collision", "shape"}
    assert words("IsBlocking") == {"is", "blocking"}
    assert words("Player_Start") == {"player", "start"} == words("PlayerStart")
    assert words("NPCWall") == {"npc", "wall"}


def test_property_values_read_true_or_false_whatever_their_type() -> None:
    assert [truth(value) for value in (True, 1, 0.5, "yes", " 1 ", "True")] == [True] * 6
    assert [truth(value) for value in (False, 0, 0.0, "no", "0", "false", "")] == [False] * 7
    assert truth("granite") is None and truth(None) is None
    assert wall_mark({"collision": "yes", "solid": False}) is True
    assert wall_mark({"sprite": "wall.png"}) is None


# -- classes --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("old_type", [False, True], ids=["class", "type"])
@pytest.mark.parametrize("kind", ["wall", "Solid", "CollisionBox", "SolidWall"])
def test_a_tile_class_saying_wall_makes_its_tiles_walls(tmp_path: Path, fmt: str, old_type: bool, kind: str) -> None:
    things = Tileset(2, "things", [Tile(0, kind=kind, old_type=old_type), Tile(1, kind="Flower")])
    path = write(tmp_path, fmt, [things], [TileLayer("Decor", {(3, 3): 2, (4, 3): 2, (6, 1): 3})])
    assert wall_cells(path) == {(3, 3), (4, 3)}


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("old_type", [False, True], ids=["class", "type"])
def test_an_object_class_saying_wall_makes_it_a_wall(tmp_path: Path, fmt: str, old_type: bool) -> None:
    items = [
        Obj(1, 0, 0, 16, 32, kind="Collider", old_type=old_type),
        Obj(2, 48, 48, 16, 16, kind="solid", old_type=old_type),
        Obj(3, 96, 96, 16, 16, kind="Chest", old_type=old_type),
    ]
    path = write(tmp_path, fmt, [], [ObjectLayer("Objects", items)])
    assert wall_cells(path) == {(0, 0), (0, 1), (3, 3)}


# -- 2. --wall-property and --wall-class -------------------------------------------------------------------

ROCKS = {(1, 1), (1, 2)}
GRASS = {(5, 5)}
SOLID = {(6, 1)}


def _terrain_map(folder: Path, fmt: str) -> Path:
    things = Tileset(
        2,
        "terrain",
        [
            Tile(0, props=[("terrain", "string", "Rock")]),
            Tile(1, props=[("terrain", "string", "grass")]),
            Tile(2, props=[("solid", "bool", True)]),
            Tile(3, props=[("height", "int", 2), ("Blocking", "bool", True)]),
            Tile(4, kind="Crate"),
        ],
    )
    cells = {**dict.fromkeys(ROCKS, 2), **dict.fromkeys(GRASS, 3), **dict.fromkeys(SOLID, 4), (3, 6): 5, (0, 7): 6}
    items = [Obj(1, 96, 48, 16, 16, kind="crate"), Obj(2, 96, 96, 16, 16, props=[("terrain", "string", "rock")])]
    return write(folder, fmt, [things], [TileLayer("Decor", cells), ObjectLayer("Things", items)])


@pytest.mark.parametrize("fmt", FORMATS)
def test_wall_property_name_equals_value_replaces_the_guess_from_property_names(tmp_path: Path, fmt: str) -> None:
    path = _terrain_map(tmp_path, fmt)
    assert wall_cells(path) == SOLID | {(3, 6)}  # guessed: solid, Blocking
    # Tiles and objects whose terrain is rock (any case); the solid and Blocking tiles are no longer guessed.
    assert wall_cells(path, wall_properties=["terrain=rock"]) == ROCKS | {(6, 6)}
    assert wall_cells(path, wall_properties=["height=2"]) == {(3, 6)}
    assert wall_cells(path, wall_properties=["height=2.0", "terrain=grass"]) == {(3, 6)} | GRASS


@pytest.mark.parametrize("fmt", FORMATS)
def test_wall_property_name_alone_takes_a_true_value(tmp_path: Path, fmt: str) -> None:
    path = _terrain_map(tmp_path, fmt)
    assert wall_cells(path, wall_properties=["Blocking"]) == {(3, 6)}


@pytest.mark.parametrize("fmt", FORMATS)
def test_wall_class_makes_tiles_and_objects_of_that_class_walls(tmp_path: Path, fmt: str) -> None:
    path = _terrain_map(tmp_path, fmt)
    assert wall_cells(path, wall_classes=["CRATE"]) == SOLID | {(3, 6), (0, 7), (6, 3)}


@pytest.mark.parametrize("fmt", FORMATS)
def test_overrides_that_match_nothing_are_warnings(tmp_path: Path, fmt: str) -> None:
    imported = import_map(
        _terrain_map(tmp_path, fmt), wall_properties=["colour", "terrain=lava"], wall_classes=["Boulder"]
    )
    joined = "\n".join(imported.warnings)
    assert "--wall-property colour: no tile or object has a property 'colour'" in joined
    assert "--wall-property terrain=lava: no tile or object's 'terrain' matches" in joined
    assert "--wall-class Boulder: no tile or object has this class" in joined


def test_the_overrides_pass_through_load_any(tmp_path: Path) -> None:
    path = _terrain_map(tmp_path, "tmx")
    level, _ = load_any(path, wall_properties=("terrain=rock",), wall_classes=("crate",))
    assert blocked_cells(level) == ROCKS | {(6, 6), (0, 7), (6, 3)}


@pytest.mark.parametrize("bad", ["=x", "  =rock", "terrain="])
def test_a_malformed_wall_property_is_a_level_error_in_the_library(tmp_path: Path, bad: str) -> None:
    from guardsim.errors import LevelError

    with pytest.raises(LevelError, match="--wall-property"):
        import_map(_terrain_map(tmp_path, "tmx"), wall_properties=[bad])


# -- 3. tile objects and image tiles at their real footprint ----------------------------------------------

HOUSE = 64
"""A house image of 64 x 64 pixels: 4 x 4 tiles of the map."""


def _houses(shapes: list[tuple[float, float, float, float]] | None = None, image: bool = True) -> Tileset:
    size: tuple[int, int] = (HOUSE, HOUSE)
    tile = Tile(0, kind="wall", image=("house.png", HOUSE, HOUSE) if image else ("house.png", None, None))
    if shapes:
        tile = Tile(0, image=tile.image, shapes=shapes)
    return Tileset(20, "houses", [tile], size=size, image=None)


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_tile_object_of_an_image_tile_covers_the_image(tmp_path: Path, fmt: str) -> None:
    """The house stands on its anchor (x, y) = its bottom-left corner: columns 1-4, rows 2-5."""
    path = write(tmp_path, fmt, [_houses()], [ObjectLayer("Props", [Obj(1, 16, 96, HOUSE, HOUSE, gid=20)])])
    assert wall_cells(path) == block(range(1, 5), range(2, 6))


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_tile_object_without_a_size_takes_its_image_size(tmp_path: Path, fmt: str) -> None:
    path = write(tmp_path, fmt, [_houses()], [ObjectLayer("Props", [Obj(1, 16, 96, gid=20)])])
    assert wall_cells(path) == block(range(1, 5), range(2, 6))


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_scaled_tile_object_covers_its_own_size(tmp_path: Path, fmt: str) -> None:
    path = write(tmp_path, fmt, [_houses()], [ObjectLayer("Props", [Obj(1, 0, 128, 32, 96, gid=20)])])
    assert wall_cells(path) == block(range(0, 2), range(2, 8))


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("rotation", "cols", "rows"),
    [
        (0, range(2, 4), range(0, 4)),  # x 32-64, y 0-64
        (90, range(2, 6), range(4, 6)),  # right of the anchor and below it: x 32-96, y 64-96
        (180, range(0, 2), range(4, 8)),  # left of it and below: x 0-32, y 64-128
        (-90, range(0, 2), range(2, 4)),  # left of it and above: x -32-32 (the map starts at 0), y 32-64
    ],
)
def test_a_rotated_tile_object_turns_about_its_bottom_left_corner(
    tmp_path: Path, fmt: str, rotation: float, cols: range, rows: range
) -> None:
    """A 32 x 64 image placed at (32, 64), its bottom-left corner, turned clockwise about that point."""
    tall = Tileset(20, "posts", [Tile(0, kind="wall", image=("post.png", 32, 64))], size=(32, 64), image=None)
    path = write(tmp_path, fmt, [tall], [ObjectLayer("Props", [Obj(1, 32, 64, 32, 64, gid=20, rotation=rotation)])])
    assert wall_cells(path) == block(cols, rows)


SHAPE_LEFT = [(0.0, 0.0, 32.0, 64.0)]
"""A collision shape over the left half of the 64 x 64 house."""
SHAPE_TOP = [(0.0, 0.0, 64.0, 32.0)]


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("shapes", "flips", "cols", "rows"),
    [
        (SHAPE_LEFT, 0, range(1, 3), range(2, 6)),
        (SHAPE_LEFT, H, range(3, 5), range(2, 6)),
        (SHAPE_LEFT, V, range(1, 3), range(2, 6)),
        (SHAPE_TOP, V, range(1, 5), range(4, 6)),
        (SHAPE_TOP, H, range(1, 5), range(2, 4)),
        (SHAPE_LEFT, D, range(1, 5), range(2, 4)),
        (SHAPE_LEFT, D | H, range(1, 5), range(2, 4)),
        (SHAPE_LEFT, D | V, range(1, 5), range(4, 6)),
    ],
    ids=["plain", "h", "v", "top-v", "top-h", "d", "dh", "dv"],
)
def test_a_tile_objects_collision_shapes_are_flipped_with_it(
    tmp_path: Path, fmt: str, shapes: list[tuple[float, float, float, float]], flips: int, cols: range, rows: range
) -> None:
    gid = 20 | flips
    path = write(tmp_path, fmt, [_houses(shapes)], [ObjectLayer("Walls", [Obj(1, 16, 96, HOUSE, HOUSE, gid=gid)])])
    assert wall_cells(path) == block(cols, rows)


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_rotated_tile_objects_collision_shapes_turn_with_it(tmp_path: Path, fmt: str) -> None:
    # The house's left half, turned 90 degrees clockwise about the anchor (16, 64): x 16-80, y 64-96.
    items = [Obj(1, 16, 64, HOUSE, HOUSE, gid=20, rotation=90)]
    path = write(tmp_path, fmt, [_houses(SHAPE_LEFT)], [ObjectLayer("Walls", items)])
    assert wall_cells(path) == block(range(1, 5), range(4, 6))


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_image_tile_in_a_tile_layer_stands_on_its_cell_at_its_size(tmp_path: Path, fmt: str) -> None:
    """Tiled draws a tile bigger than the grid from its cell's bottom-left corner, up and to the right."""
    path = write(tmp_path, fmt, [_houses()], [TileLayer("Decor", {(2, 6): 20})])
    assert wall_cells(path) == block(range(2, 6), range(3, 7))
    assert "1 image tile at image size" in import_map(path).summary()


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(("flips", "cols"), [(0, range(0, 1)), (H, range(1, 2))], ids=["plain", "h"])
def test_flipped_tiles_in_a_tile_layer_flip_their_collision_shapes(
    tmp_path: Path, fmt: str, flips: int, cols: range
) -> None:
    # A 32 x 16 tile (two map tiles wide) whose shape covers its left half.
    wide = Tileset(2, "wide", [Tile(0, shapes=[(0.0, 0.0, 16.0, 16.0)])], size=(32, 16))
    path = write(tmp_path, fmt, [wide], [TileLayer("Decor", {(0, 3): 2 | flips})])
    assert wall_cells(path) == block(cols, range(3, 4))


# -- 4. flip bits never make a gid invalid --------------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("bits", [H, V, D, H | V | D], ids=["h", "v", "d", "hvd"])
def test_a_flipped_tile_object_is_its_tile(tmp_path: Path, fmt: str, bits: int) -> None:
    path = write(tmp_path, fmt, [_houses()], [ObjectLayer("Props", [Obj(1, 16, 96, HOUSE, HOUSE, gid=20 | bits)])])
    assert wall_cells(path) == block(range(1, 5), range(2, 6))


@pytest.mark.parametrize(("fmt", "encoding"), [("tmx", "csv"), ("tmx", "xml"), ("json", "csv")])
def test_flipped_tiles_in_a_tile_layer_are_their_tiles(tmp_path: Path, fmt: str, encoding: str) -> None:
    things = Tileset(2, "things", [Tile(0, kind="wall")])
    cells = {(1, 1): 2 | H, (2, 1): 2 | V, (3, 1): 2 | D, (4, 1): 2 | H | V | D, (5, 1): 2}
    path = write(tmp_path, fmt, [things], [TileLayer("Decor", cells, encoding)])
    assert wall_cells(path) == set(cells)


# -- 5. a tileset image without width and height -----------------------------------------------------------


def test_a_tileset_image_without_a_size_loads(tmp_path: Path) -> None:
    things = Tileset(2, "things", [Tile(0, kind="wall")], image=("old.png", None, None))
    ground = Tileset(1, "ground", image=("ground.png", None, None))
    text = to_tmx([ground, things], [FLOOR, TileLayer("Decor", {(2, 2): 2})])
    path = tmp_path / "old.tmx"
    path.write_text(text)
    imported = import_map(path)
    assert not imported.warnings or all("size" not in warning for warning in imported.warnings)
    assert wall_cells(path) == {(2, 2)}


@pytest.mark.parametrize("fmt", FORMATS)
def test_an_image_tile_without_a_size_is_said_only_where_the_size_is_needed(tmp_path: Path, fmt: str) -> None:
    # With its own size the tile object needs nothing from the image.
    sized = write(tmp_path, fmt, [_houses(image=False)], [ObjectLayer("Props", [Obj(1, 16, 96, HOUSE, HOUSE, gid=20)])])
    assert wall_cells(sized) == block(range(1, 5), range(2, 6))
    assert not [warning for warning in import_map(sized).warnings if "size" in warning]
    # Without: one line says so, and the tileset's tile size (the largest image, 64 x 64) stands in.
    bare = write(tmp_path, fmt, [_houses(image=False)], [ObjectLayer("Props", [Obj(1, 16, 96, gid=20)])])
    lines = [warning for warning in import_map(bare).warnings if "no width or height" in warning]
    assert len(lines) == 1 and "tileset 'houses'" in lines[0] and "\n" not in lines[0]
    assert wall_cells(bare) == block(range(1, 5), range(2, 6))


# -- 6. player starts ------------------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
def test_player_starts_are_never_guard_spawns(tmp_path: Path, fmt: str) -> None:
    items = [
        Obj(1, 24, 24, name="player", point=True),
        Obj(2, 40, 24, name="Hero", point=True),
        Obj(3, 56, 24, name="PlayerStart", point=True),
        Obj(4, 72, 24, name="Player_Start", point=True),
        Obj(5, 88, 24, kind="PLAYER", point=True),
        Obj(6, 104, 104, name="guard", point=True),
        Obj(7, 24, 104, point=True),
    ]
    path = write(tmp_path, fmt, [], [ObjectLayer("Spawns", items)])
    imported = import_map(path)
    assert imported.player_starts == ((1.5, 1.5), (2.5, 1.5), (3.5, 1.5), (4.5, 1.5), (5.5, 1.5))
    assert [tuple(point) for point in imported.level.starts] == [(6.5, 6.5), (1.5, 6.5)]
    assert "5 player starts (1.5, 1.5) from 'player' in 'Spawns'" in imported.summary()
    assert "2 guard spawns" in imported.summary()


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_map_with_only_a_player_start_has_no_guard_start(tmp_path: Path, fmt: str) -> None:
    path = write(tmp_path, fmt, [], [ObjectLayer("Objects", [Obj(1, 40, 40, 16, 16, name="Player Start")])])
    imported = import_map(path)
    assert imported.player_starts == ((3.0, 3.0),)
    assert not imported.level.starts and "0 guard spawns" in imported.summary()


# -- 7. a missing external tileset ----------------------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_missing_tileset_is_named_in_the_warning_that_walls_may_be_missing(tmp_path: Path, fmt: str) -> None:
    missing = Tileset(2, "", source="walls.tsx")
    path = write(tmp_path, fmt, [missing], [TileLayer("Decor", {(2, 2): 2})])
    warnings = import_map(path).warnings
    named = [warning for warning in warnings if "walls.tsx" in warning]
    assert len(named) == 1 and named[0].startswith("no walls found") and "not found" in named[0]


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_missing_tileset_is_a_warning_even_when_other_walls_are_found(tmp_path: Path, fmt: str) -> None:
    missing = Tileset(2, "", source="walls.tsx")
    # A wall all round the map, so that no other warning says walls may be missing.
    ring = [Obj(1, 0, 0, 128, 16), Obj(2, 0, 112, 128, 16), Obj(3, 0, 0, 16, 128), Obj(4, 112, 0, 16, 128)]
    path = write(tmp_path, fmt, [missing], [ObjectLayer("Walls", ring)])
    named = [warning for warning in import_map(path).warnings if "walls.tsx" in warning]
    assert named == ["walls may be missing: tileset 'walls.tsx' not found, so walls its tiles mark are missing"]


# -- the command line ----------------------------------------------------------------------------------


def test_import_takes_wall_property_and_wall_class(tmp_path: Path) -> None:
    path = _terrain_map(tmp_path, "tmx")
    out = tmp_path / "level.json"
    result = run("import", path, "--out", out, "--wall-property", "terrain=rock", "--wall-class", "crate")
    assert result.exit_code == 0, result.output
    level, _ = load_any(out)
    assert blocked_cells(level) == ROCKS | {(6, 6), (0, 7), (6, 3)}


def test_other_commands_take_the_options_too(tmp_path: Path) -> None:
    path = _terrain_map(tmp_path, "json")
    result = run("validate", path, "--wall-property", "terrain=lava")
    assert "--wall-property terrain=lava: no tile or object's 'terrain' matches" in result.stderr


@pytest.mark.parametrize(
    ("args", "phrase"),
    [
        (["--wall-property", "=x"], "'=x' has no property name"),
        (["--wall-property", "terrain="], "no value after '='"),
        (["--wall-class", ""], "expected a class name"),
        (["--wall-class", "  "], "expected a class name"),
    ],
)
def test_malformed_options_are_one_line_errors(tmp_path: Path, args: list[str], phrase: str) -> None:
    path = _terrain_map(tmp_path, "tmx")
    option = args[0]
    line = assert_one_line_error(run("import", path, "--out", tmp_path / "o.json", *args), option)
    assert phrase in line
