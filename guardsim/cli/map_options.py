"""The import options every command that reads a level shares, so a map can stand wherever a level can.

``@map_options`` adds ``--cell-size``, ``--threshold``, ``--spawn-tile``, ``--wall-tile``,
``--wall-property``, ``--wall-class``, ``--wall-layer``, ``--floor-layer``, ``--view``, ``--wall-value``,
``--level`` and ``--strict`` to a command and hands it one ``map_import`` argument (a :class:`MapImport`) to pass to
:func:`guardsim.cli.common.load`.
"""

from __future__ import annotations

import dataclasses
import functools
import sys
from collections.abc import Callable
from typing import Any, TypeVar, cast

import click

from guardsim.cli.types import FiniteFloatRange
from guardsim.importers import FORMATS, ImportedLevel, ImportOptions, load_level
from guardsim.importers.image import DEFAULT_THRESHOLD
from guardsim.importers.loading import is_map_json
from guardsim.importers.tiled_checks import VIEWS
from guardsim.level import level_to_data, read_level_json

__all__ = ["STRICT_EXIT", "MapImport", "level_data", "map_options", "report_import"]

F = TypeVar("F", bound=Callable[..., Any])
#: Exit status of a command run with --strict whose map import warned.
STRICT_EXIT = 1


@dataclasses.dataclass(frozen=True)
class MapImport:
    """How a map given in place of a level is imported, and whether its warnings fail the command."""

    options: ImportOptions = dataclasses.field(default_factory=ImportOptions)
    strict: bool = False

    @property
    def keywords(self) -> dict[str, Any]:
        """The import options as the keywords of :func:`guardsim.load_level`."""
        return {field.name: getattr(self.options, field.name) for field in dataclasses.fields(self.options)}


def report_import(imported: ImportedLevel, strict: bool) -> None:
    """The import's summary and warnings on stderr; with ``strict``, warnings end the command with status 1."""
    click.echo(imported.summary(), err=True)
    for warning in imported.warnings:
        click.echo(f"guardsim: warning: {imported.level.source}: {warning}", err=True)
    if strict and imported.warnings:
        click.echo(
            f"guardsim: error: {imported.level.source}: {len(imported.warnings)} import warning(s) and --strict",
            err=True,
        )
        sys.exit(STRICT_EXIT)


def level_data(path: str, map_import: MapImport, *, max_cells: int, max_vertices: int, max_file_bytes: int) -> Any:
    """The level JSON of a level file as read (for ``validate``), or of a map imported in memory.

    A map's summary and warnings go to stderr (see :func:`report_import`).
    """
    suffix = path.lower().rsplit(".", 1)[-1] if "." in path else ""
    if f".{suffix}" != ".json" and f".{suffix}" in FORMATS:
        data = None
    else:
        data = read_level_json(path, max_file_bytes=max_file_bytes)
        if not is_map_json(data):
            return data
    level = load_level(
        path,
        report=lambda imported: report_import(imported, map_import.strict),
        max_cells=max_cells,
        max_vertices=max_vertices,
        max_file_bytes=max_file_bytes,
        **map_import.keywords,
    )
    return level_to_data(level)


def map_options(command: F) -> F:
    """Add the import options; the command receives them as one ``map_import: MapImport`` argument."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        options = ImportOptions(
            cell_size=kwargs.pop("cell_size"),
            threshold=kwargs.pop("threshold"),
            spawn_tiles=tuple(kwargs.pop("spawn_tiles")),
            wall_tiles=tuple(kwargs.pop("wall_tiles")),
            wall_properties=tuple(kwargs.pop("wall_properties")),
            wall_classes=tuple(kwargs.pop("wall_classes")),
            wall_layers=tuple(kwargs.pop("wall_layers")),
            floor_layers=tuple(kwargs.pop("floor_layers")),
            view=kwargs.pop("view"),
            wall_values=tuple(kwargs.pop("wall_values")),
            level=kwargs.pop("ldtk_level"),
        )
        return command(*args, map_import=MapImport(options, kwargs.pop("strict")), **kwargs)

    decorated: Any = wrapper
    for option in reversed(_OPTIONS):
        decorated = option(decorated)
    return cast(F, decorated)


def _check_wall_properties(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[str, ...]:
    """Click callback: each ``--wall-property`` is ``NAME`` or ``NAME=VALUE``."""
    from guardsim.importers.tiled_roles import parse_wall_property

    for value in values:
        try:
            parse_wall_property(value)
        except ValueError as error:
            raise click.BadParameter(str(error), ctx=ctx, param=param) from None
    return values


def _check_wall_values(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[str, ...]:
    """Click callback: each ``--wall-value`` is an IntGrid value's number or name."""
    if any(not value.strip() for value in values):
        raise click.BadParameter("expected an IntGrid value's number or name, got an empty text", ctx=ctx, param=param)
    return tuple(value.strip() for value in values)


