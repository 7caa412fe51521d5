"""LDtk projects (``.ldtk``, deepnight's level editor) into levels: IntGrid walls, entity spawns.

One level of the project is imported: the one named by ``level``, else the first (the summary names
the others). One cell of its first wall IntGrid layer is one world unit, x to the right and y down as
in LDtk, and the level's rectangle (``pxWid`` x ``pxHei``) is the outer ring:

* **walls** are the cells of IntGrid layers holding a wall value: a value whose name (or value
  group's name) has one of the whole words :data:`WALL_WORDS` (``walls``, ``Collision``, ``solid``,
  ``block``, ``obstacle``, any case), or the values given as ``wall_values`` (numbers or names), which
  replace that guess. Auto-layers and Tiles layers draw tiles and mark nothing: an auto-layer's walls
  are its IntGrid source's (``autoSourceLayerDefUid``), read there. The wall cells become holes with
  :func:`guardsim.importers.imported.level_from_walls`, as every grid importer's do;
* **guard spawns** are entities whose name or tags say guard, spawn or enemy (or that sit in an
  Entities layer so named), **player starts** those whose name or tags say player or hero
  (``PlayerStart``); a player start is never a guard spawn. Each stands at the centre of its box.
  Spawns are handled as in Tiled maps (:mod:`guardsim.importers.tiled`): unusable ones are dropped,
  free parts holding none are left out, and with none the start is left to the command.

No wall found is a warning, as in a Tiled map. Reading is :mod:`guardsim.importers.ldtk_read`.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from guardsim.errors import LevelError
from guardsim.files.reading import quoted
from guardsim.importers.imported import (
    ImportedLevel,
    counted,
    level_from_walls,
    listed,
    raster_vertex_count,
    with_tile_pixels,
)
from guardsim.importers.ldtk_read import Entity, Layer, LdtkLevel, ValueDef, is_ldtk_json, read_ldtk
from guardsim.importers.source import display_name, excerpt, parse_json_bytes, read_capped_bytes
from guardsim.importers.tiled_marks import PLAYER_WORDS, SPAWN_WORDS, words
from guardsim.importers.tiled_marks import WALL_WORDS as TILED_WALL_WORDS
from guardsim.importers.tiled_spawns import keep_spawn_areas, usable_starts
from guardsim.importers.walls import blocked_cell_walls
from guardsim.importers.watchers import ldtk_watchers, with_watchers
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES, level_to_data, parse_level

__all__ = ["GUARD_WORDS", "WALL_WORDS", "import_ldtk", "is_ldtk_file", "is_ldtk_json"]

#: Whole words in an IntGrid value's (or value group's) name that make it a wall: Tiled's, and ``block``.
WALL_WORDS = TILED_WALL_WORDS | {"block", "blocks"}
#: Whole words in an entity's name or tags (or its layer's name) that make it a guard spawn.
GUARD_WORDS = SPAWN_WORDS | {"enemy", "enemies", "mob", "mobs"}


def is_ldtk_file(path: str | os.PathLike[str], *, max_file_bytes: int = DEFAULT_MAX_FILE_BYTES) -> bool:
    """Whether the JSON file at ``path`` is an LDtk project (:func:`is_ldtk_json`); ``False`` if unreadable."""
    try:
        data = read_capped_bytes(path, max_file_bytes=max_file_bytes, kind="map")
        if b'"jsonVersion"' not in data and b'"__header__"' not in data:
            return False
        return is_ldtk_json(parse_json_bytes(data, display_name(path)))
    except LevelError:
        return False


def import_ldtk(
    path: str | os.PathLike[str],
    *,
    cell_size: float = 1.0,
    wall_values: Iterable[int | str] = (),
    level: str | None = None,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_vertices: int = DEFAULT_MAX_VERTICES,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
) -> ImportedLevel:
    """Convert one level of an LDtk project to a level (see the module notes).

    Parameters
    ----------
    wall_values
        IntGrid values that are walls in every IntGrid layer, as numbers or names (any case); they
        replace the guess from value names.
    level
        The identifier of the level to import (exact, else any case); the first level by default.
    """
    source = display_name(path)
    wanted = _parse_wall_values(wall_values, source)
    ldtk = read_ldtk(path, level=level, max_file_bytes=max_file_bytes, max_cells=max_cells)
    changes = list(ldtk.notes)
    warnings: list[str] = []
    int_grids = [layer for layer in ldtk.layers if layer.kind == "IntGrid"]
    chosen = [(layer, _wall_values(layer, wanted)) for layer in int_grids]
    masks = []
    for layer, values in chosen:
        painted = {value: label for value, label in values.items() if (layer.values == value).any()}
        if painted:
            masks.append((layer, painted, np.isin(layer.values, sorted(painted))))
    unit = next((layer.grid for layer, _, _ in masks), int_grids[0].grid if int_grids else ldtk.default_grid)
    width, height = ldtk.width / unit, ldtk.height / unit
    cells = width * height / cell_size**2
    if cells > max_cells:
        raise LevelError(
            f"{source}: level {quoted(ldtk.identifier, 60)} spans {width:g} x {height:g} cells of {unit} pixels = {cells:.0f} "
            f"cells at cell size {cell_size:g}, over the limit of {max_cells} (raise it with --max-cells)"
        )
    vertices = 4 + sum(raster_vertex_count(mask) for _, _, mask in masks)
    if vertices > max_vertices:
        raise LevelError(
            f"{source}: the walls of level {quoted(ldtk.identifier, 60)} need about {vertices} vertices, over the limit of "
            f"{max_vertices} (raise it with --max-vertices)"
        )
    bounds = (0.0, 0.0, width, height)
    walls = [
        piece
        for layer, _, mask in masks
        for piece in _cell_walls(mask, layer.offset[0] / unit, layer.offset[1] / unit, layer.grid / unit)
    ]
    if walls and _covered(masks, bounds, walls, unit):
        raise LevelError(f"{source}: the walls cover the whole of level {quoted(ldtk.identifier, 60)}: no free area")
    changes.append(_walls_phrase(masks, bool(wanted)))
    changes += _layer_notes(ldtk)
    if not masks:
        warnings.append(_no_walls(ldtk, int_grids, chosen, bool(wanted)))
    warnings += _unmatched(wanted, int_grids)

    name = Path(path).stem if not ldtk.others else f"{Path(path).stem} {ldtk.identifier}"
    built, report = level_from_walls(
        walls, bounds, name=name, source=source, cell_size=cell_size, max_cells=max_cells, max_vertices=max_vertices
    )
    changes.append(report.describe("wall cell runs"))
    guards, players = _entities(ldtk, unit)
    starts, dropped = usable_starts(built, [point for point, _ in guards])
    changes.append(counted(len(starts), "guard spawn") + (f" from {_labels(guards)}" if guards else ""))
    changes += [f"dropped spawn ({x:g}, {y:g}): {why}" for (x, y), why in dropped[:5]]
    if len(dropped) > 5:
        changes.append(f"dropped {len(dropped) - 5} more spawns")
    if guards and not starts:
        warnings.append(f"none of the {len(guards)} spawns is a place the guard fits: the start is left to the command")
    if starts:
        built, left_out = keep_spawn_areas(built, starts, source=source, max_cells=max_cells, max_vertices=max_vertices)
        changes += [left_out] if left_out else []
    area = built.free_area() if players else None
    standing = [point for point, _ in players if shapely.contains_xy(area, *point)]
    if players:
        where = [f"({x:g}, {y:g}) from {quoted(label, 60)}" + ("" if (x, y) in standing else ", not on the free area")
                 for (x, y), label in players]  # fmt: skip
        changes.append(
            f"{counted(len(players), 'player start')} {listed(where, 3)} (the intruder's, not a guard spawn)"
        )
    if starts or standing:
        data = level_to_data(built)
        if starts:
            data["guard"]["start"] = list(starts[0])
            data["starts"] = [list(point) for point in starts]
        if standing:
            data["player_starts"] = [list(point) for point in standing]
        built = parse_level(data, source=source, max_cells=max_cells, max_vertices=max_vertices)
    built, watchers = with_watchers(
        built, ldtk_watchers(ldtk, unit), source=source, max_cells=max_cells, max_vertices=max_vertices
    )
    changes += [watchers] if watchers else []
    built = with_tile_pixels(built, unit, unit)
    size = (math.ceil(width), math.ceil(height))
    return ImportedLevel(
        built, "LDtk project", size, tuple(changes), tuple(warnings), tuple(point for point, _ in players)
    )


def _parse_wall_values(given: Iterable[int | str], source: str) -> tuple[int | str, ...]:
    """``--wall-value`` texts as numbers (digits) or names; an empty one is an error."""
    values: list[int | str] = []
    for item in given:
        if isinstance(item, int) and not isinstance(item, bool):
            values.append(item)
            continue
        text = str(item).strip()
        if not text:
            raise LevelError(f"{source}: --wall-value must be an IntGrid value's number or name, not an empty text")
        values.append(int(text) if re.fullmatch(r"[0-9]{1,10}", text) else text)
    return tuple(values)


def _matches(value: ValueDef, item: int | str) -> bool:
    return value.value == item if isinstance(item, int) else value.identifier.lower() == item.lower()


def _wall_values(layer: Layer, wanted: tuple[int | str, ...]) -> dict[int, str]:
    """The layer's wall values, each with its label: the ``wanted`` ones, else those named like walls."""
    defined = layer.definition.values if layer.definition else ()
    if wanted:
        found = {value.value: value.label() for value in defined for item in wanted if _matches(value, item)}
        # A number stands for itself even where the definition leaves it out.
        found.update({item: str(item) for item in wanted if isinstance(item, int) and item not in found})
        return found
    return {
        value.value: value.label() for value in defined if (words(value.identifier) | words(value.group)) & WALL_WORDS
    }


