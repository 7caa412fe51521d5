"""Reading LDtk projects (``.ldtk``): the layer definitions and the one level imported, field by field.

An LDtk project (https://ldtk.io/json) is JSON: ``defs.layers`` defines each layer (its IntGrid values
and, for an auto-layer, the IntGrid layer its rules read), and ``levels`` (or ``worlds[].levels``) holds
each level's size in pixels and its ``layerInstances``. A project saved with ``externalLevels`` keeps
each level's layers in a ``.ldtkl`` file beside it (``externalRelPath``), read here too. Every field
used is checked and every fault is one :class:`~guardsim.errors.LevelError` line naming the file and the
JSON path (``map.ldtk: levels[0].layerInstances[2].intGridCsv: 40 values, expected 48``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath, PureWindowsPath
from typing import Any

import numpy as np

from guardsim.errors import LevelError
from guardsim.files.reading import json_type, quoted
from guardsim.importers.imported import listed
from guardsim.importers.source import display_name, excerpt, parse_json_bytes, read_capped_bytes

__all__ = ["LAYER_TYPES", "Entity", "Layer", "LayerDef", "LdtkLevel", "ValueDef", "is_ldtk_json", "read_ldtk"]

#: The layer types LDtk writes; layers of any other type are skipped with a note.
LAYER_TYPES = ("IntGrid", "Entities", "Tiles", "AutoLayer")
#: Largest grid size, layer offset or level side in pixels read (LDtk's own limits are far below).
MAX_PIXELS = 2**31


def is_ldtk_json(data: object) -> bool:
    """Whether decoded JSON is an LDtk project: a ``__header__`` whose ``app`` is LDtk, or a
    ``jsonVersion`` and ``defs``.

    >>> is_ldtk_json({"__header__": {"app": "LDtk"}, "levels": []}), is_ldtk_json({"outer": []})
    (True, False)
    """
    if not isinstance(data, dict) or "outer" in data:
        return False
    header = data.get("__header__")
    return (isinstance(header, dict) and header.get("app") == "LDtk") or ("jsonVersion" in data and "defs" in data)


@dataclass(frozen=True)
class ValueDef:
    """One IntGrid value of a layer definition."""

    value: int
    identifier: str
    """The value's name (``""`` when unnamed)."""
    group: str = ""
    """The name of the value group it is in (LDtk 1.4+), ``""`` for none."""

    def label(self) -> str:
        """``1 'walls'``, or ``2`` for an unnamed value."""
        return f"{self.value} {quoted(self.identifier, 60)}" if self.identifier else str(self.value)


@dataclass(frozen=True)
class LayerDef:
    """A layer definition from ``defs.layers``."""

    uid: int
    identifier: str
    kind: str
    values: tuple[ValueDef, ...] = ()
    source_uid: int | None = None
    """An auto-layer's IntGrid source layer (``autoSourceLayerDefUid``)."""


@dataclass(frozen=True)
class Entity:
    """An entity instance: its name, tags and the centre of its box in level pixels."""

    identifier: str
    tags: tuple[str, ...]
    centre: tuple[float, float]
    fields: tuple[tuple[str, Any], ...] = ()
    """Its field instances as ``(identifier, value)`` (cameras' and lamps' keys)."""


@dataclass(frozen=True)
class Layer:
    """A layer instance of the imported level."""

    identifier: str
    kind: str
    definition: LayerDef | None
    grid: int
    """Its cell size in pixels."""
    offset: tuple[float, float]
    """Its total pixel offset (``__pxTotalOffsetX/Y``)."""
    values: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), dtype=np.int64))
    """IntGrid layers: ``int64 (rows, cols)``, 0 for an empty cell (no cells for other layers)."""
    entities: tuple[Entity, ...] = ()


@dataclass(frozen=True)
class LdtkLevel:
    """The level imported from a project, and what reading it noticed."""

    identifier: str
    width: int
    """``pxWid``: the level's width in pixels."""
    height: int
    layers: tuple[Layer, ...]
    definitions: tuple[LayerDef, ...]
    default_grid: int
    """The project's ``defaultGridSize``: the unit when the level has no IntGrid layer."""
    others: tuple[str, ...]
    """The identifiers of the project's other levels."""
    notes: tuple[str, ...]
    fields: tuple[tuple[str, Any], ...] = ()
    """The level's field instances as ``(identifier, value)`` (``ambient_light``)."""


