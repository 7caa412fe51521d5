"""What each part of a Tiled map is for a guard: floor, wall or spawn, from the evidence real maps carry.

Most game maps mark nothing for guardsim, so the roles are read from what their authors did mark, in
this order of evidence (``docs/authoring.md``):

**Walls**

1. Collision marks: on an object or a tile, a property of any type whose name has a word of
   :data:`WALL_WORDS` (split at camelCase humps too: ``collision``, ``CollisionShape``, ``IsBlocking``,
   ``collides``, ``solid``) and whose value reads true (``true``, a non-zero number, the text
   ``true``/``yes``/``1``); ``false``, ``0``, ``"no"`` or ``""`` opts out, and a name saying ``not``/``no``
   (``no_collision: true``) opts out too (:func:`wall_mark`). On a layer, the boolean-like property
   ``collision`` (or ``collides``, ``collidable``, ``solid``, ``blocked``, ``obstacle``, ``wall``).
   Without such a property, a static physics body is a wall and a moving one is not (:func:`body_mark`):
   a ``bodyType`` of ``static`` (``dynamic``, ``kinematic``), or a class naming a body (``Fixture``,
   ``StaticBody2D``) with ``static`` in its class or a true property ``static``, as Tiled's own
   example ``orthogonal-outside.tmx`` marks its cliff.
2. Tile layers whose name says wall (the whole words :data:`WALL_WORDS`, any case: ``Walls 1``,
   ``base_wall``, ``Collision``): every tile in them is a wall.
3. Tiles whose class (``type`` before Tiled 1.9) is such a word (even if a property opts out).
4. Collision shapes drawn inside tiles (Tiled's tile collision editor): the shapes, not the whole tile.
5. Object layers whose name says wall (their objects are walls unless the layer mixes kinds: in a
   layer where some objects are named ``wall``, only those are), and objects whose class or name says
   wall anywhere. A tile object is a wall when its tile is.

``--wall-layer NAME`` replaces rules 2 and 5's layer names with the named layers; ``--wall-tile GID``
adds tiles; ``--wall-class NAME`` adds the tiles and objects of that class; ``--wall-property
NAME[=VALUE]`` replaces rule 1's guess from property names on tiles and objects with the named
properties.

**Floor**: tile layers with the property ``floor``, else the layers passed as ``--floor-layer``, else
the visible tile layers named with :data:`FLOOR_WORDS` (``Ground1``, ``floor``), else the lowest
visible tile layer. Wall layers, spawn layers and layers drawn above the player (names with the words
:data:`ABOVE_WORDS`) are never floor. A cell empty in every floor layer is outside the level; so is a
cell of the painted void (a tile filling the whole map edge of the first floor layer).

**Player starts** (the intruder's, never a guard's): objects whose name or class has a word of
:data:`PLAYER_WORDS` (``player``, ``Hero``, ``PlayerStart``, ``Player_Start``), or whose tile's class
does.

**Spawns**: objects in layers named with :data:`SPAWN_WORDS`, objects whose class, type or name says
guard or spawn, objects with ``guard_spawn``, tiles whose class says guard, and ``--spawn-tile`` ids.

**Side views** (platformers: the guard cannot walk them): a layer whose name or class has a word of
:data:`SIDE_VIEW_WORDS` (``platforms``, ``Ladders``), or a map property whose name says gravity or jump
with a true or non-zero value (:func:`side_view_sign`); ``--view top-down`` imports the map anyway.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from guardsim.files.reading import quoted
from guardsim.importers.imported import listed
from guardsim.importers.source import excerpt
from guardsim.importers.tiled_data import ObjectLayer, Properties, TiledMap, TiledObject, TileLayer
from guardsim.importers.tiled_marks import (
    ABOVE_WORDS,
    FLOOR_WORDS,
    GRAVITY_WORDS,
    PLAYER_WORDS,
    SIDE_VIEW_WORDS,
    SPAWN_WORDS,
    VOID_MIN_REST,
    WALL_FLAGS,
    WALL_WORDS,
    body_mark,
    flag,
    parse_wall_property,
    pulls,
    says,
    truth,
    wall_mark,
    words,
)

__all__ = [
    "ABOVE_WORDS",
    "FLOOR_WORDS",
    "PLAYER_WORDS",
    "SPAWN_WORDS",
    "WALL_WORDS",
    "Guesses",
    "RoleOptions",
    "assign_roles",
    "parse_wall_property",
    "side_view_sign",
    "truth",
    "wall_mark",
    "words",
]


@dataclass(frozen=True)
class RoleOptions:
    """The user's overrides of the guesses (the import options of every command)."""

    wall_layers: tuple[str, ...] = ()
    floor_layers: tuple[str, ...] = ()
    wall_tiles: tuple[int, ...] = ()
    spawn_tiles: tuple[int, ...] = ()
    wall_properties: tuple[tuple[str, str | None], ...] = ()
    """``--wall-property``: ``(NAME, VALUE or None)``; replaces the guess from property names."""
    wall_classes: tuple[str, ...] = ()
    """``--wall-class``: tile and object classes that are walls (any case)."""

    def wall_class(self, kind: str) -> bool:
        return bool(kind) and kind.strip().lower() in {name.strip().lower() for name in self.wall_classes}


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
    marked_gids: set[int] = field(default_factory=set)
    """Tiles whose own properties mark them walls: walls even in a layer that opts out (a game's physics
    reads the tile's own mark first)."""
    unmarked_gids: set[int] = field(default_factory=set)
    """Tiles whose own properties opt them out: never walls, even in a wall layer."""
    wall_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    spawn_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    spawn_gids: set[int] = field(default_factory=set)
    player_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    """The player's (intruder's) start objects: never guard spawns or walls."""
    boundary_objects: list[tuple[ObjectLayer, TiledObject]] = field(default_factory=list)
    void_gid: int = 0
    """A tile that paints the void around the level in the first floor layer (0: none)."""
    warnings: list[str] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)
    """How the walls were found, one phrase per kind of evidence."""


