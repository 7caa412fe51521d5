"""The kernel library: each primitive against a plain or brute-force rule, the walkers that share the
greedy step, and the cache that never runs stale compiled code."""

from __future__ import annotations

import itertools
import json
import os
import shutil
import subprocess
import sys
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from guardsim import ArgumentError, GuardsimError, Scene, Simulation
from guardsim.kernels.compiler import compiled_sources, source_digest
from guardsim.kernels.distances import FAR, distances_from, fill_states, spread_states
from guardsim.kernels.heap import heap_pop, heap_push
from guardsim.kernels.states import cell_of_state, heading_of_state, state_of
from guardsim.kernels.steps import greedy_step
from guardsim.kernels.subsets import subset_path_bound
from guardsim.planners.route_walk import descent_states
from guardsim.vision.table import view_table
from tests.common import REPO, level_from, tiny_levels

CORRIDOR = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]], dtype=np.int64)


def _grid_neighbours(rows: int, cols: int, walls: set[int]) -> np.ndarray:
    neighbours = np.full((rows * cols, 4), -1, dtype=np.int64)
    for cell in range(rows * cols):
        if cell in walls:
            continue
        row, col = divmod(cell, cols)
        for direction, (dc, dr) in enumerate(((1, 0), (0, 1), (-1, 0), (0, -1))):
            r, c = row + dr, col + dc
            if 0 <= r < rows and 0 <= c < cols and r * cols + c not in walls:
                neighbours[cell, direction] = r * cols + c
    return neighbours


