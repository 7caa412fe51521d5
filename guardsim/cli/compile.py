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

    The install step, once per installed version: about 30 s on two cores with nothing else running, a
    minute beside other work (docs/kernels.md). A COMMAND is a guardsim command that compiles: play
    (its tour planner), patrol, sneak, alert, bounds, optimum, bench, check, report, diff, watch,
    fortify; or a plan's own name (play:tour, patrol:team, optimum:team, sneak:unheard). Run again, it says they are
    compiled already.
    """
    from guardsim.kernels.ahead import compile_kernels

    began = time.perf_counter()
    with StageLine(sys.stderr, "compile") as progress:
        done = compile_kernels(commands, progress=progress)
    of = f"of {', '.join(done.commands)}" if done.commands else "of every command"
    if not done.writable:
        click.echo(
            f"guardsim: warning: could not write the cache folder {done.folder}: numba kept the kernels in its "
            "own places if it could, else each run compiles them; set GUARDSIM_CACHE_DIR to a writable folder",
            err=True,
        )
    if done.already:
        click.echo(f"the {done.functions} kernels {of} are compiled already (kept in {done.folder})")
    else:
        seconds = time.perf_counter() - began
        kept = f"kept in {done.folder}" if done.writable else "see the warning"
        click.echo(f"compiled the {done.functions} kernels {of} in {seconds:.1f} s ({kept})")