#: A layer named floor that paints fewer cells than this share of the layer painting most is not the
#: whole floor.
FLOOR_MIN_SHARE = 0.25
#: Words naming a layer painted behind the level, and the share of the map rectangle past which a layer
#: is taken as such a backdrop: neither is the layer a small floor layer is joined with.
BACKDROP_WORDS = frozenset(["background", "backdrop", "sky", "bg"])
BACKDROP_SHARE = 0.9


def _cells(layer: TileLayer) -> np.ndarray:
    """The layer's painted cells, one number each."""
    return np.unique((layer.rows.astype(np.int64) << 32) + layer.cols.astype(np.int64))


def _layer_named(layer: TileLayer | ObjectLayer, names: Sequence[str]) -> bool:
    return layer.name in names or "/".join(layer.path) in names


def _wall_layer(layer: TileLayer | ObjectLayer, options: RoleOptions) -> bool:
    marked = flag(layer.properties, *WALL_FLAGS)
    if marked is not None:
        return marked
    if options.wall_layers:
        return _layer_named(layer, options.wall_layers)
    return any(says(part, WALL_WORDS) for part in layer.path) or says(layer.kind, WALL_WORDS)


def _own_mark(kind: str, properties: Properties, options: RoleOptions) -> bool | None:
    """A tile's or object's own say: its collision properties (or ``--wall-property``), else, when no
    ``--wall-property`` replaces the guess, whether it is a static or a moving physics body."""
    mark = wall_mark(properties, options.wall_properties)
    if mark is None and not options.wall_properties:
        mark = body_mark(kind, properties)
    return mark


def _tile_says_wall(kind: str, properties: Properties, options: RoleOptions) -> bool:
    if options.wall_class(kind) or says(kind, WALL_WORDS):
        return True
    return bool(_own_mark(kind, properties, options))


def side_view_sign(tiled: TiledMap) -> str:
    """What says the map is drawn from the side (a platformer) rather than from above, or ``""``.

    A layer whose name (or group's name) or class says platforms or ladders, or a map property named for
    gravity or jumping whose value is true or a non-zero number.
    """
    layers: list[TileLayer | ObjectLayer] = [*tiled.tile_layers, *tiled.object_layers]
    for layer in layers:
        if any(says(part, SIDE_VIEW_WORDS) for part in (*layer.path, layer.kind)):
            return f"the layer {excerpt('/'.join(layer.path))}"
    for key, value in tiled.properties.items():
        if says(key, GRAVITY_WORDS) and pulls(value):
            return f"the map property {excerpt(key)} ({excerpt(value)})"
    return ""


