"""Tiny canonical levels, defined once and reused across the tests (after shapely's tests/common.py)."""

from __future__ import annotations

import copy
import csv
import json
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner, Result

from guardsim import load_level
from guardsim.cli import main
from guardsim.experiment import TIMED_COLUMNS
from guardsim.grid import state_of
from guardsim.importers import ImportedLevel
from guardsim.level import Level, parse_level
from guardsim.patrol import Patrol
from guardsim.simulation import Scene
from guardsim.trace import Trace
from guardsim.vision.rules import VisionFunction

REPO = Path(__file__).resolve().parent.parent
#: The shared data beside the clone (real maps, never committed): ``../shared`` as CI lays it out, or where
#: ``GUARDSIM_SHARED`` points (a worktree kept elsewhere than beside the shared folder).
SHARED = Path(os.environ.get("GUARDSIM_SHARED") or REPO.parent / "shared")
#: The corpus of real Tiled maps and LDtk projects (../shared/maps/corpus/SOURCES.md).
CORPUS = SHARED / "maps" / "corpus"


def import_map(path: str | os.PathLike[str], **options: Any) -> ImportedLevel:
    """What importing the map at ``path`` gives (level, changes, warnings), through :func:`guardsim.load_level`."""
    records: list[ImportedLevel] = []
    load_level(path, report=records.append, **options)
    assert len(records) == 1, f"{path} is a level file, not a map"
    return records[0]


def load_any(path: str | os.PathLike[str], **options: Any) -> tuple[Level, ImportedLevel | None]:
    """The level at ``path`` and, for a map, its import record."""
    records: list[ImportedLevel] = []
    level = load_level(path, report=records.append, **options)
    return level, (records[0] if records else None)


def needs_shared(path: Path) -> pytest.MarkDecorator:
    """Skip where ``path`` is missing, unless ``GUARDSIM_REQUIRE_SHARED`` is set (CI): then the test runs and fails."""
    missing = not path.exists() and not os.environ.get("GUARDSIM_REQUIRE_SHARED")
    return pytest.mark.skipif(missing, reason=f"the shared data is not at {path} (set GUARDSIM_SHARED)")


LEVELS = sorted((REPO / "levels").glob("*.json"))

