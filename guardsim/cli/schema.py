"""``guardsim schema``: print the level format's JSON Schema."""

from __future__ import annotations

import click

from guardsim.cli.common import reports_errors
from guardsim.schema import level_schema_text

__all__ = ["schema"]


@click.command()
@reports_errors
def schema() -> None:
    """Print the JSON Schema (draft 2020-12) of level files, for editors that check JSON as you type.

    For example: guardsim schema > level.schema.json, then point your editor's JSON schema setting at it.
    """
    click.echo(level_schema_text(), nl=False)
