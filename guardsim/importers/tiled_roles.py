"""What each part of a Tiled map is for a guard: floor, wall or spawn, from the evidence real maps carry.

Most game maps mark nothing for guardsim, so the roles are read from what their authors did mark, in
this order of evidence (``docs/authoring.md``):

**Walls**

1. Collision marks: a boolean property ``collision`` (or ``collides``, ``collidable``, ``solid``,
   ``blocked``, ``obstacle``, ``wall``) on an object, a tile, or a layer (``false`` opts out).
2. Tile layers whose name says wall (the whole words :data:`WALL_WORDS`, any case: ``Walls 1``,
   ``base_wall``, ``Collision``): every tile in them is a wall.
3. Tiles whose class, or one of whose true boolean properties, is such a word.
4. Collision shapes drawn inside tiles (Tiled's tile collision editor): the shapes, not the whole tile.
5. Object layers whose name says wall (their objects are walls unless the layer mixes kinds: in a
   layer where some objects are named ``wall``, only those are), and objects whose class or name says
   wall anywhere.

``--wall-layer NAME`` replaces rules 2 and 5's layer names with the named layers; ``--wall-tile GID``
adds tiles.

**Floor**: tile layers with the property ``floor``, else the layers passed as ``--floor-layer``, else
the visible tile layers named with :data:`FLOOR_WORDS` (``Ground1``, ``floor``), else the lowest
visible tile layer. Wall layers, spawn layers and layers drawn above the player (names with the words
:data:`ABOVE_WORDS`) are never floor. A cell empty in every floor layer is outside the level; so is a
cell of the painted void (a tile filling the whole map edge of the first floor layer).

**Spawns**: objects in layers named with :data:`SPAWN_WORDS`, objects whose class, type or name says
guard or spawn, objects with ``guard_spawn``, tiles whose class says guard, and ``--spawn-tile`` ids.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from guardsim.importers.imported import listed
from guardsim.importers.tiled_data import ObjectLayer, Properties, TiledMap, TiledObject, TileLayer

__all__ = [
    "ABOVE_WORDS",
    "FLOOR_WORDS",
    "SPAWN_WORDS",
    "WALL_WORDS",
    "Guesses",
    "RoleOptions",
    "assign_roles",
    "words",
]

#: Whole words in a layer, class or property name that say "wall".
WALL_WORDS = frozenset(
    [
        "wall",
        "walls",
        "collision",
        "collisions",
        "collide",
        "collides",
        "collider",
        "colliders",
        "collidable",
        "solid",
        "solids",
        "obstacle",
        "obstacles",
        "blocked",
        "blocking",
        "blocker",
        "blockers",
        "impassable",
        "barrier",
        "barriers",
    ]
)
#: Whole words in a layer name that say floor.
FLOOR_WORDS = frozenset(["floor", "floors", "ground", "grounds"])
#: Whole words in a layer name that say it is drawn above the player (roofs, tree tops), so not floor.
ABOVE_WORDS = frozenset(["above", "over", "overhead", "overlay", "roof", "roofs", "fringe", "canopy"])
#: Whole words in a layer, class or name that say guard spawn.
SPAWN_WORDS = frozenset(
    ["spawn", "spawns", "spawner", "spawners", "guard", "guards", "start", "starts", "patrol", "patrols"]
)
#: A painted void leaves at least this share of its layer's cells as floor.
VOID_MIN_REST = 0.05
#: Boolean properties that mark walls.
_WALL_FLAGS = ("collision", "collides", "collide", "collidable", "solid", "blocked", "obstacle", "wall")


def words(name: str) -> set[str]:
    """The lower-case words of a name: split at non-letters and camelCase humps.

    >>> sorted(words("base_wall")), sorted(words("WallsLayer2")), sorted(words("Wallpaper"))
    (['base', 'wall'], ['2', 'layer', 'walls'], ['wallpaper'])
    """
    spaced = re.sub(r"([a-z])([A-Z])|([A-Za-z])([0-9])", r"\1\3 \2\4", name)
    return {part.lower() for part in re.split(r"[^A-Za-z0-9]+", spaced) if part}


def _says(name: str, vocabulary: AbstractSet[str]) -> bool:
    return bool(words(name) & vocabulary)


def flag(properties: Properties, *keys: str) -> bool | None:
    """The first of ``keys`` present as a boolean-like property: ``True``/``False``, or ``None``."""
    for key in keys:
        if key in properties:
            value: Any = properties[key]
            if isinstance(value, str):
                return value.strip().lower() in ("true", "1", "yes")
            return bool(value)
    return None


@dataclass(frozen=True)
class RoleOptions:
    """The user's overrides of the guesses (the import options of every command)."""

    wall_layers: tuple[str, ...] = ()
    floor_layers: tuple[str, ...] = ()
    wall_tiles: tuple[int, ...] = ()
    spawn_tiles: tuple[int, ...] = ()


