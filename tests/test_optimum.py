"""The exact search: equal to brute force on tiny levels (cone and Bresenham), a real covering walk of
that length, an honest partial answer when stopped, and the command line.

Brute force is the breadth-first search over (state, seen cells as a bitmask) of ``tests/test_bounds.py``.
"""

from __future__ import annotations

import json
import re
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

import guardsim.cli.optimum as cli_optimum
from guardsim import load_level
from guardsim.bounds import lower_bounds
from guardsim.cli import main
from guardsim.kernels.frontier import drop_shadowed, frontier, frontier_work
from guardsim.optimum import OptimumResult, SearchProgress, solve
from guardsim.search.graph import build_search_graph, search_positions
from guardsim.search.residual import residual_goal
from guardsim.simulation import Scene
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import ViewTable, view_table
from tests.common import (
    EMPTY_SQUARE,
    REPO,
    SHORT_SIGHTED,
    STRIP,
    guardsim_command,
    optimum_steps,
    scene_from,
    short_sighted,
    starts,
    write_level,
)


def assert_covering_walk(
    scene: Scene, result: OptimumResult, start: tuple[int, int], heading: int, vision: VisionFunction
) -> None:
    """The walk starts where asked, moves to a connected neighbour each step, and sees every goal cell."""
    grid = scene.grid
    table = view_table(grid, vision)
    assert result.path[0] == (*start, heading)
    assert len(result.path) == result.steps + 1
    seen = np.zeros(grid.size, dtype=bool)
    previous = None
    for col, row, facing in result.path:
        cell = grid.flat(col, row)
        if previous is not None:
            assert grid.neighbours[previous, facing] == cell
        seen[table.sees(cell * 4 + facing)] = True
        previous = cell
    assert seen[grid.component(*start).ravel()].all()


@short_sighted
def test_optimum_equals_brute_force_with_the_cone(name: str) -> None:
    """The paper's cone (heading in the state): the proved optimum is the breadth-first optimum."""
    scene = scene_from(SHORT_SIGHTED[name])
    vision = scene.vision()
    for start in starts(scene, most=4):
        for heading in range(4):
            result = solve(scene, start, heading, vision)
            assert result.proved and result.stopped_by == "proved"
            assert result.headings_matter
            assert result.steps == result.lower_bound == optimum_steps(scene, start, heading, vision), (start, heading)
            assert result.root_bound <= result.steps
            assert_covering_walk(scene, result, start, heading, vision)


@short_sighted
def test_weighted_search_is_within_its_weight_of_the_brute_force_optimum(name: str) -> None:
    """``weight`` W: a covering walk of at most W times the breadth-first optimum, its bound at most the
    optimum, and W = 1 the optimum itself."""
    scene = scene_from(SHORT_SIGHTED[name])
    vision = scene.vision()
    for start in starts(scene, most=3):
        best = optimum_steps(scene, start, 1, vision)
        for weight in (1.0, 1.25, 2.0):
            result = solve(scene, start, 1, vision, weight=weight)
            assert result.proved and result.weight == weight
            assert best <= result.steps <= weight * best, (start, weight, result.steps, best)
            assert result.lower_bound <= best
            assert_covering_walk(scene, result, start, 1, vision)
            if weight == 1.0:
                assert result.steps == best


BRESENHAM_LEVELS: dict[str, tuple[dict[str, Any], dict[str, Any]]] = {
    "l-room-cone": (SHORT_SIGHTED["l-room"], {}),
    "pillar-cone": (SHORT_SIGHTED["pillar"], {}),
    "pillar-360-range-2": (SHORT_SIGHTED["pillar"], {"view_range": 2.0, "fov_degrees": 360}),
    "l-room-360-range-1": (SHORT_SIGHTED["l-room"], {"view_range": 1.0, "fov_degrees": 360}),
}


