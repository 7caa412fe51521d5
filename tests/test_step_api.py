"""The public step API: a guard stepped tick by tick, inside a caller's own pymunk space."""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pymunk
import pytest

import guardsim
from guardsim import Scene, Simulation, load_level, run_episode
from guardsim.planners import RippleFront
from guardsim.planners.base import GuardState
from tests.common import LEVELS, REPO, SQUARE_WITH_HOLE, level_from, scene_from, shipped_levels


def _stepped(simulation: Simulation) -> guardsim.Trace:
    while not simulation.done:
        simulation.step()
    return simulation.trace()


@shipped_levels
def test_stepping_gives_the_trace_of_run_and_of_the_reference(level_path) -> None:
    scene = Scene.from_level(load_level(level_path))
    runs = []
    for reference, step in ((False, False), (False, True), (True, False)):
        simulation = Simulation(scene, "ripplefront", reference=reference)
        simulation.reset(seed=3, episode=5)
        runs.append((_stepped(simulation) if step else simulation.run()).to_json())
    assert runs[0] == runs[1] == runs[2]
    assert runs[0] == run_episode(scene, seed=3, episode=5).to_json()


def test_what_a_game_reads_each_tick_agrees_with_the_trace() -> None:
    scene = Scene.from_level(load_level(LEVELS[0]))
    simulation = Simulation(scene)
    simulation.reset(seed=0)
    first_seen_by_tick: dict[int, set[tuple[int, int]]] = {0: set(simulation.newly_seen())}
    positions = [simulation.positions[0]]
    while not simulation.done:
        simulation.step()
        first_seen_by_tick[simulation.tick] = set(simulation.newly_seen())
        positions.append(simulation.positions[0])
        # The body in the physics space follows the guard.
        assert tuple(scene.world.guard_body.position) == pytest.approx(positions[-1])
        assert set(simulation.visible_cells()) >= first_seen_by_tick[simulation.tick]
    trace = simulation.trace()
    assert positions == [scene.grid.centre(col, row) for col, row in trace.path]
    for tick, cells in first_seen_by_tick.items():
        assert all(trace.first_seen[row, col] == tick for col, row in cells)
    assert simulation.coverage == 1.0 and simulation.outcome == "covered" and simulation.unseen == 0
    assert simulation.heading_degrees[0] == 90.0 * trace.headings[-1]


def test_a_subclass_that_decides_otherwise_is_not_run_on_the_compiled_tick() -> None:
    class AlwaysRight(RippleFront):
        name = "always-right"

        def next_move(self, state: GuardState) -> int | None:
            right = int(self._neighbours[state.cell, 0])
            return 0 if right >= 0 else super().next_move(state)

    class Renamed(RippleFront):
        name = "renamed"

    scene = scene_from(SQUARE_WITH_HOLE)
    plain = Simulation(scene, [RippleFront()])
    plain.reset(starts=[(0, 0)], headings=[1])
    changed = Simulation(scene, [AlwaysRight()])
    changed.reset(starts=[(0, 0)], headings=[1])
    renamed = Simulation(scene, [Renamed()])
    renamed.reset(starts=[(0, 0)], headings=[1])
    assert changed._accelerator is None and renamed._accelerator is not None
    first, second, third = plain.run(), changed.run(), renamed.run()
    assert list(second.path[:6]) == [(col, 0) for col in range(6)] and first.path != second.path
    assert third.path == first.path


def test_reset_starts_again_and_carries_on_from_cells_already_seen() -> None:
    scene = scene_from(SQUARE_WITH_HOLE)
    simulation = Simulation(scene)
    simulation.reset(starts=[(0, 0)], headings=[0])
    whole = simulation.run()
    simulation.reset(starts=[(0, 0)], headings=[0])
    assert simulation.tick == 0 and not simulation.done
    assert simulation.run().to_json() == whole.to_json()
    seen = np.zeros(scene.grid.shape, dtype=bool)
    seen[:, 3:] = True
    simulation.reset(starts=[(0, 0)], headings=[0], seen=seen)
    assert simulation.run().steps < whole.steps


def test_bad_starts_are_refused() -> None:
    simulation = Simulation(scene_from(SQUARE_WITH_HOLE))
    with pytest.raises(ValueError, match="not traversable"):
        simulation.reset(starts=[(2, 2)], headings=[0])
    with pytest.raises(ValueError, match="off the grid"):
        simulation.reset(starts=[(9, 0)], headings=[0])
    with pytest.raises(RuntimeError, match="reset"):
        Simulation(scene_from(SQUARE_WITH_HOLE)).step()