@dataclass
class Guesses:
    """The roles found and what they were found from, for the summary."""

    floor_layers: list[TileLayer] = field(default_factory=list)
    floor_rule: str = ""
    wall_tile_layers: list[TileLayer] = field(default_factory=list)
    wall_gids: set[int] = field(default_factory=set)
    """Tiles that are whole-cell walls wherever they are drawn."""
    shaped_gids: set[int] = field(default_factory=set)
    """Tiles whose collision shapes are walls."""
    wall_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    spawn_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    spawn_gids: set[int] = field(default_factory=set)
    boundary_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    void_gid: int = 0
    """A tile that paints the void around the level in the first floor layer (0: none)."""
    warnings: list[str] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)
    """How the walls were found, one phrase per kind of evidence."""


def _layer_named(layer: TileLayer | ObjectLayer, names: Sequence[str]) -> bool:
    return layer.name in names or "/".join(layer.path) in names


def _wall_layer(layer: TileLayer | ObjectLayer, options: RoleOptions) -> bool:
    marked = flag(layer.properties, *_WALL_FLAGS)
    if marked is not None:
        return marked
    if options.wall_layers:
        return _layer_named(layer, options.wall_layers)
    return any(_says(part, WALL_WORDS) for part in layer.path) or _says(layer.kind, WALL_WORDS)


def _tile_says_wall(kind: str, properties: Properties) -> bool:
    if _says(kind, WALL_WORDS):
        return True
    marked = flag(properties, *_WALL_FLAGS)
    if marked is not None:
        return marked
    return any(value is True and _says(key, WALL_WORDS) for key, value in properties.items())


def _object_spawn(layer: ObjectLayer, item: TiledObject) -> bool:
    own = flag(item.properties, "guard_spawn")
    if own is not None:
        return own
    return (
        _says(item.kind, SPAWN_WORDS)
        or _says(item.name, SPAWN_WORDS)
        or bool(flag(layer.properties, "guard_spawn", "spawner", "spawn"))
        or any(_says(part, SPAWN_WORDS) for part in layer.path)
    )


def _object_boundary(layer: ObjectLayer, item: TiledObject) -> bool:
    own = flag(item.properties, "boundary")
    if own is not None:
        return own
    return (
        item.kind.lower() == "boundary" or bool(flag(layer.properties, "boundary")) or _says(layer.name, {"boundary"})
    )


#: The object layer and object class guardsim writes patrol routes in; never walls, spawns or boundary.
ROUTE_LAYER = "guardsim"
ROUTE_CLASS = "guardsim_route"


