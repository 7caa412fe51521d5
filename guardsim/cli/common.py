"""What every command shares: one-line errors, limit options, option parsers."""

from __future__ import annotations

import dataclasses
import functools
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar, cast

import click
import numpy as np

from guardsim.cli.map_options import MapImport, map_options, report_import
from guardsim.cli.types import FiniteFloatRange
from guardsim.errors import GuardsimError, LimitError
from guardsim.files.reading import display_path
from guardsim.grid import CoverageGrid
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES, Level
from guardsim.level.limits import MAX_SNEAK_TICKS
from guardsim.scene import Scene
from guardsim.starts import episode_start
from guardsim.vision.rules import LineOfSight

__all__ = [
    "LIMIT_OPTIONS",
    "DetectionOverrides",
    "EarsOverrides",
    "build_scene",
    "cell_text",
    "check_outside",
    "cli_start",
    "detection_options",
    "ears_options",
    "gif_suffix",
    "level_options",
    "limit_options",
    "load",
    "one_line",
    "parse_point",
    "picture_option",
    "picture_path",
    "reports_errors",
    "vision_options",
    "with_options",
]

F = TypeVar("F", bound=Callable[..., Any])


#: The library names a limit (or a setting) by its keyword; the command line says which option changes it.
LIMIT_OPTIONS = {
    "max_cells": "raise it with --max-cells",
    "max_vertices": "raise it with --max-vertices",
    "max_file_bytes": "raise it with --max-file-bytes",
    "max_rays": "raise it with --max-rays",
    "max_frames": "raise it with --max-frames",
    "max_frame_size": "raise it with --max-frame-size",
    "max_view_entries": "shorten the view range or use larger cells",
    "max_wall_entries": "use fewer long walls, or a longer view range for larger buckets",
    "memory_bytes": "lower --memory-mb",
    "memory_mb": "raise it with --memory-mb",
    "update": "run with --update",
}
_LIMIT_KEYWORD = re.compile(r"\((" + "|".join(LIMIT_OPTIONS) + r")\b([^()]*)\)")


def with_options(message: str) -> str:
    """A library message with each limit keyword, ``(max_cells)``, followed by the option that raises it.

    >>> with_options("over the limit of 10 cells (max_cells)")
    'over the limit of 10 cells (max_cells: raise it with --max-cells)'
    """
    return _LIMIT_KEYWORD.sub(lambda m: f"({m[1]}{m[2]}: {LIMIT_OPTIONS[m[1]]})", message)


def _inputs() -> str:
    """The files the running command was given, for a message that has no file of its own."""
    context = click.get_current_context(silent=True)
    if context is None:
        return ""
    arguments = [param.name for param in context.command.params if isinstance(param, click.Argument)]
    given = [
        str(item)
        for name in arguments
        if (value := context.params.get(name or ""))
        for item in (value if isinstance(value, (tuple, list)) else (value,))
    ]
    return f"{', '.join(display_path(item) for item in given[:3])}: " if given else ""


def reports_errors(command: F) -> F:
    """Turn guardsim's own errors (and running out of memory) into one line on stderr and exit status 2;
    Ctrl-C into status 130. Limit keywords in the message gain the option that raises them."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return command(*args, **kwargs)
        except GuardsimError as error:
            message = str(error)
            inputs = _inputs()
            # A library limit met deep in the work (a view table, say) knows no file: name the command's input.
            if (
                isinstance(error, LimitError)
                and inputs
                and _LIMIT_KEYWORD.search(message)
                and not any(part.strip() in message for part in inputs.rstrip(": ").split(", "))
            ):
                message = inputs + message
            click.echo(f"guardsim: error: {one_line(with_options(message))}", err=True)
            sys.exit(2)
        except MemoryError:
            # Only reachable when a size limit was raised past what this machine holds.
            click.echo(f"guardsim: error: {_inputs()}out of memory; lower --max-cells or --max-vertices", err=True)
            sys.exit(2)
        except KeyboardInterrupt:
            click.echo("guardsim: interrupted", err=True)
            sys.exit(130)

    return wrapper  # type: ignore[return-value]


def one_line(text: str) -> str:
    """``text`` with line breaks turned into spaces, so that a message stays one line."""
    return " ".join(text.splitlines()) if "\n" in text or "\r" in text else text


def gif_suffix(_ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
    """A GIF output path: a name ending in another format's suffix (``x.png``) would hold a GIF that
    viewers and engines read as that format, so it is refused; a name without a suffix is kept."""
    if value is not None:
        suffix = os.path.splitext(value)[1]
        if suffix and suffix.lower() != ".gif":
            raise click.BadParameter(f"{value!r} ends in {suffix!r}, but a GIF is written: name it .gif", param=param)
    return value


def picture_option(name: str, dest: str, text: str) -> Callable[[F], F]:
    """A picture option that takes a file name, ``--gif FILE``; given bare (``--gif``, the spelling of
    old) it writes the picture's default name in the ``--out`` folder."""
    return click.option(
        name,
        dest,
        is_flag=False,
        flag_value="",
        default=None,
        metavar="FILE",
        callback=gif_suffix if name == "--gif" else None,
        help=text,
    )


