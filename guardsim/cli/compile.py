"""``guardsim compile [COMMAND...]``: compile every command's kernels now, so that no first run compiles."""

from __future__ import annotations

import sys
import time

import click

from guardsim.cli.common import reports_errors
from guardsim.cli.progress import StageLine

__all__ = ["compile_command"]


@click.command()
@click.argument("commands", metavar="[COMMAND...]", nargs=-1)
@reports_errors
def compile_command(commands: tuple[str, ...]) -> None:
    """Compile the kernels of every command (or of each COMMAND named) into the compiled cache, on two
    processes, so that each command's first run loads them instead of compiling.

    The install step: about 40 s on two cores, once per installed version (docs/kernels.md). A COMMAND is
    a plan's name: play:tour, patrol, patrol:team, sneak, alert, bounds, optimum, optimum:team, bench,
    check, report (also diff, check --baseline and watch). Run again, it says they are compiled already.
    """
    from guardsim.kernels.ahead import compile_kernels

    began = time.perf_counter()
    with StageLine(sys.stderr, "compile") as progress:
        done = compile_kernels(commands or None, progress=progress)
    plans = f"{len(done.commands)} command{'' if len(done.commands) == 1 else 's'}"
    if done.already:
        click.echo(f"the {done.functions} kernels of {plans} are compiled already (kept in {done.folder})")
    else:
        seconds = time.perf_counter() - began
        click.echo(f"compiled the {done.functions} kernels of {plans} in {seconds:.1f} s (kept in {done.folder})")