def assign_roles(tiled: TiledMap, options: RoleOptions) -> Guesses:
    """Floor layers, wall tiles and objects, spawns and boundary objects of ``tiled``."""
    found = Guesses()
    every: list[TileLayer | ObjectLayer] = [*tiled.tile_layers, *tiled.object_layers]
    known = {layer.name for layer in every} | {"/".join(layer.path) for layer in every}
    for name in (*options.wall_layers, *options.floor_layers):
        if name not in known:
            found.warnings.append(f"no layer named {name!r} (layers: {', '.join(sorted(known))[:200]})")

    # Walls: tiles.
    for gid, info in tiled.tiles.items():
        if info.shapes and (flag(info.properties, *_WALL_FLAGS) is not False):
            found.shaped_gids.add(gid)
        elif _tile_says_wall(info.kind, info.properties):
            found.wall_gids.add(gid)
    found.wall_gids |= set(options.wall_tiles)
    found.shaped_gids -= set(options.wall_tiles)
    found.wall_tile_layers = [layer for layer in tiled.tile_layers if _wall_layer(layer, options)]

    # Floor.
    marked = [layer for layer in tiled.tile_layers if flag(layer.properties, "floor")]
    if marked:
        found.floor_layers, found.floor_rule = marked, "property floor"
    elif options.floor_layers:
        found.floor_layers = [layer for layer in tiled.tile_layers if _layer_named(layer, options.floor_layers)]
        found.floor_rule = "--floor-layer"
    else:
        candidates = [
            layer
            for layer in tiled.tile_layers
            if layer.visible
            and layer not in found.wall_tile_layers
            and flag(layer.properties, "floor") is not False
            and not any(_says(part, SPAWN_WORDS | ABOVE_WORDS) for part in layer.path)
            and not flag(layer.properties, "spawner", "guard_spawn")
        ]
        named = [layer for layer in candidates if any(_says(part, FLOOR_WORDS) for part in layer.path)]
        if named:
            found.floor_layers, found.floor_rule = named, "named floor or ground"
        else:
            # Upper layers draw on the ground (furniture, wall faces); a tile of theirs over no ground is
            # not floor, so the ground is the lowest layer alone.
            found.floor_layers = candidates[:1]
            found.floor_rule = "the lowest visible tile layer not named wall, spawn or above"

    # Walls and spawns: objects. guardsim's own route layer (`guardsim patrol --tiled-out`) is neither.
    for layer in tiled.object_layers:
        if layer.name == ROUTE_LAYER:
            continue
        wall_layer = _wall_layer(layer, options)
        mixed = wall_layer and any(_says(item.name, WALL_WORDS) for item in layer.objects)
        for item in layer.objects:
            if item.kind == ROUTE_CLASS:
                continue
            if _object_boundary(layer, item):
                if item.closed:
                    found.boundary_objects.append((layer, item))
                continue
            if _object_spawn(layer, item):
                found.spawn_objects.append((layer, item))
                continue
            own = flag(item.properties, *_WALL_FLAGS)
            if own is None:
                says = _says(item.name, WALL_WORDS) or _says(item.kind, WALL_WORDS)
                nameless = not item.name and not item.kind
                own = says or (wall_layer and (not mixed or nameless) and not (item.name and mixed))
                if item.gid and not own:
                    own = item.gid in found.wall_gids or item.gid in found.shaped_gids
            if own:
                found.wall_objects.append((layer, item))
    tile_ids = set(options.spawn_tiles) | {gid for gid, info in tiled.tiles.items() if _says(info.kind, {"guard"})}
    tile_ids |= {gid for gid, info in tiled.tiles.items() if flag(info.properties, "guard_spawn")}
    found.spawn_gids = tile_ids
    # Last: the void needs the walls found above.
    found.void_gid = _void_tile(tiled, found) if found.floor_layers and not options.floor_layers else 0
    return found


def _void_tile(tiled: TiledMap, found: Guesses) -> int:
    """The tile that fills every edge cell of the first floor layer, when walls separate it from other tiles.

    Dungeons drawn on a painted background (one dark tile everywhere outside the rooms) would otherwise
    import with the background as floor. The tile counts as void only if the map has walls, the layer
    has other tiles too, and it covers the whole map edge.
    """
    layer = found.floor_layers[0]
    width, height = tiled.size
    if not (found.wall_tile_layers or found.wall_objects or found.wall_gids) or width < 3 or height < 3:
        return 0
    if layer.offset != (0.0, 0.0) or layer.gids.size != width * height:
        return 0
    grid = np.zeros((height, width), dtype=np.int64)
    inside = (layer.rows >= 0) & (layer.rows < height) & (layer.cols >= 0) & (layer.cols < width)
    grid[layer.rows[inside], layer.cols[inside]] = layer.gids[inside]
    edge = np.concatenate([grid[0], grid[-1], grid[:, 0], grid[:, -1]])
    gid = int(edge[0])
    if not gid or not (edge == gid).all():
        return 0
    # What is left must be a level: floor tiles that are not walls themselves.
    rest = (grid != gid) & (grid != 0) & ~np.isin(grid, list(found.wall_gids | found.shaped_gids))
    return gid if rest.sum() >= VOID_MIN_REST * grid.size else 0


def names(layers: Iterable[TileLayer | ObjectLayer]) -> str:
    """Layer names for a summary: ``'Walls 1', 'Walls 2'``."""
    return listed(repr("/".join(layer.path)) for layer in layers)
