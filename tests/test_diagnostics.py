"""Designer feedback: validate's warnings (pockets, narrow passages, hidden areas) and render's cone overlay."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.render import COLOURS, draw_cone_overlay, render_preview
from guardsim.validate.diagnostics import free_cells, level_warnings
from guardsim.vision import visible_cells
from tests.common import EMPTY_SQUARE, L_ROOM, SPLIT_ROOMS, SQUARE_WITH_HOLE, scene_from, write_level

#: Two 3 x 3 rooms joined by a gap 0.4 wide: the gap's cell is free area where the guard does not fit,
#: and the guard in the left room sees part of the right room through it.
KEYHOLE: dict[str, Any] = {
    "name": "keyhole",
    "outer": [[0, 0], [7, 0], [7, 3], [0, 3]],
    "holes": [[[3, 0], [4, 0], [4, 1.3], [3, 1.3]], [[3, 1.7], [4, 1.7], [4, 3], [3, 3]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}

#: A one-cell corridor where a ledge comes within 0.25 of the path between two cell centres: both cells
#: fit the guard, the line between them is clear, but the guard's circle cannot slide past.
PINCH: dict[str, Any] = {
    "name": "pinch",
    "outer": [[0, 0], [3, 0], [3, 1], [0, 1]],
    "holes": [[[0.8, 0], [1.2, 0], [1.2, 0.25], [0.8, 0.25]]],
    "guard": {"start": [0.5, 0.5], "heading": "right"},
}


def warnings_of(data: dict[str, Any], **options: Any) -> list[Any]:
    scene = scene_from(data)
    start = scene.grid.cell_of(tuple(data["guard"]["start"]))
    assert start is not None
    return level_warnings(scene, scene.grid.component(*start), **options)


@pytest.mark.parametrize(
    "data", [EMPTY_SQUARE, SQUARE_WITH_HOLE, L_ROOM], ids=["empty-square", "square-with-hole", "l-room"]
)
def test_open_levels_have_no_warnings(data: dict[str, Any]) -> None:
    """A level the guard can walk and see all of gets no warning."""
    assert warnings_of(data) == []


def test_split_rooms_pocket_is_unreachable_and_hidden() -> None:
    """The room behind the thin wall is one pocket of 9 cells centred at (4.5, 1.5), and no cone sees it."""
    warnings = warnings_of(SPLIT_ROOMS)
    assert [(w.kind, w.cells, w.where) for w in warnings] == [
        ("unreachable pocket", 9, (4.5, 1.5)),
        ("hidden area", 9, (4.5, 1.5)),
    ]
    assert str(warnings[0]) == "unreachable pocket of 9 cells around (4.5, 1.5)"


def test_keyhole_is_a_narrow_passage_and_partly_seen_through() -> None:
    """The gap cell separates two areas; the far room is a pocket, but cells in line with the gap are seen."""
    warnings = warnings_of(KEYHOLE)
    kinds = {(w.kind, w.cells, w.where) for w in warnings}
    assert ("narrow passage", 1, (3.5, 1.5)) in kinds
    assert ("unreachable pocket", 9, (5.5, 1.5)) in kinds
    hidden = sum(w.cells for w in warnings if w.kind == "hidden area")
    assert 0 < hidden < 9


def test_pinch_between_neighbours_is_a_narrow_passage() -> None:
    """Two traversable neighbours with a clear line that the guard cannot slide along are reported."""
    warnings = warnings_of(PINCH)
    assert ("narrow passage", 2, (1.0, 0.5)) in {(w.kind, w.cells, w.where) for w in warnings}
    assert ("unreachable pocket", 2, (1.5, 0.5)) in {(w.kind, w.cells, w.where) for w in warnings}


@pytest.mark.parametrize("data", [SPLIT_ROOMS, KEYHOLE, PINCH], ids=["split-rooms", "keyhole", "pinch"])
def test_hidden_cells_are_exactly_those_no_reachable_state_sees(data: dict[str, Any]) -> None:
    """Hidden cells == free cells outside every reference-vision cone of every reachable cell and heading."""
    scene = scene_from(data)
    reachable = scene.grid.component(0, 0)
    free = free_cells(scene)
    # The reference vision, asked about every free cell rather than only where the guard fits.
    widened = dataclasses.replace(scene.grid, traversable=free)
    seen = np.zeros(scene.grid.size, dtype=bool)
    for row, col in np.argwhere(reachable):
        for heading in range(4):
            seen[visible_cells(scene.world, widened, scene.cone, int(col), int(row), heading)] = True
    expected = int((free.ravel() & ~seen).sum())
    hidden = sum(w.cells for w in level_warnings(scene, reachable) if w.kind == "hidden area")
    assert hidden == expected


def test_ray_budget_bounds_the_hidden_area_search() -> None:
    """With no rays to spend, nothing is called hidden and the unchecked cells are counted."""
    warnings = warnings_of(SPLIT_ROOMS, max_rays=0)
    assert [(w.kind, w.cells) for w in warnings if w.kind != "unreachable pocket"] == [
        ("not checked for hidden areas", 9)
    ]
    assert str(warnings[-1]) == "9 cells not checked for hidden areas (the ray budget ran out)"


def test_validate_prints_warnings_without_failing(tmp_path: Path) -> None:
    """Warnings are printed after `ok`, and the exit status stays 0; --no-warnings drops them."""
    path = write_level(tmp_path, KEYHOLE)
    result = CliRunner().invoke(main, ["validate", str(path)])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == f"{path}: ok"
    assert f"{path}: warning: unreachable pocket of 9 cells around (5.5, 1.5)" in lines
    assert f"{path}: warning: narrow passage of 1 cell around (3.5, 1.5)" in lines
    quiet = CliRunner().invoke(main, ["validate", str(path), "--no-warnings"])
    assert quiet.stdout.splitlines() == [f"{path}: ok"]


def test_many_warnings_of_a_kind_are_summed_up(tmp_path: Path) -> None:
    """Past five pockets, validate prints one line with how many more and their cells."""
    holes = [[[x, 0], [x + 0.1, 0], [x + 0.1, 2], [x, 2]] for x in range(1, 8)]
    path = write_level(
        tmp_path, {"outer": [[0, 0], [8, 0], [8, 2], [0, 2]], "holes": holes, "guard": {"start": [0.5, 0.5]}}
    )
    result = CliRunner().invoke(main, ["validate", str(path), "--max-rays", "0"])
    pockets = [line for line in result.stdout.splitlines() if "unreachable pocket" in line]
    assert len(pockets) == 6
    assert pockets[-1] == f"{path}: warning: 2 more unreachable pockets (4 cells)"


def test_cone_overlay_tints_exactly_the_seen_cells() -> None:
    """Every seen cell's centre pixel is the preview blended with the cone colour (or the cone's outline or
    the guard); every other cell's centre pixel is unchanged (or outline or guard)."""
    scene = scene_from(SQUARE_WITH_HOLE)
    grid = scene.grid
    reachable = grid.component(0, 0)
    size = 300
    preview = render_preview(scene.level, grid.traversable, reachable, grid.origin, size=size)
    eye, heading = (0, 2), 0
    seen = np.zeros(grid.size, dtype=bool)
    seen[scene.vision()(eye[0], eye[1], heading)] = True
    seen = seen.reshape(grid.shape)
    overlay = draw_cone_overlay(preview, scene.level, grid.shape, seen, eye, heading, size=size)
    scale = size // max(grid.shape)
    margin = (preview.shape[1] - grid.shape[1] * scale) // 2
    drawn = {COLOURS["cone"], COLOURS["guard"]}
    blended = 0
    for row, col in np.ndindex(*grid.shape):
        y, x = margin + row * scale + scale // 2, margin + col * scale + scale // 2
        before, after = preview[y, x].astype(float), tuple(int(v) for v in overlay[y, x])
        if after in drawn:
            continue
        if seen[row, col]:
            expected = (before * 0.45 + np.asarray(COLOURS["cone"]) * 0.55).astype(np.uint8)
            assert after == tuple(int(v) for v in expected), (col, row)
            blended += 1
        else:
            assert after == tuple(int(v) for v in before), (col, row)
    assert blended >= 3


def test_render_cone_option(tmp_path: Path) -> None:
    """`guardsim render LEVEL --png OUT --cone X,Y,HEADING` writes a PNG that differs from the plain preview
    and prints how many cells the guard there sees; a spot where the guard cannot stand is one error line."""
    path = write_level(tmp_path, SQUARE_WITH_HOLE)
    plain, cone = tmp_path / "plain.png", tmp_path / "cone.png"
    assert CliRunner().invoke(main, ["render", str(path), "--png", str(plain)]).exit_code == 0
    result = CliRunner().invoke(main, ["render", str(path), "--png", str(cone), "--cone", "0.5,2.5,right"])
    assert result.exit_code == 0, result.output
    assert "a guard at (0.5, 2.5) facing right sees" in result.stdout
    assert iio.imread(plain).shape == iio.imread(cone).shape
    assert not np.array_equal(iio.imread(plain), iio.imread(cone))
    bad = CliRunner().invoke(main, ["render", str(path), "--png", str(cone), "--cone", "3,3,up"])
    assert bad.exit_code == 2
    assert bad.stderr.splitlines() == [
        f"guardsim: error: {path}: --cone (3, 3) is not in a cell where the guard (radius 0.3) can stand"
    ]
