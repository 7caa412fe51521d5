"""Patrols: every lap of a loop sees the goal (replayed through the vision, not the view table), the
scores are the idleness the definition gives, the loop beats the walked baselines, and patrol.json is
read strictly."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim import load_level
from guardsim.cli import main
from guardsim.grid import cell_of_state, heading_of_state
from guardsim.patrol import Patrol, parse_patrol, patrol_data, patrol_setup, plan_loop, plan_patrol, score_patrol
from guardsim.patrol.export import position_at, route_data
from guardsim.patrol.loops import closed_tour
from guardsim.patrol.scoring import score_timeline, seen_timeline
from guardsim.scene import Scene
from tests.common import LEVELS, TINY_LEVELS, TWO_ROOMS, scene_from, tiny_levels, write_level

#: A corridor one cell wide and five long between two 3 x 3 rooms (x 0-3 and 8-11, y 0-3; corridor y 1-2).


def _replay_sees(scene: Scene, patrol: Patrol, start: int, ticks: int) -> np.ndarray:
    """Cells seen over ``ticks`` ticks from ``start``, asking the reference vision at every tick."""
    vision = scene.reference_vision()
    grid = scene.grid
    seen = np.zeros(grid.size, dtype=bool)
    for tick in range(start, start + ticks):
        for guard in range(patrol.guards):
            state = patrol.state(guard, tick)
            col, row = grid.unflat(int(cell_of_state(state)))
            seen[vision(col, row, int(heading_of_state(state)))] = True
    return seen


def _legal(scene: Scene, patrol: Patrol) -> None:
    """Every tick of every lap is a grid move (via the strict reader, which checks each one)."""
    data = patrol_data(
        patrol, score_patrol(patrol_setup(scene).table, patrol, patrol_setup(scene).goal), scene.grid, level="x"
    )
    again = parse_patrol(json.loads(json.dumps(data)), scene.grid)
    assert again.period == patrol.period
    assert np.array_equal(again.states, patrol.states)


@tiny_levels
@pytest.mark.parametrize("guards", [1, 2])
def test_every_lap_of_a_loop_sees_the_goal(level_data: dict[str, Any], guards: int) -> None:
    scene = scene_from(level_data)
    setup = patrol_setup(scene, guards)
    for planner in ("cover", "tour"):
        patrol = plan_loop(setup, guards, planner=planner)[0].patrol
        assert patrol.period is not None
        _legal(scene, patrol)
        for lap in range(2):
            # A lap is any window of `period` ticks, not only the one starting at tick 0.
            for start in (lap * patrol.period, lap * patrol.period + patrol.period // 2):
                assert np.all(_replay_sees(scene, patrol, start, patrol.period)[setup.goal])


@pytest.fixture(scope="module")
def shipped_loops() -> dict[str, tuple[Scene, Any]]:
    loops = {}
    for path in LEVELS:
        scene = Scene.from_level(load_level(path))
        setup = patrol_setup(scene, 1)
        loops[path.stem] = (scene, setup, plan_loop(setup, 1)[0])
    return loops


@pytest.mark.slow
@pytest.mark.parametrize("name", [path.stem for path in LEVELS])
def test_shipped_loops_see_every_reachable_cell_each_lap(shipped_loops: dict[str, Any], name: str) -> None:
    scene, setup, plan = shipped_loops[name]
    patrol = plan.patrol
    vision = scene.vision()
    grid = scene.grid
    seen = np.zeros(grid.size, dtype=bool)
    for tick in range(patrol.period):
        state = patrol.state(0, tick)
        col, row = grid.unflat(int(cell_of_state(state)))
        seen[vision(col, row, int(heading_of_state(state)))] = True
    assert np.all(seen[setup.goal])
    assert plan.score.worst_idleness is not None and plan.score.worst_idleness < patrol.period
    _legal(scene, patrol)


@pytest.mark.slow
def test_loop_beats_the_walked_strategies_on_a_shipped_level(shipped_loops: dict[str, Any]) -> None:
    _, setup, plan = shipped_loops["square"]
    for strategy in ("staleness", "ripplefront", "random"):
        walked = plan_patrol(setup, strategy, laps=3, warmup_laps=1, lap=plan.patrol.period)
        assert walked.patrol.period is None
        assert walked.score.worst_idleness is not None
        assert plan.score.worst_idleness < walked.score.worst_idleness, strategy


@tiny_levels
def test_periodic_score_is_the_long_run_score(level_data: dict[str, Any]) -> None:
    """The exact lap score equals idleness measured tick by tick over many laps after a warm-up lap."""
    scene = scene_from(level_data)
    setup = patrol_setup(scene, 2)
    patrol = plan_loop(setup, 2, planner="cover")[0].patrol
    exact = score_patrol(setup.table, patrol, setup.goal)
    ticks = patrol.period * 7
    timeline = seen_timeline(setup.table, patrol.unrolled(ticks), setup.goal.size)
    long_run = score_timeline(timeline, setup.goal, periodic=False, warmup=patrol.period)
    assert exact.worst_idleness == long_run.worst_idleness
    assert exact.mean_idleness == pytest.approx(long_run.mean_idleness)
    # And by definition: the longest run of unseen ticks of each goal cell, cyclically.
    lap = seen_timeline(setup.table, patrol.states, setup.goal.size)
    for cell in np.flatnonzero(setup.goal)[:20]:
        row = np.concatenate([lap[:, cell], lap[:, cell]])
        runs = [len(part) for part in "".join("x" if v else "." for v in row).split("x")]
        assert exact.worst_gap[cell] == min(max(runs), patrol.period)


def test_team_keeps_the_better_of_shared_and_split() -> None:
    scene = scene_from(TINY_LEVELS["split-rooms"] | {"holes": []})
    setup = patrol_setup(scene, 2)
    plan, scores = plan_loop(setup, 2, planner="cover")
    assert set(scores) == {"shared", "split"}
    chosen = scores[plan.patrol.team]
    assert all(chosen.worst_idleness <= other.worst_idleness for other in scores.values())
    assert plan.patrol.notes and plan.patrol.team in plan.patrol.notes[0]


def test_closed_tour_is_a_short_cycle() -> None:
    # Four points on a ring: the cycle goes round it, never across.
    cost = np.array([[0, 1, 9, 1], [1, 0, 1, 9], [9, 1, 0, 1], [1, 9, 1, 0]])
    order = closed_tour(cost).tolist()
    assert order[0] == 0 and sorted(order) == [0, 1, 2, 3]
    assert sum(cost[a, b] for a, b in zip(order, order[1:] + order[:1])) == 4


# -- patrol.json and the command ---------------------------------------------------------------------


def _post_file(folder: Path, cell: list[int], heading: int, **changes: Any) -> Path:
    data = {"shape": [3, 11], "guards": [{"loop": [cell, cell], "headings": [heading, heading]}], **changes}
    path = folder / "post.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def test_evaluate_a_hand_written_post(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    post = _post_file(tmp_path, [5, 1], 0)
    result = CliRunner().invoke(main, ["patrol", str(level), "--out", str(tmp_path / "out"), "--evaluate", str(post)])
    assert result.exit_code == 0, result.output
    data = json.loads((tmp_path / "out" / "patrol.json").read_text())
    assert data["period"] == 1 and data["guards"][0]["loop"] == [[5, 1], [5, 1]]
    # A post never sees the rooms' far corners: their gap is unbounded.
    assert data["worst_idleness"] is None and data["never_seen"] > 0
    assert data["idleness"][1][5] == 0 and data["idleness"][0][4] is None


@pytest.mark.parametrize(
    ("guard", "message"),
    [
        (
            {"loop": [[5, 1], [6, 1], [5, 1]], "headings": [2, 1, 2]},
            "guards[0]: headings[1]: a step right must face right (0), not 1",
        ),
        (
            {"loop": [[5, 1], [7, 1], [5, 1]], "headings": [0, 0, 2]},
            "guards[0].loop[1]: [5, 1] -> [7, 1] is not a step",
        ),
        ({"loop": [[5, 1], [5, 1]], "headings": [0, 1]}, "a guard standing still keeps its heading (0), not 1"),
        ({"loop": [[5, 1], [6, 1]], "headings": [0, 0]}, "a repeating loop must end as it began"),
        (
            {"loop": [[5, 0], [5, 0]], "headings": [0, 0]},
            "guards[0].loop[0]: [5, 0] is not a cell the guard can stand in",
        ),
        ({"loop": [[50, 1]], "headings": [0]}, "guards[0].loop[0]: [50, 1] is off the grid"),
        ({"loop": [[5, 1]], "headings": [7]}, "guards[0].headings[0]: expected 0, 1, 2 or 3"),
        ({"loop": [[5, 1]], "headings": []}, "guards[0].headings: expected one heading per loop cell (1), got 0"),
    ],
    ids=["heading", "jump", "turn-on-the-spot", "open", "wall", "off-grid", "bad-heading", "count"],
)
def test_bad_patrol_files_are_one_located_line(tmp_path: Path, guard: dict[str, Any], message: str) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"shape": [3, 11], "guards": [guard]}), encoding="utf-8")
    result = CliRunner().invoke(main, ["patrol", str(level), "--out", str(tmp_path / "o"), "--evaluate", str(path)])
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"guardsim: error: {path}: ") and message in lines[0], lines


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[1]", "expected a JSON object, got a list"),
        ('{"guards": []}', 'missing "shape"'),
        (
            '{"shape": [4, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}',
            "shape: [4, 11] does not match the level's grid [3, 11]",
        ),
        ('{"shape": [3, 11], "guards": {}}', "guards: expected a non-empty list"),
        (
            '{"shape": [3, 11], "period": 5, "guards": [{"loop": [[5, 1]], "headings": [0]}]}',
            "period: 5 does not match",
        ),
        (
            '{"shape": [3, 11], "motion": "hover", "guards": []}',
            """motion: expected "grid" or "continuous", got 'hover'""",
        ),
        ('{"shape": [3, 11], "guards": [', "not valid JSON"),
    ],
    ids=["array", "no-shape", "shape", "guards", "period", "motion", "syntax"],
)
def test_bad_patrol_documents(tmp_path: Path, text: str, message: str) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    path = tmp_path / "bad.json"
    path.write_text(text, encoding="utf-8")
    result = CliRunner().invoke(main, ["patrol", str(level), "--out", str(tmp_path / "o"), "--evaluate", str(path)])
    assert result.exit_code == 2
    assert len(result.output.strip().splitlines()) == 1 and message in result.output, result.output


def test_continuous_motion_walks_loops_only(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    result = CliRunner().invoke(
        main, ["patrol", str(level), "--out", str(tmp_path / "o"), "--motion", "continuous", "--strategy", "random"]
    )
    assert result.exit_code == 2
    assert result.output.strip() == (
        "guardsim: error: --motion continuous is not yet supported for patrol strategy random (only loop and --evaluate)"
    )


@pytest.mark.parametrize("guards", [1, 2])
def test_a_loop_walked_in_continuous_motion_sees_every_cell_each_lap(tmp_path: Path, guards: int) -> None:
    level = write_level(tmp_path, TINY_LEVELS["square-with-hole"])
    out = tmp_path / "o"
    args = ["patrol", str(level), "--out", str(out), "--motion", "continuous", "--guards", str(guards)]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    data = json.loads((out / "patrol.json").read_text())
    assert data["motion"] == "continuous" and data["idleness_unit"] == "seconds" and data["never_seen"] == 0
    # Walking at 2 units a second and turning on the spot, a lap takes at least the grid lap's distance.
    assert data["period_seconds"] >= data["period"] * 0.5
    assert data["physics_ticks_per_lap"] == round(data["period_seconds"] * data["tick_hz"])
    assert 0 < data["worst_idleness"] <= data["period_seconds"]
    assert max(v for row in data["idleness"] for v in row if v is not None) == data["worst_idleness"]
    # The file reads back and is walked again the same way.
    again = CliRunner().invoke(
        main, ["patrol", str(level), "--out", str(tmp_path / "p"), "--evaluate", str(out / "patrol.json")]
    )
    assert again.exit_code == 0, again.output
    assert json.loads((tmp_path / "p" / "patrol.json").read_text())["worst_idleness"] == data["worst_idleness"]


def test_route_export_merges_straight_runs_and_unrolls_to_the_loop(tmp_path: Path) -> None:
    scene = scene_from(TINY_LEVELS["square-with-hole"])
    setup = patrol_setup(scene, 1)
    patrol = plan_loop(setup, 1)[0].patrol
    route = route_data(patrol, scene.grid, level="x", speed=4.0)
    [guard] = route["guards"]
    points = guard["waypoints"]
    assert route["seconds_per_tick"] == 0.25 and route["period_ticks"] == patrol.period
    assert guard["loop_mode"] == "loop" and guard["phase"] == 0.0
    assert points[0]["tick"] == 0 and points[-1]["tick"] == patrol.period
    assert (points[0]["x"], points[0]["y"]) == (points[-1]["x"], points[-1]["y"])
    for a, b in itertools.pairwise(points):
        assert b["time"] == pytest.approx(b["tick"] * 0.25)
        ticks = b["tick"] - a["tick"] - round(a["wait"] / 0.25)
        dx, dy = (b["x"] - a["x"]) / ticks, (b["y"] - a["y"]) / ticks
        # Between two waypoints the guard stands its wait, then goes straight at one cell per tick.
        assert (abs(dx), abs(dy)) in ((1.0, 0.0), (0.0, 1.0))
    # Replayed at every tick of two laps, the route is where the patrol is.
    for tick in range(2 * patrol.ticks):
        want = scene.grid.centre(*scene.grid.unflat(int(cell_of_state(patrol.state(0, tick)))))
        assert position_at(guard, tick * 0.25) == pytest.approx(want)
    assert len(points) < patrol.ticks


def test_patrol_command_in_a_real_process(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    out = tmp_path / "out"
    run = subprocess.run(
        [
            str(Path(sys.executable).parent / "guardsim"),
            "patrol",
            str(level),
            "--out",
            str(out),
            "--guards",
            "2",
            "--export",
            str(tmp_path / "route.json"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    data = json.loads((out / "patrol.json").read_text())
    for key in (
        "level",
        "cell_size",
        "origin",
        "shape",
        "motion",
        "strategy",
        "period",
        "guards",
        "worst_idleness",
        "mean_idleness",
        "idleness",
    ):
        assert key in data
    assert data["strategy"] == "loop" and data["motion"] == "grid" and len(data["guards"]) == 2
    assert data["team"] in ("shared", "split")
    assert all(guard["loop"][0] == guard["loop"][-1] for guard in data["guards"])
    assert len(data["idleness"]) == 3 and len(data["idleness"][0]) == 11
    assert (out / "idleness.png").stat().st_size > 1000
    assert "worst idleness" in run.stdout


TMX = """<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" renderorder="right-down" width="10" height="6"
     tilewidth="16" tileheight="16" infinite="0" nextlayerid="3" nextobjectid="1">
 <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2">
  <tile id="1"><properties><property name="collision" type="bool" value="true"/></properties></tile>
 </tileset>
 <layer id="1" name="Ground" width="10" height="6">
  <data encoding="csv">