class _Fields:
    """Typed field access on one file's JSON, every fault a one-line error at its JSON path."""

    def __init__(self, source: str) -> None:
        self.source = source

    def error(self, where: str, what: str) -> LevelError:
        return LevelError(f"{self.source}: {where}: {what}" if where else f"{self.source}: {what}")

    def required(self, item: dict[str, Any], key: str, where: str) -> Any:
        if key not in item:
            raise self.error(f"{where}.{key}" if where else key, "missing")
        return item[key]

    def obj(self, value: Any, where: str) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.error(where, f"expected an object, not {json_type(value)}")
        return value

    def objects(self, value: Any, where: str) -> list[dict[str, Any]]:
        if not isinstance(value, list):
            raise self.error(where, f"expected a list, not {json_type(value)}")
        return [self.obj(item, f"{where}[{index}]") for index, item in enumerate(value)]

    def text(self, value: Any, where: str, *, empty: bool = False) -> str:
        if value is None and empty:
            return ""
        if not isinstance(value, str) or not (value or empty):
            raise self.error(
                where, f"expected a name, not {excerpt(value) if isinstance(value, str) else json_type(value)}"
            )
        return value

    def integer(self, value: Any, where: str, *, minimum: int = 0, maximum: int = MAX_PIXELS) -> int:
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(where, f"expected a whole number, not {excerpt(value)}")
        if not minimum <= value <= maximum:
            raise self.error(where, f"must be from {minimum} to {maximum}, not {value}")
        return value

    def number(self, value: Any, where: str) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not abs(value) <= MAX_PIXELS:
            raise self.error(where, f"expected a number, not {excerpt(value)}")
        return float(value)


def read_ldtk(
    path: str | os.PathLike[str], *, level: str | None = None, max_file_bytes: int, max_cells: int
) -> LdtkLevel:
    """Read the project at ``path`` and the level ``level`` (an identifier; the first level if ``None``).

    Raises
    ------
    LevelError
        Naming the file (the project or a level file) and the JSON path at fault; for an unknown
        ``level``, listing the project's levels.
    """
    source = display_name(path)
    root = parse_json_bytes(read_capped_bytes(path, max_file_bytes=max_file_bytes, kind="map"), source)
    fields = _Fields(source)
    root = fields.obj(root, "")
    if "defs" not in root and "layerInstances" in root:
        raise fields.error("", "an LDtk level file, not a project: import the .ldtk project it belongs to")
    defs = fields.obj(fields.required(root, "defs", ""), "defs")
    definitions = tuple(
        _layer_def(fields, item, f"defs.layers[{index}]")
        for index, item in enumerate(fields.objects(fields.required(defs, "layers", "defs"), "defs.layers"))
    )
    default_grid = fields.integer(root.get("defaultGridSize", 16), "defaultGridSize", minimum=1)
    levels = _levels(fields, root)
    if not levels:
        raise fields.error("levels", "the project has no levels")
    names = [fields.text(fields.required(item, "identifier", where), f"{where}.identifier") for where, item in levels]
    notes: list[str] = []
    if level is None:
        chosen = 0
        if len(levels) > 1:
            notes.append(
                f"imported the first of {len(levels)} levels, {quoted(names[0], 60)} (others: {listed(quoted(name, 60) for name in names[1:])}; "
                "choose one with --level NAME)"
            )
    else:
        matches = [index for index, name in enumerate(names) if name == level] or [
            index for index, name in enumerate(names) if name.lower() == level.lower()
        ]
        if not matches:
            raise LevelError(f"{source}: no level {excerpt(level)}; the levels are {listed(map(repr, names), 12)}")
        chosen = matches[0]
    where, item = levels[chosen]
    width = fields.integer(fields.required(item, "pxWid", where), f"{where}.pxWid", minimum=1)
    height = fields.integer(fields.required(item, "pxHei", where), f"{where}.pxHei", minimum=1)
    instances = item.get("layerInstances")
    if instances is None:
        fields, instances, where = _external_level(fields, path, item, where, max_file_bytes)
    by_uid = {definition.uid: definition for definition in definitions}
    layers = []
    for index, raw in enumerate(fields.objects(instances, f"{where}.layerInstances")):
        layer = _layer(fields, raw, f"{where}.layerInstances[{index}]", by_uid, max_cells)
        if layer.kind in LAYER_TYPES:
            layers.append(layer)
        else:
            notes.append(f"ignored layer {quoted(layer.identifier, 60)} of unknown type {excerpt(layer.kind)}")
    others = tuple(name for index, name in enumerate(names) if index != chosen)
    return LdtkLevel(
        names[chosen], width, height, tuple(layers), definitions, default_grid, others, tuple(notes),
        _field_values(item.get("fieldInstances")),
    )  # fmt: skip