@pytest.mark.parametrize("name", list(BRESENHAM_LEVELS), ids=list(BRESENHAM_LEVELS))
def test_optimum_equals_brute_force_with_bresenham(name: str) -> None:
    """The Bresenham rule, with a cone and with a 360-degree view (where positions are cells)."""
    data, guard = BRESENHAM_LEVELS[name]
    level = scene_from(data, guard={**data.get("guard", {}), **guard}).level
    scene = Scene.from_level(level, line_of_sight="bresenham")
    vision = scene.vision()
    for start in starts(scene, most=4):
        for heading in (0, 3):
            result = solve(scene, start, heading, vision)
            assert result.proved
            assert result.headings_matter == (guard.get("fov_degrees") != 360)
            assert result.steps == optimum_steps(scene, start, heading, vision), (start, heading)
            assert_covering_walk(scene, result, start, heading, vision)


@pytest.mark.parametrize("name", [*SHORT_SIGHTED, "pillar-360"], ids=[*SHORT_SIGHTED, "pillar-360"])
def test_search_positions_counts_the_graph_without_its_views(name: str) -> None:
    """``bounds`` asks how big the search would be before running it: the count, without the views (a
    bitset of the goal per position, 8 GB on duskwood), is the graph's own, whether headings matter
    (short-sighted) or not (360-degree sight)."""
    scene, table = _frontier_level(name)
    for start in starts(scene, most=4):
        for heading in range(4):
            graph = build_search_graph(scene.grid, table, start, heading)
            assert search_positions(scene.grid, table, start, heading) == graph.positions


@pytest.mark.parametrize("name", [*SHORT_SIGHTED, "pillar-360"], ids=[*SHORT_SIGHTED, "pillar-360"])
def test_frontier_moves_cost_their_shortest_distance(name: str) -> None:
    """Each macro move is exactly the positions an avoiding walk reaches first-seeing something, costed
    at the plain breadth-first distance: the walk rebuilt along shortest paths then has the steps the
    search counted (once a detour's length, which raised "the walk has 272 steps, the search counted
    276" on arena at range 8)."""
    scene, table = _frontier_level(name)
    generator = np.random.default_rng(27)
    detours = 0
    for start in starts(scene, most=4):
        graph = build_search_graph(scene.grid, table, start, 1)
        work = frontier_work(graph.positions)
        for _ in range(60):
            bits = [generator.integers(0, 2**63, size=graph.full.size, dtype=np.uint64) for _ in range(3)]
            seen = graph.full & (bits[0] | bits[1] | bits[2])  # mostly seen: few, far frontier positions
            fresh = [bool((graph.views[p] & ~seen).any()) for p in range(graph.positions)]
            origin = int(generator.integers(graph.positions))
            plain = _distances(graph.successors, origin, lambda _: True)
            avoiding = _distances(graph.successors, origin, lambda p, fresh=fresh: not fresh[p])
            count = frontier(graph.successors, graph.views, origin, seen, *work)
            found, steps = work[2][:count].tolist(), work[3][:count].tolist()
            expected = {p for p in avoiding if fresh[p] and p != origin}
            assert set(found) == expected and len(found) == count
            assert steps == [plain[p] for p in found]
            assert (work[0] == -1).all()
            detours += sum(avoiding[p] > plain[p] for p in found)
    assert detours > 0 or name == "corridor"  # the case that once disagreed occurs


def _frontier_level(name: str) -> tuple[Scene, ViewTable]:
    """A short-sighted tiny level (``pillar-360``: the pillar seen all round at range 2) and its view table."""
    data = SHORT_SIGHTED["pillar"] if name == "pillar-360" else SHORT_SIGHTED[name]
    guard = {"view_range": 2.0, "fov_degrees": 360} if name == "pillar-360" else {}
    scene = scene_from(data, guard={**data.get("guard", {}), **guard})
    return scene, view_table(scene.grid, scene.vision())