def test_a_world_built_in_the_callers_space_adds_walls_there() -> None:
    level = level_from(SQUARE_WITH_HOLE)
    space = pymunk.Space()
    crate = pymunk.Body(1.0, 1.0)
    crate.position = (1.0, 5.0)
    space.add(crate, pymunk.Poly.create_box(crate, (1.0, 1.0)))
    scene = Scene.from_level(level, space=space)
    assert scene.world.space is space
    assert len([s for s in space.shapes if isinstance(s, pymunk.Segment)]) == 8
    # The game's crate is not a wall: it blocks neither sight nor the grid.
    plain = Scene.from_level(level)
    assert (scene.grid.traversable == plain.grid.traversable).all()
    assert scene.world.line_of_sight((0.5, 5.0), (1.5, 5.0))


def test_walls_already_in_the_space_give_the_same_guard() -> None:
    level = load_level(REPO / "levels" / "passages.json")
    space = pymunk.Space()
    for ring in (level.outer, *level.holes):
        for index, start in enumerate(ring):
            space.add(pymunk.Segment(space.static_body, start, ring[(index + 1) % len(ring)], 0.0))
    player = pymunk.Body(1.0, 1.0)
    player.position = (30.0, 30.0)
    space.add(player, pymunk.Circle(player, 0.5))
    own = Scene.from_level(level, space=space, walls_in_space=True)
    assert len(own.world.walls) == sum(len(ring) for ring in (level.outer, *level.holes))
    standalone = Scene.from_level(level)
    first, second = Simulation(own), Simulation(standalone)
    first.reset(seed=1, episode=2)
    second.reset(seed=1, episode=2)
    assert first.run().to_json() == second.run().to_json()