def _check_wall_classes(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[str, ...]:
    """Click callback: each ``--wall-class`` names a class."""
    if any(not value.strip() for value in values):
        raise click.BadParameter("expected a class name, got an empty text", ctx=ctx, param=param)
    return values


_OPTIONS = [
    click.option(
        "--cell-size",
        type=FiniteFloatRange(min=0, min_open=True, max=1e6),
        help="Maps: the level's cell_size in world units; one map cell, tile or pixel is one unit. [default: 1]",
    ),
    click.option(
        "--threshold",
        type=click.IntRange(0, 256),
        default=DEFAULT_THRESHOLD,
        show_default=True,
        help="Images: pixels darker than this grey level (0-255) are walls.",
    ),
    click.option(
        "--spawn-tile",
        "spawn_tiles",
        type=click.IntRange(min=1, max=2**32 - 1),
        multiple=True,
        metavar="GID",
        help="Tiled: a global tile id that marks a guard spawn (repeatable).",
    ),
    click.option(
        "--wall-tile",
        "wall_tiles",
        type=click.IntRange(min=1, max=2**32 - 1),
        multiple=True,
        metavar="GID",
        help="Tiled: a global tile id that is a wall wherever it is drawn (repeatable).",
    ),
    click.option(
        "--wall-property",
        "wall_properties",
        multiple=True,
        callback=_check_wall_properties,
        metavar="NAME[=VALUE]",
        help="Tiled: tiles and objects whose property NAME reads true (or equals VALUE) are walls; replaces the "
        "guess from property names (repeatable).",
    ),
    click.option(
        "--wall-class",
        "wall_classes",
        multiple=True,
        callback=_check_wall_classes,
        metavar="NAME",
        help="Tiled: tiles and objects of this class (any case) are walls (repeatable).",
    ),
    click.option(
        "--wall-layer",
        "wall_layers",
        multiple=True,
        metavar="NAME",
        help="Tiled: a layer (or group/layer) whose tiles or objects are walls, replacing the guess (repeatable).",
    ),
    click.option(
        "--floor-layer",
        "floor_layers",
        multiple=True,
        metavar="NAME",
        help="Tiled: a tile layer whose tiles are floor, replacing the guess (repeatable).",
    ),
    click.option(
        "--view",
        type=click.Choice(VIEWS),
        default="auto",
        show_default=True,
        help="Tiled: auto refuses a map that looks like a side view (a platformer: layers named platforms or "
        "ladders, a gravity property); top-down imports it as seen from above.",
    ),
    click.option(
        "--wall-value",
        "wall_values",
        multiple=True,
        callback=_check_wall_values,
        metavar="N|NAME",
        help="LDtk: an IntGrid value (its number, or its name in any case) that is a wall in every IntGrid layer; "
        "replaces the guess from value names (repeatable).",
    ),
    click.option(
        "--level",
        "ldtk_level",
        metavar="NAME",
        help="LDtk: the level to import, by identifier. [default: the first]",
    ),
    click.option(
        "--strict",
        is_flag=True,
        help=f"Maps: import warnings (no walls found, ...) end the command with exit status {STRICT_EXIT}.",
    ),
]