def _levels(fields: _Fields, root: dict[str, Any]) -> list[tuple[str, dict[str, Any]]]:
    """Every level with its JSON path: ``levels``, then the levels of each of ``worlds`` (multi-world projects)."""
    found = [(f"levels[{index}]", item) for index, item in enumerate(fields.objects(root.get("levels", []), "levels"))]
    for number, world in enumerate(fields.objects(root.get("worlds") or [], "worlds")):
        where = f"worlds[{number}].levels"
        found += [
            (f"{where}[{index}]", item) for index, item in enumerate(fields.objects(world.get("levels", []), where))
        ]
    return found


def _external_level(
    fields: _Fields, path: str | os.PathLike[str], item: dict[str, Any], where: str, max_file_bytes: int
) -> tuple[_Fields, Any, str]:
    """The ``layerInstances`` of a level saved in its own ``.ldtkl`` file, and the reader for that file."""
    relative = item.get("externalRelPath")
    if relative is None:
        raise fields.error(f"{where}.layerInstances", "missing (null, and no externalRelPath to a level file)")
    relative = fields.text(relative, f"{where}.externalRelPath")
    if PurePosixPath(relative).is_absolute() or PureWindowsPath(relative).is_absolute():
        raise fields.error(f"{where}.externalRelPath", f"must be relative to the project, not {excerpt(relative)}")
    level_path = Path(path).parent / relative
    level_source = display_name(level_path)
    try:
        found = level_path.is_file()
    except OSError as failure:  # a name longer than the system takes, a loop of links...
        why = failure.strerror or type(failure).__name__
        raise fields.error(
            f"{where}.externalRelPath", f"level file {excerpt(relative)} cannot be read: {why}"
        ) from None
    if not found:
        shown = level_source if len(level_source) <= 300 else excerpt(level_source)
        raise fields.error(f"{where}.externalRelPath", f"level file {shown} not found")
    data = parse_json_bytes(read_capped_bytes(level_path, max_file_bytes=max_file_bytes, kind="map"), level_source)
    level_fields = _Fields(level_source)
    data = level_fields.obj(data, "")
    return level_fields, level_fields.required(data, "layerInstances", ""), ""


def _layer_def(fields: _Fields, item: dict[str, Any], where: str) -> LayerDef:
    uid = fields.integer(fields.required(item, "uid", where), f"{where}.uid", maximum=2**53)
    identifier = fields.text(fields.required(item, "identifier", where), f"{where}.identifier")
    kind = fields.text(item.get("__type", item.get("type")), f"{where}.__type")
    groups = {
        fields.integer(group.get("uid"), f"{where}.intGridValuesGroups[{index}].uid", maximum=2**53): fields.text(
            group.get("identifier"), f"{where}.intGridValuesGroups[{index}].identifier", empty=True
        )
        for index, group in enumerate(
            fields.objects(item.get("intGridValuesGroups") or [], f"{where}.intGridValuesGroups")
        )
    }
    values = []
    for index, value in enumerate(fields.objects(item.get("intGridValues") or [], f"{where}.intGridValues")):
        here = f"{where}.intGridValues[{index}]"
        number = fields.integer(fields.required(value, "value", here), f"{here}.value", maximum=2**31 - 1)
        name = fields.text(value.get("identifier"), f"{here}.identifier", empty=True)
        group = value.get("groupUid")
        values.append(ValueDef(number, name, groups.get(group, "") if isinstance(group, int) else ""))
    source_uid = item.get("autoSourceLayerDefUid")
    if source_uid is not None:
        source_uid = fields.integer(source_uid, f"{where}.autoSourceLayerDefUid", maximum=2**53)
    return LayerDef(uid, identifier, kind, tuple(values), source_uid)


def _layer(fields: _Fields, raw: dict[str, Any], where: str, definitions: dict[int, LayerDef], max_cells: int) -> Layer:
    identifier = fields.text(fields.required(raw, "__identifier", where), f"{where}.__identifier")
    kind = fields.text(fields.required(raw, "__type", where), f"{where}.__type")
    if kind not in LAYER_TYPES:
        return Layer(identifier, kind, None, 1, (0.0, 0.0))
    uid = fields.integer(fields.required(raw, "layerDefUid", where), f"{where}.layerDefUid", maximum=2**53)
    definition = definitions.get(uid)
    if definition is None and kind in ("IntGrid", "AutoLayer"):
        raise fields.error(f"{where}.layerDefUid", f"{uid} is no layer of defs.layers")
    grid = fields.integer(fields.required(raw, "__gridSize", where), f"{where}.__gridSize", minimum=1)
    offset = (
        fields.number(raw.get("__pxTotalOffsetX", raw.get("pxOffsetX", 0)), f"{where}.__pxTotalOffsetX"),
        fields.number(raw.get("__pxTotalOffsetY", raw.get("pxOffsetY", 0)), f"{where}.__pxTotalOffsetY"),
    )
    if kind == "IntGrid":
        return Layer(identifier, kind, definition, grid, offset, values=_int_grid(fields, raw, where, max_cells))
    if kind == "Entities":
        entities = tuple(
            _entity(fields, item, f"{where}.entityInstances[{index}]", offset)
            for index, item in enumerate(fields.objects(raw.get("entityInstances") or [], f"{where}.entityInstances"))
        )
        return Layer(identifier, kind, definition, grid, offset, entities=entities)
    return Layer(identifier, kind, definition, grid, offset)


