"""A small stealth game: guardsim's guards against a player you move, on a Tiled map drawn with pygame-ce.

Run it (install ``guardsim[game]``: pygame-ce and pytmx)::

    python examples/game/stealth.py                 # the warehouse beside this file
    python examples/game/stealth.py MAP.tmx --guards 2

Arrows or WASD move; hold Shift to sneak (slower: quieter where the level gives the intruder ears keys).
Reach the green exit. The guards patrol loops planned by ``guardsim patrol``'s planner; they grow
suspicious as their meters (the bars above them) fill, chase at a run, search where you may have gone,
give up and walk back to their routes. Caught, the level starts again.

The game reads the map twice, as a game would: pytmx loads its tiles for drawing, guardsim imports its
walls (the ``walls`` layer) as the guards' level. Everything the guards do comes from one call a frame,
:meth:`guardsim.alert.GameGuards.frame`, given the player's position in world units (tiles).

:func:`play` runs the game; with ``script`` (a function of the frame number and what happened so far, giving
the keys held) it plays without a keyboard for ``frames`` frames, at 60 frames a second of game time, as
the headless test does (``SDL_VIDEODRIVER=dummy``).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
MAP = HERE / "warehouse.tmx"
FPS = 60
WALK = 3.5
"""The player's walking speed, tiles per second (the guards walk 2 and run 3)."""
SNEAK = 1.2
COLOURS = {
    "patrol": (90, 170, 255),
    "suspicious": (255, 220, 60),
    "investigate": (255, 160, 40),
    "chase": (255, 60, 60),
    "search": (230, 90, 230),
    "return": (140, 200, 140),
}


@dataclasses.dataclass
class Summary:
    """What happened in a played game, for a script to check."""

    frames: int = 0
    events: list[str] = dataclasses.field(default_factory=list)
    """Every guard event in order (``detected``, ``lost``, ``gave_up``, ...; ``captured`` ends a round)."""
    states: set[str] = dataclasses.field(default_factory=set)
    """Every guard state seen."""
    reached_exit: bool = False
    player: tuple[float, float] = (0.0, 0.0)
    """Where the player is (world units: tiles)."""
    guards: list[tuple[float, float, float]] = dataclasses.field(default_factory=list)
    """The guards' poses at the last frame."""
    step_seconds: list[float] = dataclasses.field(default_factory=list)
    """Wall seconds of each frame's call into the guards."""


def _require() -> Any:
    try:
        import pygame
        import pytmx
    except ImportError:
        sys.exit("the example game needs pygame-ce and pytmx: install guardsim[game]")
    return pygame, pytmx


def play(
    map_path: Path = MAP,
    *,
    guards: int = 3,
    script: Callable[[int, Summary], set[str]] | None = None,
    frames: int | None = None,
    search_seconds: float = 10.0,
) -> Summary:
    """Play the game (see the module); returns what happened."""
    import time

    import guardsim
    from guardsim.alert import GameGuards
    from guardsim.patrol.plan import patrol_setup, plan_patrol

    pygame, pytmx = _require()
    pygame.display.init()
    pygame.font.init()
    tiled = pytmx.TiledMap(str(map_path))
    tile = tiled.tilewidth
    screen = pygame.display.set_mode((tiled.width * tile, tiled.height * tile))
    pygame.display.set_caption("guardsim: stealth")
    tiles = pytmx.load_pygame(str(map_path))
    font = pygame.font.Font(None, 20)

    level = guardsim.load_level(str(map_path))
    # The game's own tuning: guards give up sooner than the level's default 30 s.
    level = dataclasses.replace(level, guard=dataclasses.replace(level.guard, search_seconds=search_seconds))
    scene = guardsim.Scene.from_level(level)
    print("planning the guards' patrols ...", flush=True)
    patrol = plan_patrol(patrol_setup(scene, guards, seed=0), "loop").patrol
    start = level.player_starts[0] if level.player_starts else scene.grid.centre(0, 0)
    exit_cell = scene.grid.cell_of((1.5, 1.5))

    def new_round() -> tuple[GameGuards, list[float]]:
        return GameGuards(scene, patrol, player=start, player_speed=WALK), [start[0], start[1]]

    team, player = new_round()
    summary = Summary()
    clock = pygame.time.Clock()
    log: list[str] = []
    frame_number = 0
    while frames is None or frame_number < frames:
        dt = 1.0 / FPS if script is not None else min(clock.tick(FPS) / 1000.0, 0.1)
        held: set[str] = set()
        for event in pygame.event.get():
            if event.type == pygame.QUIT:
                return summary
        if script is not None:
            held = script(frame_number, summary)
        else:
            keys = pygame.key.get_pressed()
            names = {"left": (pygame.K_LEFT, pygame.K_a), "right": (pygame.K_RIGHT, pygame.K_d)}
            names.update({"up": (pygame.K_UP, pygame.K_w), "down": (pygame.K_DOWN, pygame.K_s)})
            held = {name for name, codes in names.items() if any(keys[c] for c in codes)}
            if keys[pygame.K_LSHIFT] or keys[pygame.K_RSHIFT]:
                held.add("sneak")
        _move(player, held, dt, scene)
        began = time.perf_counter()
        frame = team.frame((player[0], player[1]), dt)
        summary.step_seconds.append(time.perf_counter() - began)
        summary.states.update(frame.states)
        summary.player, summary.guards = (player[0], player[1]), frame.poses
        for event in frame.events:
            summary.events.append(event.event)
            log = [*log[-5:], f"{event.tick * team.tick_seconds:6.1f} s  guard {event.guard}: {event.event}"]
        if scene.grid.cell_of((player[0], player[1])) == exit_cell:
            summary.reached_exit = True
            log.append("you got out!")
            team, player = new_round()
        elif frame.done:
            log.append("caught! again from the start")
            team, player = new_round()
        seen = [scene.grid.unflat(int(cell)) for cell in set(team.episode.seen_now.tolist())]
        _draw(pygame, screen, tiles, tile, frame, player, exit_cell, font, log, seen)
        frame_number += 1
        summary.frames = frame_number
    pygame.quit()
    return summary


