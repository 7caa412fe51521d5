"""What an outside fuzz campaign found in the inputs of the new commands, each case kept as a test.

The campaign ran LDtk projects, patrol.json, route and checks files, traces given to ``view``, and the
options of alert, sneak, optimum, patrol, import and bounds against a 10 x 10 level with a 2 x 2 pillar
(unless said). Every case must end in a correct answer, or in one line naming the file and the place at
fault with exit status 2, leaving no output behind.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from guardsim.alert.intruders import read_route_points
from guardsim.errors import CheckError, LevelError
from guardsim.validate.checks import read_checks
from guardsim.validate.repair import MAX_REPAIR_HOLES
from tests.common import REPO, assert_one_line_error, import_map, run
from tests.test_ldtk import project

PILLAR: dict[str, Any] = {
    "name": "ten",
    "outer": [[0, 0], [10, 0], [10, 10], [0, 10]],
    "holes": [[[4, 4], [6, 4], [6, 6], [4, 6]]],
}


@pytest.fixture
def level(tmp_path: Path) -> Path:
    path = tmp_path / "ten.json"
    path.write_text(json.dumps(PILLAR), encoding="utf-8")
    return path


def _write(path: Path, data: Any) -> Path:
    path.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return path


# --- patrol and check: teams up to the allowed 64 ------------------------------------------------------


def test_a_team_larger_than_the_lap_is_ticks_gets_a_loop_each() -> None:
    # The split team cut a 20-tick lap into 32 stretches, the last ones empty: IndexError.
    from guardsim.level import parse_level
    from guardsim.patrol import patrol_setup, plan_loop
    from guardsim.scene import Scene

    setup = patrol_setup(Scene.from_level(parse_level(PILLAR)), 32, seed=0)
    plan, _ = plan_loop(setup, 32)
    assert plan.patrol.states.shape[0] == 32 and plan.patrol.period >= 1


@pytest.mark.slow
def test_patrol_with_a_team_larger_than_the_lap_is_ticks(level: Path, tmp_path: Path) -> None:
    result = run("patrol", level, "--out", tmp_path / "out", "--guards", "32")
    assert result.exit_code == 0, result.output
    data = json.loads((tmp_path / "out" / "patrol.json").read_text(encoding="utf-8"))
    assert len(data["guards"]) == 32


@pytest.mark.slow
def test_check_with_64_guards_answers(level: Path) -> None:
    result = run("check", level, "--guards", "64", "--max-idleness", "100")
    assert result.exit_code == 0, result.output


@pytest.mark.parametrize("guards", [65, 1_000_000])
def test_a_checks_file_asking_for_more_guards_than_the_option_allows_is_one_line(
    level: Path, tmp_path: Path, guards: int
) -> None:
    # The schema had no upper bound: a million guards ran past a minute and a gigabyte.
    checks = _write(tmp_path / "checks.json", {"guards": guards, "max_idleness": 10})
    line = assert_one_line_error(run("check", level, "--checks", checks), checks)
    assert "guards" in line and "64" in line


# --- checks files ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text",
    [
        "safe = " + "[" * 1000 + "]" * 1000 + "\n",
        "x = " + "{a = " * 1000 + "1" + "}" * 1000 + "\n",
        "[" + ".".join(["a"] * 1000) + "]\nx = 1\n",
    ],
    ids=["arrays", "inline-tables", "dotted-tables"],
)
def test_a_toml_checks_file_nested_1000_deep_is_one_line(tmp_path: Path, text: str) -> None:
    path = _write(tmp_path / "deep.toml", text)
    with pytest.raises(CheckError, match=r"deep\.toml: not valid TOML for guardsim: nested") as error:
        read_checks(path)
    assert "\n" not in str(error.value)


def test_a_checks_file_with_no_rule_names_the_checks_file(level: Path, tmp_path: Path) -> None:
    checks = _write(tmp_path / "checks.json", {"guards": 2})
    line = assert_one_line_error(run("check", level, "--checks", checks), checks)
    assert "no rule" in line and "give" not in line


def test_an_empty_patrol_name_in_a_checks_file_names_the_file_and_key(level: Path, tmp_path: Path) -> None:
    checks = _write(tmp_path / "checks.json", {"patrol": "", "max_idleness": 5})
    line = assert_one_line_error(run("check", level, "--checks", checks), checks)
    assert "patrol: expected a patrol file name" in line


# --- LDtk projects --------------------------------------------------------------------------------------


def test_an_ldtk_level_file_path_too_long_for_the_system_is_one_line(tmp_path: Path) -> None:
    data = project()
    data["levels"][0]["layerInstances"] = None
    data["levels"][0]["externalRelPath"] = "a" * 6002
    path = _write(tmp_path / "long.ldtk", data)
    with pytest.raises(LevelError, match=r"long\.ldtk: levels\[0\]\.externalRelPath: .* cannot be read") as error:
        import_map(path)
    assert len(str(error.value)) < 300


@pytest.mark.parametrize(
    ("field", "value"), [("pxWid", 8), ("pxWid", 1), ("__gridSize", 10**9)], ids=["8px", "1px", "huge-grid"]
)
def test_an_ldtk_level_narrower_than_the_guard_is_refused_and_nothing_written(
    tmp_path: Path, field: str, value: int
) -> None:
    data = project(csv=[0] * 12)
    if field == "pxWid":
        data["levels"][0]["pxWid"] = value
    else:
        data["levels"][0]["layerInstances"][1]["__gridSize"] = value
    path = _write(tmp_path / "narrow.ldtk", data)
    out = tmp_path / "narrow.json"
    line = assert_one_line_error(run("import", path, "--out", out), path)
    assert "no cell where the guard" in line
    assert not out.exists()


def test_ldtk_identifiers_longer_than_a_level_name_import(tmp_path: Path) -> None:
    data = project()
    second = json.loads(json.dumps(data["levels"][0]))
    data["levels"][0]["identifier"], second["identifier"] = "L" * 250, "M" * 250
    data["levels"].append(second)
    imported = import_map(_write(tmp_path / "names.ldtk", data))
    assert len(imported.level.name) <= 200 and imported.level.name.startswith("names LLL")
    assert max(len(change) for change in imported.changes) < 400


# --- options and long texts -----------------------------------------------------------------------------


def test_a_long_wall_property_is_quoted_short_in_its_warning(tmp_path: Path) -> None:
    path = _write(tmp_path / "map.tmj", _tiny_tiled())
    result = run("import", path, "--out", tmp_path / "out.json", "--wall-property", "x" * 5000)
    assert result.exit_code == 0, result.output
    warning = next(line for line in result.stderr.splitlines() if "--wall-property" in line)
    assert len(warning) < 400, warning


def test_view_of_a_trace_with_a_huge_level_name_is_one_short_line(tmp_path: Path) -> None:
    data = json.loads((REPO / "tests" / "data" / "trace-empty-square.json").read_text(encoding="utf-8"))
    data["level"] = "N" * 100_000
    trace = _write(tmp_path / "trace.json", data)
    html = tmp_path / "page.html"
    line = assert_one_line_error(run("view", trace, "--html", html), trace)
    assert len(line) < 300 and "level" in line
    assert not html.exists()


def test_tick_hz_past_a_physics_rate_is_refused(level: Path, tmp_path: Path) -> None:
    result = run("alert", level, "--motion", "continuous", "--tick-hz", "100000", "--max-seconds", "20")
    assert result.exit_code == 2 and "--tick-hz" in result.output and "Traceback" not in result.output


@pytest.mark.parametrize("option", [("--level", "Level_1"), ("--wall-value", "3")])
def test_ldtk_options_on_a_tiled_map_are_refused(tmp_path: Path, option: tuple[str, str]) -> None:
    path = _write(tmp_path / "map.tmj", _tiny_tiled())
    line = assert_one_line_error(run("import", path, "--out", tmp_path / "out.json", *option), path)
    assert f"{option[0]} is for LDtk projects" in line


def test_patrol_out_empty_is_refused(level: Path) -> None:
    result = run("patrol", level, "--out", "")
    assert result.exit_code == 2 and "--out" in result.stderr


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="no /proc")
@pytest.mark.parametrize("option", ["--godot", "--export", "--tiled-out"])
def test_patrol_with_an_unwritable_export_leaves_nothing_behind(level: Path, tmp_path: Path, option: str) -> None:
    out = tmp_path / "out"
    target = "/proc/guardsim-no-such-file" + {"--godot": ".tscn", "--export": ".json", "--tiled-out": ".tmj"}[option]
    result = run("patrol", level, "--out", out, option, target)
    assert result.exit_code == 2, result.output
    assert not out.exists(), sorted(out.iterdir())


# --- routes ---------------------------------------------------------------------------------------------


def test_a_sneak_json_route_is_read_as_its_grid_cells_centres(tmp_path: Path) -> None:
    # sneak.json's path is [col, row] cells; at cell size 0.5 it was read as world [x, y] and refused.
    sneak = _write(tmp_path / "sneak.json", {"cell_size": 0.5, "origin": [1, 2], "path": [[4, 4], [5, 4], [5, 5]]})
    assert read_route_points(str(sneak)) == [(3.25, 4.25), (3.75, 4.25), (3.75, 4.75)]
    plain = _write(tmp_path / "route.json", [[2.5, 2.5], [3.5, 2.5]])
    assert read_route_points(str(plain)) == [(2.5, 2.5), (3.5, 2.5)]


@pytest.mark.slow
def test_alert_walks_the_documented_sneak_route_at_cell_size_half(tmp_path: Path) -> None:
    half = _write(tmp_path / "half.json", {**PILLAR, "name": "half", "cell_size": 0.5})
    assert run("patrol", half, "--out", tmp_path / "p").exit_code == 0
    sneak = run("sneak", half, "--patrol", tmp_path / "p" / "patrol.json", "--from", "1.25,1.25", "--to",
                "8.75,8.75", "--out", tmp_path / "s")  # fmt: skip
    assert sneak.exit_code == 0, sneak.output
    route = tmp_path / "s" / "sneak.json"
    result = run("alert", half, "--patrol", tmp_path / "p" / "patrol.json", "--intruder", "route", "--route", route)
    assert result.exit_code == 0, result.output


# --- optimum, bounds, validate --fix --------------------------------------------------------------------


def test_an_unsettled_smallest_team_keeps_the_proved_answer() -> None:
    from guardsim.level import parse_level
    from guardsim.optimum.guaranteed import guaranteed_data, guaranteed_search, search_region, smallest_team
    from guardsim.scene import Scene
    from guardsim.vision.table import view_table

    level = parse_level({**PILLAR, "guard": {"view_range": 2, "fov_degrees": 90}})
    scene = Scene.from_level(level)
    table = view_table(scene.grid, scene.vision())
    everywhere = search_region(scene.grid, None, 0)
    start = ((0, 0), 0)
    alone = guaranteed_search(scene.grid, table, [start], everywhere, max_pairs=20_000)
    assert alone.proved and alone.impossible
    # Room for the one-guard search, not for two guards (far more pairs).
    team = smallest_team(scene.grid, table, start, everywhere, max_pairs=alone.pairs)
    assert team is not None and team[0] == 2 and not team[1].proved
    data = guaranteed_data(alone, level="ten", search_from="all", radius=0, teams=[start], smallest_team=team)
    assert data["proved"] is True and data["smallest_team"] is None and data["smallest_team_settled"] is False


def test_validate_fix_of_more_holes_than_it_repairs_refuses_in_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import guardsim.validate.repair as repair

    monkeypatch.setattr(repair, "MAX_REPAIR_HOLES", 3)
    holes = [[[1 + 2 * i, 1], [2 + 2 * i, 1], [2 + 2 * i, 2], [1 + 2 * i, 2]] for i in range(4)]
    path = _write(tmp_path / "holes.json", {"outer": [[0, 0], [10, 0], [10, 4], [0, 4]], "holes": holes})
    fixed = tmp_path / "fixed.json"
    line = assert_one_line_error(run("validate", path, "--fix", fixed), path)
    assert "--fix repairs levels of at most 3 different holes and this one has 4" in line
    assert not fixed.exists()


@pytest.mark.slow
def test_validate_fix_of_24000_holes_refuses_in_one_line(tmp_path: Path) -> None:
    holes = [
        [[1 + 2.5 * i, 1 + 2.5 * j], [2 + 2.5 * i, 1 + 2.5 * j], [2 + 2.5 * i, 2 + 2.5 * j], [1 + 2.5 * i, 2 + 2.5 * j]]
        for i in range(160)
        for j in range(150)
    ]
    assert len(holes) > MAX_REPAIR_HOLES
    path = _write(tmp_path / "holes.json", {"outer": [[0, 0], [402, 0], [402, 378], [0, 378]], "holes": holes})
    fixed = tmp_path / "fixed.json"
    line = assert_one_line_error(run("validate", path, "--fix", fixed), path)
    assert f"at most {MAX_REPAIR_HOLES} different holes and this one has 24000" in line
    assert not fixed.exists()


@pytest.mark.slow
def test_bounds_by_default_searches_within_its_budget_and_says_how_to_raise_it() -> None:
    from tests.common import SHARED

    level = SHARED / "maps" / "movingai" / "random-32-32-20.map"
    if not level.exists():
        pytest.skip(f"{level} is missing")
    result = run("bounds", level)
    assert result.exit_code == 0, result.output
    assert "(stopped by expansions after 4000 expansions; --search-expansions N searches further)" in result.output


def _tiny_tiled() -> dict[str, Any]:
    """A 6 x 5 Tiled JSON map: a floor layer and a wall layer round its edge."""
    cols, rows = 6, 5
    wall = [1 if col in (0, cols - 1) or row in (0, rows - 1) else 0 for row in range(rows) for col in range(cols)]
    layer = {"type": "tilelayer", "width": cols, "height": rows, "x": 0, "y": 0, "visible": True, "opacity": 1}
    return {
        "type": "map",
        "orientation": "orthogonal",
        "renderorder": "right-down",
        "width": cols,
        "height": rows,
        "tilewidth": 16,
        "tileheight": 16,
        "infinite": False,
        "version": "1.10",
        "tiledversion": "1.10.2",
        "tilesets": [{"firstgid": 1, "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 2, "columns": 2}],
        "layers": [
            {**layer, "id": 1, "name": "floor", "data": [2] * (cols * rows)},
            {**layer, "id": 2, "name": "walls", "data": wall},
        ],
        "nextlayerid": 3,
        "nextobjectid": 1,
    }


def test_the_tiny_tiled_map_imports(tmp_path: Path) -> None:
    imported = import_map(_write(tmp_path / "map.tmj", _tiny_tiled()))
    assert int(np.asarray(imported.level.grid_shape()).prod()) > 0 and imported.level.holes


@pytest.mark.parametrize(
    ("text", "phrase"),
    [("guards = 1\nmax_idleness = " + "9" * 5001 + "\n", "not valid TOML for guardsim"),
     ("safe = [[nan, 1.5]]\n", "safe[0][0]: nan is not a finite number")],
    ids=["5001-digits", "nan"],
)  # fmt: skip
def test_toml_numbers_json_cannot_hold_are_one_line(tmp_path: Path, text: str, phrase: str) -> None:
    path = _write(tmp_path / "checks.toml", text)
    with pytest.raises(CheckError, match=r"checks\.toml: ") as error:
        read_checks(path)
    assert phrase in str(error.value) and "\n" not in str(error.value)


# --- the newer inputs: cameras, light, noise, the design commands (tests/fuzz_newer.py) -------------------


def _watched(**changes: Any) -> dict[str, Any]:
    from tests.fuzz_newer import BASE

    return {**json.loads(json.dumps(BASE)), **changes}


@pytest.mark.parametrize(
    ("camera", "phrase"),
    [({"position": [4, 3], "sweep": 360, "turn_speed": 0.001, "pause": 0}, "swing is 1440000 ticks, over the limit"),
     ({"position": [4, 3], "sweep": 90, "turn_speed": 1e-300}, "swing of 1.8e+302 s is over")],
    ids=["past-the-lap", "past-any-tick-count"],
)  # fmt: skip
def test_a_camera_swing_too_long_names_the_level_file(camera: dict[str, Any], phrase: str) -> None:
    # The limit's line named the camera but not the file it is in.
    from guardsim.detection.watch import level_watch
    from guardsim.errors import LimitError
    from guardsim.level import parse_level
    from guardsim.scene import Scene

    level = parse_level(_watched(cameras=[camera]), source="watched.json")
    with pytest.raises(LimitError, match=r"^watched\.json: cameras\[0\]'s ") as error:
        level_watch(Scene.from_level(level), 0.5)
    assert phrase in str(error.value)


def test_a_joint_lap_past_the_limit_names_the_level_file() -> None:
    from guardsim.detection.watch import joint_lap, level_watch
    from guardsim.errors import LimitError
    from guardsim.level import parse_level
    from guardsim.scene import Scene

    watch = level_watch(Scene.from_level(parse_level(_watched(), source="watched.json")), 0.5)
    assert watch.periods == (10,)
    with pytest.raises(LimitError, match=r"^watched\.json: the joint lap of the patrol's 7 ticks .* is 70 ticks"):
        joint_lap(7, watch, max_lap=20)


@pytest.mark.parametrize(
    "changes",
    [{"ambient_light": None}, {"cameras": None}, {"lights": None},
     {"cameras": [{"position": [4, 3], "heading": None}]}, {"lights": [{"position": [1, 5], "radius": 3, "intensity": None}]}],
    ids=["ambient", "cameras", "lights", "camera-heading", "light-intensity"],
)  # fmt: skip
def test_null_where_the_schema_wants_a_number_or_list_is_refused(changes: dict[str, Any]) -> None:
    # null was read as the default where the schema (and guardsim schema's users) refuse it.
    import jsonschema

    from guardsim.files.schema import level_schema
    from guardsim.level import parse_level

    data = _watched(**changes)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(data, level_schema())
    with pytest.raises(LevelError, match=r"^watched\.json: (ambient_light|cameras|lights)\S*: must be .*not null"):
        parse_level(data, source="watched.json")


def test_a_noise_heard_everywhere_is_heard_everywhere() -> None:
    # A walk_noise of 1e308 made a 309-digit step count the compiled search could not take (TypingError).
    from guardsim.kernels.noise import MAX_NOISE_STEPS, heard_within, noise_steps

    assert noise_steps(1e308, 1.0) == noise_steps(1e308, 1e-300) == MAX_NOISE_STEPS
    corridor = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1], [-1, -1, -1, -1]])
    assert heard_within(corridor, 0, 1e308, 1.0, np.array([1, 2, 3])).tolist() == [True, True, False]


@pytest.mark.parametrize(("command", "option"), [("report", "--html"), ("diff", "--png"), ("diff", "--json")])
def test_a_design_output_that_cannot_be_written_is_refused_before_any_work(
    tmp_path: Path, command: str, option: str
) -> None:
    # report wrote report.json, then failed on --html into a folder: half its outputs were left behind.
    level = _write(tmp_path / "watched.json", _watched())
    folder = tmp_path / "adir"
    folder.mkdir()
    first: list[str | Path] = ["--json", tmp_path / "r.json"] if option != "--json" else ["--png", tmp_path / "r.png"]
    levels: list[str | Path] = [level] if command == "report" else [level, level]
    line = assert_one_line_error(run(command, *levels, *first, option, folder), folder)
    assert line.startswith(f"guardsim: error: {option} ") and "Is a directory" in line
    assert not (tmp_path / "r.json").exists() and not (tmp_path / "r.png").exists()


def test_an_empty_design_output_name_is_refused(tmp_path: Path) -> None:
    result = run("report", _write(tmp_path / "watched.json", _watched()), "--json", "")
    assert result.exit_code == 2 and "--json" in result.stderr and "Traceback" not in result.output


def test_tick_hz_in_a_level_is_bounded_as_the_option_is() -> None:
    import jsonschema

    from guardsim.files.schema import level_schema
    from guardsim.level import parse_level
    from guardsim.level.limits import MAX_TICK_HZ

    data = {**PILLAR, "guard": {"tick_hz": 100_000}}
    with pytest.raises(LevelError, match=r"^ten\.json: guard\.tick_hz: must be at most 1000, not 100000$"):
        parse_level(data, source="ten.json")
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(data, level_schema())
    assert parse_level({**PILLAR, "guard": {"tick_hz": MAX_TICK_HZ}}).guard.tick_hz == MAX_TICK_HZ


@pytest.mark.parametrize(
    ("item", "phrase"),
    [({"throw": [5.5, 5.5], "at": 1, "noise": 2, "x" * 3000: 1}, "unknown key 'xxxx"),
     ({"to": [1.5, 1.5], "gait": "s" * 5000}, "gait 'ssss")],
    ids=["throw-key", "gait"],
)  # fmt: skip
def test_a_long_key_or_gait_in_a_route_file_is_quoted_short(tmp_path: Path, item: dict[str, Any], phrase: str) -> None:
    # Echoed whole: a 3,000-character line.
    from guardsim.alert.intruders import read_route_file
    from guardsim.errors import GuardsimError

    route = _write(tmp_path / "route.json", [[0.5, 0.5], item])
    with pytest.raises(GuardsimError, match=r"route\.json: item 1: ") as error:
        read_route_file(str(route))
    assert phrase in str(error.value) and len(str(error.value)) < 300


def test_report_alert_episodes_are_bounded_as_alert_s(tmp_path: Path) -> None:
    # report --alert 10**400 ran past any timeout: alert --episodes stops at 100,000.
    from guardsim.design.report import MAX_ALERT_EPISODES

    level = _write(tmp_path / "watched.json", _watched())
    result = run("report", level, "--alert", str(MAX_ALERT_EPISODES + 1))
    assert result.exit_code == 2 and "--alert" in result.stderr and "Traceback" not in result.output


def test_watch_refuses_an_empty_host_and_quotes_a_long_one_short(tmp_path: Path) -> None:
    # --host '' listened on every address of the machine; a 3,000-character host was echoed whole.
    # (A non-ASCII name too long for IDNA fails before any name is looked up: nothing is contacted.)
    pytest.importorskip("uvicorn")
    level = _write(tmp_path / "watched.json", _watched())
    empty = run("watch", level, "--host", "", "--port", "0")
    assert empty.exit_code == 2 and empty.stderr.startswith("guardsim: error: --host: an empty address")
    long = run("watch", level, "--host", "\u00fc" * 3000, "--port", "0")
    assert long.exit_code == 2 and len(long.stderr.splitlines()) == 1 and len(long.stderr) < 300, long.stderr
    assert "cannot be listened on (not an address): give another --host or --port" in long.stderr


def test_starts_on_no_part_of_the_floor_keep_the_whole_level() -> None:
    # A mutated village map whose only start lies in a wall: every part was dropped, the kept floor was
    # empty and its bounds NaN (ValueError from math.floor inside the importer).
    from guardsim.importers.tiled_spawns import keep_spawn_areas
    from guardsim.level import parse_level
    from tests.common import SPLIT_ROOMS

    level = parse_level(SPLIT_ROOMS, source="split.tmj")
    kept, said = keep_spawn_areas(level, [(3.0, 1.5)], source="split.tmj", max_cells=10_000, max_vertices=1_000)
    assert kept is level and said == ""


# --- fortify's options (tests/fuzz_newer.py's fortify-option kind) -------------------------------------

_FORTIFY_SQUARE: dict[str, Any] = {
    "name": "tiny",
    "outer": [[0, 0], [6, 0], [6, 6], [0, 6]],
    "holes": [[[2, 2], [4, 2], [4, 4], [2, 4]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}


def test_fortify_sealed_by_its_last_round_says_sealed(tmp_path: Path) -> None:
    # The second round added the post that seals the pair and the budget left no round to search it:
    # the document said "not sealed" with no open pair, and the command's line raised IndexError.
    level = _write(tmp_path / "tiny.json", _FORTIFY_SQUARE)
    result = run("fortify", level, "--from", "0.5,0.5", "--to", "5.5,5.5", "--candidates", "8", "--max-rounds", "2",
                 "--out", tmp_path / "out")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("tiny: sealed (undetected) with 2 watchers")
    document = json.loads((tmp_path / "out" / "fortify.json").read_text(encoding="utf-8"))
    assert document["sealed"] and document["reason"] is None and document["search_rounds"] == 2
    assert all(pair["sealed"] for pair in document["pairs"])


@pytest.mark.parametrize(("option", "point", "phrase"), [("--to", "3,3", "a wall"), ("--from", "60,60", "outside")])
def test_fortify_points_name_their_option(tmp_path: Path, option: str, point: str, phrase: str) -> None:
    # "pair 1's goal 3,3 is in cell [3, 3]": the line named neither --to nor --from.
    level = _write(tmp_path / "tiny.json", _FORTIFY_SQUARE)
    args = {"--from": "0.5,0.5", "--to": "5.5,5.5", option: point}
    line = assert_one_line_error(run("fortify", level, "--from", args["--from"], "--to", args["--to"]), option)
    assert phrase in line


@pytest.mark.parametrize("picture", ["adir", ""])
def test_fortify_picture_that_cannot_be_written_is_refused_before_any_work(tmp_path: Path, picture: str) -> None:
    # --out D --picture into a folder: D/fortify.json, level.json and patrol.json were written first; an
    # empty --picture failed as ".: cannot write: Device or resource busy", naming no option.
    level = _write(tmp_path / "tiny.json", _FORTIFY_SQUARE)
    (tmp_path / "adir").mkdir()
    target = str(tmp_path / picture) if picture else ""
    result = run("fortify", level, "--from", "0.5,0.5", "--to", "5.5,5.5", "--max-rounds", "2", "--candidates", "8",
                 "--out", tmp_path / "out", "--picture", target)  # fmt: skip
    assert_one_line_error(result, "--picture")
    assert not (tmp_path / "out" / "fortify.json").exists()
