"""What ``report``, ``diff`` and ``watch`` share: repeatable entry-goal pairs, progress lines."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

from guardsim.cli.common import parse_point
from guardsim.errors import GuardsimError

__all__ = ["check_outputs", "guards_option", "pair_options", "pairs_of", "progress_line"]

F = TypeVar("F", bound=Callable[..., Any])
Point = tuple[float, float]


def _each_point(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[Point, ...]:
    return tuple(point for point in (parse_point(ctx, param, value) for value in values) if point is not None)


def guards_option(command: F) -> F:
    """``--guards K``: the team size of the loop patrol made when no patrol file is given."""
    return click.option(
        "--guards",
        type=click.IntRange(min=1, max=64),
        default=1,
        show_default=True,
        help="Team size of the loop patrol made without a patrol file.",
    )(command)


def pair_options(command: F) -> F:
    """Repeatable ``--from X,Y`` and ``--to X,Y``: the k-th --from goes with the k-th --to."""
    command = click.option(
        "--to", "targets", multiple=True, callback=_each_point, metavar="X,Y", help="A goal (world units); repeatable."
    )(command)
    command = click.option(
        "--from",
        "sources",
        multiple=True,
        callback=_each_point,
        metavar="X,Y",
        help="An entry (world units), paired with the --to of the same rank; repeatable "
        "[default: each player start to the farthest floor, else across the patrolled floor].",
    )(command)
    return command


def pairs_of(sources: tuple[Point, ...], targets: tuple[Point, ...]) -> list[tuple[Point, Point]] | None:
    """The pairs given, or ``None`` (the default pairs) when neither option was."""
    if len(sources) != len(targets):
        raise GuardsimError(f"each --from needs its --to: {len(sources)} --from, {len(targets)} --to")
    return list(zip(sources, targets)) if sources else None


def progress_line(line: str) -> None:
    """A progress line on standard error, so that nothing sits silent."""
    click.echo(f"guardsim: {line}", err=True)


def check_outputs(**outputs: str | None) -> None:
    """Refuse, before any work, an output that cannot be written (``--json=path`` given as ``json=path``):
    a command that fails leaves none of its outputs behind, so each is checked before the first is written."""
    from guardsim.files.output import check_writable

    for name, target in outputs.items():
        if target is None:
            continue
        option = "--" + name.replace("_", "-")
        if not target.strip():
            raise click.BadParameter("an empty file name; give the file to write", param_hint=option)
        try:
            check_writable(target)
        except GuardsimError as error:
            raise GuardsimError(f"{option} {error}") from None