def _cell_walls(mask: np.ndarray, x: float, y: float, size: float) -> list[Polygon]:
    """The wall cells of a layer as row runs, in world units (the layer's offset and cell size applied)."""
    return blocked_cell_walls(mask, origin=(x, y), cell_size=size)


def _covered(
    masks: list[tuple[Layer, dict[int, str], np.ndarray]],
    bounds: tuple[float, float, float, float],
    walls: list[Polygon],
    unit: int,
) -> bool:
    """Whether the walls cover the whole level: on the cells when every wall layer is on the level's
    grid, else by area."""
    cols, rows = bounds[2], bounds[3]
    if (
        cols.is_integer()
        and rows.is_integer()
        and all(layer.grid == unit and layer.offset == (0.0, 0.0) for layer, _, _ in masks)
    ):
        covered = np.zeros((int(rows), int(cols)), dtype=bool)
        for _, _, mask in masks:
            part = mask[: int(rows), : int(cols)]
            covered[: part.shape[0], : part.shape[1]] |= part
        return bool(covered.all())
    return not box(*bounds).difference(shapely.union_all(walls)).area > 0


def _walls_phrase(masks: list[tuple[Layer, dict[int, str], np.ndarray]], given: bool) -> str:
    if not masks:
        return "walls from no IntGrid cells"
    how = "--wall-value" if given else "named like walls"
    parts = [
        f"{quoted(layer.identifier, 60)} values {listed(labels.values(), 4)} ({counted(int(mask.sum()), 'cell')})"
        for layer, labels, mask in masks
    ]
    return f"walls from IntGrid {listed(parts, 3)} ({how})"