@pytest.mark.parametrize("name", [*SHORT_SIGHTED, "pillar-360"], ids=[*SHORT_SIGHTED, "pillar-360"])
def test_a_move_is_dropped_exactly_when_a_shortest_path_passes_another_move(name: str) -> None:
    """``drop_shadowed`` keeps, in order, the moves no shortest path reaches through another move's
    position (the search's pruning, ``docs/optimum.md``), and leaves its work arrays clean."""
    scene, table = _frontier_level(name)
    generator = np.random.default_rng(28)
    dropped = 0
    for start in starts(scene, most=4):
        graph = build_search_graph(scene.grid, table, start, 1)
        distance, queue, found, found_steps = frontier_work(graph.positions)
        mark = np.zeros(graph.positions, dtype=np.int8)
        between = {p: _distances(graph.successors, p, lambda _: True) for p in range(graph.positions)}
        for _ in range(40):
            bits = [generator.integers(0, 2**63, size=graph.full.size, dtype=np.uint64) for _ in range(2)]
            seen = graph.full & (bits[0] | bits[1])
            origin = int(generator.integers(graph.positions))
            count = frontier(graph.successors, graph.views, origin, seen, distance, queue, found, found_steps)
            moves = found[:count].tolist()
            steps = dict(zip(moves, found_steps[:count].tolist(), strict=True))
            expected = [
                b
                for b in moves
                if not any(a != b and b in between[a] and steps[a] + between[a][b] == steps[b] for a in moves)
            ]
            kept = drop_shadowed(graph.successors, origin, found, found_steps, count, distance, queue, mark)
            assert found[:kept].tolist() == expected
            assert found_steps[:kept].tolist() == [steps[b] for b in expected]
            assert (distance == -1).all() and (mark == 0).all()
            dropped += count - kept
    assert dropped > 0 or name == "corridor"


def _distances(successors: np.ndarray, origin: int, passable: Callable[[int], bool]) -> dict[int, int]:
    """Breadth-first distances from ``origin``, expanding only ``passable`` positions (and the origin)."""
    distance, layer = {origin: 0}, [origin]
    while layer:
        following = []
        for here in layer:
            if here != origin and not passable(here):
                continue
            for there in successors[here].tolist():
                if there >= 0 and there not in distance:
                    distance[there] = distance[here] + 1
                    following.append(there)
        layer = following
    return distance


def _seen_cells(views: np.ndarray, cells: np.ndarray, position: int) -> set[int]:
    bits = np.flatnonzero(np.unpackbits(views[position].view(np.uint8), bitorder="little"))
    return {int(cells[bit]) for bit in bits if bit < cells.size}


@pytest.mark.parametrize("name", [*SHORT_SIGHTED, "pillar-360"], ids=[*SHORT_SIGHTED, "pillar-360"])
def test_a_walk_seeing_the_residual_goal_sees_the_whole_goal(name: str) -> None:
    """On random walks from spread starts, every prefix that has seen each kept cell has seen every goal
    cell; and the residual goal is smaller wherever a cell is seen on the way to another."""
    data = SHORT_SIGHTED["pillar"] if name == "pillar-360" else SHORT_SIGHTED[name]
    guard = {"view_range": 2.0, "fov_degrees": 360} if name == "pillar-360" else {}
    scene = scene_from(data, guard={**data.get("guard", {}), **guard})
    table = view_table(scene.grid, scene.vision())
    generator = np.random.default_rng(15)
    reduced_somewhere = False
    for start in starts(scene, most=4):
        graph = build_search_graph(scene.grid, table, start, 1)
        residual = residual_goal(graph)
        goal, kept = set(graph.goal_cells.tolist()), set(residual.goal_cells.tolist())
        assert kept <= goal
        reduced_somewhere |= len(kept) < len(goal)
        for _ in range(200):
            here = graph.start
            seen = _seen_cells(graph.views, graph.goal_cells, here)
            for _ in range(4 * len(goal)):
                if kept <= seen:
                    assert seen == goal, (start, sorted(goal - seen))
                    break
                moves = [there for there in graph.successors[here].tolist() if there >= 0]
                here = moves[int(generator.integers(len(moves)))]
                seen |= _seen_cells(graph.views, graph.goal_cells, here)
    assert reduced_somewhere


