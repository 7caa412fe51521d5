"""LDtk projects: LDtk's own samples land with walls exactly on their wall IntGrid cells, entities become
guard spawns and player starts, ``--level`` picks a level, and every malformed project is one line.

The samples are LDtk's (MIT) in ``../shared/maps/corpus/ldtk`` (see tests/data/maps/ldtk/SOURCES.md); the
small projects written here are our own.
"""

from __future__ import annotations

import copy
import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import shapely

from guardsim.errors import LevelError
from guardsim.importers import FORMATS
from guardsim.importers.ldtk import import_ldtk, is_ldtk_json
from tests.common import CORPUS, assert_one_line_error, import_map, load_any, needs_shared, run

LDTK_DIR = CORPUS / "ldtk"
TOP_DOWN = LDTK_DIR / "Typical_TopDown_example.ldtk"
ENTITIES = LDTK_DIR / "Entities.ldtk"
SEPARATE = LDTK_DIR / "SeparateLevelFiles.ldtk"
# LDtk's own sample projects (tests/data/maps/ldtk/SOURCES.md) are third-party data kept beside the clone.
needs_samples = needs_shared(SEPARATE)

#: (project, level, IntGrid layer holding the walls) for every level of the kept samples.
SAMPLE_LEVELS = [
    (TOP_DOWN, "World_Level_0", "Collisions"),
    (TOP_DOWN, "World_Level_1", "Collisions"),
    (TOP_DOWN, "World_Level_2", "Collisions"),
    (ENTITIES, "Entities_demo", "Collisions"),
    (SEPARATE, "World_Level_0", "IntGrid"),
    (SEPARATE, "World_Level_1", "IntGrid"),
    (SEPARATE, "World_Level_2", "IntGrid"),
]


def layer_json(project: Path, level: str, layer: str) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    """The level, the named layer instance and its definition, read straight from the JSON (and .ldtkl)."""
    root = json.loads(project.read_text(encoding="utf-8"))
    found = next(item for item in root["levels"] if item["identifier"] == level)
    if found["layerInstances"] is None:
        found = json.loads((project.parent / found["externalRelPath"]).read_text(encoding="utf-8"))
    instance = next(item for item in found["layerInstances"] if item["__identifier"] == layer)
    definition = next(item for item in root["defs"]["layers"] if item["uid"] == instance["layerDefUid"])
    return found, instance, definition


def wall_cells(project: Path, level: str, layer: str) -> np.ndarray:
    """``bool (rows, cols)``: the cells holding a value the layer definition names 'walls'."""
    _, instance, definition = layer_json(project, level, layer)
    walls = [value["value"] for value in definition["intGridValues"] if value["identifier"] == "walls"]
    grid = np.array(instance["intGridCsv"]).reshape(instance["__cHei"], instance["__cWid"])
    return np.isin(grid, walls)


def free_cells(level: Any, shape: tuple[int, int]) -> np.ndarray:
    """``bool (rows, cols)``: the cells whose centre is on the level's free area."""
    rows, cols = np.mgrid[0 : shape[0], 0 : shape[1]]
    return shapely.contains_xy(level.free_area(), cols + 0.5, rows + 0.5)


