"""The import options every command that reads a level shares, so a map can stand wherever a level can.

``@map_options`` adds one option per field of :class:`~guardsim.importers.options.ImportOptions`
(``--cell-size``, ``--threshold``, ``--spawn-tile``, ...: each field's ``OptionForm`` says how) and
``--strict`` to a command and hands it one ``map_import`` argument (a :class:`MapImport`) to pass to
:func:`guardsim.cli.common.load`.
"""

from __future__ import annotations

import dataclasses
import functools
import sys
import typing
from collections.abc import Callable
from typing import Any, TypeVar, cast

import click

from guardsim.cli.types import FiniteFloatRange
from guardsim.importers import FORMATS, ImportedLevel, load_level
from guardsim.importers.loading import is_map_json
from guardsim.importers.options import ImportOptions, option_form
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
        return self.options.keywords


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
        options = ImportOptions(**{field.name: kwargs.pop(_DEST + field.name) for field in _FIELDS})
        return command(*args, map_import=MapImport(options, kwargs.pop("strict")), **kwargs)

    decorated: Any = wrapper
    for option in reversed(_OPTIONS):
        decorated = option(decorated)
    return cast(F, decorated)


#: Prefix of the click parameter names of the import options, apart from the command's own parameters.
_DEST = "map_import_"
_FIELDS = dataclasses.fields(ImportOptions)


def _click_option(field: dataclasses.Field[Any], hint: Any) -> Callable[[F], F]:
    """The click option of one field of :class:`ImportOptions`, from its :class:`OptionForm`."""
    form = option_form(field)
    repeats = isinstance(field.default, tuple)
    kind = typing.get_args(hint)[0] if repeats or typing.get_args(hint) else hint
    bounds: dict[str, Any] = {"min": form.low, "max": form.high, "min_open": form.low_open}
    kind_of: Any = None
    if form.choices:
        kind_of = click.Choice(form.choices)
    elif kind is float:
        kind_of = FiniteFloatRange(**bounds)
    elif kind is int:
        kind_of = click.IntRange(**bounds)
    shown = field.default not in ((), None)
    extra: dict[str, Any] = {"default": field.default, "show_default": True} if shown else {}
    if form.check is not None:
        extra["callback"] = _checked(form.check)
    return click.option(
        form.flag, _DEST + field.name, type=kind_of, multiple=repeats, metavar=form.metavar, help=form.help, **extra
    )


def _checked(check: Callable[[str], str]) -> Callable[[click.Context, click.Parameter, Any], Any]:
    """A click callback that runs ``check`` on each value given (a ``ValueError`` is a bad parameter)."""

    def callback(ctx: click.Context, param: click.Parameter, values: Any) -> Any:
        if values is None:
            return None
        try:
            return tuple(check(value) for value in values) if isinstance(values, tuple) else check(values)
        except ValueError as error:
            raise click.BadParameter(str(error), ctx=ctx, param=param) from None

    return callback


_HINTS = typing.get_type_hints(ImportOptions)
_OPTIONS = [
    *(_click_option(field, _HINTS[field.name]) for field in _FIELDS),
    click.option(
        "--strict",
        is_flag=True,
        help=f"Maps: import warnings (no walls found, ...) end the command with exit status {STRICT_EXIT}.",
    ),
]
