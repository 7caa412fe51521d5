"""The corpus of real game maps beside the project (``../shared/maps/corpus``), each checked tile by tile.

Every map under ``../shared/maps/corpus/tiled`` is listed in :data:`MAPS` with what its own layers mark: which
tile layers are the floor, which layers, tile properties, tile collision shapes and objects are walls,
how many spawn and player objects it holds; or the phrase of the one-line refusal it must get. The
sources, commits and licences are in ``tests/data/maps/SOURCES.md`` and the corpus's own SOURCES.md.

The maps are read here independently of guardsim's importer (ElementTree and json only: :func:`read_map`
and :func:`read_marks`), and for each map that imports, the guard's grid (``Scene.from_level(level).grid``)
must agree with that reading cell by cell (one tile is one cell):

* no traversable cell on a wall, and none off the floor (the void);
* every open floor cell traversable, except whole parts the importer leaves out because they hold no
  guard spawn (it says so in the summary);
* cells whose centre lies within the guard's radius of a wall drawn off the tile grid (collision shapes,
  hand-placed objects) are not judged either way: whether the guard fits there is geometry, not marking;
* a map that marks no walls must import with the "no walls found" warning, not silently as an empty box.

A map the importer reads wrong is marked ``xfail(strict=True)`` with what is wrong (:data:`WRONG`, and
:data:`MISSED_PLAYER` for player starts), so fixing the importer turns it into a failure to remove the
mark. ``docs/maps.md`` holds the table of outcomes;
``GUARDSIM_UPDATE_MAPS_DOC=1 python -m pytest -m slow tests/test_map_corpus.py -n 0 -k docs`` rewrites it.
"""

from __future__ import annotations

import base64
import gzip
import json
import os
import re
import zlib
from collections import deque
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np
import pytest
import shapely
from shapely import affinity

from guardsim.errors import LevelError
from guardsim.importers import ImportedLevel
from guardsim.scene import Scene
from tests.common import CORPUS as SHARED_CORPUS
from tests.common import import_map, needs_shared

ROOT = Path(__file__).resolve().parents[1]
CORPUS = SHARED_CORPUS / "tiled"
DOC = ROOT / "docs" / "maps.md"
Cell = tuple[int, int]
# The map files are third-party data kept beside the clone (../shared/maps/corpus/SOURCES.md).
pytestmark = needs_shared(CORPUS)

# --------------------------------------------------------------------------------------------------
# What each map marks, read from its layers and tilesets.


@dataclass(frozen=True)
class Marks:
    """How one map marks its floor, walls, spawns and player, in its own terms."""

    floor: tuple[str, ...] = ()
    """Tile layers whose tiles are the ground. Empty for a side view: every cell of the map is open air."""
    void_tile: int = 0
    """A tile painting the void around the level in a floor layer (not floor)."""
    wall_layers: tuple[str, ...] = ()
    """Tile layers every tile of which is solid."""
    wall_property: str = ""
    """A tile property that marks solid tiles when true, in any layer (only ``layer_flag`` opts a layer out)."""
    layer_flag: str = ""
    """A tile layer property that makes every tile of the layer solid when true, none when false."""
    shapes: bool = False
    """Tiles with collision shapes are solid where the shapes are, in any layer not opted out.

    A solid tile (of any kind above) is solid where its collision shapes are if it has any, else whole."""
    wall_objects: tuple[str, ...] = ()
    """Object layers whose areas (and tile objects) are walls..."""
    object_names: tuple[str, ...] = ()
    """...only the objects with these names, if given..."""
    object_property: str = ""
    """...only the objects with this property true, if given."""
    spawns: int = 0
    """Objects the map places where guards or enemies start (guardsim may keep fewer: some stand on walls)."""
    players: int = 0
    """Objects the map names as the player's start."""
    refused: str = ""
    """A phrase of the one-line refusal the map must get, if it cannot be imported."""
    source: str = ""
    """The repository (a key of :data:`REPOSITORIES`)."""


@dataclass(frozen=True)
class Repository:
    url: str
    licence: str


REPOSITORIES = {
    "tiled": Repository("https://github.com/mapeditor/tiled", "samples; art PD/CC0/CC-BY 3.0 (see LICENSE)"),
    "phaser-dungeon-crawler-ts": Repository("https://github.com/edwinjoseph/phaser-dungeon-crawler-ts", "MIT"),
    "tinka8-game-dev": Repository("https://github.com/Tinka8/game-dev", "MIT"),
    "community-rpg": Repository("https://github.com/pythonarcade/community-rpg", "MIT"),
    "arcade": Repository("https://github.com/pythonarcade/arcade", "MIT"),
    "excalibur-tiled": Repository("https://github.com/excaliburjs/excalibur-tiled", "BSD-2-Clause"),
    "bevy_ecs_tiled": Repository("https://github.com/adrien-bon/bevy_ecs_tiled", "MIT"),
    "rs-tiled": Repository("https://github.com/mapeditor/rs-tiled", "MIT"),
    "sneaktime": Repository("https://github.com/micha31r/sneaktime", "MIT"),
    "love-top-down-shooter": Repository("https://github.com/remyroez/love-top-down-shooter", "MIT"),
    "lost-in-the-dark": Repository("https://github.com/lcoronelr/Lost-In-The-Dark", "MIT"),
    "pygame_tutorials": Repository("https://github.com/kidscancode/pygame_tutorials", "MIT"),
    "dungeons-of-lua": Repository("https://github.com/ikeasamoahansah/dungeons-of-lua", "CC0-1.0"),
}