def _int_grid(fields: _Fields, raw: dict[str, Any], where: str, max_cells: int) -> np.ndarray:
    """An IntGrid layer's values as ``int64 (rows, cols)``, from ``intGridCsv`` (or the pre-0.8 ``intGrid``)."""
    cols = fields.integer(fields.required(raw, "__cWid", where), f"{where}.__cWid")
    rows = fields.integer(fields.required(raw, "__cHei", where), f"{where}.__cHei")
    if "intGridCsv" in raw or "intGrid" not in raw:
        here = f"{where}.intGridCsv"
        csv = fields.required(raw, "intGridCsv", where)
        if not isinstance(csv, list):
            raise fields.error(here, f"expected a list of whole numbers, not {json_type(csv)}")
        if len(csv) != cols * rows:
            raise fields.error(here, f"{len(csv)} values, expected {cols * rows} (__cWid {cols} x __cHei {rows})")
        bad = next((index for index, value in enumerate(csv) if type(value) is not int or value < 0), None)
        if bad is not None:
            raise fields.error(f"{here}[{bad}]", f"expected a whole number from 0 up, not {excerpt(csv[bad])}")
        try:
            return np.array(csv, dtype=np.int64).reshape(rows, cols)
        except OverflowError:
            raise fields.error(here, "a value is too large") from None
    # Before LDtk 0.8: the painted cells only, {"coordId": cell, "v": value index from 0}.
    here = f"{where}.intGrid"
    if cols * rows > 16 * max_cells:
        raise fields.error(where, f"{cols} x {rows} cells, over the limit (raise it with --max-cells)")
    values = np.zeros(cols * rows, dtype=np.int64)
    for index, cell in enumerate(fields.objects(raw["intGrid"], here)):
        coord = fields.integer(fields.required(cell, "coordId", f"{here}[{index}]"), f"{here}[{index}].coordId")
        if coord >= cols * rows:
            raise fields.error(f"{here}[{index}].coordId", f"{coord} is outside the {cols} x {rows} layer")
        values[coord] = fields.integer(fields.required(cell, "v", f"{here}[{index}]"), f"{here}[{index}].v") + 1
    return values.reshape(rows, cols)


def _entity(fields: _Fields, item: dict[str, Any], where: str, offset: tuple[float, float]) -> Entity:
    """An entity and the centre of its box: ``px`` is its pivot point, ``__pivot`` where that is in the box."""
    identifier = fields.text(fields.required(item, "__identifier", where), f"{where}.__identifier")
    tags = item.get("__tags") or []
    if not isinstance(tags, list):
        raise fields.error(f"{where}.__tags", f"expected a list of names, not {json_type(tags)}")
    px = fields.required(item, "px", where)
    if not isinstance(px, list) or len(px) != 2:
        raise fields.error(f"{where}.px", f"expected [x, y], not {excerpt(px)}")
    x, y = (fields.number(value, f"{where}.px[{index}]") for index, value in enumerate(px))
    pivot = item.get("__pivot", [0.0, 0.0])
    if not isinstance(pivot, list) or len(pivot) != 2:
        raise fields.error(f"{where}.__pivot", f"expected [x, y], not {excerpt(pivot)}")
    pivot_x, pivot_y = (fields.number(value, f"{where}.__pivot[{index}]") for index, value in enumerate(pivot))
    width = fields.number(item.get("width", 0), f"{where}.width")
    height = fields.number(item.get("height", 0), f"{where}.height")
    centre = (x + offset[0] + (0.5 - pivot_x) * width, y + offset[1] + (0.5 - pivot_y) * height)
    return Entity(
        identifier,
        tuple(tag for tag in tags if isinstance(tag, str)),
        centre,
        _field_values(item.get("fieldInstances")),
    )


def _field_values(raw: Any) -> tuple[tuple[str, Any], ...]:
    """``(identifier, value)`` of each well-formed field instance; the level's checks judge the values."""
    if not isinstance(raw, list):
        return ()
    return tuple(
        (field["__identifier"], field.get("__value"))
        for field in raw
        if isinstance(field, dict) and isinstance(field.get("__identifier"), str)
    )