@short_sighted
def test_bounds_never_exceed_the_proved_optimum(name: str) -> None:
    """The bounds of `guardsim bounds` stay at or below the optimum the search proves."""
    scene = scene_from(SHORT_SIGHTED[name])
    for start in starts(scene, most=3):
        assert lower_bounds(scene, start, 1).best <= solve(scene, start, 1).steps


def test_seen_from_the_start_needs_no_step() -> None:
    scene = scene_from(EMPTY_SQUARE, guard={"view_range": 10.0, "fov_degrees": 360})
    result = solve(scene, (0, 0), 0)
    assert (result.steps, result.proved, result.path) == (0, True, ((0, 0, 0),))


def test_a_stopped_search_is_honest() -> None:
    """One expansion cannot prove the L room: the answer says so, with a valid walk and bound."""
    scene = scene_from(SHORT_SIGHTED["l-room"])
    vision = scene.vision()
    optimum = optimum_steps(scene, (0, 0), 0, vision)
    result = solve(scene, (0, 0), 0, max_expansions=1)
    assert not result.proved and result.stopped_by == "expansions"
    assert result.lower_bound <= optimum <= result.steps
    assert result.lower_bound < result.steps
    assert_covering_walk(scene, result, (0, 0), 0, vision)
    again = solve(scene, (0, 0), 0, max_expansions=1)
    assert again[:8] == result[:8]


def test_a_stopped_search_whose_walk_meets_its_bound_is_proved() -> None:
    """The 3 x 5 room after one expansion: a 4-step walk and a proved bound of 4 is the optimum (it was
    reported 'best found 4 steps (optimum >= 4); proved: false')."""
    scene = scene_from(SHORT_SIGHTED["room-3x5"])
    result = solve(scene, (0, 0), 0, max_expansions=1)
    assert (result.steps, result.lower_bound, result.proved, result.stopped_by) == (4, 4, True, "proved")
    assert result.steps == optimum_steps(scene, (0, 0), 0, scene.vision())