#: Maps that import wrong: why (each is an ``xfail(strict=True)``). None today.
WRONG: dict[str, str] = {}
#: Maps whose player start the importer misses: why.
MISSED_PLAYER: dict[str, str] = {}

PHASER = Marks(("Floors",), wall_property="collides", spawns=2, source="phaser-dungeon-crawler-ts")
SNEAKTIME = Marks(("Tile Layer 1",), wall_objects=("Walls 1", "Walls 2"), source="sneaktime")
CITY = Marks(("Ground", "Ground Level 2"), layer_flag="solid", shapes=True, players=1, source="excalibur-tiled")
FANTASY = Marks(("Ground",), layer_flag="solid", shapes=True, players=1, source="excalibur-tiled")
RPG = "community-rpg/resources/maps/"
OBSTACLES = "every tile of the floor layer 'Tile Layer 1' is an obstacle"
BEVY = "bevy_ecs_tiled/assets/maps/"
MAPS: dict[str, Marks] = {
    # mapeditor/tiled's own examples.
    "tiled/examples/orthogonal-outside.tmx": Marks(
        ("Ground",), wall_objects=("Objects",), object_property="static", spawns=2, players=1, source="tiled"
    ),
    "tiled/examples/forest/forest.tmx": Marks(
        wall_layers=("platforms",),
        refused="looks like a side view (a platformer), guessed from the layer 'platforms'",
        source="tiled",
    ),
    "tiled/examples/perspective_walls.tmx": Marks(refused="no floor layer", source="tiled"),
    "tiled/examples/hexagonal-mini.tmx": Marks(refused="orientation 'hexagonal' is not supported", source="tiled"),
    "tiled/examples/sticker-knight/map/sandbox.tmx": Marks(refused="no floor layer", source="tiled"),
    "tiled/examples/sticker-knight/map/sandbox2.tmx": Marks(refused="no floor layer", source="tiled"),
    # Top-down games.
    "phaser-dungeon-crawler-ts/public/dungeons/dungeon-01.tmx": PHASER,
    "phaser-dungeon-crawler-ts/public/dungeons/dungeon-01.json": PHASER,
    "tinka8-game-dev/reresources/dungeon-01.tmx": Marks(
        ("Ground",), wall_property="collides", spawns=6, source="tinka8-game-dev"
    ),
    RPG + "dungeon_lvl_three_maze.json": Marks(
        ("floor",), wall_layers=("walls_blocking",), shapes=True, source="community-rpg"
    ),
    RPG + "farmhouse.json": Marks(
        ("ground",), wall_layers=("walls_blocking", "furniture_blocking"), shapes=True, source="community-rpg"
    ),
    RPG + "graveyard_dungeon.json": Marks(
        ("floor",), wall_layers=("walls_blocking",), shapes=True, spawns=1, source="community-rpg"
    ),
    RPG + "graveyard_dungeon_second_level.json": Marks(
        ("floor",), wall_layers=("walls_blocking",), shapes=True, source="community-rpg"
    ),
    RPG + "main_map.json": Marks(
        ("ground",),
        wall_layers=("water_blocking", "misc_blocking", "trees_blocking"),
        shapes=True,
        source="community-rpg",
    ),
    "sneaktime/src/resources/maps/tilemap1.tmx": SNEAKTIME,
    "sneaktime/src/resources/maps/tilemap4.json": SNEAKTIME,
    "love-top-down-shooter/art/prototype.tmx": Marks(
        ("ground",),
        wall_property="collidable",
        shapes=True,
        wall_objects=("object",),
        object_property="collidable",
        spawns=5,
        players=1,
        source="love-top-down-shooter",
    ),
    "love-top-down-shooter/art/simple.tmx": Marks(
        ("ground",),
        wall_property="collidable",
        shapes=True,
        wall_objects=("object",),
        object_property="collidable",
        spawns=8,
        players=1,
        source="love-top-down-shooter",
    ),
    "lost-in-the-dark/maps/level1.tmj": Marks(
        ("Tile Layer 1",),
        void_tile=79,
        wall_layers=("walls",),
        wall_objects=("walls",),
        spawns=9,
        players=1,
        source="lost-in-the-dark",
    ),
    "pygame_tutorials/tilemap/working/maps/level1.tmx": Marks(
        ("ground",),
        wall_layers=("walls",),
        wall_objects=("Obstacles",),
        object_names=("wall",),
        spawns=30,
        players=1,
        source="pygame_tutorials",
    ),
    "dungeons-of-lua/assets/maps/dungeon.tmx": Marks(
        ("floor",), wall_layers=("base_wall",), wall_objects=("wall",), spawns=11, source="dungeons-of-lua"
    ),
    "excalibur-tiled/example/formats/example-city.tmx": CITY,
    "excalibur-tiled/example/formats/example-city-infinite-base64-compressed.tmx": CITY,
    "excalibur-tiled/example/formats/example-city-zstd.tmx": Marks(
        refused="zstd compression is not supported", source="excalibur-tiled"
    ),
    "excalibur-tiled/example/formats/example-city.tmj": Marks(
        refused="template cone.tx not found", source="excalibur-tiled"
    ),
    "excalibur-tiled/example/orthogonal/orthogonal.tmx": FANTASY,
    "excalibur-tiled/example/orthogonal-infinite/orthogonal-infinite.tmx": FANTASY,
    "excalibur-tiled/example/orthogonal-infinite/orthogonal-infinite.tmj": Marks(
        refused="template coin.tx is not a JSON (.tj) object template", source="excalibur-tiled"
    ),
    # Side views (platformers).
    "arcade/arcade/resources/assets/tiled_maps/map_with_ladders.json": Marks(
        wall_layers=("Platforms",),
        spawns=3,
        refused="looks like a side view (a platformer), guessed from the layer 'Platforms'",
        source="arcade",
    ),
    # Engine and loader samples: collision shapes of every kind, chunks, flips, templates. bevy_ecs_tiled's
    # physics samples draw obstacles (every tile a collider) on empty cells: no ground.
    BEVY + "orthogonal/finite.tmx": Marks(
        ("Tile Layer 1",), shapes=True, wall_objects=("Collisions",), refused=OBSTACLES, source="bevy_ecs_tiled"
    ),
    BEVY + "orthogonal/infinite.tmx": Marks(
        ("Tile Layer 1",), shapes=True, wall_objects=("Collisions",), refused=OBSTACLES, source="bevy_ecs_tiled"
    ),
    BEVY + "orthogonal/multiple_layers_with_colliders.tmx": Marks(
        ("First layer",),
        shapes=True,
        wall_objects=("Colliders",),
        refused="the walls cover the whole floor",
        source="bevy_ecs_tiled",
    ),
    BEVY + "isometric/finite_diamond.tmx": Marks(
        refused="orientation 'isometric' is not supported", source="bevy_ecs_tiled"
    ),
    "rs-tiled/assets/templates/example.tmx": Marks(("Tile Layer 1",), shapes=True, spawns=4, source="rs-tiled"),
    "rs-tiled/assets/tiled_base64_zlib_infinite.tmx": Marks(("Ground",), source="rs-tiled"),
    "rs-tiled/assets/tiled_flipped.tmx": Marks(("Tile Layer 1",), source="rs-tiled"),
    "rs-tiled/assets/tiled_object_template.tmx": Marks(("Tile Layer 1",), source="rs-tiled"),
}
NAMES = sorted(MAPS)
IMPORTED = [name for name in NAMES if not MAPS[name].refused]
REFUSED = [name for name in NAMES if MAPS[name].refused]

