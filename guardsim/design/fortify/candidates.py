"""The watchers fortify may add: cameras on wall-adjacent cells and guard posts, and their gains.

The candidate set is fixed before the loop starts, so that "the fewest watchers" has a meaning:

- **cameras**: one per wall-adjacent floor cell (a traversable cell with a blocked side), at the cell's
  centre, its swing's middle facing away from the wall (away from both walls in a corner; along the
  corridor where walls face each other). Its cone, range and sweep are the :class:`CameraShape`'s; it
  pauses one tick at each end of its swing and turns so that the swing lasts as many ticks as a post's
  turn, so the joint lap grows by at most that factor.
- **posts**: a guard standing on a floor cell, turning through its four headings (right, down, left, up),
  holding each a quarter of the turn: a patrol loop of one cell (:func:`post_headings`).

The turn (:func:`swing_ticks`) is the smallest divisor of the watchers' lap from 4 to 16 ticks, else 4
ticks, so that adding candidates lengthens the joint lap as little as it can.

Only cells in the parts of the floor that hold an entry count, and not the entries and goals themselves
(a watcher on the player's spawn point seals nothing a designer wants). When there are more cells than
the ``candidates`` budget, the budget is split evenly between the two kinds (all of it to one kind when
the other's cap is 0); in each kind, the cells around the entries and goals (the eight about each) take
up to three quarters of it, since every way through passes by them, and the rest keeps one cell per
square block of the floor, the blocks as small as the budget allows (:func:`_spread`): the set is spread
over the floor and the same for the same inputs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.detection.cameras import camera_gains, camera_sight
from guardsim.detection.light import scene_sight
from guardsim.detection.model import GuardDetection
from guardsim.detection.sight import patrol_gains
from guardsim.grid import CoverageGrid, state_of
from guardsim.level import Camera, Level
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable

__all__ = [
    "DEFAULT_CANDIDATES",
    "SWING_RANGE",
    "SWING_TICKS",
    "CameraShape",
    "Candidate",
    "candidate_gains",
    "fortify_candidates",
    "post_states",
    "swing_ticks",
]


def swing_ticks(period: int) -> int:
    """The candidates' turn in ticks for watchers whose joint lap is ``period`` ticks.

    >>> swing_ticks(474), swing_ticks(1), swing_ticks(40), swing_ticks(337)
    (6, 4, 4, 4)
    """
    # The joint lap grows least with a divisor of the period (it stays the period), else with the shortest turn.
    return min(SWING_RANGE, key=lambda ticks: (math.lcm(period, ticks), ticks))


#: Ticks of a post's turn through its four headings and of a candidate camera's swing there and back
#: where the caller gives none (``fortify`` takes :func:`swing_ticks` of the watchers' lap).
SWING_TICKS = 8
#: The turns fortify may choose to fit the patrol's lap.
SWING_RANGE = range(4, 17)
#: Candidates considered when the caller gives no budget.
DEFAULT_CANDIDATES = 64

# Grid directions 0..3 (right, down, left, up) as unit vectors in world axes (y down).
_DIRECTIONS = ((1, 0), (0, 1), (-1, 0), (0, -1))


class CameraShape(NamedTuple):
    """The cone of every candidate camera."""

    fov_degrees: float = 60.0
    """Full opening angle."""
    view_range: float | None = None
    """World units; ``None``: the level guard's view range."""
    sweep: float = 90.0
    """Total swing in degrees (0: a fixed camera, a period of one tick)."""


class Candidate(NamedTuple):
    """One watcher fortify may add."""

    kind: str
    """``"camera"`` or ``"post"``."""
    cell: int
    """Flat cell it stands on."""
    camera: Camera | None
    """The camera as it would be written into the level (``None`` for a post)."""

    def position(self, grid: CoverageGrid) -> tuple[float, float]:
        """Its position in world units (the cell's centre)."""
        return grid.centre(*grid.unflat(self.cell))


def _away_heading(neighbours: np.ndarray, cell: int) -> float | None:
    """Degrees facing away from the cell's blocked sides; ``None`` when no side is blocked (or all are)."""
    blocked = [d for d in range(4) if neighbours[cell, d] < 0]
    if not blocked or len(blocked) == 4:
        return None
    x = -sum(_DIRECTIONS[d][0] for d in blocked)
    y = -sum(_DIRECTIONS[d][1] for d in blocked)
    if x == 0 and y == 0:
        # Walls on opposite sides: look along the corridor, the first open way.
        first = next(d for d in range(4) if neighbours[cell, d] >= 0)
        x, y = _DIRECTIONS[first]
    return math.degrees(math.atan2(y, x)) % 360.0


