"""``guardsim validate``: every problem in each level file."""

from __future__ import annotations

import sys

import click
import numpy as np

from guardsim.cli.common import limit_options, reports_errors
from guardsim.errors import GuardsimError
from guardsim.level import check_level_data, read_level_json
from guardsim.simulation import Scene, choose_start

__all__ = ["validate"]


@click.command()
@click.argument("level_paths", metavar="LEVEL...", nargs=-1, required=True)
@limit_options
@reports_errors
def validate(level_paths: tuple[str, ...], max_cells: int, max_vertices: int, max_file_bytes: int) -> None:
    """Report every problem in each LEVEL; exit 0 only if all are valid."""
    invalid = 0
    for path in level_paths:
        try:
            data = read_level_json(path, max_file_bytes=max_file_bytes)
        except GuardsimError as error:
            click.echo(str(error))
            invalid += 1
            continue
        level, problems = check_level_data(data, source=path, max_cells=max_cells, max_vertices=max_vertices)
        if level is not None:
            try:
                # Problems only the grid can find: a start cell where the guard does not fit.
                scene = Scene.from_level(level)
                for point in ([level.guard.start] if level.guard.start else []) + list(level.starts):
                    choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
            except GuardsimError as error:
                click.echo(str(error))
                invalid += 1
                continue
        for problem in problems:
            click.echo(f"{path}: {problem}")
        if problems:
            invalid += 1
        else:
            click.echo(f"{path}: ok")
    if invalid:
        click.echo(f"{invalid} of {len(level_paths)} level(s) invalid", err=True)
        sys.exit(2)
