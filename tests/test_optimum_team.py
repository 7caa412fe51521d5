"""The team optimum (makespan): equal to a plain breadth-first search over the guards' joint states on
tiny levels (the cone and a 360-degree view), one guard equal to the one-guard optimum, walks that
really see every cell at the claimed tick, and the command line.

Brute force: each tick every guard steps to a connected 4-neighbour (facing the way it stepped) or waits
(keeping its heading); breadth-first over (the guards' states, the cells seen as a bitmask) until a
layer holds the full mask. Nothing of the search is used.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.optimum import solve
from guardsim.optimum.team import TeamOptimumResult, solve_team
from guardsim.simulation import Scene
from guardsim.vision.rules import VisionFunction
from tests.common import SHORT_SIGHTED, goal_masks, guardsim_command, scene_from, starts, write_level

#: Tiny levels with a 360-degree view (positions are cells).
ALL_ROUND = {
    name: {**SHORT_SIGHTED[name], "guard": {**SHORT_SIGHTED[name]["guard"], "fov_degrees": 360.0}}
    for name in ("corridor", "room-3x5", "l-room", "pillar")
}
CONE = {name: SHORT_SIGHTED[name] for name in ("corridor", "room-3x5", "l-room", "pillar")}


def team_steps(scene: Scene, team: list[tuple[tuple[int, int], int]], vision: VisionFunction) -> int:
    """The fewest ticks until guards from ``team`` have together seen every cell reachable from the first."""
    grid = scene.grid
    mask, full = goal_masks(scene, team[0][0], vision)
    neighbours = grid.neighbours.tolist()

    def moves(state: int) -> list[int]:
        return [state] + [cell * 4 + d for d, cell in enumerate(neighbours[state // 4]) if cell >= 0]

    first = tuple(grid.flat(*cell) * 4 + heading for cell, heading in team)
    seen = 0
    for state in first:
        seen |= mask(state)
    layer = {(first, seen)}
    visited = set(layer)
    ticks = 0
    while not any(seen == full for _, seen in layer):
        following = set()
        for guards, seen in layer:
            combos: list[tuple[int, ...]] = [()]
            for state in guards:
                combos = [(*combo, there) for combo in combos for there in moves(state)]
            for combo in combos:
                after = seen
                for state in combo:
                    after |= mask(state)
                pair = (combo, after)
                if pair not in visited:
                    visited.add(pair)
                    following.add(pair)
        layer = following
        ticks += 1
    return ticks


def assert_team_covers(
    scene: Scene, result: TeamOptimumResult, team: list[tuple[tuple[int, int], int]], vision: VisionFunction
) -> None:
    """Replayed together, tick by tick (a guard done early waits), the walks start where asked, step to a
    connected neighbour, and have seen every goal cell at tick ``result.steps``, not before all are done."""
    grid = scene.grid
    assert len(result.paths) == len(team)
    assert max(len(path) - 1 for path in result.paths) == result.steps
    seen = np.zeros(grid.size, dtype=bool)
    for path, (cell, heading) in zip(result.paths, team, strict=True):
        assert path[0] == (*cell, heading)
    for tick in range(result.steps + 1):
        for path in result.paths:
            col, row, facing = path[min(tick, len(path) - 1)]
            if 0 < tick < len(path):
                before = grid.flat(*path[tick - 1][:2])
                assert grid.neighbours[before, facing] == grid.flat(col, row)
            seen[vision(col, row, facing)] = True
    assert seen[grid.component(*team[0][0]).ravel()].all()


def _pairs(scene: Scene) -> list[list[tuple[tuple[int, int], int]]]:
    spread = starts(scene, most=4)
    return [
        [(spread[0], 0), (spread[-1], 2)],
        [(spread[1], 1), (spread[1], 3)],
        [(spread[-1], 3), (spread[len(spread) // 2], 0)],
    ]


@pytest.mark.parametrize("name", list(CONE), ids=list(CONE))
def test_two_guards_equal_brute_force_with_the_cone(name: str) -> None:
    scene = scene_from(CONE[name])
    vision = scene.vision()
    for team in _pairs(scene):
        result = solve_team(scene, team, vision)
        assert result.proved and result.stopped_by == "proved" and result.headings_matter
        assert result.steps == result.lower_bound == team_steps(scene, team, vision), team
        assert result.root_bound <= result.steps
        assert_team_covers(scene, result, team, vision)


@pytest.mark.parametrize("name", list(ALL_ROUND), ids=list(ALL_ROUND))
def test_two_guards_equal_brute_force_all_round(name: str) -> None:
    scene = scene_from(ALL_ROUND[name])
    vision = scene.vision()
    for team in _pairs(scene):
        result = solve_team(scene, team, vision)
        assert result.proved and not result.headings_matter
        assert result.steps == team_steps(scene, team, vision), team
        assert_team_covers(scene, result, team, vision)


def test_three_guards_equal_brute_force() -> None:
    scene = scene_from(ALL_ROUND["l-room"])
    vision = scene.vision()
    spread = starts(scene, most=3)
    team = [(cell, 0) for cell in spread]
    result = solve_team(scene, team, vision)
    assert result.proved and result.steps == team_steps(scene, team, vision)
    assert_team_covers(scene, result, team, vision)


@pytest.mark.parametrize("name", list(CONE), ids=list(CONE))
def test_one_guard_is_the_one_guard_optimum(name: str) -> None:
    scene = scene_from(CONE[name])
    vision = scene.vision()
    for start in starts(scene, most=3):
        for heading in (0, 3):
            alone = solve(scene, start, heading, vision)
            result = solve_team(scene, [(start, heading)], vision)
            assert result.proved and result.steps == alone.steps
            assert_team_covers(scene, result, [(start, heading)], vision)


def test_a_stopped_search_is_honest() -> None:
    scene = scene_from(CONE["pillar"])
    vision = scene.vision()
    team = _pairs(scene)[0]
    optimum = team_steps(scene, team, vision)
    result = solve_team(scene, team, vision, max_expansions=1)
    assert result.lower_bound <= optimum <= result.steps
    assert result.proved == (result.stopped_by == "proved")
    assert_team_covers(scene, result, team, vision)


def test_a_start_the_first_cannot_reach_is_refused(tmp_path: Path) -> None:
    # A Moving AI map with a wall down the middle: two rooms.
    two_rooms = tmp_path / "two.map"
    two_rooms.write_text("type octile\nheight 3\nwidth 5\nmap\n..@..\n..@..\n..@..\n")
    result = CliRunner().invoke(
        main, ["optimum", str(two_rooms), "--guards", "2", "--start", "0.5,0.5", "--start", "4.5,0.5"]
    )
    assert result.exit_code == 2 and "Traceback" not in result.output
    # The import's note, then the one error line.
    assert result.stderr.splitlines()[-1] == (
        f"guardsim: error: {two_rooms}: the start cell [4, 0] cannot be reached from the first start [0, 0]"
    )


def test_the_command_prints_and_writes_the_team(tmp_path: Path) -> None:
    level = write_level(tmp_path, CONE["room-3x5"])
    out = tmp_path / "team.json"
    team = ["--guards", "2", "--start", "0.5,0.5", "--start", "4.5,2.5", "--heading", "right"]
    result = CliRunner().invoke(main, ["optimum", str(level), *team, "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert (
        "2 guards from 0.5,0.5 (cell [0, 0]) facing right, 4.5,2.5 (cell [4, 2]) facing right: optimum" in result.output
    )
    data = json.loads(out.read_text())
    assert data["guards"] == 2 and data["objective"] == "makespan" and data["proved"] is True
    assert data["starts"] == [[0, 0, "right"], [4, 2, "right"]]
    assert max(len(path) - 1 for path in data["paths"]) == data["steps"]
    scene = scene_from(CONE["room-3x5"])
    assert data["steps"] == team_steps(scene, [((0, 0), 0), ((4, 2), 0)], scene.vision())
    # --guards 3 with one start: all three from it.
    three = CliRunner().invoke(main, ["optimum", str(level), "--start", "0.5,0.5", "--guards", "3"])
    assert three.exit_code == 0 and "3 guards from 0.5,0.5 (cell [0, 0]) facing" in three.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--guards", "0"], "--guards"),
        (["--guards", "9"], "--guards"),
        (
            ["--start", "0.5,0.5", "--start", "1.5,0.5", "--start", "2.5,0.5", "--guards", "2"],
            "3 --start options for --guards 2",
        ),
        (["--guards", "2", "--start", "0.5,0.5", "--weight", "2"], "--weight is for one guard"),
        (["--start", "0.5,0.5", "--start", "1.5,0.5"], "need --search-from (the guaranteed search) or --guards K"),
        (
            ["--guards", "2", "--start", "0.5,0.5", "--start", "1.5,0.5", *(["--heading", "up"] * 3)],
            "3 --heading",
        ),
    ],
    ids=["no-guards", "too-many-guards", "too-many-starts", "weight", "starts-without-guards", "headings"],
)
def test_the_command_refuses_bad_teams_in_one_line(tmp_path: Path, args: list[str], message: str) -> None:
    level = write_level(tmp_path, CONE["room-3x5"])
    result = CliRunner().invoke(main, ["optimum", str(level), *args])
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    if args[0] == "--guards":
        assert message in result.output  # click's usage error
    else:
        lines = result.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("guardsim: error: ") and message in lines[0], result.stderr


def test_the_command_runs_as_a_process(tmp_path: Path) -> None:
    level = write_level(tmp_path, ALL_ROUND["corridor"])
    done = subprocess.run(
        [*guardsim_command(), "optimum", str(level), "--guards", "2", "--start", "3.5,0.5", "--start", "0.5,0.5"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "2 guards from 3.5,0.5 (cell [3, 0])" in done.stdout and "proved: true" in done.stdout
