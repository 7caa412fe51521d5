"""How close a call a sneak path is: its meters replayed tick by tick, its risk, and the lap's slack.

:func:`grade_path` replays a path through :class:`~guardsim.detection.AwarenessMeter`, deciding sight
from the view table and distance from the guards' cells, apart from the search's precomputed gains: it
is the independent check of what the search reports.

The risk score is the mean, over the path's ticks, of the highest guard meter at that tick: 0 for a path
no guard sees, 1 for one detected on entry and watched to the end. It grades a path the way the
awareness bars a player watches do, in the spirit of the risk measures compared by Tremblay, Torres and
Verbrugge ("Measuring risk in stealth games", FDG 2014), who found that measures built from time in view
and distance to guards tracked players' judgement of danger, and of Stealth-Simulator's path risk in
[0, 1]; see docs/detection.md.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from guardsim.detection.model import AwarenessMeter, DetectionModel, GuardDetection
from guardsim.detection.watch import LevelWatch
from guardsim.grid import CoverageGrid
from guardsim.kernels.compiler import jit
from guardsim.kernels.gaits import GAIT_MOVES, SILENT, WALK_MOVES, gait_move
from guardsim.kernels.steps import cell_of_state
from guardsim.vision.table import ViewTable

__all__ = ["PathGrade", "grade_path", "unseen_reach"]


class PathGrade(NamedTuple):
    """A path replayed through the guards' awareness meters."""

    meters: np.ndarray
    """``float64 (ticks + 1, watchers)``: each watcher's meter after each tick of the path (the guards,
    then the level's cameras)."""
    in_view: np.ndarray
    """``bool (ticks + 1,)``: whether some watcher sees the intruder at each tick (in its sight, and lit
    enough or within its dark sight)."""
    detected_at: int | None
    """Tick of the path (0 = entering) at which a meter first fills; ``None`` when none does."""
    closest_distance: float | None
    """Smallest distance, world units, from the intruder to a guard over the path (in view or not)."""

    @property
    def detected(self) -> bool:
        """Whether some guard's meter fills on the path."""
        return self.detected_at is not None

    @property
    def peak_by_guard(self) -> list[float]:
        """Each watcher's highest meter (the guards, then the cameras)."""
        return [float(value) for value in self.meters.max(axis=0)]

    @property
    def peak(self) -> float:
        """The highest meter of any guard."""
        return float(self.meters.max())

    @property
    def ticks_in_view(self) -> int:
        """Ticks at which some guard sees the intruder."""
        return int(self.in_view.sum())

    @property
    def risk(self) -> float:
        """The mean over the path's ticks of the highest meter: 0 (never noticed) to 1."""
        return float(self.meters.max(axis=1).mean())


def grade_path(
    grid: CoverageGrid,
    table: ViewTable,
    states: np.ndarray,
    detection: GuardDetection,
    start_tick: int,
    cells: np.ndarray,
    *,
    watch: LevelWatch | None = None,
) -> PathGrade:
    """Replay the intruder's flat ``cells``, entering at lap tick ``start_tick`` of the lap ``states``
    (``int64 (guards, period)``), through one awareness meter per guard, then one per camera of ``watch``
    (whose light also dims what every watcher makes of the intruder)."""
    period = states.shape[1]
    guards = states.shape[0]
    cameras = () if watch is None else watch.cameras
    model = detection.model
    meters = [AwarenessMeter(model, detection.view_range) for _ in range(guards)] + [
        AwarenessMeter(
            DetectionModel(camera.detect_near, camera.detect_far, model.forget, model.suspicious, dark_sight=0.0),
            camera.view_range,
        )
        for camera in cameras
    ]
    levels = np.zeros((len(cells), len(meters)))
    in_view = np.zeros(len(cells), dtype=bool)
    detected_at: int | None = None
    closest = math.inf
    cols = grid.shape[1]
    for tick, cell in enumerate(int(value) for value in cells):
        row, col = divmod(cell, cols)
        light = 1.0 if watch is None else float(watch.light[cell])
        for guard, meter in enumerate(meters[:guards]):
            state = int(states[guard, (start_tick + tick) % period])
            guard_row, guard_col = divmod(int(cell_of_state(state)), cols)
            distance = grid.cell_size * math.hypot(row - guard_row, col - guard_col)
            closest = min(closest, distance)
            sees = bool(np.isin(cell, table.sees(state)))
            in_view[tick] |= sees and model.gain(detection.dt, distance, detection.view_range, light) > 0
            levels[tick, guard] = meter.update(detection.dt, sees, distance, light)
            if meter.detected and detected_at is None:
                detected_at = tick
        for index, (camera, meter) in enumerate(zip(cameras, meters[guards:])):
            where = np.searchsorted(camera.cells, cell)
            sees = bool(where < camera.cells.size and camera.cells[where] == cell)
            sees = sees and bool(camera.in_cone[(start_tick + tick) % camera.ticks, where])
            distance = float(camera.distances[where]) if sees else 0.0
            in_view[tick] |= sees and meter.model.gain(detection.dt, distance, meter.view_range, light) > 0
            levels[tick, guards + index] = meter.update(detection.dt, sees, distance, light)
            if meter.detected and detected_at is None:
                detected_at = tick
    return PathGrade(levels, in_view, detected_at, None if math.isinf(closest) else closest)