#: An empty 4 x 4 room.
EMPTY_SQUARE: dict[str, Any] = {
    "name": "empty square",
    "outer": [[0, 0], [4, 0], [4, 4], [0, 4]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}

#: A 6 x 6 room with a 2 x 2 pillar in the middle.
SQUARE_WITH_HOLE: dict[str, Any] = {
    "name": "square with hole",
    "outer": [[0, 0], [6, 0], [6, 6], [0, 6]],
    "holes": [[[2, 2], [4, 2], [4, 4], [2, 4]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}

#: An L-shaped room: a 6 x 2 bar along the top and a 2 x 4 leg down the left.
L_ROOM: dict[str, Any] = {
    "name": "L room",
    "outer": [[0, 0], [6, 0], [6, 2], [2, 2], [2, 6], [0, 6]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}

#: Two 3 x 3 rooms side by side, split by a thin wall the guard can neither cross nor see through.
SPLIT_ROOMS: dict[str, Any] = {
    "name": "split rooms",
    "outer": [[0, 0], [6, 0], [6, 3], [0, 3]],
    "holes": [[[2.9, 0], [3.1, 0], [3.1, 3], [2.9, 3]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}

#: The keys issue 2 requires in a trace's JSON.
TRACE_KEYS = frozenset(
    {"level", "planner", "seed", "cell_size", "origin", "shape", "start", "path", "steps", "covered",
     "unseen_percent", "reachable", "unreachable"}
)  # fmt: skip

TINY_LEVELS = {
    "empty-square": EMPTY_SQUARE,
    "square-with-hole": SQUARE_WITH_HOLE,
    "l-room": L_ROOM,
    "split-rooms": SPLIT_ROOMS,
}

#: ``pytest.mark.parametrize`` over the tiny levels with readable ids.
tiny_levels = pytest.mark.parametrize("level_data", list(TINY_LEVELS.values()), ids=list(TINY_LEVELS))
#: ``pytest.mark.parametrize`` over the shipped levels.
shipped_levels = pytest.mark.parametrize("level_path", LEVELS, ids=[path.stem for path in LEVELS])
#: The same, with every level but Square in the slow tier (for checks that take seconds a level).
shipped_levels_square_fast = pytest.mark.parametrize(
    "level_path",
    [path if path.stem == "square" else pytest.param(path, marks=pytest.mark.slow) for path in LEVELS],
    ids=[path.stem for path in LEVELS],
)


def level_from(data: dict[str, Any], **changes: Any) -> Level:
    """A level from a dictionary, with top-level keys replaced by ``changes``."""
    merged = copy.deepcopy(data)
    merged.update(changes)
    return parse_level(merged, source="test.json")


def scene_from(data: dict[str, Any], **changes: Any) -> Scene:
    """The scene of :func:`level_from`."""
    return Scene.from_level(level_from(data, **changes))


def write_level(folder: Path, data: Any, name: str = "level.json") -> Path:
    """Write level data (or raw text) as a file and return its path."""
    path = folder / name
    path.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return path


# Running the command line: in-process, or as the real installed program.


def run(*args: str | Path) -> Result:
    """Invoke ``guardsim ARGS`` in-process, keeping stdout and stderr apart."""
    return CliRunner().invoke(main, [str(arg) for arg in args])


def assert_one_line_error(result: Result, path: Path | str) -> str:
    """Exit status 2, exactly one stderr line ``guardsim: error: ...`` naming ``path``, and no traceback."""
    assert "Traceback" not in result.output
    assert isinstance(result.exception, SystemExit), result.exception
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("guardsim: error: ")
    assert str(path) in lines[0]
    return lines[0]


def guardsim_command() -> list[str]:
    """The installed console script next to the interpreter, else its entry point through ``python -c``."""
    script = Path(sys.executable).with_name("guardsim")
    if script.exists():
        return [str(script)]
    return [sys.executable, "-c", "from guardsim.cli import run; run()"]


# guardsim bench: the shipped Square, a run in-process, its results table.

SQUARE = REPO / "levels" / "square.json"


def bench(*args: str | Path) -> Result:
    """Invoke ``guardsim bench ARGS`` in-process, keeping stdout and stderr apart."""
    return CliRunner().invoke(main, ["bench", *(str(arg) for arg in args)])


def rows(folder: Path) -> list[dict[str, str]]:
    """The rows of ``folder/results.csv`` as dictionaries."""
    with (folder / "results.csv").open(encoding="utf-8", newline="") as stream:
        return list(csv.DictReader(stream))


def without_seconds(table: list[dict[str, str]]) -> list[dict[str, str]]:
    """Rows minus the wall-time columns (seconds, plan_us_per_step), the columns that are not deterministic."""
    return [{name: value for name, value in row.items() if name not in TIMED_COLUMNS} for row in table]


# Small levels several test files share.

#: Two 3 x 3 rooms joined by a corridor one cell wide (patrols, sneaks, posts).
TWO_ROOMS: dict[str, Any] = {
    "name": "corridor",
    "outer": [[0, 0], [3, 0], [3, 1], [8, 1], [8, 0], [11, 0], [11, 3], [8, 3], [8, 2], [3, 2], [3, 3], [0, 3]],
    "guard": {"start": [0.5, 0.5], "heading": "right", "radius": 0.3},
}

#: The corridor of TWO_ROOMS with an alcove below its middle cell ([5, 2]): a guard posted there facing the
#: alcove's wall (ALCOVE_POST) sees its own cell only, and hears steps in the corridor (hearing tests).
ALCOVE: dict[str, Any] = {
    "name": "alcove",
    "outer": [
        [0, 0], [3, 0], [3, 1], [8, 1], [8, 0], [11, 0], [11, 3], [8, 3], [8, 2], [6, 2], [6, 3], [5, 3], [5, 2],
        [3, 2], [3, 3], [0, 3],
    ],
    "guard": {"start": [0.5, 0.5], "heading": "right", "radius": 0.3},
}  # fmt: skip
#: patrol.json of a guard posted in the alcove, facing down into its wall.
ALCOVE_POST: dict[str, Any] = {"shape": [3, 11], "guards": [{"loop": [[5, 2]], "headings": [1]}]}

#: A 1 x N corridor: a guard with view range 1 sees its own cell and the next one ahead.
STRIP_CELLS = 7
STRIP: dict[str, Any] = {
    "name": "corridor",
    "outer": [[0, 0], [STRIP_CELLS, 0], [STRIP_CELLS, 1], [0, 1]],
    "guard": {"view_range": 1.0},
}

#: Tiny levels with short sight, so that seeing everything takes several steps and turns.
SHORT_SIGHTED: dict[str, dict[str, Any]] = {
    "corridor": STRIP,
    "room-3x5": {"name": "room 3 x 5", "outer": [[0, 0], [5, 0], [5, 3], [0, 3]], "guard": {"view_range": 1.5}},
    "l-room": {**L_ROOM, "guard": {"view_range": 1.5}},
    "pillar": {**SQUARE_WITH_HOLE, "guard": {"view_range": 1.5}},
    "pillar-range-2": {**SQUARE_WITH_HOLE, "guard": {"view_range": 2.0}},
    "empty-square": {**EMPTY_SQUARE, "guard": {"view_range": 1.0}},
}
short_sighted = pytest.mark.parametrize("name", list(SHORT_SIGHTED), ids=list(SHORT_SIGHTED))

#: A 24 x 24 room with a 4 x 4 pillar and a 90-degree cone of range 4 (tours and their polish).
OPEN_ROOM = {
    "name": "open room",
    "outer": [[0, 0], [24, 0], [24, 24], [0, 24]],
    "holes": [[[10, 10], [14, 10], [14, 14], [10, 14]]],
    "guard": {"start": [1.5, 1.5], "heading": "right", "view_range": 4.0, "fov_degrees": 90.0},
}


def goal_masks(scene: Scene, start: tuple[int, int], vision: VisionFunction) -> tuple[Callable[[int], int], int]:
    """For brute-force searches: what a state sees of the cells reachable from ``start``, as a bitmask
    (cached), and the mask of all of them."""
    grid = scene.grid
    goal = np.flatnonzero(grid.component(*start).ravel()).tolist()
    bit = {cell: 1 << number for number, cell in enumerate(goal)}
    masks: dict[int, int] = {}

    def mask(state: int) -> int:
        if state not in masks:
            col, row = grid.unflat(state // 4)
            masks[state] = sum(bit.get(int(cell), 0) for cell in vision(col, row, state % 4))
        return masks[state]

    return mask, (1 << len(goal)) - 1


def optimum_steps(scene: Scene, start: tuple[int, int], heading: int, vision: VisionFunction) -> int:
    """The fewest steps after which a guard from ``(start, heading)`` has seen every reachable cell.

    Breadth-first over (state, seen goal cells as a bitmask): the first layer holding a full mask.
    """
    grid = scene.grid
    mask, full = goal_masks(scene, start, vision)
    neighbours = grid.neighbours.tolist()
    first = grid.flat(*start) * 4 + heading
    layer = {(first, mask(first))}
    visited = set(layer)
    steps = 0
    while not any(seen == full for _, seen in layer):
        following = set()
        for state, seen in layer:
            for direction, cell in enumerate(neighbours[state // 4]):
                if cell >= 0:
                    pair = (cell * 4 + direction, seen | mask(cell * 4 + direction))
                    if pair not in visited:
                        visited.add(pair)
                        following.add(pair)
        layer = following
        steps += 1
    return steps


def starts(scene: Scene, most: int = 8) -> list[tuple[int, int]]:
    """Up to ``most`` traversable cells spread evenly over the level, in row order."""
    cells = np.flatnonzero(scene.grid.traversable.ravel())
    picked = cells[np.linspace(0, cells.size - 1, min(most, cells.size)).round().astype(int)]
    return [scene.grid.unflat(int(cell)) for cell in np.unique(picked)]


# Patrols made by hand for the sneak and detection tests.


def random_loop(scene: Scene, rng: np.random.Generator, length: int) -> np.ndarray:
    """A random walk out and the same way back: a legal closed lap of ``2 * length`` ticks."""
    grid = scene.grid
    goal = np.flatnonzero(grid.largest_component())
    cells = [int(goal[rng.integers(goal.size)])]
    moves: list[int] = []
    for _ in range(length):
        options = [d for d in range(4) if grid.neighbours[cells[-1], d] >= 0] + [-1]
        move = int(options[rng.integers(len(options))])
        moves.append(move)
        cells.append(cells[-1] if move < 0 else int(grid.neighbours[cells[-1], move]))
    back = [(-1 if move < 0 else (move + 2) % 4) for move in reversed(moves)]
    path_moves = moves + back
    # The heading at the start is the one the guard has after the last move back (or any, if it stood).
    heading = next((move for move in reversed(path_moves) if move >= 0), 0)
    states, cell = [], cells[0]
    for move in path_moves:
        states.append(state_of(cell, heading))
        if move >= 0:
            cell, heading = int(grid.neighbours[cell, move]), move
    assert state_of(cell, heading) == states[0]
    return np.asarray(states, dtype=np.int64)


def corridor_post(scene: Scene, col: int, heading: int) -> Patrol:
    """A post at ``(col, 1)`` facing ``heading``: one guard standing still for ever."""
    return Patrol(np.array([[state_of(scene.grid.flat(col, 1), heading)]]), 1, "post")


def fast_equals_reference(scene: Scene, planner: Any = "ripplefront", **episode: Any) -> Trace:
    """The episode run on the fast path (compiled tick, vision cache), asserted byte-identical to the same
    episode on the reference loop and vision; the fast trace (the one fast-path check every test uses)."""
    from guardsim.motion import run_episode

    fresh = (lambda: planner) if isinstance(planner, str) else (lambda: type(planner)())
    fast = run_episode(scene, fresh(), **episode)
    reference = run_episode(scene, fresh(), reference=True, **episode)
    assert fast.to_json() == reference.to_json()
    return fast
