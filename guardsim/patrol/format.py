"""patrol.json: a patrol and its scores, written by ``guardsim patrol`` and read back strictly.

The format (see ``docs/patrols.md``)::

    {"level": "Square", "cell_size": 1.0, "origin": [0, 0], "shape": [rows, cols], "motion": "grid",
     "strategy": "loop", "period": 498,
     "guards": [{"loop": [[col, row], ...], "headings": [0, ...]}, ...],
     "worst_idleness": 497, "mean_idleness": 199.8, "idleness": [[gap or null, ...], ...]}

A repeating guard's ``loop`` lists its cell at each tick of a lap and ends where it began (a post is a
one-cell loop, ``[[c, r]]`` or ``[[c, r], [c, r]]``, with a fixed heading); ``headings`` gives the
heading number (0 right, 1 down, 2 left, 3 up) at each of those ticks. Moves obey the grid: each tick a
guard steps to a connected 4-neighbour, facing the way it stepped, or stays, keeping its heading.
Reading checks the file against ``patrol.schema.json`` (:mod:`guardsim.files.schema`), then every one of those
rules, and says where the first broken one is, in one line.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from guardsim.errors import PatrolError
from guardsim.files.reading import excerpt, read_json_file
from guardsim.files.schema import check
from guardsim.grid import CoverageGrid, state_of
from guardsim.patrol.model import Patrol
from guardsim.patrol.scoring import NEVER, PatrolScore

__all__ = [
    "DEFAULT_MAX_PATROL_BYTES",
    "MAX_UNROLLED_BYTES",
    "PatrolError",
    "parse_patrol",
    "patrol_data",
    "read_patrol",
]

#: Largest patrol file read.
DEFAULT_MAX_PATROL_BYTES = 64 * 1024 * 1024
#: Most bytes the states of a repeating team may take once its loops are repeated over their common period
#: (the least common multiple of the laps): 8 bytes per guard and tick (duskwood's 4 guards over a
#: 22 784-tick lap take 0.7 MB). The reader builds nothing over the cells: a command that would (a page's
#: lap timeline, a dense search) bounds its own arrays.
MAX_UNROLLED_BYTES = 256 * 2**20


#: Most ticks times cells a patrol read from a file may be scored over (one byte each).
MAX_TIMELINE_CELLS = 400_000_000


def patrol_data(
    patrol: Patrol,
    score: PatrolScore,
    grid: CoverageGrid,
    *,
    level: str,
    motion: str = "grid",
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """The JSON-ready dictionary of a patrol and its score."""
    guards = []
    for guard in range(patrol.guards):
        cells = [list(cell) for cell in patrol.cells(grid, guard)]
        headings = patrol.headings(guard)
        if patrol.period is not None:
            cells.append(cells[0])
            headings.append(headings[0])
        guards.append({"loop": cells, "headings": headings})
    rows, cols = grid.shape
    gaps = score.worst_gap.reshape(rows, cols)
    idleness = [
        [None if value == -2 else (None if value == NEVER else int(value)) for value in row] for row in gaps.tolist()
    ]
    data: dict[str, Any] = {
        "level": level,
        "cell_size": grid.cell_size,
        "origin": list(grid.origin),
        "shape": [rows, cols],
        "motion": motion,
        "strategy": patrol.strategy,
        "period": patrol.period,
        "guards": guards,
        "worst_idleness": score.worst_idleness,
        "mean_idleness": None if score.mean_idleness is None else round(score.mean_idleness, 3),
        "idleness": idleness,
        "never_seen": score.never_seen,
        "ticks_scored": score.ticks_scored,
    }
    if patrol.planner is not None:
        data["planner"] = patrol.planner
    if patrol.team is not None:
        data["team"] = patrol.team
    if patrol.notes:
        data["notes"] = list(patrol.notes)
    data.update(extra or {})
    return data


def read_patrol(
    path: str, grid: CoverageGrid, *, max_file_bytes: int = DEFAULT_MAX_PATROL_BYTES, level: str | None = None
) -> Patrol:
    """Read a patrol file made for ``grid``'s level; every fault one :class:`PatrolError` line.

    ``level``, the level's name: a patrol that does not fit and names another level says so.
    """
    data = read_json_file(path, max_file_bytes=max_file_bytes, kind="patrol file", error=PatrolError)
    try:
        return parse_patrol(data, grid, source=str(path))
    except PatrolError as error:
        made_for = data.get("level") if isinstance(data, dict) else None
        if level is None or not isinstance(made_for, str) or made_for == level:
            raise
        raise PatrolError(
            f"{error} (the patrol was made for level {excerpt(made_for)}, not {excerpt(level)})"
        ) from None


def _fail(source: str, where: str, message: str) -> PatrolError:
    return PatrolError(f"{source}: {where}: {message}" if where else f"{source}: {message}")


def parse_patrol(data: Any, grid: CoverageGrid, *, source: str = "<patrol>") -> Patrol:
    """A :class:`Patrol` from patrol.json data, checked against ``patrol.schema.json``, then against the
    level's grid.

    Examples
    --------
    >>> grid = CoverageGrid((0.0, 0.0), 1.0, np.ones((1, 2), dtype=bool), np.array([[1, -1, -1, -1], [-1, -1, 0, -1]]))
    >>> patrol = parse_patrol({"shape": [1, 2], "guards": [{"loop": [[0, 0], [0, 0]], "headings": [0, 0]}]}, grid)
    >>> patrol.period, patrol.states.tolist()
    (1, [[0]])
    >>> parse_patrol({"shape": [1, 2], "guards": [{"loop": [[0, 0], [1, 0]], "headings": [0, 2]}]}, grid)
    Traceback (most recent call last):
    ...
    guardsim.errors.PatrolError: <patrol>: guards[0]: headings[1]: a step right must face right (0), not 2
    """
    check(data, "patrol", source=source, error=PatrolError)
    rows, cols = grid.shape
    if data["shape"] != [rows, cols]:
        raise _fail(source, "shape", f"{data['shape']} does not match the level's grid [{rows}, {cols}]")
    size = data.get("cell_size", grid.cell_size)
    if not math.isclose(size, grid.cell_size):
        raise _fail(source, "cell_size", f"{size!r} does not match the level's cell size {grid.cell_size:g}")
    origin = data.get("origin", list(grid.origin))
    if not all(math.isclose(a, b, abs_tol=1e-9) for a, b in zip(origin, grid.origin)):
        raise _fail(source, "origin", f"{origin!r} does not match the level's grid origin {list(grid.origin)}")
    motion, period, strategy = data.get("motion", "grid"), data.get("period", 0), data.get("strategy", "evaluate")
    repeating = period is not None
    laps = [_read_guard(guard, grid, repeating, source, f"guards[{n}]") for n, guard in enumerate(data["guards"])]
    if not repeating:
        ticks = max(lap.size for lap in laps)
        if ticks * grid.size > MAX_TIMELINE_CELLS:
            raise _fail(
                source,
                "guards",
                f"walked paths of {ticks} ticks on {grid.size} cells are over the limit of {MAX_TIMELINE_CELLS} cell-ticks",
            )
        states = np.stack([np.concatenate([lap, np.full(ticks - lap.size, lap[-1])]) for lap in laps])
        return Patrol(states, None, strategy, motion=motion)
    common = math.lcm(*(lap.size for lap in laps))
    needed = 8 * len(laps) * common
    if needed > MAX_UNROLLED_BYTES:
        raise _fail(
            source,
            "guards",
            f"the laps' lengths {[lap.size for lap in laps]} repeat together only every {common} ticks: "
            f"{len(laps)} guards' states over them would take {-(-needed // 2**20)} MB, over the limit of "
            f"{MAX_UNROLLED_BYTES // 2**20} MB (give the loops lengths with a large common factor, or raise "
            "guardsim.patrol.format.MAX_UNROLLED_BYTES)",
        )
    if period not in (0, common):
        raise _fail(source, "period", f"{period} does not match the loops, which repeat every {common} ticks")
    states = np.stack([np.tile(lap, common // lap.size) for lap in laps])
    return Patrol(states, common, strategy, motion=motion)


_NAMES = ("right", "down", "left", "up")


def _read_guard(guard: dict[str, Any], grid: CoverageGrid, repeating: bool, source: str, where: str) -> np.ndarray:
    """One guard's states per tick (one lap when ``repeating``), every move checked (the schema has
    checked the types)."""
    loop, headings = guard["loop"], guard["headings"]
    if len(headings) != len(loop):
        raise _fail(
            source, f"{where}.headings", f"expected one heading per loop cell ({len(loop)}), got {len(headings)}"
        )
    rows, cols = grid.shape
    cells: list[int] = []
    for index, (col, row) in enumerate(loop):
        if not (0 <= col < cols and 0 <= row < rows):
            raise _fail(source, f"{where}.loop[{index}]", f"[{col}, {row}] is off the grid ({cols} x {rows})")
        if not grid.traversable[row, col]:
            raise _fail(source, f"{where}.loop[{index}]", f"[{col}, {row}] is not a cell the guard can stand in")
        cells.append(grid.flat(col, row))
    post = bool(guard.get("post", False))
    if post and len(set(cells)) != 1:
        raise _fail(source, f"{where}.loop", "a post stands on one cell: every loop cell must be the same")
    for index in range(1, len(cells)):
        if not post:
            _check_move(grid, loop, headings, cells, index, source, where)
    states = state_of(np.asarray(cells, dtype=np.int64), np.asarray(headings, dtype=np.int64))
    if not repeating or len(cells) == 1:
        return states
    if cells[0] != cells[-1] or headings[0] != headings[-1]:
        raise _fail(
            source,
            f"{where}.loop",
            f"a repeating loop must end as it began: {loop[0]} heading {headings[0]}, not {loop[-1]} heading {headings[-1]}",
        )
    return states[:-1]


def _check_move(
    grid: CoverageGrid, loop: list[Any], headings: list[int], cells: list[int], index: int, source: str, where: str
) -> None:
    """Tick ``index`` is a wait keeping the heading or a step to a connected 4-neighbour facing its way."""
    before, after = cells[index - 1], cells[index]
    if before == after:
        if headings[index] != headings[index - 1]:
            raise _fail(
                source,
                where,
                f"headings[{index}]: a guard standing still keeps its heading ({headings[index - 1]}), not {headings[index]}",
            )
        return
    direction = next((d for d in range(4) if int(grid.neighbours[before, d]) == after), -1)
    if direction < 0:
        raise _fail(
            source,
            f"{where}.loop[{index}]",
            f"{loop[index - 1]} -> {loop[index]} is not a step to a connected 4-neighbour",
        )
    if headings[index] != direction:
        name = _NAMES[direction]
        raise _fail(
            source, where, f"headings[{index}]: a step {name} must face {name} ({direction}), not {headings[index]}"
        )