def _object_player(item: TiledObject, tiled: TiledMap) -> bool:
    """Whether an object is the player's start: a property named for the player that is not false, or its
    name or class (or its tile's class) says player."""
    if flag(item.properties, "guard_spawn"):
        return False
    # A property named for the player (player_spawn, PlayerStart) that is not false: Lost-In-The-Dark
    # marks its start with the string property player_spawn = "player_spawn".
    if any(says(key, PLAYER_WORDS) and truth(value) is not False for key, value in item.properties.items()):
        return True
    tile = tiled.tiles.get(item.gid) if item.gid else None
    kinds = (item.name, item.kind, tile.kind if tile is not None else "")
    return any(says(kind, PLAYER_WORDS) for kind in kinds) or any(_bare_start(kind) for kind in kinds)


#: Words that, with ``start`` and nothing else, name where the player starts: ``Start Position``, class
#: ``start``. A guard's start says so (``guard start``, ``spawn``), or lies in a layer named for guards.
_START_ONLY = frozenset(["start", "starts", "starting", "position", "pos", "point", "location", "spot", "place"])


def _bare_start(name: str) -> bool:
    found = words(name)
    return "start" in found and found <= _START_ONLY


def _says_player(item: TiledObject, tiled: TiledMap) -> bool:
    """Whether the object names the player outright (not only ``start``)."""
    tile = tiled.tiles.get(item.gid) if item.gid else None
    kinds = (item.name, item.kind, tile.kind if tile is not None else "")
    return any(says(kind, PLAYER_WORDS) for kind in kinds) or any(says(key, PLAYER_WORDS) for key in item.properties)


def _object_spawn(layer: ObjectLayer, item: TiledObject) -> bool:
    own = flag(item.properties, "guard_spawn")
    if own is not None:
        return own
    return (
        says(item.kind, SPAWN_WORDS)
        or says(item.name, SPAWN_WORDS)
        or bool(flag(layer.properties, "guard_spawn", "spawner", "spawn"))
        or any(says(part, SPAWN_WORDS) for part in layer.path)
    )