@needs_samples
@pytest.mark.parametrize(
    ("project", "level", "layer"), SAMPLE_LEVELS, ids=[f"{p.stem}-{lv}" for p, lv, _ in SAMPLE_LEVELS]
)
def test_sample_walls_are_exactly_the_wall_cells(project: Path, level: str, layer: str) -> None:
    """Cell by cell: a cell is wall exactly where the IntGrid layer holds its 'walls' value.

    The Entities sample has guard spawns, so a free pocket holding none is left out (as in Tiled maps):
    those cells are not walls, not free, closed in by walls, and hold no spawn.
    """
    walls = wall_cells(project, level, layer)
    imported = import_ldtk(project, level=level)
    found, _, _ = layer_json(project, level, layer)
    assert imported.map_size == (found["pxWid"] // 16, found["pxHei"] // 16) == walls.shape[::-1]
    whole = (0, 0, walls.shape[1], walls.shape[0])
    if project == ENTITIES:  # parts left out: the level is cropped to the whole cells around those kept
        left, top, right, bottom = imported.level.bounds
        assert left >= 0 and top >= 0 and right <= whole[2] and bottom <= whole[3]
        assert (left, top, right, bottom) != whole and "cropped to the parts kept" in imported.summary()
    else:
        assert imported.level.bounds == whole
    free = free_cells(imported.level, walls.shape)
    assert not (free & walls).any(), "a wall cell is free"
    left_out = ~free & ~walls
    if project != ENTITIES:
        assert not left_out.any(), np.argwhere(left_out)[:5]
        return
    assert left_out.sum() == 40
    # Closed in: each neighbour is left out too, a wall, or outside the level.
    closed = np.pad(left_out | walls, 1, constant_values=True)
    for row, col in np.argwhere(left_out) + 1:
        assert closed[row - 1, col] and closed[row + 1, col] and closed[row, col - 1] and closed[row, col + 1]
    for x, y in imported.level.starts:
        assert not left_out[int(y), int(x)]


@needs_samples
def test_sample_counts() -> None:
    """The numbers the samples give (floor cells, wall cells, guard spawns, player starts)."""
    counts = {}
    for project, level, layer in SAMPLE_LEVELS:
        imported = import_ldtk(project, level=level)
        walls = wall_cells(project, level, layer)
        free = free_cells(imported.level, walls.shape)
        counts[f"{project.stem}/{level}"] = (
            int(free.sum()),
            int(walls.sum()),
            len(imported.level.starts),
            len(imported.player_starts),
        )
    assert counts == {
        "Typical_TopDown_example/World_Level_0": (312, 200, 0, 1),
        "Typical_TopDown_example/World_Level_1": (166, 90, 0, 0),
        "Typical_TopDown_example/World_Level_2": (183, 73, 0, 0),
        "Entities/Entities_demo": (370, 1069, 3, 1),
        "SeparateLevelFiles/World_Level_0": (207, 18, 0, 0),
        "SeparateLevelFiles/World_Level_1": (205, 20, 0, 0),
        "SeparateLevelFiles/World_Level_2": (212, 13, 0, 0),
    }


@needs_samples
def test_entities_become_guard_spawns_and_a_player_start() -> None:
    """Enemy entities are guard spawns at their boxes' centres, PlayerStart the player's start only."""
    root = json.loads(ENTITIES.read_text(encoding="utf-8"))
    entities = [item for layer in root["levels"][0]["layerInstances"] for item in layer["entityInstances"]]

    def centre(item: dict[str, Any]) -> tuple[float, float]:
        (x, y), (px, py) = item["px"], item["__pivot"]
        return ((x + (0.5 - px) * item["width"]) / 16, (y + (0.5 - py) * item["height"]) / 16)

    enemies = [centre(item) for item in entities if item["__identifier"] == "Enemy"]
    player = [centre(item) for item in entities if item["__identifier"] == "PlayerStart"]
    imported = import_ldtk(ENTITIES)
    level = imported.level
    assert [tuple(point) for point in level.starts] == enemies
    assert level.guard.start is not None and tuple(level.guard.start) == enemies[0]
    assert imported.player_starts == tuple(player) == ((4.5, 22.375),)
    assert [tuple(point) for point in level.player_starts] == player
    assert not set(player) & {tuple(point) for point in level.starts}
    assert any("3 guard spawns from entities 'Enemy' x 3" in change for change in imported.changes)
    assert any("1 player start (4.5, 22.375) from 'PlayerStart'" in change for change in imported.changes)


@needs_samples
def test_no_guard_spawn_leaves_the_start_to_the_command() -> None:
    """As for Tiled maps: no spawn, no starts in the level; the player start is still kept."""
    imported = import_ldtk(TOP_DOWN)
    assert imported.level.starts == ()
    assert imported.player_starts == ((10.5, 10.5),)
    assert "0 guard spawns" in imported.changes
    assert not imported.warnings


@needs_samples
def test_first_level_by_default_names_the_others() -> None:
    imported = import_ldtk(TOP_DOWN)
    assert imported.level.name == "Typical_TopDown_example World_Level_0"
    note = next(change for change in imported.changes if change.startswith("imported the first"))
    assert "'World_Level_0'" in note and "'World_Level_1'" in note and "'World_Level_2'" in note
    assert "--level" in note


@needs_samples
def test_level_option_picks_a_level(tmp_path: Path) -> None:
    out = tmp_path / "level.json"
    result = run("import", TOP_DOWN, "--out", out, "--level", "World_Level_2")
    assert result.exit_code == 0, result.output
    data = json.loads(out.read_text(encoding="utf-8"))
    assert data["name"] == "Typical_TopDown_example World_Level_2"
    assert data["outer"] == [[0, 0], [16, 0], [16, 16], [0, 16]]
    assert "imported the first" not in result.stdout
    # Any case, when no level has the exact name.
    assert import_ldtk(TOP_DOWN, level="world_level_1").level.name.endswith("World_Level_1")


@needs_samples
def test_unknown_level_is_one_line_listing_the_levels(tmp_path: Path) -> None:
    result = run("import", TOP_DOWN, "--out", tmp_path / "out.json", "--level", "Basement")
    line = assert_one_line_error(result, TOP_DOWN)
    assert line.endswith("no level 'Basement'; the levels are 'World_Level_0', 'World_Level_1', 'World_Level_2'")
    assert not (tmp_path / "out.json").exists()


@needs_samples
def test_external_level_files_are_read(tmp_path: Path) -> None:
    """externalLevels: the level's layers come from its .ldtkl; a missing one is one line naming it."""
    imported = import_ldtk(SEPARATE, level="World_Level_1")
    assert len(imported.level.holes) == 3
    copy_dir = tmp_path / "project"
    shutil.copytree(LDTK_DIR, copy_dir, ignore=shutil.ignore_patterns("*.md", "Typical*", "Entities*"))
    (copy_dir / "SeparateLevelFiles" / "World_Level_2.ldtkl").unlink()
    result = run(
        "import", copy_dir / "SeparateLevelFiles.ldtk", "--out", tmp_path / "o.json", "--level", "World_Level_2"
    )
    line = assert_one_line_error(result, copy_dir / "SeparateLevelFiles.ldtk")
    assert "levels[2].externalRelPath: level file" in line and "World_Level_2.ldtkl not found" in line


@needs_samples
def test_ldtk_json_file_is_imported_as_ldtk(tmp_path: Path) -> None:
    """A project saved as .json is told from a Tiled map and a level by its content."""
    path = tmp_path / "project.json"
    shutil.copy(ENTITIES, path)
    assert is_ldtk_json(json.loads(path.read_text(encoding="utf-8")))
    level, imported = load_any(path)
    assert imported is not None and imported.kind == "LDtk project"
    assert len(level.starts) == 3
    assert import_map(path).kind == "LDtk project"
    result = run("validate", path)
    assert result.exit_code == 0, result.output


# Small projects written here.


def project(
    csv: list[Any] | None = None,
    *,
    cols: int = 4,
    rows: int = 3,
    values: tuple[tuple[int, str], ...] = ((1, "walls"),),
    entities: tuple[tuple[str, int, int], ...] = (),
) -> dict[str, Any]:
    """A one-level project: an Entities layer and an IntGrid layer 'Terrain' of 16-pixel cells."""
    csv = [1] * cols + [1, 0, 0, 1] * (rows - 2) + [1] * cols if csv is None else csv
    return {
        "__header__": {"fileType": "LDtk Project JSON", "app": "LDtk"},
        "jsonVersion": "1.5.3",
        "defaultGridSize": 16,
        "defs": {
            "layers": [
                {"__type": "Entities", "identifier": "Things", "uid": 2, "gridSize": 16},
                {
                    "__type": "IntGrid",
                    "identifier": "Terrain",
                    "uid": 1,
                    "gridSize": 16,
                    "intGridValues": [{"value": value, "identifier": name} for value, name in values],
                },
            ]
        },
        "levels": [
            {
                "identifier": "Level_0",
                "pxWid": cols * 16,
                "pxHei": rows * 16,
                "layerInstances": [
                    {
                        "__identifier": "Things",
                        "__type": "Entities",
                        "__gridSize": 16,
                        "layerDefUid": 2,
                        "entityInstances": [
                            {"__identifier": name, "px": [x, y], "__pivot": [0.5, 0.5], "width": 16, "height": 16}
                            for name, x, y in entities
                        ],
                    },
                    {
                        "__identifier": "Terrain",
                        "__type": "IntGrid",
                        "__cWid": cols,
                        "__cHei": rows,
                        "__gridSize": 16,
                        "layerDefUid": 1,
                        "intGridCsv": csv,
                    },
                ],
            }
        ],
    }


def write(folder: Path, data: Any, name: str = "map.ldtk") -> Path:
    path = folder / name
    path.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return path


def test_small_project_walls_spawn_and_player(tmp_path: Path) -> None:
    data = project(cols=6, rows=4, csv=[1] * 6 + [1, 0, 0, 0, 0, 1] * 2 + [1] * 6,
                   entities=(("Guard", 24, 24), ("Hero", 72, 40)))  # fmt: skip
    imported = import_ldtk(write(tmp_path, data))
    assert imported.level.holes and imported.level.bounds == (0, 0, 6, 4)
    assert imported.level.starts == ((1.5, 1.5),)
    assert imported.level.player_starts == ((4.5, 2.5),)
    assert imported.level.tile_pixels == (16, 16)  # one 16-px cell is one world unit
    assert not imported.warnings


@pytest.mark.parametrize(
    ("name", "group", "wall"),
    [("Walls", "", True), ("SOLID_rock", "", True), ("block", "", True), ("obstacle", "", True),
     ("Wallpaper", "", False), ("dirt", "", False), ("dirt", "walls", True), ("ladder", "climb", False)],
)  # fmt: skip
def test_value_names_say_wall_in_whole_words(tmp_path: Path, name: str, group: str, wall: bool) -> None:
    data = project(values=((1, name),))
    if group:
        layer = data["defs"]["layers"][1]
        layer["intGridValuesGroups"] = [{"uid": 5, "identifier": group}]
        layer["intGridValues"][0]["groupUid"] = 5
    imported = import_ldtk(write(tmp_path, data))
    assert bool(imported.level.holes) == wall
    assert any(warning.startswith("no walls found") for warning in imported.warnings) == (not wall)


def test_no_wall_values_warn_and_wall_value_fixes_it(tmp_path: Path) -> None:
    path = write(tmp_path, project(values=((1, "dirt"), (2, "water"))))
    imported = import_ldtk(path)
    assert imported.level.holes == ()
    (warning,) = imported.warnings
    assert warning.startswith("no walls found: no IntGrid value is named like a wall")
    assert "'Terrain' has 1 'dirt', 2 'water'" in warning and "--wall-value" in warning
    result = run("import", path, "--out", tmp_path / "o.json", "--strict")
    assert result.exit_code == 1 and "no walls found" in result.stderr
    for given in ("dirt", "DIRT", "1"):
        assert import_ldtk(path, wall_values=[given]).level.holes, given
    result = run("import", path, "--out", tmp_path / "o.json", "--wall-value", "dirt", "--wall-value", "lava")
    assert result.exit_code == 0, result.output
    assert "walls from IntGrid 'Terrain' values 1 'dirt'" in result.stdout
    assert "--wall-value 'lava' matches no IntGrid value" in result.stderr


def test_wall_value_replaces_the_name_guess(tmp_path: Path) -> None:
    csv = [2] * 4 + [1, 0, 0, 1] + [2] * 4
    imported = import_ldtk(write(tmp_path, project(csv, values=((1, "walls"), (2, "water")))), wall_values=[2])
    assert "values 2 'water' (8 cells) (--wall-value)" in "; ".join(imported.changes)


def test_old_intgrid_format_is_read(tmp_path: Path) -> None:
    """Before LDtk 0.8, IntGrid cells were {coordId, v} with v the value's index from 0."""
    data = project()
    layer = data["levels"][0]["layerInstances"][1]
    del layer["intGridCsv"]
    layer["intGrid"] = [{"coordId": 0, "v": 0}, {"coordId": 5, "v": 0}]
    imported = import_ldtk(write(tmp_path, data))
    assert len(imported.level.holes) == 2


def test_unknown_layer_type_is_ignored_with_a_note(tmp_path: Path) -> None:
    data = project()
    data["levels"][0]["layerInstances"].append({"__identifier": "Lights", "__type": "Lighting"})
    imported = import_ldtk(write(tmp_path, data))
    assert "ignored layer 'Lights' of unknown type 'Lighting'" in imported.changes
    assert imported.level.holes


def test_entities_in_a_layer_named_for_guards_are_spawns(tmp_path: Path) -> None:
    data = project(cols=6, rows=4, csv=[1] * 6 + [1, 0, 0, 0, 0, 1] * 2 + [1] * 6,
                   entities=(("Marker", 24, 24), ("PlayerStart", 56, 24), ("Crate", 72, 40)))  # fmt: skip
    data["levels"][0]["layerInstances"][0]["__identifier"] = "Enemies"
    data["levels"][0]["layerInstances"][0]["entityInstances"][2]["__tags"] = ["loot"]
    level = import_ldtk(write(tmp_path, data)).level
    assert level.starts == ((1.5, 1.5), (4.5, 2.5))
    assert level.player_starts == ((3.5, 1.5),)


def mutate(data: dict[str, Any], path: str, value: Any) -> dict[str, Any]:
    """A copy of ``data`` with the value at the dotted ``path`` replaced (``DELETE`` removes the key)."""
    data = copy.deepcopy(data)
    *parents, last = [int(part) if part.isdigit() else part for part in path.split(".")]
    target: Any = data
    for part in parents:
        target = target[part]
    if value is DELETE:
        del target[last]
    else:
        target[last] = value
    return data


DELETE = object()
LAYER = "levels.0.layerInstances.1"

BAD_PROJECTS = [
    (f"{LAYER}.intGridCsv", [1] * 10, "levels[0].layerInstances[1].intGridCsv: 10 values, expected 12"),
    (f"{LAYER}.intGridCsv", "1,0,1", "levels[0].layerInstances[1].intGridCsv: expected a list of whole numbers"),
    (f"{LAYER}.intGridCsv.5", "x", "levels[0].layerInstances[1].intGridCsv[5]: expected a whole number from 0 up"),
    (f"{LAYER}.intGridCsv.5", -1, "intGridCsv[5]: expected a whole number from 0 up, not -1"),
    (f"{LAYER}.intGridCsv.5", 1.5, "intGridCsv[5]: expected a whole number from 0 up, not 1.5"),
    (f"{LAYER}.intGridCsv", DELETE, "levels[0].layerInstances[1].intGridCsv: missing"),
    (f"{LAYER}.__cWid", "four", "levels[0].layerInstances[1].__cWid: expected a whole number, not 'four'"),
    (f"{LAYER}.__gridSize", 0, "levels[0].layerInstances[1].__gridSize: must be from 1"),
    (f"{LAYER}.__gridSize", True, "levels[0].layerInstances[1].__gridSize: expected a whole number, not true"),
    (f"{LAYER}.__type", DELETE, "levels[0].layerInstances[1].__type: missing"),
    (f"{LAYER}.layerDefUid", 99, "levels[0].layerInstances[1].layerDefUid: 99 is no layer of defs.layers"),
    ("levels.0.pxWid", DELETE, "levels[0].pxWid: missing"),
    ("levels.0.pxHei", "tall", "levels[0].pxHei: expected a whole number, not 'tall'"),
    ("levels.0.identifier", 7, "levels[0].identifier: expected a name, not a number"),
    ("levels.0.layerInstances", DELETE, "levels[0].layerInstances: missing (null, and no externalRelPath"),
    ("levels.0.layerInstances", {"a": 1}, "levels[0].layerInstances: expected a list, not an object"),
    ("levels.0.layerInstances.0.entityInstances.0.px", [1], "entityInstances[0].px: expected [x, y], not [1]"),
    ("levels.0.layerInstances.0.entityInstances.0.px.1", "y", "entityInstances[0].px[1]: expected a number, not 'y'"),
    ("levels.0.externalRelPath", "/etc/level.ldtkl", "levels[0].externalRelPath: must be relative to the project"),
    ("levels", [], "levels: the project has no levels"),
    ("levels", "all", "levels: expected a list, not a string"),
    ("defs", DELETE, "defs: missing"),
    ("defs.layers.1.intGridValues.0.value", "one", "defs.layers[1].intGridValues[0].value: expected a whole number"),
    ("defs.layers.1.uid", None, "defs.layers[1].uid: expected a whole number, not null"),
]


@pytest.mark.parametrize(
    ("path", "value", "message"),
    BAD_PROJECTS,
    # The same ids in every xdist worker: DELETE's repr would hold its address.
    ids=[(f"{p}-deleted" if v is DELETE else f"{p}={v!r}")[:40] for p, v, _ in BAD_PROJECTS],
)
def test_malformed_project_is_one_line(tmp_path: Path, path: str, value: Any, message: str) -> None:
    data = project(entities=(("Guard", 24, 24),))
    if path == "levels.0.externalRelPath":
        data["levels"][0]["layerInstances"] = None
    bad = write(tmp_path, mutate(data, path, value))
    with pytest.raises(LevelError) as caught:
        import_ldtk(bad)
    assert str(caught.value).startswith(f"{bad}: ")
    assert message in str(caught.value)
    commands: list[list[str | Path]] = [["import", bad, "--out", tmp_path / "out.json"], ["play", bad]]
    for command in commands:
        line = assert_one_line_error(run(*command), bad)
        assert message in line
    result = run("validate", bad)
    assert result.exit_code != 0 and "Traceback" not in result.output
    assert message in result.stdout


@pytest.mark.parametrize(
    ("text", "message"),
    [("{", "not valid JSON"), ("[1, 2]", "expected an object, not a list"), ('{"__header__": {"app": "LDtk"}}', "defs: missing")],
)  # fmt: skip
def test_broken_json_is_one_line(tmp_path: Path, text: str, message: str) -> None:
    bad = write(tmp_path, text)
    line = assert_one_line_error(run("import", bad, "--out", tmp_path / "out.json"), bad)
    assert message in line


@needs_samples
def test_level_file_given_alone_says_to_import_the_project(tmp_path: Path) -> None:
    level_file = LDTK_DIR / "SeparateLevelFiles" / "World_Level_0.ldtkl"
    line = assert_one_line_error(run("play", level_file), level_file)
    assert "an LDtk level file: import the .ldtk project beside it" in line
    renamed = write(tmp_path, level_file.read_text(encoding="utf-8"))
    line = assert_one_line_error(run("import", renamed, "--out", tmp_path / "o.json"), renamed)
    assert "an LDtk level file, not a project" in line


def test_size_limit_is_one_line(tmp_path: Path) -> None:
    path = write(tmp_path, project())
    line = assert_one_line_error(run("import", path, "--out", tmp_path / "o.json", "--max-cells", "5"), path)
    assert "over the limit of 5 (raise it with --max-cells)" in line


@pytest.mark.parametrize(
    ("name", "text", "what"),
    [("level.tscn", '[gd_scene load_steps=2 format=3]\n\n[node name="L" type="Node2D"]\n', "(a Godot scene)"),
     ("res.tres", "[gd_resource]\n", "(a Godot resource)"), ("project.godot", "; Engine configuration\n", "(a Godot project)"),
     ("notes.txt", "hello", "and not JSON"), ("list.lvl", "[1, 2", "and not JSON")],
)  # fmt: skip
def test_unread_file_types_get_one_line_naming_the_formats(tmp_path: Path, name: str, text: str, what: str) -> None:
    path = write(tmp_path, text, name)
    commands: list[list[str | Path]] = [["play", path], ["import", path, "--out", tmp_path / "o.json"]]
    for command in commands:
        line = assert_one_line_error(run(*command), path)
        assert (
            f"unknown map type '{Path(name).suffix}' {what}; guardsim reads guardsim levels (.json) and imports" in line
        )
        assert all(suffix in line for suffix in FORMATS)
        assert "LDtk project .ldtk" in line


def test_import_options_carry_wall_values_and_level(tmp_path: Path) -> None:
    path = write(tmp_path, project(values=((1, "dirt"),)))
    level, imported = load_any(path, wall_values=("dirt",), level="level_0")
    assert imported is not None and level.holes and not imported.warnings


def test_walls_covering_the_level_is_one_line(tmp_path: Path) -> None:
    path = write(tmp_path, project([1] * 12))
    line = assert_one_line_error(run("import", path, "--out", tmp_path / "o.json"), path)
    assert line.endswith("the walls cover the whole of level 'Level_0': no free area")


def fine_layer(data: dict[str, Any], cells: list[tuple[int, int]], offset: tuple[int, int] = (0, 0)) -> None:
    """Add an IntGrid layer 'Fine' of 8-pixel cells (half the level's) whose value 1 is 'solid'."""
    csv = [0] * 48
    for col, row in cells:
        csv[row * 8 + col] = 1
    data["defs"]["layers"].append(
        {"__type": "IntGrid", "identifier": "Fine", "uid": 3, "gridSize": 8,
         "intGridValues": [{"value": 1, "identifier": "solid"}]}
    )  # fmt: skip
    data["levels"][0]["layerInstances"].append(
        {"__identifier": "Fine", "__type": "IntGrid", "__cWid": 8, "__cHei": 6, "__gridSize": 8, "layerDefUid": 3,
         "__pxTotalOffsetX": offset[0], "__pxTotalOffsetY": offset[1], "intGridCsv": csv}
    )  # fmt: skip


def test_a_finer_or_offset_wall_layer_lands_at_its_own_scale(tmp_path: Path) -> None:
    """One cell of the first wall layer is one unit; an 8-pixel layer's cells are half units, offsets in pixels."""
    data = project()
    fine_layer(data, [(3, 2)], offset=(4, 0))
    level = import_ldtk(write(tmp_path, data)).level
    free = level.free_area()
    assert shapely.area(free) == pytest.approx(2 - 0.25)
    # The 8-pixel cell (3, 2) shifted 4 pixels right: x 1.75 to 2.25, y 1 to 1.5.
    assert shapely.contains_xy(free, 1.7, 1.1) and not shapely.contains_xy(free, 1.8, 1.1)
    assert not shapely.contains_xy(free, 2.2, 1.4) and shapely.contains_xy(free, 2.3, 1.1)
    assert shapely.contains_xy(free, 2.0, 1.6)
    covered = project([1] * 4 + [1, 0, 0, 1] + [1] * 4, cols=4, rows=3)
    fine_layer(covered, [(2, 2), (3, 2), (4, 2), (5, 2), (2, 3), (3, 3), (4, 3), (5, 3)])
    with pytest.raises(LevelError, match="the walls cover the whole of level 'Level_0'"):
        import_ldtk(write(tmp_path, covered))


def test_levels_of_multi_world_projects_count(tmp_path: Path) -> None:
    data = project()
    data["worlds"] = [{"identifier": "Overworld", "levels": copy.deepcopy(data["levels"])}]
    data["worlds"][0]["levels"][0]["identifier"] = "Cave"
    data["worlds"][0]["levels"][0]["layerInstances"][1]["intGridCsv"] = [1] * 4 + [0, 0, 0, 1] + [1] * 4
    path = write(tmp_path, data)
    assert "(others: 'Cave'" in "; ".join(import_ldtk(path).changes)
    cave = import_ldtk(path, level="Cave").level
    assert cave.name == "map Cave" and shapely.area(cave.free_area()) == 3
    data["worlds"][0]["levels"][0]["pxWid"] = "wide"
    with pytest.raises(LevelError, match=r"map\.ldtk: worlds\[0\]\.levels\[0\]\.pxWid: expected a whole number"):
        import_ldtk(write(tmp_path, data), level="Cave")


def test_wall_values_painted_nowhere_warn(tmp_path: Path) -> None:
    imported = import_ldtk(write(tmp_path, project([0] * 12)))
    assert imported.warnings == ("no walls found: the wall values 1 'walls' are painted nowhere in level 'Level_0'",)
