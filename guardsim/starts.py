"""Where and facing which way an episode starts: the one start rule every command shares.

Every random choice goes through the episode's :class:`numpy.random.Generator`, drawn in a fixed order
(guard 0's cell, its heading, then each further guard's cell and heading), so one guard's episode is the
same with or without teammates, and an episode of a batch is the same whichever worker runs it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from guardsim.errors import ArgumentError, LevelError
from guardsim.grid import CoverageGrid, start_cell
from guardsim.level import HEADINGS
from guardsim.scene import Scene

__all__ = ["check_headings", "checked_starts", "choose_start", "episode_generator", "episode_start", "team_starts"]


def episode_generator(seed: int, episode: int) -> np.random.Generator:
    """The generator of episode ``episode`` in a batch seeded with ``seed``.

    It is the ``episode``-th child of ``SeedSequence(seed).spawn(...)``, built directly, so an episode
    draws the same numbers whether it runs alone, in a batch, or on any worker.

    Examples
    --------
    >>> children = np.random.SeedSequence(5).spawn(3)
    >>> bool(episode_generator(5, 2).integers(1000) == np.random.default_rng(children[2]).integers(1000))
    True
    """
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(episode,)))


def choose_start(
    scene: Scene,
    *,
    rng: np.random.Generator,
    point: tuple[float, float] | None = None,
    heading: str | None = None,
) -> tuple[tuple[int, int], int]:
    """The start cell and heading number of an episode.

    The start is ``point`` if given, else drawn uniformly from the largest connected area; the heading
    is ``heading`` (a name of :data:`guardsim.level.HEADINGS`) if given, else drawn uniformly from the
    four. The draws happen in that order, start first, so a given seed always gives the same episode.
    """
    grid = scene.grid
    if point is not None:
        cell = start_cell(scene.level, grid, point)
    else:
        candidates = np.flatnonzero(grid.largest_component())
        if candidates.size == 0:
            raise LevelError(f"{scene.level.source}: no cell where the guard fits; nothing to cover")
        cell = grid.unflat(int(candidates[rng.integers(candidates.size)]))
    heading_number = HEADINGS[heading] // 90 if heading is not None else int(rng.integers(4))
    return cell, heading_number


def episode_start(
    scene: Scene,
    *,
    seed: int = 0,
    episode: int | None = None,
    point: tuple[float, float] | None = None,
    heading: str | None = None,
) -> tuple[np.random.Generator, tuple[int, int], int]:
    """The generator, start cell and heading of ``guardsim play`` (and of :meth:`Simulation.reset`).

    Without ``episode``: ``point``, else the level's ``guard.start``, else drawn from
    ``default_rng(seed)``; likewise the heading. With ``episode`` K, both are drawn from episode K's
    generator (as ``guardsim bench`` does) unless given. The generator is returned so that later draws
    (other guards, the planners) follow on from it.
    """
    level = scene.level
    if episode is not None:
        rng = episode_generator(seed, episode)
    else:
        rng = np.random.default_rng(seed)
        point, heading = point or level.guard.start, heading or level.guard.heading
    cell, first_heading = choose_start(scene, rng=rng, point=point, heading=heading)
    return rng, cell, first_heading


def team_starts(
    scene: Scene,
    first: tuple[tuple[int, int], int],
    guards: int,
    *,
    rng: np.random.Generator,
) -> tuple[list[tuple[int, int]], list[int]]:
    """Starts and headings of a team: ``first`` for guard 0, the others drawn from its connected area.

    Each further guard draws a cell uniformly from the cells reachable from guard 0, then a heading,
    in guard order, after guard 0's own draws, so one guard's episode is the same with or without
    this call.
    """
    cells, headings = [first[0]], [first[1]]
    area = np.flatnonzero(scene.grid.component(*first[0]))
    for _ in range(guards - 1):
        cells.append(scene.grid.unflat(int(area[rng.integers(area.size)])))
        headings.append(int(rng.integers(4)))
    return cells, headings


def check_headings(headings: Sequence[int] | None, guards: int) -> list[int] | None:
    """Headings a caller gives, checked: one heading number per guard, 0 (right), 1 (down), 2 (left) or 3 (up)."""
    if headings is None:
        return None
    facing = [int(heading) for heading in headings]
    if len(facing) != guards:
        raise ArgumentError(f"{len(facing)} headings for {guards} guards")
    if not all(0 <= heading < 4 for heading in facing):
        raise ArgumentError(f"headings {facing} must be heading numbers 0 (right), 1 (down), 2 (left) or 3 (up)")
    return facing


def checked_starts(
    grid: CoverageGrid, starts: Sequence[tuple[int, int]], headings: Sequence[int] | None, guards: int
) -> tuple[list[tuple[int, int]], list[int]]:
    """Starts a caller gives, checked: one traversable ``(col, row)`` cell and one heading per guard.

    The one start validation of :class:`~guardsim.simulation.Simulation`,
    :class:`~guardsim.motion.ContinuousSimulation` and the environments.

    >>> from guardsim.level import parse_level
    >>> from guardsim.scene import Scene
    >>> grid = Scene.from_level(parse_level({"outer": [[0, 0], [3, 0], [3, 2], [0, 2]]})).grid
    >>> checked_starts(grid, [(2, 1)], [3], 1)
    ([(2, 1)], [3])
    >>> checked_starts(grid, [(3, 1)], [0], 1)
    Traceback (most recent call last):
    guardsim.errors.ArgumentError: start cell (3, 1) is off the grid
    """
    if len(starts) != guards:
        raise ArgumentError(f"{len(starts)} starts for {guards} guards")
    facing = check_headings(headings, guards)
    if facing is None:
        raise ArgumentError("starts need headings")
    cells = [(int(col), int(row)) for col, row in starts]
    rows, cols = grid.shape
    for col, row in cells:
        if not (0 <= row < rows and 0 <= col < cols):
            raise ArgumentError(f"start cell ({col}, {row}) is off the grid")
        if not grid.traversable[row, col]:
            raise ArgumentError(f"start cell ({col}, {row}) is not traversable")
    return cells, facing