def test_cli_prints_and_writes_the_optimum(tmp_path: Path) -> None:
    """`guardsim optimum` on the corridor from its middle: 6 steps, proved, and the JSON walk."""
    path = write_level(tmp_path, STRIP)
    out = tmp_path / "optimum.json"
    result = CliRunner().invoke(
        main, ["optimum", str(path), "--start", "3.5,0.5", "--heading", "right", "--out", str(out)]
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("corridor: from 3.5,0.5 (cell [3, 0]) facing right: optimum 6 steps; proved: true;")
    data = json.loads(out.read_text())
    assert (data["steps"], data["proved"], data["lower_bound"]) == (6, True, 6)
    assert data["path"][0] == [3, 0, 0] and len(data["path"]) == 7


def test_cli_bad_start_is_one_line(tmp_path: Path) -> None:
    path = write_level(tmp_path, STRIP)
    result = CliRunner().invoke(main, ["optimum", str(path), "--start", "9,9"])
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [f"guardsim: error: {path}: start (9, 9) lies outside the level"]


def test_console_script_optimum(tmp_path: Path) -> None:
    """The real process, stopped by --max-expansions: proved false, and a bound."""
    path = write_level(tmp_path, SHORT_SIGHTED["l-room"])
    completed = subprocess.run(
        [
            *guardsim_command(),
            "optimum",
            str(path),
            "--start",
            "0.5,0.5",
            "--heading",
            "right",
            "--max-expansions",
            "1",
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert completed.returncode == 0, completed.stderr
    assert "proved: false" in completed.stdout
    assert re.search(r": best found \d+ steps \(stopped by expansions; optimum >= \d+\); ", completed.stdout)


def test_progress_reports_the_search_as_it_goes() -> None:
    """The progress callback sees the expansions grow and the optimum bracketed, ending where the result is."""
    scene = scene_from(SHORT_SIGHTED["pillar"])
    seen: list[SearchProgress] = []
    result = solve(scene, (0, 0), 0, progress=seen.append)
    assert seen, "no progress call"
    assert [where.expansions for where in seen] == sorted(where.expansions for where in seen)
    assert seen[-1].expansions == result.expansions and seen[-1].nodes == result.nodes
    assert all(where.lower_bound <= result.steps <= where.best for where in seen)
    assert seen[-1].best == result.steps


def test_cli_optimum_prints_progress_on_stderr(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A long search prints where it is on stderr (here every chunk, the interval set to 0)."""
    monkeypatch.setattr(cli_optimum, "PROGRESS_SECONDS", 0.0)
    path = write_level(tmp_path, SHORT_SIGHTED["pillar"])
    result = CliRunner().invoke(main, ["optimum", str(path), "--start", "0.5,0.5", "--heading", "right"])
    assert result.exit_code == 0, result.output
    line = result.stderr.splitlines()[-1]
    match = re.fullmatch(
        r"guardsim: optimum: (\d+) expansions, \d+ nodes, optimum between (\d+) and (\d+) steps \(\d+ s\)", line
    )
    assert match, line
    steps = int(re.search(r"optimum (\d+) steps", result.stdout).group(1))  # type: ignore[union-attr]
    assert int(match.group(2)) == int(match.group(3)) == steps


def _bounds_line(path: Path, *options: str) -> str:
    result = CliRunner().invoke(main, ["bounds", str(path), *options])
    assert result.exit_code == 0, result.output
    return result.stdout


@pytest.mark.parametrize("name", ["l-room", "pillar"])
def test_bounds_search_bound_is_the_optimum_when_proved(tmp_path: Path, name: str) -> None:
    """`guardsim bounds` on a small level runs the exact search: its bound is the brute-force optimum,
    and the best bound with it; with one expansion it stops and its bound is at most the optimum."""
    scene = scene_from(SHORT_SIGHTED[name])
    optimum = optimum_steps(scene, (0, 0), 0, scene.vision())
    path = write_level(tmp_path, SHORT_SIGHTED[name])
    line = _bounds_line(path, "--start", "0.5,0.5", "--heading", "right")
    assert f"best bound {optimum} steps; search bound {optimum} (the optimum, proved in " in line
    line = _bounds_line(path, "--start", "0.5,0.5", "--heading", "right", "--search-expansions", "1")
    match = re.search(
        r"best bound (\d+) steps; search bound (\d+) \(stopped by expansions after 1 expansions; --search-expansions N",
        line,
    )
    assert match and int(match.group(2)) <= int(match.group(1)) <= optimum, line
    line = _bounds_line(path, "--start", "0.5,0.5", "--heading", "right", "--search-expansions", "0")
    assert "; search bound not run (--search-expansions 0);" in line


def test_bounds_search_bound_skipped_on_a_large_level() -> None:
    """On a shipped 60 x 60 level the search is not run by default, and the line says why."""
    line = _bounds_line(Path("levels/mgs_docks.json"), "--episode", "0")
    assert re.search(r"; search bound not run \(\d+ positions, over 6000: see --search-expansions\);", line), line


def test_the_proved_bound_never_falls_as_the_search_goes(monkeypatch: pytest.MonkeyPatch) -> None:
    # The heap's least f falls back now and then as lazy estimates come in (on Passages 14 times in
    # 400 expansions); every value read is a bound, so the one reported is the largest read so far.
    import guardsim.optimum as optimum

    monkeypatch.setattr(optimum, "_CHUNK", 1)
    # The weighted first walks change nothing here and were 17 of the test's 20 s.
    monkeypatch.setattr(optimum, "_weighted_walks", lambda graph, heuristic, walk, steps, *rest: (walk, steps))
    level = load_level(REPO / "levels" / "passages.json")
    scene = Scene.from_level(level)
    seen: list[SearchProgress] = []
    assert level.guard is not None and level.guard.start is not None
    start = scene.grid.cell_of(level.guard.start)
    assert start is not None
    result = solve(scene, start, 0, max_expansions=400, progress=seen.append)
    bounds = [where.lower_bound for where in seen]
    assert len(bounds) == 400 and bounds[-1] > bounds[0]
    assert bounds == sorted(bounds)
    assert result.lower_bound >= bounds[-1]
