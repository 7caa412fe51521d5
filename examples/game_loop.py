"""A small headless pymunk "game" that drives a guardsim guard from its own loop.

The game owns its physics space: it builds the walls of a level itself, adds a player (a dynamic body
bouncing around), and steps the space at 60 frames a second. guardsim is handed that same space: the
guard's world is built on it (its walls are the space's static segments) and the guard's body lives in
it. Every fourth frame the game advances the guard by one guardsim tick and asks what it sees, and
whether the player stands in a cell the guard is looking at.

Run it from the repository root::

    python examples/game_loop.py levels/square.json --frames 600
"""

from __future__ import annotations

import argparse

import pymunk

import guardsim

FRAMES_PER_SECOND = 60
FRAMES_PER_GUARD_TICK = 4


def build_game_space(level: guardsim.Level) -> tuple[pymunk.Space, pymunk.Body]:
    """The game's own space: the level's walls as static segments, and a bouncing player."""
    space = pymunk.Space()
    for ring in (level.outer, *level.holes):
        for index, start in enumerate(ring):
            wall = pymunk.Segment(space.static_body, start, ring[(index + 1) % len(ring)], 0.0)
            wall.elasticity = 1.0
            space.add(wall)
    player = pymunk.Body(1.0, pymunk.moment_for_circle(1.0, 0, 0.4))
    _, _, max_x, max_y = level.bounds
    player.position = (max_x - 2.0, max_y - 2.0)
    player.velocity = (-3.0, -2.0)
    shape = pymunk.Circle(player, 0.4)
    shape.elasticity = 1.0
    space.add(player, shape)
    return space, player


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("level", nargs="?", default="levels/square.json")
    parser.add_argument("--frames", type=int, default=600)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    level = guardsim.load_level(args.level)
    space, player = build_game_space(level)
    # guardsim takes the game's space as it is: the static segments already in it are the walls.
    scene = guardsim.Scene.from_level(level, space=space, walls_in_space=True)
    guard = guardsim.Simulation(scene, "ripplefront")
    guard.reset(seed=args.seed)

    dt = 1.0 / FRAMES_PER_SECOND
    spotted_frames = 0
    for frame in range(args.frames):
        space.step(dt)
        if frame % FRAMES_PER_GUARD_TICK or guard.done:
            continue
        guard.step()
        in_view = set(guard.visible_cells())
        player_cell = scene.grid.cell_of((player.position.x, player.position.y))
        spotted = player_cell in in_view
        spotted_frames += spotted
        x, y = scene.world.guard_body.position
        print(
            f"frame {frame:4d} tick {guard.tick:3d}: guard at ({x:.1f}, {y:.1f}) facing "
            f"{guard.heading_degrees[0]:5.1f} deg sees {len(in_view):3d} cells, "
            f"{100 * guard.coverage:5.1f}% of the level seen; player {'SPOTTED' if spotted else 'hidden'}"
        )
    print(
        f"after {args.frames} frames: guard {guard.outcome or 'still patrolling'} at tick {guard.tick}, "
        f"player spotted on {spotted_frames} guard ticks"
    )


if __name__ == "__main__":
    main()
