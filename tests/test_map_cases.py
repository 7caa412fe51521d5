"""Small Tiled maps, made by hand in ``tests/data/maps/cases``, each showing how a kind of real map marks
its level, and imported as its game plays it.

* ``village_bridges.tmj``: per-tile ``collision`` properties; a bridge (not colliding) drawn over a river
  (colliding); roofs on a layer at ``z`` 1, above the walker, marked colliding; a fence tile marked not
  colliding whose 2-pixel rail is a collision shape; the player's ``Start Position`` of class ``start``.
* ``forest_paths.tmj``: a path one tile wide between trees, and on it, in a hidden layer named
  ``Collision``, tiles whose collision shape is a thin rail: walls where the shapes are, not whole tiles.
* ``house_lawn.tmj``: a house on a wider lawn, the player inside, no guard spawn.
* ``forest_narrows.tmj``: a path two tiles wide narrowed by half-tile shapes to a gap the guard passes,
  which the grid at cell size 1 cuts.
* ``dungeon_corridors.tmj``: the ground on a layer called ``corridors``, two decorative tiles on a layer
  called ``floor squares``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from guardsim.scene import Scene
from tests.common import REPO, import_map

CASES = REPO / "tests" / "data" / "maps" / "cases"


def walkable(path: Path) -> tuple[set[tuple[int, int]], object]:
    """The guard's traversable cells in the map's tile coordinates, and the import."""
    imported = import_map(path)
    grid = Scene.from_level(imported.level).grid
    left, top = (round(v) for v in imported.level.bounds[:2])
    rows, cols = np.nonzero(grid.traversable)
    return set(zip((cols + left).tolist(), (rows + top).tolist())), imported


def test_a_bridge_over_a_river_is_walked_and_roofs_never_block() -> None:
    cells, imported = walkable(CASES / "village_bridges.tmj")
    assert {(4, 2), (5, 2)} <= cells, "the bridge"
    assert not {(4, r) for r in (0, 1, 3, 4, 5)} & cells, "the river"
    assert {(1, 1), (2, 1), (7, 4)} <= cells, "under the roofs (z 1, above the walker)"
    assert (1, 4) in cells, "beside the fence's rail (its shape blocks, not the whole tile)"
    # One village: the bridge joins both banks, nothing is left out.
    assert "left out" not in imported.summary()  # type: ignore[attr-defined]
    assert {(0, 0), (9, 5)} <= cells


def test_the_start_position_is_the_players_not_a_guards() -> None:
    _, imported = walkable(CASES / "village_bridges.tmj")
    assert imported.player_starts == ((8.5, 3.5),)  # type: ignore[attr-defined]
    assert imported.level.starts == ()  # type: ignore[attr-defined]


def test_collision_shapes_in_a_wall_layer_block_where_they_are() -> None:
    cells, imported = walkable(CASES / "forest_paths.tmj")
    path = {(col, 2) for col in range(9)}
    assert path <= cells, sorted(path - cells)
    assert not {(col, row) for col in range(9) for row in (0, 1, 3, 4)} & cells
    assert "tile collision shape" in imported.summary()  # type: ignore[attr-defined]


def test_with_no_guard_spawn_the_guard_starts_where_the_player_is_and_the_level_is_cropped() -> None:
    cells, imported = walkable(CASES / "house_lawn.tmj")
    level = imported.level  # type: ignore[attr-defined]
    # The inside of the house only: the lawn round it is left out and the level cropped to the house.
    assert cells == {(col, row) for col in range(4, 10) for row in range(4, 8)}
    assert level.bounds == (4, 4, 10, 8)
    summary = imported.summary()  # type: ignore[attr-defined]
    assert "left out 1 free part holding no player start" in summary and "cropped to the parts kept" in summary
    assert level.player_starts == ((6.5, 5.5),)


def test_a_small_layer_named_floor_is_not_the_whole_floor() -> None:
    cells, imported = walkable(CASES / "dungeon_corridors.tmj")
    assert cells == {(col, row) for col in range(1, 11) for row in range(1, 7)}
    assert "floor from 'corridors', 'floor squares'" in imported.summary()  # type: ignore[attr-defined]


def test_a_grid_that_cuts_a_passage_the_guard_fits_says_which_cell_size_keeps_it() -> None:
    # forest_narrows.tmj: half-tile shapes above and below leave a one-tile gap the guard's circle
    # passes, but no cell centre there at cell size 1 (nor 0.5) clears its radius.
    path = CASES / "forest_narrows.tmj"
    _, imported = walkable(path)
    warning = next(w for w in imported.warnings if "guard's grid falls into" in w)  # type: ignore[attr-defined]
    assert "falls into 2 parts where its circle can move in 1" in warning and "--cell-size 0.25" in warning
    # The half tile at column 4, row 2 of the 'Collision' layer: the cell that cuts the path, named.
    assert "no room for the guard's circle (radius 0.3) at their centre" in warning
    assert "as the cell at (4.5, 2.5) does" in warning
    finer = import_map(path, cell_size=0.25)
    assert not [w for w in finer.warnings if "guard's grid falls into" in w]
    grid = Scene.from_level(finer.level).grid
    assert int(grid.component_labels.max()) == 0, "one part at cell size 0.25"


def test_the_viewer_outlines_the_floor_not_the_cuts_between_touching_holes() -> None:
    # An importer opens an enclosing wall by cutting it in two holes that touch along a line; the page
    # stroked every ring, drawing that line across the wall (the GIF never did).
    from guardsim.level import parse_level
    from guardsim.simulation import Simulation
    from guardsim.viewer.page import page_data

    level = parse_level(
        {
            "outer": [[0, 0], [8, 0], [8, 8], [0, 8]],
            "holes": [[[2, 2], [4, 2], [4, 6], [2, 6]], [[4, 2], [6, 2], [6, 6], [4, 6]]],
            "guard": {"start": [0.5, 0.5]},
        }
    )
    simulation = Simulation(Scene.from_level(level))
    simulation.reset(seed=0)
    data = page_data(level, simulation.run())
    edges = {
        frozenset((tuple(ring[i]), tuple(ring[(i + 1) % len(ring)])))
        for ring in data["outline"]
        for i in range(len(ring))
    }
    assert frozenset(((4.0, 2.0), (4.0, 6.0))) not in edges and frozenset(((4.0, 6.0), (4.0, 2.0))) not in edges
    assert len(data["outline"]) == 2 and len(data["rings"]) == 3
