"""The import options: how a map is turned into a level, each option written once.

:class:`ImportOptions` is the one list. Each field carries its :class:`OptionForm` (the command-line
flag, help, bounds and which reader takes it), from which the shared click options
(:mod:`guardsim.cli.map_options`), the keywords of :func:`guardsim.load_level` and the keywords each
reader receives are all derived. Adding an import option is adding a field here (and reading it in
its importer).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

from guardsim.importers.image import DEFAULT_THRESHOLD
from guardsim.importers.tiled_checks import VIEWS

__all__ = ["READERS", "ImportOptions", "OptionForm", "option_form"]

#: Reader name -> the maps it reads, as errors name them.
READERS = {"tiled": "Tiled maps", "ldtk": "LDtk projects", "image": "images"}


@dataclasses.dataclass(frozen=True)
class OptionForm:
    """How one import option reads on the command line, and which reader takes it."""

    flag: str
    """The option's flag (``--spawn-tile``); a field whose default is a tuple repeats."""
    help: str
    """The option's help text."""
    reader: str | None = None
    """The reader that takes it (a key of :data:`READERS`); ``None``: every map."""
    metavar: str | None = None
    """What the value is called in the help (``GID``); ``None``: click's name for the type."""
    low: float | None = None
    """Smallest value, for numbers."""
    high: float | None = None
    """Largest value, for numbers."""
    low_open: bool = False
    """Whether ``low`` itself is refused."""
    choices: tuple[str, ...] = ()
    """The only values allowed, for words."""
    check: Callable[[str], str] | None = None
    """Checks one value and returns it as kept (a ``ValueError`` saying what is wrong)."""


def _option(default: Any, form: OptionForm) -> Any:
    return dataclasses.field(default=default, metadata={"form": form})


def option_form(field: dataclasses.Field[Any]) -> OptionForm:
    """The :class:`OptionForm` of a field of :class:`ImportOptions`."""
    form: OptionForm = field.metadata["form"]
    return form


def _wall_property(value: str) -> str:
    from guardsim.importers.tiled_roles import parse_wall_property

    parse_wall_property(value)
    return value


def _class_name(value: str) -> str:
    if not value.strip():
        raise ValueError("expected a class name, got an empty text")
    return value


def _intgrid_value(value: str) -> str:
    if not value.strip():
        raise ValueError("expected an IntGrid value's number or name, got an empty text")
    return value.strip()


#: Tiled's global tile ids are unsigned 32-bit numbers; 0 is no tile.
_LAST_GID = 2**32 - 1


@dataclasses.dataclass(frozen=True, kw_only=True)
class ImportOptions:
    """How maps are imported; the defaults are what ``guardsim import`` does without options.

    Examples
    --------
    >>> ImportOptions(wall_layers=["Walls"]).for_reader("tiled")["wall_layers"]
    ('Walls',)
    """

    cell_size: float | None = _option(
        None,
        OptionForm(
            "--cell-size",
            "Maps: the level's cell_size in world units; one map cell, tile or pixel is one unit. [default: 1]",
            low=0,
            high=1e6,
            low_open=True,
        ),
    )
    threshold: int = _option(
        DEFAULT_THRESHOLD,
        OptionForm(
            "--threshold", "Images: pixels darker than this grey level (0-255) are walls.", "image", low=0, high=256
        ),
    )
    spawn_tiles: tuple[int, ...] = _option(
        (),
        OptionForm(
            "--spawn-tile",
            "Tiled: a global tile id that marks a guard spawn (repeatable).",
            "tiled",
            "GID",
            1,
            _LAST_GID,
        ),
    )
    wall_tiles: tuple[int, ...] = _option(
        (),
        OptionForm(
            "--wall-tile",
            "Tiled: a global tile id that is a wall wherever it is drawn (repeatable).",
            "tiled",
            "GID",
            1,
            _LAST_GID,
        ),
    )
    wall_properties: tuple[str, ...] = _option(
        (),
        OptionForm(
            "--wall-property",
            "Tiled: tiles and objects whose property NAME reads true (or equals VALUE) are walls; replaces the "
            "guess from property names (repeatable).",
            "tiled",
            metavar="NAME[=VALUE]",
            check=_wall_property,
        ),
    )
    wall_classes: tuple[str, ...] = _option(
        (),
        OptionForm(
            "--wall-class",
            "Tiled: tiles and objects of this class (any case) are walls (repeatable).",
            "tiled",
            metavar="NAME",
            check=_class_name,
        ),
    )
    wall_layers: tuple[str, ...] = _option(
        (),
        OptionForm(
            "--wall-layer",
            "Tiled: a layer (or group/layer) whose tiles or objects are walls, replacing the guess (repeatable).",
            "tiled",
            metavar="NAME",
        ),
    )
    floor_layers: tuple[str, ...] = _option(
        (),
        OptionForm(
            "--floor-layer",
            "Tiled: a tile layer whose tiles are floor, replacing the guess (repeatable).",
            "tiled",
            metavar="NAME",
        ),
    )
    view: str = _option(
        "auto",
        OptionForm(
            "--view",
            "Tiled: auto refuses a map that looks like a side view (a platformer: layers named platforms or "
            "ladders, a gravity property); top-down imports it as seen from above.",
            "tiled",
            choices=VIEWS,
        ),
    )
    wall_values: tuple[str, ...] = _option(
        (),
        OptionForm(
            "--wall-value",
            "LDtk: an IntGrid value (its number, or its name in any case) that is a wall in every IntGrid layer; "
            "replaces the guess from value names (repeatable).",
            "ldtk",
            metavar="N|NAME",
            check=_intgrid_value,
        ),
    )
    level: str | None = _option(
        None,
        OptionForm("--level", "LDtk: the level to import, by identifier. [default: the first]", "ldtk", metavar="NAME"),
    )

    def __post_init__(self) -> None:
        # The library takes any iterable where the command line gives tuples; one kind is kept.
        for field in dataclasses.fields(self):
            if isinstance(field.default, tuple):
                object.__setattr__(self, field.name, tuple(getattr(self, field.name)))

    @property
    def keywords(self) -> dict[str, Any]:
        """Every option by name: the import keywords of :func:`guardsim.load_level`."""
        return {field.name: getattr(self, field.name) for field in dataclasses.fields(self)}

    def for_reader(self, reader: str) -> dict[str, Any]:
        """The options ``reader`` (a key of :data:`READERS`) takes, as its keywords."""
        return {
            field.name: getattr(self, field.name)
            for field in dataclasses.fields(self)
            if option_form(field).reader == reader
        }

    def given(self) -> list[tuple[str, str]]:
        """``(flag, reader)`` of each reader-specific option given a value (left at an empty default no
        more), in the order of the fields."""
        return [
            (form.flag, form.reader)
            for field in dataclasses.fields(self)
            if (form := option_form(field)).reader is not None
            and field.default in ((), None)
            and getattr(self, field.name) not in ((), None)
        ]
