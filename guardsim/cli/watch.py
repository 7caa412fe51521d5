"""``guardsim watch``: a live page of a level's analysis, redrawn each time the file is saved."""

from __future__ import annotations

import click

from guardsim.cli.common import reports_errors
from guardsim.cli.design_common import StepLines, guards_option, pair_options, pairs_of

__all__ = ["watch"]


@click.command()
@click.argument("level_path", metavar="MAP_OR_LEVEL")
@click.option(
    "--patrol",
    "patrol_path",
    type=str,
    help="patrol.json, re-read on each save [default: the loop patrol of --guards guards].",
)
@guards_option
@pair_options
@click.option(
    "--host", default="127.0.0.1", show_default=True, help="Address to listen on (this machine only by default)."
)
@click.option(
    "--port",
    type=click.IntRange(min=0, max=65535),
    default=8000,
    show_default=True,
    help="Port to listen on (0: any free one).",
)
@click.option("--open", "open_browser", is_flag=True, help="Open the page in the default browser.")
@reports_errors
def watch(
    level_path: str,
    patrol_path: str | None,
    guards: int,
    sources: tuple[tuple[float, float], ...],
    targets: tuple[tuple[float, float], ...],
    host: str,
    port: int,
    open_browser: bool,
) -> None:
    """Serve a page of MAP_OR_LEVEL's analysis (patrol routes, idleness, exposure, safe and hiding spots,
    each pair's sneak path, the difficulty report) and redraw it each time the file is saved, until
    Ctrl-C. A save that cannot be read shows its one-line error and keeps the last analysis drawn.
    """
    from guardsim.viewer.serve.app import watch as serve

    # An analysis's steps tick while they run; its result, a save noticed or an error ends the step.
    with StepLines(is_step=lambda line: line.startswith("analysing: ")) as steps:
        serve(
            level_path,
            patrol=patrol_path,
            guards=guards,
            pairs=pairs_of(sources, targets),
            host=host,
            port=port,
            open_browser=open_browser,
            echo=steps,
        )