# --------------------------------------------------------------------------------------------------
# An independent reading of a Tiled map: tile layers, tilesets (properties, classes, collision shapes),
# object layers and templates. Pixels throughout; flip bits are kept on the layer's gids.

GID_BITS = 0x0FFFFFFF
FLIP_H, FLIP_V, FLIP_D = 0x80000000, 0x40000000, 0x20000000


@dataclass
class Tile:
    kind: str = ""
    properties: dict[str, Any] = field(default_factory=dict)
    size: tuple[float, float] = (0.0, 0.0)
    shapes: list[shapely.Geometry] = field(default_factory=list)


@dataclass
class MapObject:
    name: str
    kind: str
    properties: dict[str, Any]
    outline: shapely.Geometry | None
    """The area (pixels, rotated): ``None`` for points, polylines and text."""
    gid: int = 0
    """A tile object's tile, with its flip bits."""
    place: tuple[float, ...] = ()
    """A tile object's ``x, y, width, height, rotation`` (pixels; it stands on ``x, y``)."""


@dataclass
class TiledMap:
    orientation: str
    tile_size: tuple[int, int]
    size: tuple[int, int]
    tile_layers: dict[str, dict[Cell, int]] = field(default_factory=dict)
    layer_properties: dict[str, dict[str, Any]] = field(default_factory=dict)
    object_layers: dict[str, list[MapObject]] = field(default_factory=dict)
    tiles: dict[int, Tile] = field(default_factory=dict)
    sources: dict[str, int] = field(default_factory=dict)
    """External tileset file (resolved) -> its first gid in this map."""


def _value(kind: str, text: Any) -> Any:
    if kind == "bool" and isinstance(text, str):
        return text == "true"
    if kind in ("int", "float") and isinstance(text, str):
        return float(text)
    return text


