"""The ``guardsim`` command line.

Each command lives in its own module and is registered here. Every error a user can cause is printed as
one line on standard error, with exit status 2 (see :func:`guardsim.cli.common.reports_errors`).
"""

from __future__ import annotations

import click

from guardsim.cli.bench import bench
from guardsim.cli.bounds import bounds
from guardsim.cli.importing import import_command
from guardsim.cli.play import play
from guardsim.cli.regress import regress
from guardsim.cli.render import render
from guardsim.cli.schema import schema
from guardsim.cli.validate import validate

__all__ = ["main"]


@click.group()
@click.version_option(package_name="guardsim")
def main() -> None:
    """Coverage path planning for guards in games."""


for command in (bench, bounds, import_command, play, regress, render, schema, validate):
    main.add_command(command)
