"""What every command shares: one-line errors, limit options, option parsers."""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from typing import Any, TypeVar

import click
import numpy as np

from guardsim.errors import GuardsimError
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES, Level, load_level

__all__ = ["limit_options", "load", "parse_point", "reports_errors"]

F = TypeVar("F", bound=Callable[..., Any])


def reports_errors(command: F) -> F:
    """Turn guardsim's own errors into one line on stderr and exit status 2; Ctrl-C into status 130."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return command(*args, **kwargs)
        except GuardsimError as error:
            click.echo(f"guardsim: error: {error}", err=True)
            sys.exit(2)
        except KeyboardInterrupt:
            click.echo("guardsim: interrupted", err=True)
            sys.exit(130)

    return wrapper  # type: ignore[return-value]


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


def load(path: str, max_cells: int, max_vertices: int, max_file_bytes: int) -> Level:
    """Load a level with the limits given on the command line."""
    return load_level(path, max_cells=max_cells, max_vertices=max_vertices, max_file_bytes=max_file_bytes)