def _spread(grid: CoverageGrid, cells: np.ndarray, count: int) -> np.ndarray:
    """At most ``count`` of ``cells``, spread evenly over the floor: the grid is cut into square blocks, the
    smallest that leave at most ``count`` blocks holding a cell, and each block keeps its cell nearest its
    centre (the lowest flat index on a tie). All of them when they fit."""
    if cells.size <= count:
        return cells
    if count <= 0:
        return cells[:0]
    cols = grid.shape[1]
    rows_of, cols_of = cells // cols, cells % cols
    block = 2
    while True:
        keys = (rows_of // block) * (cols // block + 1) + cols_of // block
        if np.unique(keys).size <= count:
            break
        block += 1
    centre = (block - 1) / 2
    distance = (rows_of % block - centre) ** 2 + (cols_of % block - centre) ** 2
    order = np.lexsort((cells, distance, keys))
    first = np.ones(order.size, dtype=bool)
    first[1:] = keys[order][1:] != keys[order][:-1]
    return np.sort(cells[order][first])


def camera_at(grid: CoverageGrid, cell: int, heading: float, shape: CameraShape, dt: float, swing: int) -> Camera:
    """The candidate camera on ``cell``: it pauses a tick at each end and swings there and back in
    ``swing`` ticks."""
    if shape.sweep <= 0:
        return Camera(grid.centre(*grid.unflat(cell)), heading=heading, fov_degrees=shape.fov_degrees,
                      view_range=shape.view_range)  # fmt: skip
    turn = (swing / 2 - 1) * dt
    return Camera(
        grid.centre(*grid.unflat(cell)), heading=round(heading, 6), fov_degrees=shape.fov_degrees,
        view_range=shape.view_range, sweep=shape.sweep, turn_speed=shape.sweep / turn, pause=dt,
    )  # fmt: skip


def fortify_candidates(
    grid: CoverageGrid,
    entries: Sequence[int],
    *,
    exclude: Sequence[int] = (),
    near: Sequence[int] = (),
    shape: CameraShape,
    dt: float,
    swing: int = SWING_TICKS,
    cameras: bool,
    posts: bool,
    budget: int = DEFAULT_CANDIDATES,
) -> tuple[Candidate, ...]:
    """The candidate set (see the module): cameras first, then posts, each in row-major cell order.

    The floor cells around each of ``near`` (the entries and goals: the eight cells about each) take up
    to three quarters of each kind's budget, since every way through passes by them; the rest is spread."""
    labels = grid.component_labels
    floor = np.isin(labels, np.asarray([labels[cell] for cell in entries], dtype=labels.dtype))
    floor &= grid.traversable.ravel()
    floor[np.asarray(exclude, dtype=np.int64)] = False
    cells = np.flatnonzero(floor)
    neighbours = grid.neighbours
    walled = np.asarray(
        [cell for cell in cells.tolist() if _away_heading(neighbours, cell) is not None], dtype=np.int64
    )
    camera_budget = (budget if not posts else (budget + 1) // 2) if cameras else 0
    post_budget = budget - camera_budget if posts else 0
    if cameras and posts and walled.size < camera_budget:
        post_budget = budget - int(walled.size)
    cols = grid.shape[1]
    ring = np.zeros(grid.size, dtype=bool)
    for centre in near:
        row, col = divmod(int(centre), cols)
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                if 0 <= row + dr < grid.shape[0] and 0 <= col + dc < cols:
                    ring[(row + dr) * cols + col + dc] = True

    def pick(pool: np.ndarray, count: int) -> np.ndarray:
        # At most three quarters of the budget: the spread keeps the rest of the floor watched.
        close = _spread(grid, pool[ring[pool]], count - count // 4)
        rest = pool[~ring[pool]]
        return np.sort(np.concatenate([close, _spread(grid, rest, count - close.size)]))

    out: list[Candidate] = []
    for cell in pick(walled, camera_budget).tolist():
        heading = _away_heading(neighbours, cell)
        assert heading is not None
        out.append(Candidate("camera", cell, camera_at(grid, cell, heading, shape, dt, swing)))
    out.extend(Candidate("post", cell, None) for cell in pick(cells, post_budget).tolist())
    return tuple(out)


def post_headings(swing: int) -> np.ndarray:
    """``int64 (swing,)``: a post's heading at each tick of its turn: right, down, left, up, each held a
    quarter of the turn (the first ones a tick longer when it does not divide by four).

    >>> post_headings(6).tolist()
    [0, 0, 1, 1, 2, 3]
    """
    holds = [swing // 4 + (1 if heading < swing % 4 else 0) for heading in range(4)]
    return np.repeat(np.arange(4, dtype=np.int64), holds)


def post_states(cells: Sequence[int], swing: int = SWING_TICKS) -> np.ndarray:
    """``int64 (posts, swing)``: each post's states over its turn (:func:`post_headings`)."""
    if not len(cells):
        return np.zeros((0, swing), dtype=np.int64)
    headings = post_headings(swing)
    return np.stack([state_of(np.full(swing, cell, dtype=np.int64), headings) for cell in cells]).astype(np.int64)


class _GainJob(NamedTuple):
    """A chunk of candidates to compute the gains of on a worker: all it needs to rebuild the scene."""

    number: int
    level: Level
    scene_options: dict[str, Any]
    candidates: tuple[Candidate, ...]
    swing: int


# Scenes and view tables a worker built, by level and options, so that a worker builds each once.
_WORKER_SCENES: dict[str, tuple[Scene, ViewTable]] = {}


def _scene_key(level: Level, options: dict[str, Any]) -> str:
    return repr((level, sorted(options.items())))


def _chunk_gains(job: _GainJob) -> list[np.ndarray]:
    """Worker side of :func:`candidate_gains`: the gains of each candidate of the chunk."""
    from guardsim.vision.table import view_table

    key = _scene_key(job.level, job.scene_options)
    if key not in _WORKER_SCENES:
        scene = Scene.from_level(job.level, **job.scene_options)
        _WORKER_SCENES[key] = (scene, view_table(scene.grid, scene.vision()))
    scene, table = _WORKER_SCENES[key]
    return _gains_here(scene, table, job.candidates, job.swing)


def _gains_here(scene: Scene, table: ViewTable, candidates: Sequence[Candidate], swing: int) -> list[np.ndarray]:
    from guardsim.detection.watch import level_watch

    level = scene.level
    detection = GuardDetection.of_level(level)
    grid = scene.grid
    watch = level_watch(scene, detection.dt, gains=False) if not level.lit else None
    light = None if watch is None or not watch.dark else watch.light
    lit = np.ones(grid.size, dtype=np.float64) if light is None else light
    out: list[np.ndarray] = []
    cameras = [candidate.camera for candidate in candidates if candidate.camera is not None]
    sight = None
    if cameras:
        import dataclasses

        # The level's own cameras and the candidates: the sight reaches as far as the farthest of them.
        sight = scene_sight(dataclasses.replace(scene, level=dataclasses.replace(level, cameras=tuple(cameras))))
    for candidate in candidates:
        if candidate.camera is not None:
            assert sight is not None
            sweep = camera_sight(candidate.camera, level.guard, sight, detection.dt)
            out.append(camera_gains(sweep, lit, detection.dt, grid.size))
        else:
            gains = patrol_gains(
                grid, table, post_states([candidate.cell], swing), detection.model, view_range=detection.view_range,
                dt=detection.dt, light=light,
            )  # fmt: skip
            out.append(gains.gain[0])
    return out


def candidate_gains(
    scene: Scene,
    table: ViewTable,
    candidates: Sequence[Candidate],
    *,
    scene_options: dict[str, Any],
    swing: int = SWING_TICKS,
    workers: int = 1,
    scheduler: str | None = None,
    chunk: int = 16,
) -> list[np.ndarray]:
    """Each candidate's ``float64 (its period, cells)`` gains, in candidate order.

    With ``workers`` > 1 or a Dask ``scheduler``, chunks of ``chunk`` candidates run on the executors of
    :mod:`guardsim.experiment.executors`; each candidate's gains depend on it alone, so the result is the
    same bytes whatever the worker count. ``scene_options`` are the keywords that rebuild ``scene`` from
    its level (:meth:`Scene.from_level`) on a worker that does not share this process's memory.
    """
    if workers <= 1 and scheduler is None:
        return _gains_here(scene, table, candidates, swing)
    from guardsim.errors import GuardsimError
    from guardsim.experiment.executors import make_executor

    _WORKER_SCENES[_scene_key(scene.level, scene_options)] = (scene, table)
    jobs = [
        _GainJob(index, scene.level, scene_options, tuple(candidates[start : start + chunk]), swing)
        for index, start in enumerate(range(0, len(candidates), chunk))
    ]
    results: dict[int, list[np.ndarray]] = {}
    with make_executor(workers, scheduler) as executor:
        for done in executor.run_unordered(_chunk_gains, jobs):
            if done.failure is not None:
                raise GuardsimError(f"a worker computing candidate gains failed: {done.failure}")
            results[done.item.number] = done.result
    return [gain for index in range(len(jobs)) for gain in results[index]]
