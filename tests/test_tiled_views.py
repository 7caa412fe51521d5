"""Three readings of a Tiled map the corpus of real maps asked for (``tests/test_map_corpus.py``), each on
small maps written here, as TMX and as Tiled JSON, so that they are tested where the fetched corpus is not:

* a static physics body is a wall, a moving one is not (Tiled's ``orthogonal-outside.tmx``: an object of
  class ``Fixture`` with ``static = true``; sticker-knight's ``bodyType``);
* a side view (a platformer: layers named platforms or ladders, a gravity map property) is refused in one
  line that says what was guessed, and ``--view top-down`` imports it anyway (Tiled's ``forest.tmx``,
  arcade's ``map_with_ladders.json``);
* a floor made only of obstacles, on which the guard fits nowhere, is refused in one line (bevy_ecs_tiled's
  physics samples: every tile a collider, drawn on empty cells), while obstacles drawn on ground import.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from guardsim.errors import LevelError
from guardsim.importers.tiled_marks import body_mark
from tests.common import assert_one_line_error, import_map, run
from tests.test_tiled_conventions import (
    FLOOR,
    FORMATS,
    GROUND,
    SIZE,
    TILE,
    Obj,
    ObjectLayer,
    Tile,
    TileLayer,
    Tileset,
    block,
    blocked_cells,
    to_json,
    to_tmx,
    wall_cells,
    write,
)

# -- static physics bodies ------------------------------------------------------------------------------

CLIFF = block(range(1, 3), range(1, 3))
"""The cells of the body drawn in every case below: a 2 x 2 tile rectangle at tile (1, 1)."""


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("kind", "props", "wall"),
    [
        ("Fixture", [("static", "bool", True)], True),
        ("Fixture", [("static", "bool", False)], False),
        ("PhysicsBody", [("isStatic", "string", "yes")], True),
        ("StaticBody2D", [], True),
        ("RigidBody2D", [], False),
        ("", [("bodyType", "string", "static")], True),
        ("", [("bodyType", "string", "dynamic")], False),
        ("Fixture", [], False),
        ("Sign", [("static", "bool", True)], False),
        # A collision property says more than the body type: a static sensor that collides with nothing.
        ("Fixture", [("static", "bool", True), ("collides", "bool", False)], False),
    ],
    ids=["fixture-static", "fixture-moving", "is-static", "static-body", "rigid-body", "body-type-static",
         "body-type-dynamic", "fixture-unsaid", "not-a-body", "sensor"],
)  # fmt: skip
def test_a_static_physics_body_is_a_wall_and_a_moving_one_is_not(
    tmp_path: Path, fmt: str, kind: str, props: list[tuple[str, str, Any]], wall: bool
) -> None:
    """As Tiled's orthogonal-outside.tmx draws its cliff: a polygon of class Fixture, static = true, in a
    layer 'Objects' that says nothing of walls."""
    body = Obj(1, TILE, TILE, 2 * TILE, 2 * TILE, name="unreachable", kind=kind, props=props)
    path = write(tmp_path, fmt, [], [ObjectLayer("Objects", [body])])
    assert wall_cells(path) == (CLIFF if wall else set())


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_moving_body_in_a_wall_layer_is_no_wall(tmp_path: Path, fmt: str) -> None:
    crate = Obj(1, TILE, TILE, 2 * TILE, 2 * TILE, name="crate", props=[("bodyType", "string", "dynamic")])
    rock = Obj(2, 5 * TILE, 5 * TILE, TILE, TILE, name="rock")
    path = write(tmp_path, fmt, [], [ObjectLayer("Collisions", [crate, rock])])
    assert wall_cells(path) == {(5, 5)}


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_tile_of_a_static_body_class_is_a_wall(tmp_path: Path, fmt: str) -> None:
    bodies = Tileset(
        2, "bodies", [Tile(0, kind="StaticBody"), Tile(1, kind="Fixture", props=[("static", "bool", False)])]
    )
    path = write(tmp_path, fmt, [bodies], [TileLayer("Decor", {(1, 1): 2, (2, 2): 3})])
    assert wall_cells(path) == {(1, 1)}


@pytest.mark.parametrize("fmt", FORMATS)
def test_wall_property_replaces_the_static_body_guess(tmp_path: Path, fmt: str) -> None:
    body = Obj(1, TILE, TILE, 2 * TILE, 2 * TILE, kind="Fixture", props=[("static", "bool", True)])
    rock = Obj(2, 5 * TILE, 5 * TILE, TILE, TILE, props=[("blocks", "bool", True)])
    path = write(tmp_path, fmt, [], [ObjectLayer("Objects", [body, rock])])
    assert wall_cells(path, wall_properties=["blocks"]) == {(5, 5)}


def test_body_mark_reads_a_body_type_before_a_class() -> None:
    assert body_mark("StaticBody", {"bodyType": "kinematic"}) is False
    assert body_mark("RigidBody", {"body_type": "Static"}) is True
    assert body_mark("Fixture", {"static": "maybe"}) is None


# -- side views -----------------------------------------------------------------------------------------


def with_map_properties(path: Path, props: list[tuple[str, str, Any]]) -> Path:
    """The map at ``path`` given map-level custom properties (the writers above give none)."""
    text = path.read_text()
    if path.suffix == ".tmx":
        items = "".join(f'<property name="{name}" type="{kind}" value="{value}"/>' for name, kind, value in props)
        text = re.sub(r"(<map [^>]*>)", rf"\1<properties>{items}</properties>", text, count=1)
    else:
        data = json.loads(text)
        data["properties"] = [{"name": name, "type": kind, "value": value} for name, kind, value in props]
        text = json.dumps(data)
    path.write_text(text)
    return path


PLATFORMS = TileLayer("Platforms", {(col, 6): 1 for col in range(SIZE)})


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("layers", "props", "sign"),
    [
        ([PLATFORMS], [], "the layer 'Platforms'"),
        ([ObjectLayer("Ladders", [Obj(1, TILE, TILE, TILE, 4 * TILE)])], [], "the layer 'Ladders'"),
        ([TileLayer("Moving Platform", {(2, 2): 1})], [], "the layer 'Moving Platform'"),
        ([], [("gravity", "float", 9.8)], "the map property 'gravity' (9.8)"),
        ([], [("JumpHeight", "int", 3)], "the map property 'JumpHeight' (3)"),
    ],
    ids=["platforms", "ladders", "moving-platform", "gravity", "jump"],
)
def test_a_side_view_is_refused_in_one_line_saying_what_was_guessed(
    tmp_path: Path, fmt: str, layers: list[TileLayer | ObjectLayer], props: list[tuple[str, str, Any]], sign: str
) -> None:
    path = with_map_properties(write(tmp_path, fmt, [], layers), props)
    with pytest.raises(LevelError) as error:
        import_map(path)
    message = str(error.value)
    assert "\n" not in message and path.name in message
    assert f"looks like a side view (a platformer), guessed from {sign}" in message
    assert "import it with --view top-down" in message
    # As the message says: drawn from above after all, it imports, and the summary says what it overrode.
    imported = import_map(path, view="top-down")
    assert imported.level.free_area().area > 0
    assert f"taken as drawn from above (--view top-down), though {sign} suggests a side view" in imported.summary()


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize(
    ("layers", "props"),
    [
        ([TileLayer("Background", {(2, 2): 1})], []),
        ([TileLayer("Platformed", {(2, 2): 1})], []),
        ([], [("gravity", "float", 0.0)]),
        ([], [("gravity", "string", "none")]),
    ],
    ids=["background", "not-a-whole-word", "no-gravity", "gravity-none"],
)
def test_a_top_down_map_is_not_taken_for_a_side_view(
    tmp_path: Path, fmt: str, layers: list[TileLayer | ObjectLayer], props: list[tuple[str, str, Any]]
) -> None:
    path = with_map_properties(write(tmp_path, fmt, [], layers), props)
    assert import_map(path).level.free_area().area > 0


def test_map_properties_that_cannot_be_read_are_left_out_with_a_note(tmp_path: Path) -> None:
    """They are only a hint (gravity): a malformed list does not refuse the map."""
    path = write(tmp_path, "json", [], [])
    data = json.loads(path.read_text())
    data["properties"] = "gravity"
    path.write_text(json.dumps(data))
    imported = import_map(path)
    assert "the map's own custom properties could not be read: left out" in imported.summary()


def test_the_view_option_on_the_command_line(tmp_path: Path) -> None:
    path = write(tmp_path, "tmx", [], [PLATFORMS])
    out = tmp_path / "level.json"
    line = assert_one_line_error(run("import", path, "--out", out), path)
    assert "--view top-down" in line and not out.exists()
    assert run("import", path, "--out", out, "--view", "top-down").exit_code == 0
    assert out.exists()
    assert run("import", path, "--out", out, "--view", "sideways").exit_code == 2


def test_an_unknown_view_is_refused(tmp_path: Path) -> None:
    path = write(tmp_path, "json", [], [])
    with pytest.raises(LevelError, match="--view must be one of auto, top-down, not 'side'"):
        import_map(path, view="side")


# -- a floor made only of obstacles ---------------------------------------------------------------------

SLAB = Tileset(2, "slab", [Tile(0, shapes=[(0.0, 0.0, float(TILE), TILE - 2.0)])])
"""A tile whose collision shape leaves a strip far narrower than the guard."""
PEBBLE = Tileset(3, "pebble", [Tile(0, shapes=[(0.0, 0.0, 3.0, 3.0)])])
"""A tile whose collision shape is a pebble in its corner."""
RING = {(col, row): 2 for col in range(SIZE) for row in range(SIZE) if col in (0, SIZE - 1) or row in (0, SIZE - 1)}
ROWS = {(col, row): 2 for col in range(2, SIZE - 2) for row in (2, 4)}
"""A ring of slabs round the map and two rows of slabs inside it; the rest of the cells empty."""


def obstacles_map(folder: Path, fmt: str, layers: list[TileLayer | ObjectLayer]) -> Path:
    path = folder / f"obstacles.{fmt}"
    sets = [GROUND, SLAB, PEBBLE]
    path.write_text(to_tmx(sets, layers) if fmt == "tmx" else to_json(sets, layers))
    return path


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_floor_made_only_of_obstacles_is_refused_in_one_line(tmp_path: Path, fmt: str) -> None:
    """As bevy_ecs_tiled's physics samples draw theirs: colliders on empty cells, no ground."""
    path = obstacles_map(tmp_path, fmt, [TileLayer("Tile Layer 1", {**RING, **ROWS})])
    with pytest.raises(LevelError) as error:
        import_map(path)
    message = str(error.value)
    assert "\n" not in message and path.name in message
    assert "every tile of the floor layer 'Tile Layer 1' is an obstacle (36 tiles" in message
    assert "the guard (radius 0.3 tiles) fits on none" in message
    line = assert_one_line_error(run("import", path, "--out", tmp_path / "level.json"), path)
    assert "is an obstacle" in line


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_same_obstacles_on_ground_import_as_drawn(tmp_path: Path, fmt: str) -> None:
    path = obstacles_map(tmp_path, fmt, [FLOOR, TileLayer("Obstacles", {**RING, **ROWS})])
    imported = import_map(path)
    walls = set(RING) | set(ROWS)
    assert blocked_cells(imported.level) == walls
    assert not [warning for warning in imported.warnings if "fits on no cell" in warning]


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_floor_whose_every_tile_has_a_small_shape_imports(tmp_path: Path, fmt: str) -> None:
    """Every floor tile carries a collision shape, but the guard fits beside each: ground with pebbles."""
    pebbles = {(col, row): 3 for col in range(SIZE) for row in range(SIZE)}
    path = obstacles_map(tmp_path, fmt, [TileLayer("Tile Layer 1", pebbles)])
    assert import_map(path).level.free_area().area > 0