def _plain_state_distances(neighbours: np.ndarray, start: int, backward: bool) -> list[int]:
    """Breadth-first over states with a deque: forward steps, or the reversed graph."""
    states = neighbours.shape[0] * 4
    edges: list[list[int]] = [[] for _ in range(states)]
    for state in range(states):
        for direction in range(4):
            there = int(neighbours[state // 4, direction])
            if there >= 0:
                a, b = state, there * 4 + direction
                edges[b if backward else a].append(a if backward else b)
    distance = [-1] * states
    distance[start] = 0
    queue = deque([start])
    while queue:
        state = queue.popleft()
        for other in edges[state]:
            if distance[other] < 0:
                distance[other] = distance[state] + 1
                queue.append(other)
    return distance


def test_state_numbering_round_trips_on_arrays() -> None:
    cells, headings = np.arange(10), np.arange(10) % 4
    states = state_of(cells, headings)
    assert np.array_equal(cell_of_state(states), cells)
    assert np.array_equal(heading_of_state(states), headings)


@pytest.mark.parametrize("backward", [False, True], ids=["forward", "backward"])
def test_state_fills_match_a_plain_search(backward: bool) -> None:
    neighbours = _grid_neighbours(4, 5, walls={6, 7, 13})
    for start in (0, 9 * 4 + 2, 19 * 4 + 3):
        distance = np.full(neighbours.shape[0] * 4, -1, dtype=np.int32)
        distance[start] = 0
        queue = np.empty(distance.shape[0], dtype=np.int64)
        queue[0] = start
        label = np.full(distance.shape[0], -1, dtype=np.int32)
        label[start] = 7
        spread_states(neighbours, queue, 1, -1, distance, backward, label)
        assert distance.tolist() == _plain_state_distances(neighbours, start, backward)
        assert set(label[distance >= 0].tolist()) == {7}
        if not backward:
            filled = np.empty_like(distance)
            fill_states(neighbours, start, -1, filled)
            assert np.array_equal(filled, distance)


def test_cell_fill_marks_the_unreached_far() -> None:
    neighbours = _grid_neighbours(3, 3, walls={1, 4, 7})
    distance = distances_from(neighbours, np.array([0]))
    assert distance.reshape(3, 3).tolist() == [[0, FAR, FAR], [1, FAR, FAR], [2, FAR, FAR]]


@pytest.mark.parametrize(
    ("heading", "field", "expected"),
    [
        (2, [5, 1, 1, 1, 1], 2),  # every neighbour as near: keep the heading
        (3, [5, 2, 1, 1, 2], 1),  # down and left tie: down comes first
        (0, [5, 3, 3, 3, 0], 3),  # up is nearest
    ],
)
def test_greedy_step_tie_rule(heading: int, field: list[int], expected: int) -> None:
    # Cell 0 in the middle, its neighbours right, down, left, up are cells 1..4.
    assert greedy_step(np.array(field), np.array([1, 2, 3, 4]), heading) == expected
    assert greedy_step(np.array(field), np.array([-1, -1, -1, -1]), heading) == -1


def test_heap_pops_in_key_order() -> None:
    rng = np.random.default_rng(3)
    keys_in = rng.integers(0, 20, size=200)
    keys = np.empty(200, dtype=np.int64)
    items = np.empty(200, dtype=np.int64)
    size = 0
    for index, key in enumerate(keys_in):
        size = heap_push(keys, items, size, int(key), index)
    popped = []
    while size:
        key, item, size = heap_pop(keys, items, size)
        assert keys_in[item] == key
        popped.append(key)
    assert popped == sorted(keys_in.tolist())


def test_subset_path_bound_matches_brute_force() -> None:
    rng = np.random.default_rng(11)
    for size in range(1, 6):
        between = rng.integers(1, 9, size=(size, size))
        between = np.minimum(between, between.T)
        start = rng.integers(0, 9, size=size)
        members = np.arange(size)
        brute = 0
        for count in range(1, size + 1):
            for subset in itertools.combinations(range(size), count):
                shortest = min(
                    start[order[0]] + sum(between[a, b] for a, b in itertools.pairwise(order))
                    for order in itertools.permutations(subset)
                )
                brute = max(brute, int(shortest))
        order_work = np.empty((1 << size) * size, dtype=np.int64)
        assert subset_path_bound(start, between, members, size, order_work, 1 << 30) == brute


@tiny_levels
def test_descent_walks_as_ripplefront_exact(level_data: dict) -> None:
    scene = Scene.from_level(level_from(level_data))
    simulation = Simulation(scene, "ripplefront-exact")
    simulation.reset(seed=0)
    seen_at_start = simulation.seen.ravel().copy()
    while not simulation.done:
        simulation.step()
    trace = simulation.trace()
    grid = scene.grid
    table = view_table(grid, scene.vision())
    (col, row), heading = trace.path[0], trace.headings[0]
    states = descent_states(
        table, grid.neighbours, trace.goal.ravel(), seen_at_start, grid.flat(col, row), heading, limit=10_000
    )
    walked = [state_of(grid.flat(c, r), h) for (c, r), h in zip(trace.path[1:], trace.headings[1:])]
    assert states.tolist() == walked


def test_compiled_sources_cover_every_compiled_file() -> None:
    sources = {path.relative_to(REPO / "guardsim").as_posix() for path in compiled_sources()}
    assert {"kernels/distances.py", "kernels/states.py", "planners/viewpoint_cover.py", "search/astar.py"}
    assert "planners/polish.py" not in sources  # plain Python around the compiled walk <= sources
    assert "cli/play.py" not in sources


_CALL = (
    "import numpy as np; from guardsim.bounds.watchers import state_distances; "
    "n = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]], dtype=np.int64); "
    "print(state_distances(n, 0)[[4, 8, 12]].tolist())"
)


@pytest.mark.slow  # 7-12 s: the README command stays under 5 minutes; CI runs the slow tier
def test_an_edited_kernel_is_compiled_again(tmp_path: Path) -> None:
    # A caller in bounds/ carries a compiled copy of the fill it calls in kernels/: editing only the
    # kernel's file must still change what the caller computes, with no cache deleted by hand.
    copy = tmp_path / "src" / "guardsim"
    shutil.copytree(REPO / "guardsim", copy, ignore=shutil.ignore_patterns("__pycache__"))
    cache = tmp_path / "cache"
    env = dict(os.environ, PYTHONPATH=str(copy.parent), GUARDSIM_CACHE_DIR=str(cache), GUARDSIM_COMPILE_NOTICE="0")

    def run() -> str:
        done = subprocess.run(
            [sys.executable, "-c", _CALL], env=env, cwd=tmp_path, capture_output=True, text=True, check=True
        )
        return done.stdout.strip()

    before_digest = source_digest(copy)
    assert run() == "[1, 2, 3]"
    folders = list(cache.glob("kernels-*"))
    assert [folder.name for folder in folders] == [f"kernels-{before_digest}"]
    assert any(folders[0].rglob("*.nbi"))
    assert run() == "[1, 2, 3]"  # from the cache
    kernel = copy / "kernels" / "distances.py"
    text = kernel.read_text()
    assert text.count("step = distance[state] + 1") == 1
    kernel.write_text(text.replace("step = distance[state] + 1", "step = distance[state] + 2"))
    assert source_digest(copy) != before_digest
    assert run() == "[2, 4, 6]"


@pytest.mark.slow  # 7-12 s: the README command stays under 5 minutes; CI runs the slow tier
def test_compiling_is_said_once_on_one_line(tmp_path: Path) -> None:
    env = dict(os.environ, GUARDSIM_CACHE_DIR=str(tmp_path / "cache"), GUARDSIM_COMPILE_NOTICE="0.01")

    def stderr() -> list[str]:
        done = subprocess.run(
            [sys.executable, "-c", _CALL], env=env, cwd=REPO, capture_output=True, text=True, check=True
        )
        return done.stderr.splitlines()

    said = stderr()
    assert len(said) == 1 and said[0].startswith("guardsim: compiling kernels once for this version (kept in ")
    assert str(tmp_path / "cache" / "kernels-") in said[0]
    assert stderr() == []  # loaded from the cache: nothing compiled, nothing said
    env["GUARDSIM_COMPILE_NOTICE"] = "0"
    env["GUARDSIM_CACHE_DIR"] = str(tmp_path / "other")
    assert stderr() == []


_UNPLANNED = """
import json, sys
from numba.core import event
from guardsim.kernels.ahead import compile_ahead
depth, unplanned = [0], []
class Watch(event.Listener):
    def on_start(self, e):
        depth[0] += 1
    def on_end(self, e):
        depth[0] -= 1
        if depth[0] == 0:
            unplanned.append(f"{e.data['dispatcher'].py_func.__qualname__}{tuple(map(str, e.data['args']))}")
command = sys.argv[1]
compile_ahead(command)
event.register("numba:compile", Watch())
from guardsim.cli import main
try:
    main(sys.argv[2:])
except SystemExit as stop:
    print(json.dumps(unplanned))
    raise
print(json.dumps(unplanned))
"""


@pytest.mark.parametrize(
    "command",
    [
        "play:tour",
        *(
            pytest.param(name, marks=pytest.mark.slow)
            for name in (
                "patrol",
                "sneak",
                "alert",
                "bounds",
                "optimum",
                "bench",
                "optimum:team",
                "patrol:team",
                "check",
                "report",
                "fortify",
                "sneak:unheard",
            )
        ),
    ],
)
def test_compiling_ahead_covers_what_the_command_compiles(command: str, tmp_path: Path) -> None:
    # After compile_ahead(command), running the command compiles nothing more: the plan is current.
    # (When this fails, run `python benchmarks/compile_plan.py --commands COMMAND`.)
    square = str(REPO / "levels" / "square.json")
    room = tmp_path / "room.json"
    room.write_text('{"outer": [[0, 0], [12, 0], [12, 9], [0, 9]], "holes": [[[5, 4], [7, 4], [7, 5], [5, 5]]]}')
    patrol = tmp_path / "patrol"
    lines = {
        "play:tour": ["play", square, "--planner", "tour"],
        "patrol": ["patrol", square, "--out", str(patrol)],
        "sneak": ["sneak", square, "--patrol", str(patrol / "patrol.json"), "--from", "2.5,2.5", "--to", "57.5,57.5"],
        "alert": ["alert", square, "--patrol", str(patrol / "patrol.json"), "--from", "10.5,10.5", "--to", "50.5,50.5"],
        "bounds": ["bounds", square],
        "optimum": ["optimum", str(room), "--start", "0.5,0.5"],
        "bench": ["bench", square, "--episodes", "2", "--workers", "1", "--out", str(tmp_path / "bench")],
        "optimum:team": ["optimum", str(room), "--start", "0.5,0.5", "--start", "11.5,8.5", "--guards", "2"],
        "patrol:team": ["patrol", square, "--guards", "2", "--out", str(patrol)],
        "check": ["check", square, "--patrol", str(patrol / "patrol.json"), "--max-idleness", "1000",
                  "--no-unreachable", "--sneak", "2.5,2.5", "57.5,57.5", "--expect", "sneaks"],
        "report": ["report", square],
        "fortify": ["fortify", square, "--patrol", str(patrol / "patrol.json"), "--from", "2.5,2.5",
                    "--to", "57.5,57.5", "--cameras", "1", "--posts", "0"],
        "sneak:unheard": ["sneak", square, "--patrol", str(patrol / "patrol.json"), "--from", "2.5,2.5", "--to",
                          "57.5,57.5", "--unheard", "--walk-noise", "3", "--sneak-noise", "1"],
    }  # fmt: skip
    # A cache of its own, empty: in a shared one a kernel missing from the plan but compiled by another
    # test (or by `guardsim compile`) would load without compiling, and the test could not fail.
    env = dict(os.environ, GUARDSIM_COMPILE_NOTICE="0", GUARDSIM_CACHE_DIR=str(tmp_path / "cache"))
    if command in ("sneak", "alert", "check", "fortify", "sneak:unheard"):
        setup = dict(env, GUARDSIM_CACHE_DIR=str(tmp_path / "setup-cache"))
        subprocess.run([sys.executable, "-m", "guardsim.cli", *lines["patrol"]], env=setup, cwd=tmp_path,
                       check=True, capture_output=True)  # fmt: skip
    done = subprocess.run([sys.executable, "-c", _UNPLANNED, command, *lines[command]], env=env, cwd=tmp_path,
                          capture_output=True, text=True)  # fmt: skip
    assert done.returncode in ((0, 1) if command == "fortify" else (0,)), done.stderr  # fortify: 1, not sealed
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []


def test_both_processes_take_ready_entries_longest_chain_first() -> None:
    from guardsim.kernels.ahead import COMPILED, FREE, TAKEN, take, urgency

    # Entries 0 and 1 are callees of 2 (and 2 of 4); 3 stands alone, the longest single entry.
    entries = [
        ["m", name, [], seconds, -1] for name, seconds in (("a", 1.0), ("b", 0.5), ("c", 1.0), ("d", 2.5), ("e", 1.0))
    ]
    below = [[], [], [0, 1], [], [0, 1, 2]]
    chain = urgency(entries, below)
    assert chain == [3.0, 2.5, 2.0, 2.5, 1.0]
    state = [FREE] * 5
    # The callee under the longest chain first, then the lone entry (first in the plan on a tie).
    assert take(state, below, chain) == 0 and state == [TAKEN, FREE, FREE, FREE, FREE]
    assert take(state, below, chain) == 1
    assert take(state, below, chain) == 3
    # Only callers are left, and their callees are being compiled: they wait.
    assert take(state, below, chain) is None
    state[0] = COMPILED
    assert take(state, below, chain) is None  # 1 is still being compiled
    state[1] = COMPILED
    assert take(state, below, chain) == 2
    assert take(state, below, chain) is None  # 4 waits on 2
    state[2] = state[3] = COMPILED
    assert take(state, below, chain) == 4
    assert take(state, below, chain) == -1  # nothing free: done


def _guardsim(args: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "guardsim.cli", *args], env=env, cwd=cwd, capture_output=True,
                          text=True)  # fmt: skip


def test_guardsim_compile_is_the_install_step(tmp_path: Path) -> None:
    # After `guardsim compile play:tour`, the command's first run compiles nothing: no notice, even one
    # due after a millisecond of compiling.
    env = dict(os.environ, GUARDSIM_CACHE_DIR=str(tmp_path / "cache"), GUARDSIM_COMPILE_NOTICE="0.001")
    done = _guardsim(["compile", "play"], env, tmp_path)  # play's compiled planner: the tour
    assert done.returncode == 0, done.stderr
    folder = next((tmp_path / "cache").glob("kernels-*"))
    functions = len(json.loads((REPO / "guardsim" / "kernels" / "plan.json").read_text())["play:tour"])
    assert done.stdout.startswith(f"compiled the {functions} kernels of play in ")
    assert done.stdout.endswith(f" s (kept in {folder})\n")
    assert "compiling kernels once" not in done.stderr  # compiling is what was asked: no notice of it
    assert (folder / "ahead-play-tour").exists() and any(folder.rglob("*.nbc"))
    played = _guardsim(["play", str(REPO / "levels" / "square.json"), "--planner", "tour"], env, tmp_path)
    assert played.returncode == 0 and "compiling" not in played.stderr, played.stderr
    again = _guardsim(["compile", "play:tour"], env, tmp_path)
    assert again.stdout == f"the {functions} kernels of play:tour are compiled already (kept in {folder})\n"
    wrong = _guardsim(["compile", "play:tour", "tours", "render"], env, tmp_path)
    assert wrong.returncode == 2 and wrong.stdout == ""
    assert wrong.stderr.startswith(
        "guardsim: error: no compiled kernels for tours, render: the commands that compile are alert, bench, "
        "bounds, check, diff, fortify, optimum, patrol, play, report, sneak, watch (the others need none), the "
        "plans play:tour, patrol, "
    )
    assert wrong.stderr.count("\n") == 1


def test_each_command_compiles_its_own_plans_and_the_analysis_it_shares() -> None:
    from guardsim.kernels.ahead import compile_kernels, plans_of

    assert plans_of("play") == ("play:tour",) and plans_of("play:tour") == ("play:tour",)
    assert plans_of("patrol") == ("patrol", "patrol:team") and plans_of("patrol:team") == ("patrol:team",)
    assert plans_of("diff") == plans_of("watch") == ("report",)
    assert plans_of("check") == ("check", "report", "sneak:unheard")
    assert plans_of("sneak") == ("sneak", "sneak:unheard")
    assert plans_of("render") == () and plans_of("play:sweep") == ()
    with pytest.raises(ArgumentError, match="no compiled kernels for a, l, e:"):
        compile_kernels(["a", "l", "e"])
    with pytest.raises(ArgumentError, match="no compiled kernels for ale:"):  # one name, not its letters
        compile_kernels("ale")


def test_guardsim_compile_without_its_plans_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    from guardsim.kernels import ahead

    monkeypatch.setattr(ahead, "plan", dict)  # what plan() gives for a missing plan.json
    with pytest.raises(GuardsimError, match=r"plan\.json: no compile plans \(the file is missing or unreadable\)"):
        ahead.compile_kernels()


def test_guardsim_compile_says_when_it_cannot_write_the_cache(tmp_path: Path) -> None:
    # A folder under a file cannot be made, even by root: numba keeps the kernels where it can (its own
    # fallbacks), and the step says it could not keep them in the folder it names.
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    env = dict(os.environ, GUARDSIM_CACHE_DIR=str(blocker / "cache"))
    done = _guardsim(["compile", "alert"], env, tmp_path)
    assert done.returncode == 0, done.stderr
    functions = len(json.loads((REPO / "guardsim" / "kernels" / "plan.json").read_text())["alert"])
    assert done.stdout.startswith(f"compiled the {functions} kernels of alert in ")
    assert done.stdout.endswith(" s (see the warning)\n")
    warning = [line for line in done.stderr.splitlines() if "warning" in line]
    assert len(warning) == 1
    assert warning[0].startswith(f"guardsim: warning: could not write the cache folder {blocker / 'cache'}/kernels-")


@pytest.mark.slow  # about 30 s on two cores: every plan
def test_after_guardsim_compile_no_command_compiles(tmp_path: Path) -> None:
    env = dict(os.environ, GUARDSIM_CACHE_DIR=str(tmp_path / "cache"), GUARDSIM_COMPILE_NOTICE="0.001")
    done = _guardsim(["compile"], env, tmp_path)
    assert done.returncode == 0, done.stderr
    plans = json.loads((REPO / "guardsim" / "kernels" / "plan.json").read_text())
    union = {(m, f, json.dumps(a)) for entries in plans.values() for m, f, a, *_ in entries}
    assert done.stdout.startswith(f"compiled the {len(union)} kernels of every command in ")
    square, passages = str(REPO / "levels" / "square.json"), str(REPO / "levels" / "passages.json")
    patrol = tmp_path / "p"
    for line in (["patrol", square, "--guards", "2", "--out", str(patrol)], ["bounds", square],
                 ["diff", square, passages], ["sneak", square, "--patrol", str(patrol / "patrol.json"), "--from",
                  "2.5,2.5", "--to", "57.5,57.5", "--undetected"]):  # fmt: skip
        ran = _guardsim(line, env, tmp_path)
        assert ran.returncode == 0 and "compiling" not in ran.stderr, (line[0], ran.stderr)