@jit
def _reach(
    neighbours: np.ndarray, seen: np.ndarray, heard: np.ndarray, cap: int, moves: int, target: int
) -> np.ndarray:
    """``bool (cap + 1, period, cells)``: the (ticks still, lap tick, cell) nodes from which the target is
    reached neither seen nor heard, found backwards from the target's unseen ticks: a node's
    predecessors are the unseen nodes a tick earlier from which some move
    (:func:`~guardsim.kernels.gaits.gait_move`) lands on it unheard (the grid's moves are symmetric, so
    they are its cell's and its neighbours'). Without gaits ``cap`` is 0, ``moves`` 5 and ``heard``
    :data:`~guardsim.kernels.gaits.SILENT`."""
    period, cells = seen.shape
    layer = period * cells
    reach = np.zeros((cap + 1) * layer, dtype=np.bool_)
    queue = np.empty((cap + 1) * layer, dtype=np.int64)
    tail = 0
    for phase in range(period):
        if not seen[phase, target]:
            for still in range(cap + 1):
                node = still * layer + phase * cells + target
                reach[node] = True
                queue[tail] = node
                tail += 1
    head = 0
    while head < tail:
        node = queue[head]
        head += 1
        still, rest = node // layer, node % layer
        phase, cell = rest // cells, rest % cells
        before = (phase - 1) % period
        for direction in range(5):
            other = cell if direction == 4 else neighbours[cell, direction]
            if other < 0 or seen[before, other]:
                continue
            for earlier in range(cap + 1):
                previous = earlier * layer + before * cells + other
                if reach[previous]:
                    continue
                for move in range(moves):
                    lands, still_after, loud = gait_move(neighbours, heard, phase, other, earlier, cap, move)
                    if lands == cell and still_after == still and not loud:
                        reach[previous] = True
                        queue[tail] = previous
                        tail += 1
                        break
    return reach.reshape((cap + 1, period, cells))


def unseen_reach(
    neighbours: np.ndarray,
    seen: np.ndarray,
    target: int,
    *,
    heard: np.ndarray | None = None,
    sneak_ticks: int = 2,
) -> np.ndarray:
    """``bool (period, cells)``: the (lap tick, cell) nodes from which ``target`` can be reached unseen;
    its column at an entry cell says from which lap ticks a player entering there gets through unseen
    (their count is the unseen slack). With ``heard`` (see :func:`guardsim.sneak.search.find_sneak`),
    unseen and unheard, choosing gaits, for a player who has just arrived in the cell (or entered): one
    who has stood there longer gets through from these nodes and maybe others.

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> seen = np.array([[False, True, False], [False, False, False]])
    >>> unseen_reach(neighbours, seen, 2)[:, 0].tolist()
    [True, True]
    """
    gaits = (SILENT, 0, WALK_MOVES) if heard is None else (heard, int(sneak_ticks) - 1, GAIT_MOVES)
    reach = _reach(
        np.ascontiguousarray(neighbours, dtype=np.int64), np.ascontiguousarray(seen, dtype=np.bool_),
        np.ascontiguousarray(gaits[0], dtype=np.bool_), gaits[1], gaits[2], int(target),
    )  # fmt: skip
    return reach[0]