def _xml_properties(node: ElementTree.Element) -> dict[str, Any]:
    found = node.find("properties")
    items = found.findall("property") if found is not None else []
    return {item.get("name", ""): _value(item.get("type", ""), item.get("value", item.text or "")) for item in items}


def _json_properties(items: Any) -> dict[str, Any]:
    if isinstance(items, dict):  # Tiled before 1.2
        return dict(items)
    return {item["name"]: _value(item.get("type", ""), item.get("value")) for item in items or ()}


def _area(attrs: dict[str, Any], points: list[tuple[float, float]] | None, ellipse: bool) -> shapely.Geometry | None:
    """An object's area in pixels: rectangle, ellipse, polygon or tile, rotated about its position."""
    x, y, width, height = (float(attrs.get(key) or 0) for key in ("x", "y", "width", "height"))
    if points is not None:
        area = shapely.Polygon([(x + px, y + py) for px, py in points]) if len(points) > 2 else None
    elif width <= 0 or height <= 0:
        return None
    elif ellipse:
        area = affinity.scale(shapely.Point(x + width / 2, y + height / 2).buffer(1, 16), width / 2, height / 2)
    else:
        top = y - height if int(attrs.get("gid") or 0) else y  # a tile object stands on its position
        area = shapely.box(x, top, x + width, top + height)
    if area is not None and float(attrs.get("rotation") or 0):
        area = affinity.rotate(area, float(attrs["rotation"]), origin=(x, y))
    return None if area is None else area.buffer(0)


def _xml_object(node: ElementTree.Element, folder: Path, tiled: TiledMap | None) -> MapObject:
    attrs: dict[str, Any] = dict(node.attrib)
    properties: dict[str, Any] = {}
    shape_node = node
    if "template" in attrs:
        template = _template(folder / attrs["template"], tiled)
        attrs = {**template.attrib, **attrs}
        properties = _xml_properties(template)
        if not any(node.find(tag) is not None for tag in ("polygon", "polyline", "ellipse", "point")):
            shape_node = template
    properties.update(_xml_properties(node))
    polygon = shape_node.find("polygon")
    points = None
    if polygon is not None:
        points = [(float(a), float(b)) for a, b in (pair.split(",") for pair in polygon.get("points", "").split())]
    open_shape = any(shape_node.find(tag) is not None for tag in ("polyline", "point", "text"))
    outline = None if open_shape else _area(attrs, points, shape_node.find("ellipse") is not None)
    kind = attrs.get("class", attrs.get("type", ""))
    return MapObject(attrs.get("name", ""), kind, properties, outline, int(attrs.get("gid", 0)), _position(attrs))


def _position(attrs: dict[str, Any]) -> tuple[float, ...]:
    return tuple(float(attrs.get(key) or 0) for key in ("x", "y", "width", "height", "rotation"))


def _template(path: Path, tiled: TiledMap | None) -> ElementTree.Element:
    """A ``.tx`` template's object, its ``gid`` renumbered into the map's tilesets."""
    root = ElementTree.parse(path).getroot()
    found = root.find("object")
    assert found is not None, path
    tileset = root.find("tileset")
    if tileset is not None and "gid" in found.attrib and tiled is not None:
        source = str((path.parent / tileset.get("source", "")).resolve())
        gid = int(found.get("gid", 0))
        flips, local = gid & ~GID_BITS, (gid & GID_BITS) - int(tileset.get("firstgid", 1))
        # A template whose tileset the map lacks draws a tile the map cannot name: keep its box only.
        found.set("gid", str((tiled.sources[source] + local) | flips) if source in tiled.sources else "0")
    return found


def _json_object(item: dict[str, Any], folder: Path) -> MapObject:
    if "template" in item:
        template = json.loads((folder / item["template"]).read_text(encoding="utf-8-sig"))["object"]
        merged = {**_json_properties(template.get("properties")), **_json_properties(item.get("properties"))}
        item = {**template, **item, "properties": [{"name": k, "value": v} for k, v in merged.items()]}
    points = [(p["x"], p["y"]) for p in item["polygon"]] if "polygon" in item else None
    open_shape = item.get("point") or "polyline" in item or "text" in item
    outline = None if open_shape else _area(item, points, bool(item.get("ellipse")))
    kind = item.get("class", item.get("type", ""))
    return MapObject(
        item.get("name", ""),
        kind,
        _json_properties(item.get("properties")),
        outline,
        int(item.get("gid", 0)),
        _position(item),
    )


