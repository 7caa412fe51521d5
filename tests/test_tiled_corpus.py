"""Every real Tiled map in ``../shared/maps/tiled`` imports into the level its author drew.

For each map, :data:`AUTHOR` says in plain terms what its own layers mean (read from the maps and
``SOURCES.md`` there, not from the importer's rules): which tile layers hold the floor, which tile
layers and objects are walls, which tile property marks wall tiles, which tile paints the void. The
tests then check, tile by tile, that every cell the guard can reach from its start lies on that floor
and off those walls, that the guard can reach a fair share of the floor, that the walls were found at
all, that the summary names what it guessed, and that spawns were found where the map has them.

The maps are third-party files (licences beside them). CI keeps a copy of ``shared/`` next to the clone;
without it these tests are skipped.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.importers.tiled_data import TiledMap
from guardsim.importers.tiled_read import read_tiled
from guardsim.scene import Scene
from tests.common import load_any

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "maps" / "tiled"
needs_corpus = pytest.mark.skipif(not CORPUS.is_dir(), reason=f"the shared Tiled maps are not at {CORPUS}")


@dataclass(frozen=True)
class Author:
    """What a map's author drew, in the map's own terms."""

    floor: tuple[str, ...]
    """Tile layers whose tiles are the ground."""
    wall_layers: tuple[str, ...] = ()
    """Tile layers every tile of which is a wall."""
    wall_property: str = ""
    """A boolean tile property that marks wall tiles."""
    wall_objects: tuple[str, ...] = ()
    """Object layers whose closed objects are walls."""
    wall_names: tuple[str, ...] = ()
    """If set, only objects with these names in ``wall_objects`` are walls."""
    void_tile: int = 0
    """A tile that paints the void around the level (not floor)."""
    spawns: int = 0
    """Spawn objects the map holds (points or areas guards start from)."""
    guessed: tuple[str, ...] = ()
    """Phrases the summary must contain."""


SNEAKTIME = Author(("Tile Layer 1",), wall_objects=("Walls 1", "Walls 2"), guessed=("'Walls 1', 'Walls 2'",))
TUXEMON = Author(("Tile Layer 1",), wall_objects=("Collisions",), guessed=("in 'Collisions'",))
AUTHOR: dict[str, Author] = {
    "sneaktime_tilemap1.tmx": SNEAKTIME,
    "sneaktime_tilemap1.json": SNEAKTIME,
    "sneaktime_tilemap4.tmx": SNEAKTIME,
    "sneaktime_tilemap4.json": SNEAKTIME,
    "sneaktime_tilemap10.tmx": SNEAKTIME,
    "sneaktime_tilemap10.json": SNEAKTIME,
    "real/Lost-In-The-Dark/maps/level1.tmj": Author(
        ("Tile Layer 1",),
        wall_layers=("walls",),
        wall_objects=("walls",),
        void_tile=79,
        # Its tenth 'Spawn' point carries player_spawn: the player's start, not a guard's.
        spawns=8,
        guessed=("tile 79 fills the edge", "every tile of 'walls'", "8 objects in 'Spawn'", "1 player start"),
    ),
    "real/Tuxemon/mods/tuxemon/maps/candy_town.tmx": TUXEMON,
    "real/Tuxemon/mods/tuxemon/maps/taba_ba_passageway_1.tmx": TUXEMON,
    "real/phaser-3-tilemap-blog-posts/examples/post-1/assets/tilemaps/tuxemon-town.json": Author(
        ("Below Player",), wall_property="collides", spawns=1, guessed=("collision-marked tiles", "in 'Objects'")
    ),
    "real/pygame_tutorials/tilemap/working/maps/level1.tmx": Author(
        ("ground",),
        wall_layers=("walls",),
        wall_objects=("Obstacles",),
        wall_names=("wall",),
        guessed=("every tile of 'walls'", "in 'Obstacles'"),
    ),
    "real/dungeons-of-lua/assets/maps/dungeon.tmx": Author(
        ("floor",), wall_layers=("base_wall",), wall_objects=("wall",), guessed=("every tile of 'base_wall'",)
    ),
    "real/tmwa-client-data/maps/011-3.tmx": Author(
        ("Ground1",), wall_layers=("Collision",), spawns=2, guessed=("every tile of 'Collision'",)
    ),
    "real/tmwa-client-data/maps/009-1.tmx": Author(
        ("Ground1", "Ground2", "Ground3"), wall_layers=("Collision",), spawns=6, guessed=("every tile of 'Collision'",)
    ),
    "real/love-top-down-shooter/art/simple.tmx": Author(
        ("ground",), wall_property="collidable", spawns=8, guessed=("collision-marked tiles", "in 'spawner'")
    ),
    "real/love-top-down-shooter/art/prototype.tmx": Author(
        ("ground",), wall_property="collidable", spawns=1, guessed=("tile collision shapes", "in 'spawner'")
    ),
}
MAPS = sorted(AUTHOR)


def test_every_map_in_the_corpus_is_listed() -> None:
    """A map added to the corpus must say here what its author drew."""
    if not CORPUS.is_dir():
        pytest.skip(f"the shared Tiled maps are not at {CORPUS}")
    found = {
        str(path.relative_to(CORPUS))
        for pattern in ("**/*.tmx", "**/*.tmj", "**/*.json")
        for path in CORPUS.glob(pattern)
    }
    assert found == set(AUTHOR)


def _cells(tiled: TiledMap, names: tuple[str, ...], gids: set[int] | None = None) -> set[tuple[int, int]]:
    """Cells of the named tile layers holding one of ``gids`` (any tile for ``None``)."""
    cells: set[tuple[int, int]] = set()
    for layer in tiled.tile_layers:
        if layer.name in names:
            keep = np.ones(layer.gids.size, dtype=bool) if gids is None else np.isin(layer.gids, list(gids))
            cells |= set(zip(layer.cols[keep].tolist(), layer.rows[keep].tolist()))
    return cells


def author_view(path: Path, author: Author) -> tuple[set[tuple[int, int]], set[tuple[int, int]], shapely.Geometry]:
    """Floor tiles, wall tiles and wall objects (in tiles) exactly as ``author`` describes the map."""
    tiled = read_tiled(path)
    floor = set()
    for layer in tiled.tile_layers:
        if layer.name in author.floor:
            keep = layer.gids != author.void_tile
            floor |= set(zip(layer.cols[keep].tolist(), layer.rows[keep].tolist()))
    walls = _cells(tiled, author.wall_layers)
    if author.wall_property:
        # A layer can opt out (prototype.tmx's ground layer says collidable: false).
        marked = {gid for gid, info in tiled.tiles.items() if info.properties.get(author.wall_property) is True}
        opted_in = tuple(
            layer.name for layer in tiled.tile_layers if layer.properties.get(author.wall_property) is not False
        )
        walls |= _cells(tiled, opted_in, marked)
    scale = np.array([tiled.tile_width, tiled.tile_height])
    shapes = [
        shapely.Polygon(np.asarray(item.outline) / scale)
        for layer in tiled.object_layers
        if layer.name in author.wall_objects
        for item in layer.objects
        if item.closed and (not author.wall_names or item.name in author.wall_names)
    ]
    return floor, walls, shapely.union_all(shapes) if shapes else shapely.Polygon()


def reachable_cells(path: Path) -> tuple[list[tuple[int, int]], str, int]:
    """Tiles (col, row) the guard reaches from its start (or in the largest area), the summary, the spawns."""
    level, imported = load_any(path)
    assert imported is not None
    scene = Scene.from_level(level)
    grid = scene.grid
    if level.guard.start is not None:
        cell = grid.cell_of(level.guard.start)
        assert cell is not None
        reach = grid.component(*cell)
    else:
        reach = grid.largest_component()
    min_x, min_y, _, _ = level.bounds
    rows, cols = np.nonzero(reach)
    # One cell is one tile at cell size 1; the grid starts at the level's (whole-tile) bounds.
    tiles = [(int(col + min_x), int(row + min_y)) for row, col in zip(rows.tolist(), cols.tolist())]
    return tiles, imported.summary(), len(level.starts)


@needs_corpus
@pytest.mark.parametrize("name", MAPS, ids=MAPS)
def test_the_guard_walks_the_floor_the_author_drew_and_never_a_wall(name: str) -> None:
    author = AUTHOR[name]
    path = CORPUS / name
    floor, wall_tiles, wall_shapes = author_view(path, author)
    tiles, summary, _ = reachable_cells(path)
    assert tiles, summary
    near_edge = wall_shapes.boundary if not wall_shapes.is_empty else None
    off_floor, on_wall, in_object = [], [], []
    for col, row in tiles:
        centre = shapely.Point(col + 0.5, row + 0.5)
        if (col, row) not in floor:
            off_floor.append((col, row))
        if (col, row) in wall_tiles:
            on_wall.append((col, row))
        # Hand-placed wall objects off the tile grid decide a cell only when its centre is clearly in them.
        if near_edge is not None and wall_shapes.contains(centre) and near_edge.distance(centre) > 0.05:
            in_object.append((col, row))
    assert not off_floor, f"{len(off_floor)} reachable cells off the floor, e.g. {off_floor[:5]}"
    assert not on_wall, f"{len(on_wall)} reachable cells on wall tiles, e.g. {on_wall[:5]}"
    assert not in_object, f"{len(in_object)} reachable cells inside wall objects, e.g. {in_object[:5]}"
    walkable = {
        cell for cell in floor - wall_tiles if not wall_shapes.contains(shapely.Point(cell[0] + 0.5, cell[1] + 0.5))
    }
    # Not an empty box: the guard has a real share of the floor the author left free.
    assert len(tiles) >= 0.2 * len(walkable), (len(tiles), len(walkable))


@needs_corpus
@pytest.mark.parametrize("name", MAPS, ids=MAPS)
def test_the_summary_names_what_was_guessed(name: str) -> None:
    author = AUTHOR[name]
    _, summary, _ = reachable_cells(CORPUS / name)
    floor_phrase = "floor from " + ", ".join(repr(layer) for layer in author.floor)
    assert floor_phrase in summary
    assert "walls from" in summary and "walls from 0 wall objects (0" not in summary
    for phrase in author.guessed:
        assert phrase in summary, phrase


@needs_corpus
@pytest.mark.parametrize("name", [name for name in MAPS if AUTHOR[name].spawns], ids=str)
def test_spawns_are_found(name: str) -> None:
    _, summary, starts = reachable_cells(CORPUS / name)
    assert f"from {AUTHOR[name].spawns} objects in" in summary or f"{AUTHOR[name].spawns} objects" in summary
    # The count the summary reports is the count of starts the level keeps (each dropped one is named).
    kept = re.search(r"(\d+) guard spawns? from", summary)
    assert kept is not None and int(kept.group(1)) == starts, summary
    assert starts + summary.count("dropped spawn") >= 1


@needs_corpus
@pytest.mark.parametrize(
    "name",
    [
        "real/Lost-In-The-Dark/maps/level1.tmj",
        "real/tmwa-client-data/maps/011-3.tmx",
        "real/love-top-down-shooter/art/prototype.tmx",
    ],
    ids=str,
)
def test_play_takes_the_map_itself_and_writes_a_gif(tmp_path: Path, name: str) -> None:
    """`guardsim play MAP --gif out.gif` imports in memory: no separate import step."""
    gif = tmp_path / "out.gif"
    result = CliRunner().invoke(main, ["play", str(CORPUS / name), "--gif", str(gif), "--max-steps", "300"])
    assert result.exit_code == 0, result.output
    assert gif.stat().st_size > 0
    assert "Tiled map" in result.stderr and "floor from" in result.stderr