def test_the_game_loop_example_runs() -> None:
    result = subprocess.run(
        [
            sys.executable,
            str(REPO / "examples" / "game_loop.py"),
            str(REPO / "levels" / "square.json"),
            "--frames",
            "400",
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    lines = result.stdout.splitlines()
    assert len(lines) == 101
    assert lines[-1].startswith("after 400 frames: guard still patrolling at tick 100")
    # The guard walks: its position changes over the run.
    assert lines[0].split(" sees ")[0].split(": ")[1] != lines[-2].split(" sees ")[0].split(": ")[1]


def test_public_names_resolve_and_import_guardsim_loads_no_compiler() -> None:
    for name in guardsim.__all__:
        assert getattr(guardsim, name) is not None
    code = "import sys, guardsim; guardsim.Level; guardsim.load_level; print('numba' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout == "False\n"


@pytest.mark.parametrize(("seed", "episode"), [(0, None), (4, 2)])
def test_a_script_on_public_names_walks_the_path_of_play(tmp_path, seed: int, episode: int | None) -> None:
    """Only names from guardsim.__all__: load, step tick by tick, and get `guardsim play --trace`'s path."""
    level_path = REPO / "levels" / "mgs_docks.json"
    trace_path = tmp_path / "trace.json"
    command = [
        sys.executable,
        "-m",
        "guardsim.cli",
        "play",
        str(level_path),
        "--seed",
        str(seed),
        "--trace",
        str(trace_path),
    ]
    if episode is not None:
        command += ["--episode", str(episode)]
    subprocess.run(command, check=True, capture_output=True, timeout=300)
    played = guardsim.Trace.from_data(json.loads(trace_path.read_text()))
    simulation = guardsim.Simulation(guardsim.Scene.from_level(guardsim.load_level(level_path)))
    simulation.reset(seed=seed, episode=episode)
    path = [simulation.cells[0]]
    while not simulation.done:
        simulation.step()
        path.append(simulation.cells[0])
    assert tuple(path) == played.path
    assert simulation.trace().to_json() == trace_path.read_text()


def test_the_recorded_field_is_the_field_each_decision_saw() -> None:
    scene = scene_from(SQUARE_WITH_HOLE)
    traces = []
    for reference in (False, True):
        simulation = Simulation(scene, "ripplefront", record_field=True, reference=reference)
        simulation.reset(starts=[(0, 0)], headings=[0])
        traces.append(simulation.run())
    fast, plain = traces
    assert fast.field is not None and plain.field is not None
    assert fast.field.shape == (fast.steps + 1, *scene.grid.shape)
    assert (fast.field == plain.field).all()
    # Each recorded field sends the guard downhill: the move taken goes to the smallest D around it.
    grid = scene.grid
    for tick in range(fast.steps):
        field = fast.field[tick].ravel()
        here, there = grid.flat(*fast.path[tick]), grid.flat(*fast.path[tick + 1])
        options = [field[other] for other in grid.neighbours[here] if other >= 0]
        assert field[there] == min(options)
    again = guardsim.Trace.from_data(json.loads(fast.to_json()))
    assert again.field is not None and (again.field == fast.field).all()
    unrecorded = Simulation(scene)
    unrecorded.reset(starts=[(0, 0)], headings=[0])
    assert unrecorded.run().path == fast.path and "field" not in json.loads(unrecorded.trace().to_json())


def test_a_view_table_past_its_limit_is_one_line_naming_the_level(monkeypatch: pytest.MonkeyPatch) -> None:
    """A fine grid with a long view range would fill billions of (state, cell) pairs: stop at the limit."""
    from click.testing import CliRunner

    from guardsim.cli import main
    from guardsim.errors import LimitError
    from guardsim.vision import table

    scene = scene_from(SQUARE_WITH_HOLE)
    with pytest.raises(LimitError, match="max_view_entries"):
        table.build_view_table(scene.grid, scene.vision(), max_entries=100)
    assert table.build_view_table(scene.grid, scene.vision()).sight.size > 100
    monkeypatch.setattr(table, "MAX_VIEW_ENTRIES", 10_000)
    level = str(REPO / "levels" / "square.json")
    result = CliRunner().invoke(main, ["bounds", level])
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"guardsim: error: {level}: ")
    assert "max_view_entries: shorten the view range or use larger cells" in lines[0]


def test_the_view_table_size_is_estimated_before_it_is_built() -> None:
    """A level whose table would pass the limit is refused from a sample of its states, not after
    filling the table: the vision is asked about at most the sample's states."""
    from guardsim.errors import LimitError
    from guardsim.vision import table

    small = scene_from(SQUARE_WITH_HOLE)
    # A level no bigger than the sample is asked whole: the estimate is the count.
    assert small.grid.traversable.sum() <= table.ESTIMATE_SAMPLE_CELLS
    exact = table.build_view_table(small.grid, small.vision()).sight.size
    assert table.estimate_entries(small.grid, small.vision()) == exact
    scene = Scene.from_level(load_level(REPO / "levels" / "square.json"))
    vision = scene.vision()
    asked: list[int] = []

    def counted(col: int, row: int, heading: int) -> np.ndarray:
        asked.append(heading)
        return np.asarray(vision(col, row, heading))

    with pytest.raises(LimitError, match=r"about \d+ cells, over the limit of 1000 \(max_view_entries\)"):
        table.build_view_table(scene.grid, counted, max_entries=1000)
    assert 0 < len(asked) <= 4 * table.ESTIMATE_SAMPLE_CELLS < 4 * int(scene.grid.traversable.sum())


@pytest.mark.parametrize("name", ["square", "mgs_docks", "king_snurre"])
def test_the_view_table_estimate_is_close_on_shipped_levels(name: str) -> None:
    from guardsim.vision import table

    scene = Scene.from_level(load_level(REPO / "levels" / f"{name}.json"))
    exact = table.view_table(scene.grid, scene.vision()).sight.size
    assert table.estimate_entries(scene.grid, scene.vision()) == pytest.approx(exact, rel=0.05)


def test_load_level_and_the_environment_take_every_map_the_commands_take(tmp_path: Path) -> None:
    """guardsim.load_level and gymnasium's guardsim/Coverage-v0 import a map as the commands do (a Moving
    AI map here); a file that is neither a level nor a map is one GuardsimError naming it."""
    grid_map = tmp_path / "room.map"
    grid_map.write_text("type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n")
    level = guardsim.load_level(grid_map)
    assert level.name == "room" and level.grid_shape() == (3, 4) and len(level.holes) == 1
    gymnasium = pytest.importorskip("gymnasium")
    importlib.import_module("guardsim.envs")  # registers the environment

    observation, _ = gymnasium.make("guardsim/Coverage-v0", level=str(grid_map)).reset(seed=0)
    assert observation["grid"].shape[-2:] == (3, 4)
    notes = tmp_path / "notes.md"
    notes.write_text("# not a level\n")
    with pytest.raises(guardsim.GuardsimError, match=r"notes\.md: unknown map type '\.md'"):
        guardsim.load_level(notes)


def test_a_team_says_which_guard_sees_and_seen_by_answers_for_every_cell() -> None:
    """visible_cells of a team needs a guard; seen_by(point) lists exactly the guards whose view holds the
    point's cell, checked on every cell at several ticks."""
    scene = scene_from(SQUARE_WITH_HOLE)
    simulation = Simulation(scene, guards=2)
    simulation.reset(seed=3)
    with pytest.raises(ValueError, match="say which guard"):
        simulation.visible_cells()
    with pytest.raises(ValueError, match="guard 2 is not one"):
        simulation.visible_cells(guard=2)
    grid = scene.grid
    for _ in range(4):
        views = [set(simulation.visible_cells(guard=guard)) for guard in range(2)]
        for row in range(grid.shape[0]):
            for col in range(grid.shape[1]):
                expected = [guard for guard in range(2) if (col, row) in views[guard]]
                assert simulation.seen_by(grid.centre(col, row)) == expected
        simulation.step()
    assert simulation.seen_by((-100.0, -100.0)) == []
    assert any(simulation.seen_by(grid.centre(*cell)) for cell in simulation.visible_cells(guard=0))