2,2,2,2,2,2,2,2,2,2,
2,1,1,1,1,2,1,1,1,2,
2,1,1,1,1,1,1,1,1,2,
2,1,1,1,1,2,1,1,1,2,
2,1,1,1,1,2,1,1,1,2,
2,2,2,2,2,2,2,2,2,2
</data>
 </layer>
</map>
"""


def test_tiled_copy_holds_the_route_and_reimports_to_the_same_level(tmp_path: Path) -> None:
    from xml.etree import ElementTree

    from guardsim.level import level_to_data
    from tests.common import import_map

    source = tmp_path / "map.tmx"
    source.write_text(TMX, encoding="utf-8")
    out = tmp_path / "out"
    copy = tmp_path / "routed.tmx"
    args = ["patrol", str(source), "--out", str(out), "--guards", "2", "--tiled-out", str(copy), "--speed", "4"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    root = ElementTree.parse(copy).getroot()
    [layer] = [group for group in root.iter("objectgroup") if group.get("name") == "guardsim"]
    routes = [item for item in layer.findall("object") if item.get("type") == "guardsim_route"]
    assert len(routes) == 2
    period = json.loads((out / "patrol.json").read_text())["period"]
    for route in routes:
        properties = {item.get("name"): item.get("value") for item in route.iter("property")}
        shared = {key: properties.pop(key) for key in ("period", "period_ticks", "speed")}
        assert shared == {"period": str(period * 0.25), "period_ticks": str(period), "speed": "4.0"}
        assert len(properties["headings"].split()) == len(properties["times"].split())
        points = [tuple(float(v) for v in pair.split(",")) for pair in route.find("polyline").get("points").split()]
        # Closed (or walked there and back), in map pixels (16 per tile), on tile centres.
        assert properties["loop_mode"] in ("loop", "ping-pong")
        assert (points[0] == points[-1]) == (properties["loop_mode"] == "loop") and all(
            (x / 16 - 0.5) % 1 == 0 for x, _ in points
        )
    # Re-importing the copy gives the same level: the route layer is neither wall nor spawn.
    routed, plain = (level_to_data(import_map(path).level) for path in (copy, source))
    assert routed.pop("name") == "routed" and plain.pop("name") == "map"
    assert routed == plain
    # Writing again replaces the layer rather than adding a second one.
    again = CliRunner().invoke(main, ["patrol", str(copy), "--out", str(out), "--tiled-out", str(copy)])
    assert again.exit_code == 0, again.output
    assert [g.get("name") for g in ElementTree.parse(copy).getroot().iter("objectgroup")] == ["guardsim"]


def test_tiled_out_of_a_plain_level_writes_a_fresh_map_that_imports_to_the_same_level(tmp_path: Path) -> None:
    import shapely.affinity

    from guardsim import load_level
    from tests.common import import_map

    level = write_level(tmp_path, TWO_ROOMS)
    for suffix in (".tmx", ".tmj"):
        fresh = tmp_path / f"fresh{suffix}"
        result = CliRunner().invoke(
            main, ["patrol", str(level), "--out", str(tmp_path / "o"), "--tiled-out", str(fresh)]
        )
        assert result.exit_code == 0, result.output
        imported = import_map(fresh)
        assert imported.warnings == ()
        # The fresh map puts a wall border one tile wide around the level, so it comes back moved by (1, 1).
        again, drawn = imported.level.free_area(), shapely.affinity.translate(load_level(level).free_area(), 1, 1)
        assert again.symmetric_difference(drawn).area == 0 and imported.level.starts == ((1.5, 1.5),)


TMJ = {
    "type": "map",
    "orientation": "orthogonal",
    "renderorder": "right-down",
    "width": 10,
    "height": 6,
    "tilewidth": 16,
    "tileheight": 16,
    "infinite": False,
    "nextlayerid": 2,
    "nextobjectid": 1,
    "tilesets": [
        {
            "firstgid": 1,
            "name": "t",
            "tilewidth": 16,
            "tileheight": 16,
            "tilecount": 2,
            "columns": 2,
            "tiles": [{"id": 1, "properties": [{"name": "collision", "type": "bool", "value": True}]}],
        }
    ],
    "layers": [
        {
            "id": 1,
            "name": "Ground",
            "type": "tilelayer",
            "width": 10,
            "height": 6,
            "x": 0,
            "y": 0,
            "opacity": 1,
            "visible": True,
            "data": [
                int(v) for v in TMX.split('<data encoding="csv">')[1].split("</data>")[0].replace(",", " ").split()
            ],
        }
    ],
}


def test_tiled_json_copy_reimports_to_the_same_level(tmp_path: Path) -> None:
    from guardsim.level import level_to_data
    from tests.common import import_map

    source = tmp_path / "map.tmj"
    source.write_text(json.dumps(TMJ), encoding="utf-8")
    copy = tmp_path / "routed.tmj"
    result = CliRunner().invoke(main, ["patrol", str(source), "--out", str(tmp_path / "o"), "--tiled-out", str(copy)])
    assert result.exit_code == 0, result.output
    layers = json.loads(copy.read_text())["layers"]
    assert [layer["name"] for layer in layers] == ["Ground", "guardsim"]
    [route] = [item for item in layers[1]["objects"] if item["type"] == "guardsim_route"]
    mode = {item["name"]: item["value"] for item in route["properties"]}["loop_mode"]
    assert route["type"] == "guardsim_route" and (route["polyline"][0] == route["polyline"][-1]) == (mode == "loop")
    routed, plain = (level_to_data(import_map(path).level) for path in (copy, source))
    routed.pop("name"), plain.pop("name")
    assert routed == plain
    # A copy in the other format is refused before any work, in one line.
    wrong = CliRunner().invoke(
        main, ["patrol", str(source), "--out", str(tmp_path / "o"), "--tiled-out", str(tmp_path / "x.tmx")]
    )
    assert wrong.exit_code == 2 and wrong.output.strip().endswith("must keep its format (.tmj or .json)")


@pytest.mark.parametrize("strategy", ["loop", "random", "staleness"])
def test_same_seed_same_patrol(tmp_path: Path, strategy: str) -> None:
    level = write_level(tmp_path, TINY_LEVELS["square-with-hole"])
    written = []
    for run in range(2):
        out = tmp_path / f"run{run}"
        args = ["patrol", str(level), "--out", str(out), "--strategy", strategy, "--guards", "2", "--laps", "3"]
        result = CliRunner().invoke(main, args)
        assert result.exit_code == 0, result.output
        written.append((out / "patrol.json").read_bytes())
    assert written[0] == written[1]


def test_a_patrol_of_another_level_says_which_level_it_was_made_for(tmp_path: Path) -> None:
    """Square and Passages share a 60 x 60 grid: a Square patrol read on Passages failed on a wall cell
    without saying it was made for another level."""
    repo = Path(__file__).resolve().parent.parent
    runner = CliRunner()
    made = runner.invoke(main, ["patrol", str(repo / "levels" / "square.json"), "--out", str(tmp_path / "p")])
    assert made.exit_code == 0, made.output
    patrol = tmp_path / "p" / "patrol.json"
    result = runner.invoke(
        main,
        [
            "sneak",
            str(repo / "levels" / "passages.json"),
            "--patrol",
            str(patrol),
            "--from",
            "2.5,2.5",
            "--to",
            "57.5,57.5",
        ],
    )
    [line] = result.stderr.splitlines()
    assert result.exit_code == 2 and line.startswith(f"guardsim: error: {patrol}: guards[0].loop[")
    assert line.endswith('(the patrol was made for level "Square", not "Passages")')


def test_a_tiled_copy_in_another_folder_still_finds_its_external_tileset(tmp_path: Path) -> None:
    """The copy kept ``source="tileset.tsx"``, which names a file only beside the original map: re-imported
    from elsewhere it warned "tileset tileset.tsx not found" (and Tiled would open it without tiles)."""
    import shutil
    from xml.etree import ElementTree

    from guardsim.level import level_to_data
    from tests.common import import_map

    maps = Path(__file__).resolve().parent.parent.parent / "shared" / "maps" / "tiled"
    if not (maps / "sneaktime_tilemap1.tmx").exists():
        pytest.skip("../shared/maps is not beside the repository")
    source = tmp_path / "maps" / "level.tmx"
    source.parent.mkdir()
    shutil.copy(maps / "sneaktime_tilemap1.tmx", source)
    shutil.copy(maps / "tileset.tsx", source.parent / "tileset.tsx")
    copy = tmp_path / "out" / "deeper" / "routed.tmx"
    copy.parent.mkdir(parents=True)
    result = CliRunner().invoke(main, ["patrol", str(source), "--out", str(tmp_path / "o"), "--tiled-out", str(copy)])
    assert result.exit_code == 0, result.output
    [tileset] = ElementTree.parse(copy).getroot().iter("tileset")
    assert tileset.get("source") == "../../maps/tileset.tsx"
    routed, plain = import_map(copy), import_map(source)
    assert not any("not found" in warning for warning in routed.warnings), routed.warnings
    routed_data, plain_data = level_to_data(routed.level), level_to_data(plain.level)
    routed_data.pop("name"), plain_data.pop("name")
    assert routed_data == plain_data
