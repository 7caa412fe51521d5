"""What a designer expects of game guards, checked by replaying an alert trace tick by tick.

:func:`check_alert_trace` reads the JSON data of an alert trace (:func:`~guardsim.alert.alert_trace_data`,
the files ``guardsim alert --out`` writes) and the level's grid, and lists every :class:`Violation`:

- ``jitter``: a guard walks back and forth between the same two cells more than :data:`MAX_REVERSALS`
  times in a row. A reversal is a step back to the cell it came from; one where the guard stood at the
  turning cell for two ticks or more (a look around, a turn in place) does not count.
- ``stacked``: two guards within one cell of each other (the same cell or 4-neighbours) for more than
  :data:`MAX_TOGETHER_TICKS` consecutive ticks, except ticks where both chase an intruder in view or
  either stands in a corridor one cell wide (a cell with two traversable neighbours, on opposite sides).
- ``moonwalk``: a guard that stepped during a tick faces another way than the step's (grid motion: a
  step of two cells straight, a run, counts as one step that way). In continuous motion (a trace with
  ``poses``), a body that moved during a tick more than 90 degrees away from its heading both at the
  start and at the end of the tick (walking backwards or sideways; turning is at the turn speed).
- ``radio``: a ``joined`` event at a tick when, the tick before, no guard was chasing or searching, the
  intruder had left, or the search area was empty.
- ``wrong_way``: a guard that starts searching walks away from the last known cell on the side
  opposite to the intruder's last seen direction of travel (its position after :data:`SEARCH_WINDOW`
  ticks of search is behind the last known cell and farther from it than where it started), although
  the cell beyond the last known cell in that direction is traversable.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

__all__ = [
    "MAX_REVERSALS",
    "MAX_TOGETHER_TICKS",
    "SEARCH_WINDOW",
    "VIOLATIONS",
    "Violation",
    "check_alert_trace",
    "corridor_cells",
]

#: Consecutive reversals between the same two cells a guard may make.
MAX_REVERSALS = 3
#: Consecutive ticks two guards may stay within one cell of each other.
MAX_TOGETHER_TICKS = 10
#: Ticks of search after which a searcher's side of the last known cell is judged.
SEARCH_WINDOW = 6
#: The kinds of :class:`Violation`.
VIOLATIONS = ("jitter", "stacked", "moonwalk", "radio", "wrong_way")

_DIRECTIONS = ((1, 0), (0, 1), (-1, 0), (0, -1))


class Violation(NamedTuple):
    """One broken expectation in a trace."""

    kind: str
    """One of :data:`VIOLATIONS`."""
    tick: int
    """The tick it starts at."""
    guards: tuple[int, ...]
    ticks: int
    """How long it lasted (ticks; 1 for a single event)."""


def corridor_cells(traversable: np.ndarray) -> np.ndarray:
    """``bool (rows, cols)``: the traversable cells of a corridor one cell wide (at most two traversable
    4-neighbours, no two of them at a right angle: a straight corridor or a dead end).

    >>> corridor_cells(np.array([[True, True, True], [False, True, False]])).astype(int).tolist()
    [[1, 0, 1], [0, 1, 0]]
    """
    free = np.pad(np.asarray(traversable, dtype=bool), 1)
    right, down, left, up = free[1:-1, 2:], free[2:, 1:-1], free[1:-1, :-2], free[:-2, 1:-1]
    count = right.astype(int) + down + left + up
    bent = (right & down) | (down & left) | (left & up) | (up & right)
    return free[1:-1, 1:-1] & (count <= 2) & ~bent


def check_alert_trace(data: dict[str, Any], traversable: np.ndarray) -> list[Violation]:
    """Every violation in the alert trace ``data`` (see the module) on a grid whose traversable cells are
    ``traversable`` (``bool (rows, cols)``).

    >>> free = np.ones((1, 4), dtype=bool)
    >>> trace = {"paths": [[[0, 0], [1, 0], [0, 0], [1, 0], [0, 0], [1, 0]]],
    ...          "headings": [[0, 0, 2, 0, 2, 0]], "guard_states": [["search"] * 6],
    ...          "events": [], "contaminated": [1] * 6, "last_known": [None] * 6, "intruder_path": [None] * 6}
    >>> [v.kind for v in check_alert_trace(trace, free)]
    ['jitter']
    """
    out: list[Violation] = []
    paths: list[list[Any]] = data["paths"]
    headings: list[list[int]] = data["headings"]
    states: list[list[str]] = data["guard_states"]
    guards = len(paths)
    for guard in range(guards):
        out.extend(_jitter(paths[guard], guard))
        if "poses" in data:
            out.extend(_moonwalk_poses(data["poses"][guard], guard))
        else:
            out.extend(_moonwalk(paths[guard], headings[guard], guard))
    out.extend(_stacked(paths, states, traversable))
    out.extend(_radio(data, states))
    out.extend(_wrong_way(data, paths, states, traversable))
    return sorted(out, key=lambda v: (v.tick, v.kind, v.guards))


def _jitter(path: Sequence[Any], guard: int) -> list[Violation]:
    visits: list[tuple[tuple[int, int], int, int]] = []  # (cell, first tick, ticks stayed)
    for tick, cell in enumerate(path):
        if cell is None:
            continue
        key = (int(cell[0]), int(cell[1]))
        if visits and visits[-1][0] == key:
            visits[-1] = (key, visits[-1][1], visits[-1][2] + 1)
        else:
            visits.append((key, tick, 1))
    out, run, start = [], 0, 0
    for index in range(1, len(visits) - 1):
        reversal = visits[index + 1][0] == visits[index - 1][0] and visits[index][2] < 2
        if reversal:
            if run == 0:
                start = visits[index - 1][1]
            run += 1
        if not reversal or index == len(visits) - 2:
            if run > MAX_REVERSALS:
                out.append(Violation("jitter", start, (guard,), run))
            run = 0
    return out


def _moonwalk(path: Sequence[Any], headings: Sequence[int], guard: int) -> list[Violation]:
    out = []
    for tick in range(1, len(path)):
        before, after = path[tick - 1], path[tick]
        if before is None or after is None:
            continue
        dx, dy = after[0] - before[0], after[1] - before[1]
        if (dx, dy) == (0, 0) or (dx != 0 and dy != 0):
            continue  # no step, or two steps round a corner (continuous motion's cell crossings)
        step = (int(np.sign(dx)), int(np.sign(dy)))
        if _DIRECTIONS.index(step) != int(headings[tick]) % 4:
            out.append(Violation("moonwalk", tick, (guard,), 1))
    return out


def _moonwalk_poses(poses: Sequence[Sequence[float]], guard: int) -> list[Violation]:
    out = []
    for tick in range(1, len(poses)):
        _, x0, y0, before = poses[tick - 1]
        _, x1, y1, after = poses[tick]
        if np.hypot(x1 - x0, y1 - y0) < 1e-6:
            continue
        travel = np.degrees(np.arctan2(y1 - y0, x1 - x0))
        off = [abs((travel - heading + 180.0) % 360.0 - 180.0) for heading in (before, after)]
        if min(off) > 90.0 + 1e-6:
            out.append(Violation("moonwalk", tick, (guard,), 1))
    return out


def _stacked(paths: list[list[Any]], states: list[list[str]], traversable: np.ndarray) -> list[Violation]:
    out = []
    guards = len(paths)
    corridor = corridor_cells(traversable)
    for first in range(guards):
        for second in range(first + 1, guards):
            run = start = 0
            for tick in range(len(paths[first]) + 1):
                near = False
                if tick < len(paths[first]):
                    a, b = paths[first][tick], paths[second][tick]
                    chasing = states[first][tick] == "chase" and states[second][tick] == "chase"
                    if a is not None and b is not None and not chasing:
                        near = abs(a[0] - b[0]) + abs(a[1] - b[1]) <= 1
                        near = near and not (corridor[a[1], a[0]] or corridor[b[1], b[0]])
                if near:
                    start = tick if run == 0 else start
                    run += 1
                    continue
                if run > MAX_TOGETHER_TICKS:
                    out.append(Violation("stacked", start, (first, second), run))
                run = 0
    return out


def _radio(data: dict[str, Any], states: list[list[str]]) -> list[Violation]:
    left = min((e["tick"] for e in data["events"] if e["event"] == "arrived"), default=None)
    out = []
    for event in data["events"]:
        if event["event"] != "joined":
            continue
        tick = event["tick"]
        joined = {e["guard"] for e in data["events"] if e["event"] == "joined" and e["tick"] == tick}
        alarmed = any(states[g][tick] in ("chase", "search") for g in range(len(states)) if g not in joined)
        gone = left is not None and left <= tick
        if not alarmed or gone or data["contaminated"][tick] == 0:
            out.append(Violation("radio", tick, (event["guard"],), 1))
    return out


def _gap(cell: Sequence[int], other: Sequence[int]) -> int:
    return abs(cell[0] - other[0]) + abs(cell[1] - other[1])


def _travel(data: dict[str, Any], tick: int) -> tuple[int, int] | None:
    """The intruder's last seen direction of travel at ``tick``: from the last known cell before the
    latest one to the latest (its last step while in sight)."""
    known = data["last_known"]
    latest = known[tick]
    if latest is None:
        return None
    for earlier in range(tick - 1, -1, -1):
        cell = known[earlier]
        if cell is not None and cell != latest:
            dx, dy = latest[0] - cell[0], latest[1] - cell[1]
            return (int(np.sign(dx)), int(np.sign(dy)))
    return None


def _wrong_way(
    data: dict[str, Any], paths: list[list[Any]], states: list[list[str]], traversable: np.ndarray
) -> list[Violation]:
    out = []
    rows, cols = traversable.shape
    for event in data["events"]:
        if event["event"] != "lost":
            continue
        guard, tick = event["guard"], event["tick"]
        travel = _travel(data, tick)
        known = data["last_known"][tick]
        if travel is None or known is None or tick + SEARCH_WINDOW >= len(paths[guard]):
            continue
        beyond = (known[0] + travel[0], known[1] + travel[1])
        if not (0 <= beyond[0] < cols and 0 <= beyond[1] < rows and traversable[beyond[1], beyond[0]]):
            continue
        if any(states[guard][t] != "search" for t in range(tick, tick + SEARCH_WINDOW + 1)):
            continue
        start, end = paths[guard][tick], paths[guard][tick + SEARCH_WINDOW]
        if start is None or end is None:
            continue

        side = (end[0] - known[0]) * travel[0] + (end[1] - known[1]) * travel[1]
        if side < 0 and _gap(end, known) > _gap(start, known):
            out.append(Violation("wrong_way", tick, (guard,), SEARCH_WINDOW))
    return out