def picture_path(value: str | None, folder: str | None, default_name: str, option: str) -> Path | None:
    """Where a picture option (:func:`picture_option`) writes: its file name, or ``default_name`` in the
    ``--out`` folder when given bare; ``None`` when not given."""
    if value is None:
        return None
    if value:
        return Path(value)
    if folder is None:
        raise GuardsimError(f"{option} FILE: give a file name (a bare {option} writes into the --out folder)")
    return Path(folder) / default_name


def check_outside(folder: str | None, *paths: str | Path | None) -> None:
    """Check before the work that each output named outside the ``--out`` folder (anywhere, without one)
    can be written, so a failed command leaves nothing behind, not even an empty folder; one inside it
    is written once the folder is made."""
    from guardsim.files.output import check_writable

    inside = None if folder is None else Path(folder).resolve()
    for named in paths:
        if named is not None and (inside is None or not Path(named).resolve().is_relative_to(inside)):
            check_writable(named)


def cell_text(grid: CoverageGrid, cell: tuple[int, int]) -> str:
    """A cell as a summary gives it: its centre in world units as the command line takes a point, then the
    cell, ``3.5,0.5 (cell [3, 0])``."""
    x, y = grid.centre(*cell)
    return f"{x:g},{y:g} (cell [{cell[0]}, {cell[1]}])"


def parse_point(_ctx: click.Context, param: click.Parameter, value: str | None) -> tuple[float, float] | None:
    """Click callback: ``X,Y`` into a pair of finite floats."""
    if value is None:
        return None
    try:
        x, y = (float(part) for part in value.split(","))
    except ValueError:
        raise click.BadParameter(f"expected X,Y (two numbers), got {value!r}", param=param) from None
    if not (np.isfinite(x) and np.isfinite(y)):
        raise click.BadParameter(f"expected finite numbers, got {value!r}", param=param)
    return x, y


def limit_options(command: F) -> F:
    """Options that raise the loader's size limits: --max-cells, --max-vertices, --max-file-bytes."""
    command = click.option(
        "--max-file-bytes",
        type=click.IntRange(min=1),
        default=DEFAULT_MAX_FILE_BYTES,
        show_default=True,
        help="Largest level file read.",
    )(command)
    command = click.option(
        "--max-vertices",
        type=click.IntRange(min=3),
        default=DEFAULT_MAX_VERTICES,
        show_default=True,
        help="Most vertices over all rings.",
    )(command)
    command = click.option(
        "--max-cells",
        type=click.IntRange(min=1),
        default=DEFAULT_MAX_CELLS,
        show_default=True,
        help="Largest grid (rows x cols) a level may produce.",
    )(command)
    return command


def load(path: str, max_cells: int, max_vertices: int, max_file_bytes: int, map_import: Any = None) -> Level:
    """:func:`guardsim.load_level` with the command's options; an imported map's summary and warnings on stderr."""
    from guardsim.importers import load_level

    map_import = map_import or MapImport()
    return load_level(
        path,
        report=lambda imported: report_import(imported, map_import.strict),
        max_cells=max_cells,
        max_vertices=max_vertices,
        max_file_bytes=max_file_bytes,
        **map_import.keywords,
    )


def vision_options(command: F) -> F:
    """Options that change how the guard sees: --los, --fov, --view-range."""
    command = click.option(
        "--view-range",
        type=FiniteFloatRange(min=0, min_open=True),
        help="Override the guard's view range (world units) [default: the level's; unlimited with --los bresenham].",
    )(command)
    command = click.option(
        "--fov",
        type=FiniteFloatRange(min=0, max=360, min_open=True),
        help="Override the guard's field of view in degrees.",
    )(command)
    command = click.option(
        "--los",
        type=click.Choice(LineOfSight.names()),
        default="pymunk",
        show_default=True,
        help="Line of sight: pymunk rays against the walls, or Bresenham lines over free cells (grid solvers' rule).",
    )(command)
    return command


@dataclasses.dataclass(frozen=True)
class DetectionOverrides:
    """The detection options a command was given (:func:`detection_options`): each replaces the level's
    key of the same name (:class:`guardsim.level.GuardSpec`); ``None`` keeps the level's."""

    detect_near: float | None = None
    detect_far: float | None = None
    forget: float | None = None
    suspicious: float | None = None

    def apply(self, level: Level) -> Level:
        """``level`` with the overrides given applied (the level itself when none is)."""
        given = {key: value for key, value in dataclasses.asdict(self).items() if value is not None}
        return dataclasses.replace(level, guard=dataclasses.replace(level.guard, **given)) if given else level