def _xml_tileset(node: ElementTree.Element, folder: Path, first: int, tiles: dict[int, Tile]) -> None:
    size = (float(node.get("tilewidth", 0)), float(node.get("tileheight", 0)))
    for local in range(int(node.get("tilecount", 0))):
        tiles[first + local] = Tile(size=size)
    for item in node.findall("tile"):
        image = item.find("image")
        own = (
            size
            if image is None
            else (float(item.get("width", image.get("width", 0))), float(item.get("height", image.get("height", 0))))
        )
        group = item.find("objectgroup")
        parts = [_xml_object(part, folder, None).outline for part in (group if group is not None else [])]
        kind = item.get("class", item.get("type", ""))
        tiles[first + int(item.get("id", 0))] = Tile(kind, _xml_properties(item), own, [p for p in parts if p])


def _json_tileset(data: dict[str, Any], folder: Path, first: int, tiles: dict[int, Tile]) -> None:
    size = (float(data.get("tilewidth", 0)), float(data.get("tileheight", 0)))
    for local in range(int(data.get("tilecount", 0))):
        tiles[first + local] = Tile(size=size)
    for item in data.get("tiles", ()):
        own = (float(item.get("imagewidth", size[0])), float(item.get("imageheight", size[1])))
        objects = (item.get("objectgroup") or {}).get("objects", ())
        parts = [_json_object(part, folder).outline for part in objects]
        kind = item.get("class", item.get("type", ""))
        tiles[first + int(item["id"])] = Tile(
            kind, _json_properties(item.get("properties")), own, [p for p in parts if p]
        )


def _tileset(tiled: TiledMap, folder: Path, first: int, source: str | None, embedded: Any) -> None:
    if source is None:
        loader = _json_tileset if isinstance(embedded, dict) else _xml_tileset
        loader(embedded, folder, first, tiled.tiles)
        return
    path = folder / source
    tiled.sources[str(path.resolve())] = first
    if path.suffix in (".tsx", ".xml"):
        _xml_tileset(ElementTree.parse(path).getroot(), path.parent, first, tiled.tiles)
    else:
        _json_tileset(json.loads(path.read_text(encoding="utf-8-sig")), path.parent, first, tiled.tiles)


def _gids(text: str, encoding: str | None, compression: str | None) -> list[int]:
    if encoding == "csv":
        return [int(value) for value in text.replace("\n", "").split(",") if value.strip()]
    raw = base64.b64decode(text.strip())
    if compression == "zlib":
        raw = zlib.decompress(raw)
    elif compression == "gzip":
        raw = gzip.decompress(raw)
    return [int(gid) for gid in np.frombuffer(raw, dtype="<u4")]