def _layer_notes(ldtk: LdtkLevel) -> list[str]:
    """What became of the auto-layers and Tiles layers: read through their IntGrid source, or not at all."""
    names = {definition.uid: definition for definition in ldtk.definitions}
    present = {layer.definition.uid for layer in ldtk.layers if layer.definition and layer.kind == "IntGrid"}
    through: dict[str, list[str]] = {}
    unread: list[str] = []
    for layer in ldtk.layers:
        if layer.kind not in ("AutoLayer", "Tiles"):
            continue
        uid = layer.definition.source_uid if layer.definition else None
        source = names.get(uid) if uid is not None else None
        if source is not None and source.kind == "IntGrid" and uid in present:
            through.setdefault(source.identifier, []).append(repr(layer.identifier))
        else:
            unread.append(repr(layer.identifier))
    notes = [
        f"auto-layer{'s' if len(drawn) > 1 else ''} {listed(drawn, 4)} drawn from IntGrid {quoted(source, 60)}: its values are read"
        for source, drawn in through.items()
    ]
    if unread:
        notes.append(f"tiles of {listed(unread, 4)} not read (tiles mark no walls; only IntGrid values do)")
    return notes


def _no_walls(ldtk: LdtkLevel, int_grids: list[Layer], chosen: list[tuple[Layer, dict[int, str]]], given: bool) -> str:
    """The warning for a level with no wall cell, saying what to pass."""
    hint = "pass --wall-value N or NAME for the IntGrid values that are walls"
    if not int_grids:
        return f"no walls found: level {quoted(ldtk.identifier, 60)} has no IntGrid layer, so it is one open room"
    labels = [label for _, values in chosen for label in values.values()]
    if labels:
        return f"no walls found: the wall values {listed(labels, 4)} are painted nowhere in level {quoted(ldtk.identifier, 60)}"
    defined = [
        f"{quoted(layer.identifier, 60)} has {listed([value.label() for value in layer.definition.values], 5)}"
        for layer in int_grids
        if layer.definition and layer.definition.values
    ]
    said = (
        "no IntGrid value matches --wall-value"
        if given
        else ("no IntGrid value is named like a wall (wall, collision, solid, block, obstacle...)")
    )
    return f"no walls found: {said}; {listed(defined, 3)}; {hint}"


