"""The game's own player as the intruder: guards that patrol, notice, chase, search and return against a
player the game moves, a frame at a time.

:class:`GameGuards` wraps an :class:`~guardsim.alert.AlertEpisode` whose intruder is a
:class:`PlayerIntruder`. Each frame the game calls :meth:`GameGuards.frame` with the player's position
in world coordinates and the frame's seconds; the guards decide a grid tick at a time (a tick is one
cell at the guard's walking speed, :func:`guardsim.detection.grid_tick_seconds`), so most frames only
carry time forward and move the guards' drawn poses between their last two ticks. A frame that
completes a tick places the player in the cell under its position and steps the episode.

**Noise from speed.** With ears (the level's ``intruder`` keys ``walk_noise`` or ``sneak_noise`` above 0),
a tick in which the player changed cells makes one noise in the cell it is in: ``sneak_noise`` when it
moved at most ``1 / sneak_ticks`` cells a tick over the tick's cells (4-connected steps between the
tick's first and last cell) since its last change of cell, the sneaking pace, else ``walk_noise`` (the
first step counts the ticks from the start as at least ``sneak_ticks``). Standing still is silent.

See ``docs/alert.md`` (the game's own player) and ``examples/game/``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.intruders import Intruder
from guardsim.alert.model import AlertEvent, AlertRules
from guardsim.alert.movement import ContinuousMovement, make_movement
from guardsim.errors import GuardsimError
from guardsim.patrol.model import Patrol
from guardsim.scene import Scene

__all__ = ["GameGuards", "GuardsFrame", "PlayerIntruder"]


class PlayerIntruder(Intruder):
    """An intruder the caller places (:meth:`place`); it never moves by itself and never leaves."""

    def __init__(self, neighbours: np.ndarray, cell: int, *, columns: int = 1, sneak_ticks: int = 2) -> None:
        super().__init__("player", neighbours, cell, sneak_ticks=sneak_ticks)
        self._columns = columns
        self._tick_start = int(cell)
        # Standing at its start before its first step: that step is judged as if it had stood still since.
        self._ticks_since_move = sneak_ticks

    def place(self, cell: int, columns: int) -> None:
        """Put the player in flat ``cell``; its heading becomes the main direction of the move."""
        if cell == self.cell:
            return
        (row, col), (to_row, to_col) = divmod(self.cell, columns), divmod(cell, columns)
        dx, dy = to_col - col, to_row - row
        self.heading = (0 if dx > 0 else 2) if abs(dx) >= abs(dy) else (1 if dy > 0 else 3)
        self.cell = int(cell)

    def advance(self, tick: int, guard_cells: Sequence[int], chased: bool, alarmed: bool) -> None:
        """The game moved it already: this tick's step, if it changed cells, lands where it is, in the gait
        its pace gives (see the module)."""
        self.landed = []
        if self._tick_start != self.cell:
            (row, col), (to_row, to_col) = divmod(self._tick_start, self._columns), divmod(self.cell, self._columns)
            steps = abs(to_row - row) + abs(to_col - col)
            sneaking = steps * self.sneak_ticks <= max(1, self._ticks_since_move)
            self.landed = [(self.cell, "sneak" if sneaking else "walk")]
            self._ticks_since_move = 0
        self._ticks_since_move += 1
        self._tick_start = self.cell


class GuardsFrame(NamedTuple):
    """What the guards are doing at a frame, for the game to draw and react to."""

    tick: int
    """Grid ticks played so far."""
    poses: list[tuple[float, float, float]]
    """Per guard: ``(x, y, heading_degrees)`` in world coordinates, between its last two ticks (0 degrees
    faces +x, 90 faces +y)."""
    states: list[str]
    """Per guard: one of :data:`~guardsim.alert.GUARD_STATES`."""
    meters: list[float]
    """Per guard: its awareness meter, 0 to 1."""
    events: list[AlertEvent]
    """What happened at the ticks this frame completed."""
    done: bool
    """The player was captured (the episode is over)."""


class GameGuards:
    """``patrol``'s guards on ``scene`` against the game's player, who starts at ``player`` (world units).

    ``search``: the strategy once sight is lost; ``motion``: ``"grid"`` or ``"continuous"`` (see
    :mod:`guardsim.alert.movement`); ``player_speed``: the fastest the player moves, world units per
    second (default 1.5 times the guard's walking speed), what the search assumes of its reach (times
    the square root of 2 in 4-connected cells: a diagonal move).

    >>> import guardsim
    >>> from guardsim.patrol.model import Patrol
    >>> scene = guardsim.Scene.from_level(guardsim.parse_level({"outer": [[0, 0], [6, 0], [6, 3], [0, 3]]}))
    >>> post = Patrol.standing(scene.grid, [((0.5, 1.5), "right")])
    >>> guards = GameGuards(scene, post, player=(5.5, 0.5))
    >>> frame = guards.frame((5.5, 1.5), 0.25)
    >>> frame.tick, frame.states
    (0, [<GuardState.PATROL: 'patrol'>])
    >>> [guards.frame((5.5, 1.5), 0.25).tick for _ in range(3)]
    [1, 1, 2]
    """

    def __init__(
        self,
        scene: Scene,
        patrol: Patrol,
        *,
        player: tuple[float, float],
        search: str = "ripple",
        phase: int = 0,
        motion: str = "grid",
        player_speed: float | None = None,
    ) -> None:
        from guardsim.detection import GuardDetection, grid_tick_seconds
        from guardsim.motion.parameters import DEFAULT_MOVE_SPEED
        from guardsim.vision.table import view_table

        level = scene.level
        self.scene, self.grid = scene, scene.grid
        walking = level.guard.move_speed if level.guard.move_speed is not None else DEFAULT_MOVE_SPEED
        speed = 1.5 * walking if player_speed is None else float(player_speed)
        if not (math.isfinite(speed) and speed >= 0):
            raise GuardsimError(f"player_speed: must be a finite number >= 0, not {player_speed!r}")
        # The search's reach is in 4-connected steps: a diagonal move covers sqrt(2) times its length in them.
        self.rules = AlertRules.of_level(level, intruder_speed=speed * math.sqrt(2.0))
        self.tick_seconds = grid_tick_seconds(level)
        table = view_table(self.grid, scene.vision())
        detection = GuardDetection.of_level(level)
        self.player = PlayerIntruder(
            self.grid.neighbours,
            self.cell_of(player, "player"),
            columns=self.grid.shape[1],
            sneak_ticks=self.rules.sneak_ticks,
        )
        movement = make_movement(motion, scene, table, detection, dt=self.rules.dt, guards=patrol.guards)
        self.episode = AlertEpisode(
            self.grid,
            table,
            patrol,
            self.player,
            rules=self.rules,
            detection=detection,
            search=search,
            phase=phase,
            max_ticks=2**62,
            movement=movement,
        )
        self._time = 0.0
        self._before = self._poses()
        self._after = self._before

    def cell_of(self, position: tuple[float, float], argument: str = "position") -> int:
        """The flat cell under ``position``; a :class:`~guardsim.errors.GuardsimError` naming ``argument``
        when it is not on the level's floor (a wall, outside, or a cell the guards cannot reach)."""
        try:
            x, y = (float(v) for v in position)
        except (TypeError, ValueError):
            raise GuardsimError(f"{argument}: not an (x, y) pair of numbers: {position!r}") from None
        own = self.grid.cell_of((x, y)) if math.isfinite(x) and math.isfinite(y) else None
        if own is None or not self.grid.traversable[own[1], own[0]]:
            raise GuardsimError(f"{argument}: ({x:g}, {y:g}) is not on the level's floor (a wall or outside)")
        return int(self.grid.flat(*own))

    def frame(self, position: tuple[float, float], dt: float) -> GuardsFrame:
        """The player is at ``position`` (world units) after ``dt`` seconds more of game time."""
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt >= 0):
            raise GuardsimError(f"dt: must be a finite number of seconds >= 0, not {dt!r}")
        cell = self.cell_of(position)
        episode = self.episode
        self.player.place(cell, self.grid.shape[1])
        seen = len(episode.events)
        self._time += dt
        while self._time >= self.tick_seconds - 1e-12 and not episode.done:
            self._time -= self.tick_seconds
            self._before = self._after
            episode.step()
            self._after = self._poses()
        if episode.done:
            self._time = 0.0
        share = min(1.0, self._time / self.tick_seconds)
        poses = [_between(a, b, share) for a, b in zip(self._before, self._after, strict=True)]
        return GuardsFrame(
            episode.tick,
            poses,
            list(episode.modes),
            [round(meter.level, 4) for meter in episode.meters],
            list(episode.events[seen:]),
            episode.done,
        )

    def _poses(self) -> list[tuple[float, float, float]]:
        movement = self.episode.movement
        if isinstance(movement, ContinuousMovement):
            return [movement.pose(guard) for guard in range(len(self.episode.modes))]
        grid = self.grid
        out = []
        for cell, heading in zip(self.episode.cells, self.episode.headings, strict=True):
            x, y = grid.centre(*grid.unflat(cell))
            out.append((float(x), float(y), 90.0 * heading))
        return out


def _between(
    before: tuple[float, float, float], after: tuple[float, float, float], share: float
) -> tuple[float, float, float]:
    turn = (after[2] - before[2] + 180.0) % 360.0 - 180.0
    return (
        before[0] + (after[0] - before[0]) * share,
        before[1] + (after[1] - before[1]) * share,
        (before[2] + turn * share) % 360.0,
    )
