"""The ``guardsim`` command line.

Each command lives in its own module, listed in :data:`COMMANDS` and imported only when it runs (or
when its own ``--help`` is asked for), so ``guardsim --help`` and ``guardsim validate`` start without
loading the compiled simulation. Every error a user can cause is printed as one line on standard error,
with exit status 2 (see :func:`guardsim.cli.common.reports_errors`).
"""

from __future__ import annotations

import atexit
import contextlib
import importlib
import os
import sys
from collections.abc import Iterator
from typing import Any

import click

__all__ = ["COMMANDS", "main", "run"]

#: Command name -> (module, the click command's name in it, one-line help for ``guardsim --help``).
COMMANDS: dict[str, tuple[str, str, str]] = {
    "bench": ("guardsim.cli.bench", "bench", "Run many episodes from random starts and summarise them."),
    "bounds": ("guardsim.cli.bounds", "bounds", "Lower bounds on the steps needed to see every reachable cell."),
    "patrol": ("guardsim.cli.patrol", "patrol", "Build a repeating patrol of LEVEL and score its idleness."),
    "import": ("guardsim.cli.importing", "import_command", "Convert a Tiled, LDtk, Moving AI or image map to a level."),
    "compile": (
        "guardsim.cli.compile",
        "compile_command",
        "Compile every command's kernels now (the install step), so no first run compiles.",
    ),
    "optimum": (
        "guardsim.cli.optimum",
        "optimum",
        "The fewest steps needed to see every reachable cell, proved by search.",
    ),
    "alert": (
        "guardsim.cli.alert",
        "alert",
        "Guards that notice, chase, search and return, against an intruder.",
    ),
    "check": (
        "guardsim.cli.check",
        "check",
        "CI gates: exit 1 when LEVEL breaks a rule (cover steps, idleness, sneaks).",
    ),
    "fortify": (
        "guardsim.cli.fortify",
        "fortify",
        "Add cameras and guard posts until no player gets through, with a proof.",
    ),
    "play": ("guardsim.cli.play", "play", "Walk a guard over LEVEL until it has seen every reachable cell."),
    "regress": ("guardsim.cli.regress", "regress", "Re-play levels and compare them with stored references."),
    "render": ("guardsim.cli.render", "render", "Draw a level preview as a PNG."),
    "report": (
        "guardsim.cli.report",
        "report",
        "How hard LEVEL is: sneak measures, patrol readability, a 0-100 score.",
    ),
    "diff": ("guardsim.cli.diff", "diff", "What an edit changed: two versions of a level compared, with a picture."),
    "watch": ("guardsim.cli.watch", "watch", "A live page of LEVEL's analysis, redrawn on each save."),
    "schema": ("guardsim.cli.schema", "schema", "Print the level format's JSON Schema."),
    "sneak": ("guardsim.cli.sneak", "sneak", "Can a player get from here to there unseen by a patrol?"),
    "validate": ("guardsim.cli.validate", "validate", "Check level files and warn about designer problems."),
    "view": ("guardsim.cli.view", "view", "Write a saved trace as an interactive HTML page."),
}


@contextlib.contextmanager
def _one_line_usage_errors() -> Iterator[None]:
    """A bad option or argument is one ``guardsim: error:`` line naming it, like every other error, not
    click's usage block (usage, hint, blank line, error)."""
    try:
        yield
    except click.exceptions.NoArgsIsHelpError as error:
        # No command at all: the help, as it is, is the answer (not an error squashed into one line).
        click.echo(error.format_message())
        sys.exit(0)
    except click.UsageError as error:
        command = error.ctx.info_name if error.ctx is not None and error.ctx.parent is not None else None
        hint = f" (see guardsim {command} --help)" if command else " (see guardsim --help)"
        message = " ".join(error.format_message().split())
        click.echo(f"guardsim: error: {message}{hint}", err=True)
        sys.exit(error.exit_code)


class _LazyGroup(click.Group):
    """A group whose commands are imported when used; the listing reads :data:`COMMANDS` alone."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        entry = COMMANDS.get(cmd_name)
        if entry is None:
            return None
        module, name, _ = entry
        command = getattr(importlib.import_module(module), name)
        if not isinstance(command, click.Command):
            raise TypeError(f"{module}.{name} is not a click command")
        return command

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        with _one_line_usage_errors():
            return super().parse_args(ctx, args)

    def invoke(self, ctx: click.Context) -> Any:
        with _one_line_usage_errors():
            return super().invoke(ctx)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = [(name, COMMANDS[name][2]) for name in self.list_commands(ctx)]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


@click.group(cls=_LazyGroup)
@click.version_option(package_name="guardsim")
def main() -> None:
    """Coverage path planning for guards in games."""


def run() -> None:
    """The ``guardsim`` program: :func:`main`, then exit at once.

    Tearing the interpreter down after a command that loaded compiled code took about 0.3 s (freeing
    what the operating system frees anyway), a third of a warm ``guardsim play``. The exit handlers
    still run (temporary folders, worker pools) and the output streams are flushed first.
    """
    try:
        main()
        code = 0
    except SystemExit as stop:
        code = _exit_status(stop.code)
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):  # a closed pipe (``guardsim ... | head``) is not an error
            stream.flush()
    os._exit(code)


def _exit_status(code: object) -> int:
    """The status ``sys.exit(code)`` would end the process with (a message is printed, status 1)."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code
    print(code, file=sys.stderr)
    return 1