def _unmatched(wanted: tuple[int | str, ...], int_grids: list[Layer]) -> list[str]:
    """A warning for each ``--wall-value`` that no IntGrid layer defines or holds."""
    found = []
    for item in wanted:
        defined = any(
            _matches(value, item) for layer in int_grids if layer.definition for value in layer.definition.values
        )
        painted = isinstance(item, int) and any(bool((layer.values == item).any()) for layer in int_grids)
        if not defined and not painted:
            found.append(f"--wall-value {excerpt(item)} matches no IntGrid value: no walls from it")
    return found


def _entities(
    ldtk: LdtkLevel, unit: int
) -> tuple[list[tuple[tuple[float, float], str]], list[tuple[tuple[float, float], str]]]:
    """Guard spawns and player starts, each ``((x, y), identifier)`` in world units, in layer order."""
    guards = []
    players = []
    for layer in ldtk.layers:
        for entity in layer.entities:
            point = (round(entity.centre[0] / unit, 6), round(entity.centre[1] / unit, 6))
            if _says(entity, PLAYER_WORDS):
                players.append((point, entity.identifier))
            elif _says(entity, GUARD_WORDS) or words(layer.identifier) & GUARD_WORDS:
                guards.append((point, entity.identifier))
    return guards, players


def _says(entity: Entity, vocabulary: frozenset[str]) -> bool:
    return any(words(name) & vocabulary for name in (entity.identifier, *entity.tags))


def _labels(points: list[tuple[tuple[float, float], str]]) -> str:
    """``entities 'Enemy' x 3, 'Guard'``: how many of each kind."""
    kinds: dict[str, int] = {}
    for _, label in points:
        kinds[label] = kinds.get(label, 0) + 1
    return "entities " + listed(
        [f"{quoted(label, 60)}" + (f" x {count}" if count > 1 else "") for label, count in kinds.items()]
    )
