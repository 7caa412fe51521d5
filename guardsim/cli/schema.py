"""``guardsim schema [NAME]``: print the JSON Schema of one of the formats guardsim reads."""

from __future__ import annotations

import click

from guardsim.cli.common import reports_errors
from guardsim.files.schema import SCHEMAS, schema_text

__all__ = ["schema"]


@click.command()
@click.argument("name", type=click.Choice(SCHEMAS), default="level", required=False)
@reports_errors
def schema(name: str) -> None:
    """Print the JSON Schema (draft 2020-12) of NAME files, for editors that check JSON as you type.

    NAME is level (the default), patrol (patrol.json), checks (a `guardsim check` checks file), manifest
    (a regress manifest.json) or trace (`guardsim play --trace`). Every command checks the files it reads
    against the same schemas.

    For example: guardsim schema > level.schema.json, then point your editor's JSON schema setting at it.
    """
    click.echo(schema_text(name), nl=False)