def detection_options(command: F) -> F:
    """Options that override the level's detection keys: --detect-near, --detect-far, --forget, --suspicious.

    The command receives them as one ``detection_overrides: DetectionOverrides`` argument to apply to the level it
    loads (:meth:`DetectionOverrides.apply`).
    """
    helps = {
        "suspicious": "Awareness level (0 to 1) at which a guard becomes suspicious [default: the level's, else 0.5].",
        "forget": "Seconds for a full awareness meter to drain out of view [default: the level's, else 4].",
        "detect-far": "Seconds in view to be detected at the edge of the view range [default: the level's, else 1.5].",
        "detect-near": "Seconds in view to be detected at distance 0 (0 and --detect-far 0: seen is caught) "
        "[default: the level's, else 0.25].",
    }
    keys = [field.name for field in dataclasses.fields(DetectionOverrides)]

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        overrides = DetectionOverrides(**{key: kwargs.pop(key) for key in keys})
        return command(*args, detection_overrides=overrides, **kwargs)

    decorated: Any = wrapper
    for name, text in helps.items():
        upper = 1 if name == "suspicious" else None
        decorated = click.option(f"--{name}", type=FiniteFloatRange(min=0, max=upper), help=text)(decorated)
    return cast(F, decorated)


def level_options(*, vision: bool = True, detection: bool = False) -> Callable[[F], F]:
    """The stack every command that reads a LEVEL shares, in the order its help lists them: with
    ``detection`` the detection overrides, with ``vision`` --los/--fov/--view-range, then the import
    options (one ``map_import`` argument), the size limits, and guardsim's errors as one line each."""

    def decorate(command: F) -> F:
        stacked = map_options(limit_options(reports_errors(command)))
        stacked = vision_options(stacked) if vision else stacked
        return detection_options(stacked) if detection else stacked

    return decorate


@dataclasses.dataclass(frozen=True)
class EarsOverrides:
    """The noise options a command was given (:func:`ears_options`): each replaces the level's
    ``intruder`` key of the same name (:class:`guardsim.level.model.IntruderSpec`); ``None`` keeps it."""

    walk_noise: float | None = None
    sneak_noise: float | None = None
    sneak_ticks: int | None = None

    def apply(self, level: Level) -> Level:
        """``level`` with the overrides given applied (the level itself when none is)."""
        given = {key: value for key, value in dataclasses.asdict(self).items() if value is not None}
        return dataclasses.replace(level, intruder=dataclasses.replace(level.intruder, **given)) if given else level


def ears_options(command: F) -> F:
    """Options that override the level's intruder noise keys: --walk-noise, --sneak-noise, --sneak-ticks.

    The command receives them as one ``ears_overrides: EarsOverrides`` argument (:meth:`EarsOverrides.apply`).
    """
    keys = [field.name for field in dataclasses.fields(EarsOverrides)]

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        return command(*args, ears_overrides=EarsOverrides(**{key: kwargs.pop(key) for key in keys}), **kwargs)

    decorated: Any = wrapper
    decorated = click.option(
        "--sneak-ticks",
        type=click.IntRange(min=1, max=MAX_SNEAK_TICKS),
        help="Ticks a sneaking step takes [level's key].",
    )(decorated)
    decorated = click.option(
        "--sneak-noise",
        type=FiniteFloatRange(min=0, max=1e6),
        help="World units a sneaking step carries [level's key].",
    )(decorated)
    decorated = click.option(
        "--walk-noise",
        type=FiniteFloatRange(min=0, max=1e6),
        help="World units a walking step carries [level's intruder key].",
    )(decorated)
    return cast(F, decorated)


def build_scene(level: Level, los: str = "pymunk", fov: float | None = None, view_range: float | None = None) -> Scene:
    """The scene of a level with the vision options applied (:meth:`Scene.from_level`): with
    ``--los bresenham`` and no ``--view-range``, the range is unlimited."""
    return Scene.from_level(level, **Scene.vision_options(los, fov, view_range))


def cli_start(
    scene: Scene,
    *,
    seed: int,
    episode: int | None,
    start: tuple[float, float] | None,
    heading: str | None,
) -> tuple[np.random.Generator, tuple[int, int], int]:
    """The generator, start cell and heading the way `play` and `bounds` choose them
    (:func:`guardsim.starts.episode_start`)."""
    return episode_start(scene, seed=seed, episode=episode, point=start, heading=heading)