def _move(player: list[float], held: set[str], dt: float, scene: Any) -> None:
    """Move by the keys held, sliding along walls (one axis at a time)."""
    speed = SNEAK if "sneak" in held else WALK
    dx = float(("right" in held) - ("left" in held))
    dy = float(("down" in held) - ("up" in held))
    if dx and dy:
        dx, dy = dx / math.sqrt(2), dy / math.sqrt(2)
    grid = scene.grid
    for axis, delta in ((0, dx * speed * dt), (1, dy * speed * dt)):
        moved = list(player)
        moved[axis] += delta
        cell = grid.cell_of((moved[0], moved[1]))
        if cell is not None and grid.traversable[cell[1], cell[0]]:
            player[axis] = moved[axis]


def _draw(pygame: Any, screen: Any, tiles: Any, tile: int, frame: Any, player: list[float], exit_cell: Any,
          font: Any, log: list[str], seen: list[tuple[int, int]]) -> None:  # fmt: skip
    for layer in tiles.visible_layers:
        if hasattr(layer, "tiles"):
            for x, y, image in layer.tiles():
                screen.blit(image, (x * tile, y * tile))
    if exit_cell is not None:
        pygame.draw.rect(screen, (40, 200, 90), (exit_cell[0] * tile, exit_cell[1] * tile, tile, tile), 3)
    # What the guards saw at their last tick (walls block it): the cells themselves, lit.
    cone = pygame.Surface(screen.get_size(), pygame.SRCALPHA)
    for col, row in seen:
        cone.fill((255, 255, 190, 55), (col * tile, row * tile, tile, tile))
    for (x, y, heading), state, meter in zip(frame.poses, frame.states, frame.meters, strict=True):
        centre = (x * tile, y * tile)
        colour = COLOURS[state]
        nose = (
            centre[0] + math.cos(math.radians(heading)) * tile * 0.6,
            centre[1] + math.sin(math.radians(heading)) * tile * 0.6,
        )
        pygame.draw.line(screen, colour, centre, nose, 3)
        pygame.draw.circle(screen, colour, centre, tile * 0.35)
        pygame.draw.rect(screen, (30, 30, 30), (centre[0] - 16, centre[1] - 26, 32, 5))
        pygame.draw.rect(screen, colour, (centre[0] - 16, centre[1] - 26, 32 * meter, 5))
    screen.blit(cone, (0, 0))
    pygame.draw.circle(screen, (250, 250, 250), (player[0] * tile, player[1] * tile), tile * 0.3)
    for row, line in enumerate(log[-6:]):
        screen.blit(font.render(line, True, (255, 255, 255)), (8, 8 + 18 * row))
    pygame.display.flip()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("map", nargs="?", default=str(MAP), help="A Tiled map (.tmx) with a 'walls' layer.")
    parser.add_argument("--guards", type=int, default=3)
    args = parser.parse_args()
    play(Path(args.map), guards=args.guards)


if __name__ == "__main__":
    main()
