"""``guardsim validate``: every problem in each level file, designer warnings, and ``--fix OUT``."""

from __future__ import annotations

import sys
from collections import defaultdict
from typing import Any

import click

from guardsim.cli.common import level_options, with_options
from guardsim.cli.map_options import STRICT_EXIT, MapImport, level_data
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.files.reading import captured_warnings, display_path, warning_note
from guardsim.level import check_level_data, level_json_text
from guardsim.validate.diagnostics import DEFAULT_MAX_RAYS, DesignerWarning, level_warnings, scene_and_reachable
from guardsim.validate.repair import Repair, repair_level_data

__all__ = ["validate"]

#: Warnings of one kind printed per level before the rest are summed up in one line.
WARNINGS_PER_KIND = 5
#: Repairs listed one per line; the rest are counted in one.
SHOWN_REPAIRS = 200


@click.command()
@click.argument("level_paths", metavar="LEVEL...", nargs=-1, required=True)
@click.option(
    "--fix",
    "fix_path",
    metavar="OUT",
    help="Write a repaired copy of LEVEL to OUT: ring orientation, duplicate and straight-edge points, "
    "overlapping or touching holes merged. Only with one LEVEL.",
)
@click.option(
    "--warnings/--no-warnings",
    "show_warnings",
    default=True,
    show_default=True,
    help="Designer warnings: unreachable pockets, narrow passages, hidden areas.",
)
@click.option(
    "--max-rays",
    type=click.IntRange(min=0),
    default=DEFAULT_MAX_RAYS,
    show_default=True,
    help="Sight rays the hidden-area warning may cast before it stops.",
)
@level_options(vision=False)
def validate(
    level_paths: tuple[str, ...],
    fix_path: str | None,
    show_warnings: bool,
    max_rays: int,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
    map_import: MapImport,
) -> None:
    """Report every problem in each LEVEL, then warnings; exit 0 only if all are valid.

    Warnings do not change the exit status. With --fix, the repairs are listed first and the problems
    and warnings are those of the repaired level, which is written to OUT only if it is valid; the last
    line says how many repairs were made (or that none were needed) and whether OUT was written.
    """
    if fix_path is not None and len(level_paths) != 1:
        click.echo(f"guardsim: error: --fix {fix_path} takes exactly one LEVEL, not {len(level_paths)}", err=True)
        sys.exit(2)
    invalid: list[str] = []
    warned = False  # with --strict, designer warnings fail the run (exit status 1)
    for given in level_paths:
        path = display_path(given)
        try:
            data = level_data(
                given, map_import, max_cells=max_cells, max_vertices=max_vertices, max_file_bytes=max_file_bytes
            )
        except GuardsimError as error:
            click.echo(with_options(str(error)))
            invalid.append(path)
            continue
        if fix_path is not None:
            data, repairs = _repair(path, data)
        level, problems = check_level_data(data, source=path, max_cells=max_cells, max_vertices=max_vertices)
        scene = None
        if level is not None:
            try:
                with captured_warnings() as caught:
                    scene, reachable = scene_and_reachable(level)
            except GuardsimError as error:
                click.echo(with_options(f"{error}{warning_note(caught)}"))
                invalid.append(path)
                if fix_path is not None:
                    _write_fixed(path, fix_path, data, repairs=len(repairs), written=False)
                continue
        for problem in problems:
            click.echo(with_options(f"{path}: {problem}"))
        if problems:
            invalid.append(path)
        elif fix_path is None:
            click.echo(f"{path}: ok")
        if scene is not None and show_warnings:
            with captured_warnings():
                found = level_warnings(scene, reachable, max_rays=max_rays)
            _echo_warnings(path, found)
            warned = warned or bool(found)
        if fix_path is not None:
            _write_fixed(path, fix_path, data, repairs=len(repairs), written=not problems and level is not None)
    if invalid:
        # One line on stderr naming the files, whatever the number of problems listed above.
        names = ", ".join(invalid[:3]) + (f" and {len(invalid) - 3} more" if len(invalid) > 3 else "")
        click.echo(f"guardsim: error: {len(invalid)} of {len(level_paths)} level(s) invalid: {names}", err=True)
        sys.exit(2)
    if warned and map_import.strict:
        click.echo(f"guardsim: error: warnings in {len(level_paths)} level(s) and --strict", err=True)
        sys.exit(STRICT_EXIT)


def _repair(path: str, data: Any) -> tuple[Any, list[Repair]]:
    """--fix's repairs of a level's data, the first few listed; a level that cannot be repaired exits 2."""
    try:
        with captured_warnings():  # GEOS overflows on absurd coordinates; the check after says what is wrong
            data, repairs = repair_level_data(data)
    except GuardsimError as error:
        click.echo(f"guardsim: error: {path}: {error}", err=True)
        sys.exit(2)
    for repair in repairs[:SHOWN_REPAIRS]:
        click.echo(f"{path}: repaired {repair}")
    if len(repairs) > SHOWN_REPAIRS:
        click.echo(f"{path}: repaired {len(repairs) - SHOWN_REPAIRS} more rings the same ways")
    return data, repairs


def _echo_warnings(path: str, warnings: list[DesignerWarning]) -> None:
    """The first few warnings of each kind, then one line summing up the rest of that kind."""
    by_kind: dict[str, list[DesignerWarning]] = defaultdict(list)
    for warning in warnings:
        by_kind[warning.kind].append(warning)
    for kind, items in by_kind.items():
        for warning in items[:WARNINGS_PER_KIND]:
            click.echo(f"{path}: warning: {warning}")
        rest = items[WARNINGS_PER_KIND:]
        if rest:
            cells = sum(warning.cells for warning in rest)
            click.echo(f"{path}: warning: {len(rest)} more {kind}s ({cells} cells)")


def _write_fixed(path: str, fix_path: str, data: Any, *, repairs: int, written: bool) -> None:
    """Write the repaired level if it is valid, and say in one line what was fixed and where it went
    (never 'ok' for a file that needed repairs)."""
    if written:
        write_text_atomic(fix_path, level_json_text(data))
        if repairs:
            # Repairs, not problems: some (a ring's orientation) change what validate alone accepts.
            click.echo(
                f"{path}: made {repairs} repair{'s' if repairs != 1 else ''} (above), the result is valid -> {fix_path}"
            )
        else:
            click.echo(f"{path}: ok, nothing to fix -> {fix_path} (the same level)")
    else:
        click.echo(f"{path}: not written to {fix_path}: the problems above need a designer's decision")