def _place(gids: list[int], left: int, top: int, width: int) -> dict[Cell, int]:
    return {(left + i % width, top + i // width): gid for i, gid in enumerate(gids) if gid}


def read_map(path: Path) -> TiledMap:
    """The parts of a TMX or Tiled JSON map this test judges by (see :class:`TiledMap`)."""
    if path.suffix == ".tmx":
        root = ElementTree.parse(path).getroot()
        tiled = TiledMap(
            root.get("orientation", ""),
            (int(root.get("tilewidth", 1)), int(root.get("tileheight", 1))),
            (int(root.get("width", 0)), int(root.get("height", 0))),
        )
        for node in root.findall("tileset"):
            _tileset(tiled, path.parent, int(node.get("firstgid", 1)), node.get("source"), node)
        _xml_layers(root, path.parent, "", {}, tiled)
    else:
        data = json.loads(path.read_text(encoding="utf-8-sig"))
        tiled = TiledMap(data["orientation"], (data["tilewidth"], data["tileheight"]), (data["width"], data["height"]))
        for item in data.get("tilesets", ()):
            _tileset(tiled, path.parent, item["firstgid"], item.get("source"), item)
        _json_layers(data["layers"], path.parent, "", {}, tiled)
    return tiled


def _xml_layers(
    node: ElementTree.Element, folder: Path, prefix: str, inherited: dict[str, Any], tiled: TiledMap
) -> None:
    for child in node:
        name, properties = prefix + child.get("name", ""), {**inherited, **_xml_properties(child)}
        if child.tag == "group":
            _xml_layers(child, folder, name + "/", properties, tiled)
        elif child.tag == "layer":
            data = child.find("data")
            assert data is not None, name
            cells: dict[Cell, int] = {}
            for part in data.findall("chunk") or [data]:
                gids = _gids(part.text or "", data.get("encoding"), data.get("compression"))
                width = int(part.get("width", child.get("width", 0)))
                cells.update(_place(gids, int(part.get("x", 0)), int(part.get("y", 0)), width))
            tiled.tile_layers[name], tiled.layer_properties[name] = cells, properties
        elif child.tag == "objectgroup":
            tiled.object_layers[name] = [_xml_object(item, folder, tiled) for item in child.findall("object")]
            tiled.layer_properties[name] = properties


def _json_layers(
    layers: list[dict[str, Any]], folder: Path, prefix: str, inherited: dict[str, Any], tiled: TiledMap
) -> None:
    for layer in layers:
        name, properties = prefix + layer["name"], {**inherited, **_json_properties(layer.get("properties"))}
        if layer["type"] == "group":
            _json_layers(layer["layers"], folder, name + "/", properties, tiled)
        elif layer["type"] == "tilelayer":
            cells: dict[Cell, int] = {}
            for part in layer.get("chunks") or [layer]:
                gids = part["data"]
                if isinstance(gids, str):
                    gids = _gids(gids, "base64", layer.get("compression"))
                cells.update(_place(gids, part.get("x", 0), part.get("y", 0), part["width"]))
            tiled.tile_layers[name], tiled.layer_properties[name] = cells, properties
        elif layer["type"] == "objectgroup":
            tiled.object_layers[name] = [_json_object(item, folder) for item in layer["objects"]]
            tiled.layer_properties[name] = properties


def _flipped(shape: shapely.Geometry, gid: int, width: float, height: float) -> shapely.Geometry:
    """A tile's collision shape as drawn with the gid's flip bits (the diagonal flip first)."""
    if gid & FLIP_D:
        shape = affinity.affine_transform(shape, [0, 1, 1, 0, 0, 0])
    if gid & FLIP_H:
        shape = affinity.affine_transform(shape, [-1, 0, 0, 1, width, 0])
    if gid & FLIP_V:
        shape = affinity.affine_transform(shape, [1, 0, 0, -1, 0, height])
    return shape


# --------------------------------------------------------------------------------------------------
# What the map says about each cell, and what the import made of it.


@dataclass(frozen=True)
class Reading:
    """One map as :data:`MAPS` says to read it, cell by cell (cells are tiles, in the map's coordinates)."""

    floor: frozenset[Cell]
    walls: frozenset[Cell]
    """Floor cells the map makes solid: whole wall tiles, or centres well inside a drawn wall."""
    open: frozenset[Cell]
    """Floor cells clear of every wall by more than the guard's radius: the guard must stand there."""
    unsure: frozenset[Cell]
    """The rest of the floor: a drawn wall's edge passes within the guard's radius of the centre."""
    marked: bool
    """Whether the map marks any wall at all."""


#: Cells whose centre lies this close to a wall drawn off the grid are not judged (the guard's radius
#: is 0.3; vertices move up to 0.04 when snapped)...
FIT_MARGIN = 0.35
#: ...nor those this little inside one.
INSIDE_MARGIN = 0.05


def _solid(tile: Tile, raw: int, place: tuple[float, ...]) -> list[shapely.Geometry]:
    """Where a solid tile blocks (pixels): its collision shapes if it has any, else its whole box.

    ``place`` is ``x, y, width, height, rotation``: the tile is drawn ``width`` by ``height`` standing on
    ``x, y`` (its bottom-left corner) and turned about that point, as tile objects are.
    """
    x, y, width, height, rotation = place
    own_width, own_height = tile.size if all(tile.size) else (width, height)
    shapes = [_flipped(shape, raw, own_width, own_height) for shape in tile.shapes]
    shapes = shapes or [shapely.box(0, 0, own_width, own_height)]
    scale = (width / own_width, height / own_height)
    out = [affinity.translate(affinity.scale(s, *scale, origin=(0, 0)), x, y - height) for s in shapes]
    return [affinity.rotate(s, rotation, origin=(x, y)) for s in out] if rotation else out


def read_marks(path: Path, marks: Marks) -> Reading:
    tiled = read_map(path)
    tw, th = tiled.tile_size
    layers = tiled.tile_layers
    if marks.floor:
        floor = {
            cell for name in marks.floor for cell, gid in layers[name].items() if gid & GID_BITS != marks.void_tile
        }
    else:  # a side view: the open air is every cell of the map
        floor = {(col, row) for col in range(tiled.size[0]) for row in range(tiled.size[1])}
    whole: set[Cell] = set()
    drawn: list[shapely.Geometry] = []

    for name, cells in layers.items():
        flag = tiled.layer_properties[name].get(marks.layer_flag) if marks.layer_flag else None
        for (col, row), raw in cells.items():
            tile = tiled.tiles.get(raw & GID_BITS, Tile(size=(tw, th)))
            solid = name in marks.wall_layers or (marks.layer_flag and flag is True)
            solid = solid or (marks.wall_property and tile.properties.get(marks.wall_property) is True)
            if not (solid or (marks.shapes and tile.shapes)) or flag is False:
                continue
            if tile.shapes:
                drawn.extend(_solid(tile, raw, (col * tw, (row + 1) * th, *tile.size, 0)))
            else:
                whole.add((col, row))
    for name, objects in tiled.object_layers.items():
        for item in objects:
            shown = tiled.tiles.get(item.gid & GID_BITS) if item.gid else None
            chosen = name in marks.wall_objects and (not marks.object_names or item.name in marks.object_names)
            chosen = chosen and (not marks.object_property or item.properties.get(marks.object_property) is True)
            if item.outline is None or not (chosen or (marks.shapes and shown is not None and shown.shapes)):
                continue
            drawn.extend(_solid(shown, item.gid, item.place) if shown is not None else [item.outline])
    drawn = [affinity.scale(shape, 1 / tw, 1 / th, origin=(0, 0)) for shape in drawn if not shapely.is_empty(shape)]

    candidates = sorted(floor - whole)
    inside = np.zeros(len(candidates), dtype=bool)
    near = np.zeros(len(candidates), dtype=bool)
    if drawn and candidates:
        union = shapely.union_all(drawn)
        centres = np.asarray(shapely.points(np.array(candidates, dtype=float) + 0.5))
        close = shapely.STRtree(drawn).query(centres, predicate="dwithin", distance=FIT_MARGIN)[0]
        close = np.unique(close)
        inside[close] = shapely.contains(union, centres[close])
        edge = shapely.distance(union.boundary, centres[close])
        near[close] = np.where(inside[close], edge <= INSIDE_MARGIN, edge <= FIT_MARGIN)
    walls = whole & floor | {cell for cell, i, n in zip(candidates, inside, near) if i and not n}
    unsure = {cell for cell, n in zip(candidates, near) if n}
    return Reading(
        frozenset(floor), frozenset(walls), frozenset(floor - walls - unsure), frozenset(unsure), bool(whole or drawn)
    )


@dataclass(frozen=True)
class Outcome:
    imported: ImportedLevel
    traversable: frozenset[Cell]
    """The grid's traversable cells, in the map's tile coordinates."""


@cache
def outcome(name: str) -> Outcome:
    imported = import_map(CORPUS / name)
    grid = Scene.from_level(imported.level).grid
    left, top = (round(v) for v in imported.level.bounds[:2])
    rows, cols = np.nonzero(grid.traversable)
    return Outcome(imported, frozenset(zip((cols + left).tolist(), (rows + top).tolist())))


@cache
def reading(name: str) -> Reading:
    return read_marks(CORPUS / name, MAPS[name])


def parts(cells: frozenset[Cell]) -> list[set[Cell]]:
    """The 4-connected parts of a set of cells."""
    left = set(cells)
    found = []
    while left:
        part, queue = set(), deque([left.pop()])
        while queue:
            col, row = queue.popleft()
            part.add((col, row))
            for step in ((col + 1, row), (col - 1, row), (col, row + 1), (col, row - 1)):
                if step in left:
                    left.remove(step)
                    queue.append(step)
        found.append(part)
    return found


def sample(cells: set[Cell] | frozenset[Cell]) -> str:
    return f"{len(cells)} cells, e.g. {sorted(cells)[:6]}"


# --------------------------------------------------------------------------------------------------
# The tests.


def test_every_map_in_the_corpus_is_listed_with_its_licence() -> None:
    found = {
        str(path.relative_to(CORPUS))
        for pattern in ("**/*.tmx", "**/*.tmj", "**/*.json")
        for path in CORPUS.glob(pattern)
        if path.suffix != ".json" or "layers" in json.loads(path.read_text(encoding="utf-8-sig"))
    }
    assert found == set(MAPS)
    for name, marks in MAPS.items():
        assert name.split("/")[0] == marks.source and marks.source in REPOSITORIES, name
        assert (CORPUS / marks.source / "LICENSE").is_file(), marks.source
    sources = (CORPUS.parent / "SOURCES.md").read_text(encoding="utf-8")
    missing = [name for name in MAPS if f"`{name}`" not in sources]
    assert not missing, f"{CORPUS.parent}/SOURCES.md does not list {missing}"


@pytest.mark.parametrize("name", REFUSED, ids=REFUSED)
def test_a_map_that_cannot_be_imported_is_refused_in_one_line_naming_it(name: str) -> None:
    with pytest.raises(LevelError) as error:
        import_map(CORPUS / name)
    message = str(error.value)
    assert "\n" not in message and Path(name).name in message and MAPS[name].refused in message, message
    if MAPS[name].floor:  # the refusal's reason, checked against the map itself
        assert not reading(name).open, "the map leaves open floor, yet the import finds none"


SIDE_VIEWS = [name for name in REFUSED if "side view" in MAPS[name].refused]


@pytest.mark.parametrize("name", SIDE_VIEWS, ids=SIDE_VIEWS)
def test_a_side_view_is_refused_saying_how_to_import_it_anyway(name: str) -> None:
    with pytest.raises(LevelError, match="import it with --view top-down"):
        import_map(CORPUS / name)
    assert import_map(CORPUS / name, view="top-down").level.free_area().area > 0


#: Maps whose import and independent reading take seconds (rs-tiled's template sample: 7 627 tile
#: collision shapes; the 100 x 100 city; the maze's shapes): their tests, and the table's that imports
#: every map, run in the slow tier.
HEAVY = frozenset(
    [
        "rs-tiled/assets/templates/example.tmx",
        "excalibur-tiled/example/formats/example-city.tmx",
        RPG + "dungeon_lvl_three_maze.json",
    ]
)


def _walls_cases() -> list[Any]:
    return [
        pytest.param(name, id=name, marks=pytest.mark.xfail(strict=True, reason=WRONG[name]))
        if name in WRONG
        else pytest.param(name, id=name, marks=[pytest.mark.slow] if name in HEAVY else [])
        for name in IMPORTED
    ]


def _imported_cases() -> list[Any]:
    return [pytest.param(name, id=name, marks=[pytest.mark.slow] if name in HEAVY else []) for name in IMPORTED]


@pytest.mark.parametrize("name", _walls_cases())
def test_the_grid_has_walls_exactly_where_the_map_marks_them(name: str) -> None:
    read, result = reading(name), outcome(name)
    walked = result.traversable
    assert walked, result.imported.summary()
    on_wall = walked & read.walls
    assert not on_wall, f"the guard walks on walls the map marks: {sample(on_wall)}"
    in_void = walked - read.floor
    assert not in_void, f"the guard walks off the floor the map draws (the void): {sample(in_void)}"
    dropped = []
    for part in parts(read.open | read.unsure):
        must = part & read.open
        if not must & walked:
            dropped.append(must)
            continue
        blocked = must - walked
        assert not blocked, f"walls where the map marks none: {sample(blocked)}"
    left_out = set().union(*dropped) if dropped else set()
    if left_out:
        # Only whole parts, only when the map has guard spawns or player starts elsewhere: the importer
        # keeps the parts the guards and the player start in, and says so.
        anchored = result.imported.level.starts or result.imported.player_starts
        assert anchored and "left out" in result.imported.summary(), sample(left_out)
    assert len(walked) >= 0.2 * len(read.open), "the guard has only a sliver of the open floor"
    if not read.marked:
        assert any(text.startswith("no walls found") for text in result.imported.warnings)


@pytest.mark.parametrize("name", _imported_cases())
def test_spawns_and_player_starts_are_the_maps_own(name: str) -> None:
    marks, imported = MAPS[name], outcome(name).imported
    assert len(imported.level.starts) <= marks.spawns, "guard starts the map does not place"
    if name in MISSED_PLAYER:
        pytest.xfail(MISSED_PLAYER[name])
    assert len(imported.player_starts) == marks.players


# --------------------------------------------------------------------------------------------------
# docs/maps.md: the table of outcomes.

COLUMNS = "| map | source | licence | walls found | floor cells | spawns | player starts | outcome |"
END = "<!-- end of the table tests/test_map_corpus.py writes -->"
NOTES = sorted(set(WRONG.values()) | set(MISSED_PLAYER.values()))


def table_row(name: str) -> str:
    marks = MAPS[name]
    repo = REPOSITORIES[marks.source]
    link = f"[{marks.source}]({repo.url})"
    if marks.refused:
        return f"| `{name}` | {link} | {repo.licence} | - | - | - | - | refused: {marks.refused} |"
    read, result = reading(name), outcome(name)
    summary = result.imported.summary()
    found = re.search(r"walls from (.*?)(?:; merged|$)", summary)
    walls = found.group(1) if found else "none"
    verdict = f"**wrong** ({NOTES.index(WRONG[name]) + 1})" if name in WRONG else "imports, walls as marked"
    if name in MISSED_PLAYER:
        verdict += f"; player start missed ({NOTES.index(MISSED_PLAYER[name]) + 1})"
    if result.imported.warnings:
        verdict += f"; {len(result.imported.warnings)} warning{'s' if len(result.imported.warnings) > 1 else ''}"
    floor = f"{len(result.traversable)} of {len(read.open | read.unsure)}"
    starts = f"{len(result.imported.level.starts)} of {marks.spawns}"
    return (
        f"| `{name}` | {link} | {repo.licence} | {walls}; {len(read.walls)} floor cells solid | {floor} | {starts} | "
        f"{len(result.imported.player_starts)} | {verdict} |"
    )


def doc_table() -> str:
    """The table of docs/maps.md and its numbered notes (what each wrong import gets wrong)."""
    notes = [f"{number}. {note[0].upper()}{note[1:]}." for number, note in enumerate(NOTES, 1)]
    rows = [COLUMNS, "| --- | --- | --- | --- | ---: | ---: | ---: | --- |", *map(table_row, NAMES)]
    wrong = ["", "What the wrong imports get wrong:", "", *notes] if notes else ["", "No map imports wrong."]
    return "\n".join([*rows, *wrong, "", END])


@pytest.mark.slow
def test_docs_maps_md_holds_the_current_table() -> None:
    text = DOC.read_text(encoding="utf-8")
    start = text.index(COLUMNS)
    end = text.find(END, start)
    end = len(text) if end < 0 else end + len(END)
    table = doc_table()
    if os.environ.get("GUARDSIM_UPDATE_MAPS_DOC") and text[start:end] != table:
        DOC.write_text(text[:start] + table + text[end:], encoding="utf-8")
        pytest.skip("docs/maps.md rewritten")
    assert text[start:end] == table, "docs/maps.md is stale: GUARDSIM_UPDATE_MAPS_DOC=1 rewrites it"
