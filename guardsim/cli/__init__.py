"""The ``guardsim`` command line.

Each command lives in its own module, listed in :data:`COMMANDS` and imported only when it runs (or
when its own ``--help`` is asked for), so ``guardsim --help`` and ``guardsim validate`` start without
loading the compiled simulation. Every error a user can cause is printed as one line on standard error,
with exit status 2 (see :func:`guardsim.cli.common.reports_errors`).
"""

from __future__ import annotations

import importlib

import click

__all__ = ["COMMANDS", "main"]

#: Command name -> (module, the click command's name in it, one-line help for ``guardsim --help``).
COMMANDS: dict[str, tuple[str, str, str]] = {
    "bench": ("guardsim.cli.bench", "bench", "Run many episodes from random starts and summarise them."),
    "bounds": ("guardsim.cli.bounds", "bounds", "Lower bounds on the steps needed to see every reachable cell."),
    "patrol": ("guardsim.cli.patrol", "patrol", "Build a repeating patrol of LEVEL and score its idleness."),
    "import": ("guardsim.cli.importing", "import_command", "Convert a Tiled, Moving AI or image map to a level."),
    "optimum": (
        "guardsim.cli.optimum",
        "optimum",
        "The fewest steps needed to see every reachable cell, proved by search.",
    ),
    "check": (
        "guardsim.cli.check",
        "check",
        "CI gates: exit 1 when LEVEL breaks a rule (cover steps, idleness, sneaks).",
    ),
    "play": ("guardsim.cli.play", "play", "Walk a guard over LEVEL until it has seen every reachable cell."),
    "regress": ("guardsim.cli.regress", "regress", "Re-play levels and compare them with stored references."),
    "render": ("guardsim.cli.render", "render", "Draw a level preview as a PNG."),
    "schema": ("guardsim.cli.schema", "schema", "Print the level format's JSON Schema."),
    "sneak": ("guardsim.cli.sneak", "sneak", "Can a player get from here to there unseen by a patrol?"),
    "validate": ("guardsim.cli.validate", "validate", "Check level files and warn about designer problems."),
    "view": ("guardsim.cli.view", "view", "Write a saved trace as an interactive HTML page."),
}


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

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = [(name, COMMANDS[name][2]) for name in self.list_commands(ctx)]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


@click.group(cls=_LazyGroup)
@click.version_option(package_name="guardsim")
def main() -> None:
    """Coverage path planning for guards in games."""
