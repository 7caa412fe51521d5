"""The continuous-motion options that ``play``, ``bench``, ``regress`` and ``alert`` share: --motion, speeds."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

from guardsim.cli.types import FiniteFloatRange
from guardsim.errors import GuardsimError
from guardsim.level.limits import MAX_TICK_HZ
from guardsim.motion.parameters import DEFAULT_MOVE_SPEED, DEFAULT_TICK_HZ, DEFAULT_TURN_SPEED, MOTIONS, GuardMotion
from guardsim.scene import Scene

__all__ = [
    "MAX_TICK_HZ",
    "MOTIONS",
    "alert_motion_options",
    "check_motion",
    "check_speed_up",
    "motion_of",
    "motion_options",
    "motion_override_options",
    "speed_up_option",
]

F = TypeVar("F", bound=Callable[..., Any])


_SPEED_HELP = (
    ("--move-speed", f"Continuous motion: walking speed, world units/s [default: the level's, else {DEFAULT_MOVE_SPEED:g}]."),
    ("--turn-speed", f"Continuous motion: turning speed, degrees/s [default: the level's, else {DEFAULT_TURN_SPEED:g}]."),
    ("--tick-hz", f"Continuous motion: physics ticks per second [default: the level's, else {DEFAULT_TICK_HZ:g}]."),
)  # fmt: skip
_MOTION_HELP = (
    "grid: a cell per tick, turning free (the paper's model); continuous: a physics body walking and turning "
    "at game speeds along the planner's route (docs/motion.md)."
)


def _speed_options(command: F, options: tuple[tuple[str, str], ...]) -> F:
    positive = FiniteFloatRange(min=0, min_open=True)
    ticks = FiniteFloatRange(min=0, min_open=True, max=MAX_TICK_HZ)
    for name, help_text in reversed(options):
        command = click.option(name, type=ticks if name == "--tick-hz" else positive, help=help_text)(command)
    return command


def motion_options(command: F) -> F:
    """--motion, --move-speed, --turn-speed, --tick-hz, --max-seconds."""
    max_seconds = ("--max-seconds", "Continuous motion: game-time limit [default: --max-steps walked at --move-speed].")
    command = _speed_options(command, (*_SPEED_HELP, max_seconds))
    return click.option("--motion", type=click.Choice(MOTIONS), default="grid", show_default=True, help=_MOTION_HELP)(
        command
    )


def motion_override_options(command: F) -> F:
    """``regress``'s --motion (no default: each reference episode's own) and the speeds over the episodes'."""
    command = _speed_options(command, _SPEED_HELP)
    return click.option(
        "--motion",
        type=click.Choice(MOTIONS),
        help="Re-play every episode in this motion [default: each episode's, from its manifest]; with --update, "
        "the references are rewritten in it. " + _MOTION_HELP,
    )(command)


def alert_motion_options(command: F) -> F:
    """``alert``'s --motion and the guard's speeds (play's speeds; alert has its own --max-seconds)."""
    command = _speed_options(command, _SPEED_HELP)
    return click.option(
        "--motion",
        type=click.Choice(MOTIONS),
        default="grid",
        show_default=True,
        help="grid: a cell per tick, turning free; continuous: each guard a physics body walking its decisions "
        "at game speeds and looking from its pose every physics tick (docs/alert.md).",
    )(command)


def speed_up_option(command: F) -> F:
    """``play``'s --speed-up: the GIF of a continuous episode in game time."""
    return click.option(
        "--speed-up",
        type=FiniteFloatRange(min=0, min_open=True),
        help="Continuous motion: the GIF plays this many game seconds a second (1 = real time), frames at "
        "least --frame-ms apart [default: each frame shown --frame-ms].",
    )(command)


def check_speed_up(motion: str, speed_up: float | None) -> None:
    """Refuse --speed-up for grid episodes, whose ticks have no game time."""
    if speed_up is not None and motion != "continuous":
        raise click.BadParameter("grid ticks have no game time; it needs --motion continuous", param_hint="--speed-up")


def check_motion(motion: str, guards: int, los: str, **speeds: float | None) -> None:
    """Refuse what continuous motion does not do: teams (``los`` is accepted either way: under
    Bresenham the continuous guard sees along grid lines from the cell its eye is in); and speeds given
    to a grid episode, which would be ignored without a word (``speeds``: ``move_speed=`` ... by name)."""
    if motion == "continuous" and guards > 1:
        raise GuardsimError("--motion continuous walks one guard; drop --guards")
    given = [name for name, value in speeds.items() if value is not None]
    if motion != "continuous" and given:
        option = "--" + given[0].replace("_", "-")
        raise click.BadParameter("grid episodes have no game time; it needs --motion continuous", param_hint=option)


def motion_of(scene: Scene, move_speed: float | None, turn_speed: float | None, tick_hz: float | None) -> GuardMotion:
    """The options over the level guard's motion over the defaults."""
    return GuardMotion.of_guard(scene.level.guard, move_speed=move_speed, turn_speed=turn_speed, tick_hz=tick_hz)