def _object_boundary(layer: ObjectLayer, item: TiledObject) -> bool:
    own = flag(item.properties, "boundary")
    if own is not None:
        return own
    return item.kind.lower() == "boundary" or bool(flag(layer.properties, "boundary")) or says(layer.name, {"boundary"})


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
        mark = _own_mark(info.kind, info.properties, options)
        if mark is True:
            found.marked_gids.add(gid)
        elif mark is False:
            found.unmarked_gids.add(gid)
        # A tile's collision shapes block even when its property says it does not collide as a whole
        # tile: the game's physics blocks on the shapes it is given.
        if info.shapes:
            found.shaped_gids.add(gid)
        elif _tile_says_wall(info.kind, info.properties, options):
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
            and not any(says(part, SPAWN_WORDS | ABOVE_WORDS) for part in layer.path)
            and not flag(layer.properties, "spawner", "guard_spawn")
        ]
        named = [layer for layer in candidates if any(says(part, FLOOR_WORDS) for part in layer.path)]
        # Backdrops (a layer named so, or painting nearly the whole map rectangle) are never that layer.
        area = max(1, tiled.size[0] * tiled.size[1])
        painting = [
            layer
            for layer in candidates
            if not any(says(part, BACKDROP_WORDS) for part in layer.path) and _cells(layer).size < BACKDROP_SHARE * area
        ]
        widest = max(painting, key=lambda layer: _cells(layer).size, default=None)
        if named and widest is not None and not any(widest is layer for layer in named):
            # A layer named floor that paints a small part of what is painted (decorative "floor squares"
            # over a dungeon whose ground is a layer called "corridors") is not the whole floor: the
            # layer painting most cells is floor too.
            share = np.unique(np.concatenate([_cells(layer) for layer in named])).size
            if share < FLOOR_MIN_SHARE * _cells(widest).size:
                found.floor_layers = [
                    layer for layer in tiled.tile_layers if layer is widest or any(layer is other for other in named)
                ]
                found.floor_rule = (
                    f"named floor or ground, and {quoted(widest.name)}, which paints {_cells(widest).size} cells "
                    f"where they paint {share}"
                )
                named = []
        if named:
            found.floor_layers, found.floor_rule = named, "named floor or ground"
        elif not found.floor_layers:
            # Upper layers draw on the ground (furniture, wall faces); a tile of theirs over no ground is
            # not floor, so the ground is the lowest layer alone.
            found.floor_layers = candidates[:1]
            found.floor_rule = "the lowest visible tile layer not named wall, spawn or above"

    # Walls and spawns: objects. guardsim's own route layer (`guardsim patrol --tiled-out`) is neither.
    for layer in tiled.object_layers:
        if layer.name == ROUTE_LAYER:
            continue
        wall_layer = _wall_layer(layer, options)
        mixed = wall_layer and any(says(item.name, WALL_WORDS) for item in layer.objects)
        for item in layer.objects:
            if item.kind == ROUTE_CLASS or item.kind.strip().lower() in ("camera", "light"):
                continue  # guardsim's route, or a watcher or lamp (guardsim.importers.watchers)
            if _object_boundary(layer, item):
                if item.closed:
                    found.boundary_objects.append((layer, item))
                continue
            guard_layer = any(says(part, SPAWN_WORDS - {"start", "starts"}) for part in layer.path)
            if _object_player(item, tiled) and not (guard_layer and not _says_player(item, tiled)):
                found.player_objects.append((layer, item))
                continue
            if _object_spawn(layer, item):
                found.spawn_objects.append((layer, item))
                continue
            own = True if options.wall_class(item.kind) else _own_mark(item.kind, item.properties, options)
            if own is None:
                walled = says(item.name, WALL_WORDS) or says(item.kind, WALL_WORDS)
                nameless = not item.name and not item.kind
                own = walled or (wall_layer and (not mixed or nameless) and not (item.name and mixed))
                if item.gid and not own:
                    own = item.gid in found.wall_gids or item.gid in found.shaped_gids
            if own:
                found.wall_objects.append((layer, item))
    tile_ids = set(options.spawn_tiles) | {gid for gid, info in tiled.tiles.items() if says(info.kind, {"guard"})}
    tile_ids |= {gid for gid, info in tiled.tiles.items() if flag(info.properties, "guard_spawn")}
    found.spawn_gids = tile_ids
    found.warnings += _unmatched_overrides(tiled, options)
    # Last: the void needs the walls found above.
    found.void_gid = _void_tile(tiled, found) if found.floor_layers and not options.floor_layers else 0
    return found


def _unmatched_overrides(tiled: TiledMap, options: RoleOptions) -> list[str]:
    """A warning for each ``--wall-property`` and ``--wall-class`` that no tile or object of the map has."""
    things = [(info.kind, info.properties) for info in tiled.tiles.values()]
    things += [(item.kind, item.properties) for layer in tiled.object_layers for item in layer.objects]
    warnings = []
    for name, value in options.wall_properties:
        # Quoted and cut short: an option may be as long as the shell takes, a warning is one short line.
        shown = _option(name if value is None else f"{name}={value}")
        if not any(name in properties for _, properties in things):
            warnings.append(
                f"--wall-property {shown}: no tile or object has a property {quoted(name)}: no walls from it"
            )
        elif not any(wall_mark(properties, [(name, value)]) for _, properties in things):
            warnings.append(f"--wall-property {shown}: no tile or object's {quoted(name)} matches: no walls from it")
    for kind in options.wall_classes:
        if not any(own.strip().lower() == kind.strip().lower() for own, _ in things):
            warnings.append(f"--wall-class {_option(kind)}: no tile or object has this class: no walls from it")
    return warnings


def _option(text: str) -> str:
    """An option's value as typed when short and printable, else quoted and cut short."""
    return text if len(text) <= 40 and text.isprintable() else quoted(text)


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
