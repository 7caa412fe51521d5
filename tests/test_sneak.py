"""The sneak check: complete (agrees with a brute-force search over absolute time on tiny levels), its
paths are never seen when replayed against the guards, and a post in a one-cell corridor stops it."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.detection import GuardDetection
from guardsim.grid import cell_of_state, heading_of_state
from guardsim.patrol import Patrol, patrol_setup, plan_loop
from guardsim.scene import Scene
from guardsim.sneak import sneak_check
from guardsim.sneak.search import hiding_windows
from tests.common import TINY_LEVELS, TWO_ROOMS, corridor_post, level_from, random_loop, scene_from, write_level


def _brute_force(neighbours: np.ndarray, seen: np.ndarray, source: int, target: int) -> tuple[bool, int, int]:
    """Over absolute time, long enough to visit every (cell, lap tick) pair: (found, fastest unseen
    ticks, fewest ticks in view)."""
    period, cells = seen.shape
    horizon = period * cells + period
    big = 10**9
    hidden = np.full(cells, False)
    fewest = np.full(cells, big)
    best_ticks, best_seen = -1, big
    duration = np.full(cells, big)
    for tick in range(horizon):
        row = seen[tick % period]
        if tick:
            stepped_hidden = hidden.copy()
            stepped_fewest = fewest.copy()
            stepped_duration = np.where(hidden, duration + 1, big)
            for d in range(4):
                others = neighbours[:, d]
                valid = others >= 0
                froms, tos = np.flatnonzero(valid), others[valid]
                np.logical_or.at(stepped_hidden, tos, hidden[froms])
                np.minimum.at(stepped_duration, tos, np.where(hidden[froms], duration[froms] + 1, big))
                np.minimum.at(stepped_fewest, tos, fewest[froms])
            hidden = stepped_hidden & ~row
            duration = np.where(hidden, stepped_duration, big)
            fewest = stepped_fewest + row
        if not row[source]:
            hidden[source] = True
            duration[source] = 0
        fewest[source] = min(fewest[source], int(row[source]))
        if hidden[target] and (best_ticks < 0 or duration[target] < best_ticks):
            best_ticks = int(duration[target])
        best_seen = min(best_seen, int(fewest[target]))
    return best_ticks >= 0, best_ticks, best_seen


def _replay_never_seen(scene: Scene, patrol: Patrol, start: int, cells: np.ndarray) -> int:
    """Ticks of the path at which a guard, asked through the reference vision, sees the intruder."""
    vision = scene.reference_vision()
    grid = scene.grid
    caught = 0
    for offset, cell in enumerate(cells.tolist()):
        tick = start + offset
        for guard in range(patrol.guards):
            state = patrol.state(guard, tick)
            col, row = grid.unflat(int(cell_of_state(state)))
            if cell in vision(col, row, int(heading_of_state(state))).tolist():
                caught += 1
                break
    return caught


@pytest.mark.parametrize("name", ["square-with-hole", "l-room", "empty-square"])
def test_sneak_agrees_with_brute_force(name: str) -> None:
    scene = scene_from(TINY_LEVELS[name] | {"guard": {"start": [0.5, 0.5], "heading": "right", "view_range": 2.5}})
    setup = patrol_setup(scene)
    rng = np.random.default_rng(7)
    grid = scene.grid
    cells = np.flatnonzero(setup.goal)
    found_both = set()
    for trial in range(6):
        guards = 1 + trial % 2
        laps = [random_loop(scene, rng, int(rng.integers(1, 5))) for _ in range(guards)]
        period = int(np.lcm.reduce([lap.size for lap in laps]))
        patrol = Patrol(np.stack([np.tile(lap, period // lap.size) for lap in laps]), period, "test")
        for _ in range(3):
            source, target = (int(cells[rng.integers(cells.size)]) for _ in range(2))
            result = sneak_check(
                grid, setup.table, patrol, source, target, detection=GuardDetection.of_level(scene.level)
            )
            found, fastest, fewest = _brute_force(grid.neighbours, result.seen, source, target)
            assert result.path is not None
            assert result.found == found
            found_both.add(found)
            if found:
                assert result.path.ticks == fastest
                assert _replay_never_seen(scene, patrol, result.path.start_tick, result.path.cells) == 0
            else:
                assert result.path.ticks_in_view == fewest > 0
                assert _replay_never_seen(scene, patrol, result.path.start_tick, result.path.cells) == fewest
            # Every step is a move to a connected neighbour or a wait.
            for a, b in zip(result.path.cells[:-1].tolist(), result.path.cells[1:].tolist()):
                assert a == b or b in grid.neighbours[a].tolist()
            assert result.path.cells[0] == source and result.path.cells[-1] == target
    assert found_both == {True, False}


def test_a_post_in_a_one_cell_corridor_stops_every_sneak() -> None:
    scene = scene_from(TWO_ROOMS)
    setup = patrol_setup(scene)
    grid = scene.grid
    source, target = grid.flat(0, 0), grid.flat(10, 2)
    for heading in range(4):
        result = sneak_check(
            grid,
            setup.table,
            corridor_post(scene, 5, heading),
            source,
            target,
            detection=GuardDetection.of_level(scene.level),
        )
        assert not result.found
        assert result.path is not None and result.path.ticks_in_view >= 1
        assert 5 + 1 * 11 in result.path.cells.tolist()
    # The loop patrol of the same level, by contrast, leaves a gap to slip through.
    loop = plan_loop(setup, 1, planner="cover")[0].patrol
    assert sneak_check(grid, setup.table, loop, source, target, detection=GuardDetection.of_level(scene.level)).found


def test_hiding_windows_are_the_longest_unseen_runs() -> None:
    seen = np.array([[True, False, False], [False, False, True], [True, False, False]])
    windows = hiding_windows(seen, np.array([True, True, False]))
    # Cell 0: unseen only at tick 1 (a run of 1); cell 1 never seen: the whole lap; cell 2 is a wall.
    assert windows.tolist() == [1, 3, -1]


def test_sneak_command_writes_the_answer_and_a_gif(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    patrol = tmp_path / "post.json"
    patrol.write_text(json.dumps({"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}))
    out = tmp_path / "out"
    args = [
        "sneak",
        str(level),
        "--patrol",
        str(patrol),
        "--from",
        "0.5,0.5",
        "--to",
        "10.5,2.5",
        "--out",
        str(out),
        "--gif",
    ]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "caught" in result.output
    data: dict[str, Any] = json.loads((out / "sneak.json").read_text())
    assert data["found"] is False and data["closest_call"] is True and data["ticks_in_view"] >= 1
    assert data["path"][0] == [0, 0] and data["path"][-1] == [10, 2] and len(data["path"]) == data["ticks"] + 1
    assert data["never_seen_cells"] > 0
    assert (out / "sneak.gif").read_bytes()[:6] == b"GIF89a"
    assert (out / "hiding.png").stat().st_size > 1000


def test_sneak_gif_caption_counts_the_sneaks_ticks_and_the_laps(tmp_path: Path) -> None:
    """The sneak GIF's caption gives the sneak's tick and the lap tick it falls on (wrapping round the lap's
    end), and the GIF's frames carry that caption, not the plain one."""
    import imageio.v3 as iio

    from guardsim.patrol.replay import patrol_trace
    from guardsim.render.frames import FrameDrawer
    from guardsim.render.gif import GifOptions
    from guardsim.render.palette import palette_rgb
    from guardsim.render.sneak import SneakFrames, write_sneak_gif

    level = level_from(TWO_ROOMS)
    scene = Scene.from_level(level)
    setup = patrol_setup(scene)
    loop = plan_loop(setup, 1, planner="cover")[0].patrol
    assert loop.period is not None and loop.period > 4
    start = loop.period - 2
    goal = np.asarray(scene.grid.largest_component()).ravel()
    trace = patrol_trace(scene, setup.table, loop, goal, start=start, ticks=5, label="sneak")
    frames = SneakFrames(level, trace, size=200, lap_start=start, period=loop.period)
    assert f"  |  sneak tick 0 / 5 \u00b7 lap tick {start} / {loop.period}  |  " in frames.caption(0)[0]
    assert f"  |  sneak tick 3 / 5 \u00b7 lap tick 1 / {loop.period}  |  " in frames.caption(3)[0]
    assert "lap" not in SneakFrames(level, trace, size=200).caption(3)[0]
    gif = tmp_path / "sneak.gif"
    options = GifOptions(size=200)
    write_sneak_gif(gif, level, trace, [(0, 0)] * 6, options=options, lap_start=start, period=loop.period)
    top = frames.layout.top
    shown = iio.imread(gif, index=0)[:top, :, :3]
    assert (shown == palette_rgb()[frames.frame(0)][:top]).all()
    assert (shown != palette_rgb()[FrameDrawer(level, trace, size=200).frame(0)][:top]).any()


@pytest.mark.parametrize(
    ("point", "message"),
    [
        ("99,99", "--from 99,99 lies outside the level"),
        ("4.5,0.5", "--from 4.5,0.5 is in cell [4, 0], where a guard-sized intruder does not fit"),
    ],
)
def test_sneak_bad_points_are_one_line(tmp_path: Path, point: str, message: str) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    patrol = tmp_path / "post.json"
    patrol.write_text(json.dumps({"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}))
    result = CliRunner().invoke(
        main, ["sneak", str(level), "--patrol", str(patrol), "--from", point, "--to", "10.5,2.5"]
    )
    assert result.exit_code == 2
    assert result.output.strip() == f"guardsim: error: {message}"


def test_sneak_gif_draws_each_guards_meter_and_colours_the_intruder_by_state(tmp_path: Path) -> None:
    """Past the corridor post (caught, detected as it passes the post, the meter draining after): decoded
    back, each frame has a bar over the post framed in the outline colour and filled from the left by the
    meter of sneak.json's ``awareness`` at that tick (red once full, orange from the suspicious level,
    white where empty), and the intruder's disc is white while unseen and red once detected."""
    import imageio.v3 as iio

    from guardsim.detection import path_states
    from guardsim.patrol.replay import patrol_trace
    from guardsim.render.gif import GifOptions
    from guardsim.render.palette import COLOURS, GUARD_COLOURS
    from guardsim.render.sneak import SneakFrames, write_sneak_gif
    from guardsim.sneak import sneak_data

    level = level_from(TWO_ROOMS)
    scene = Scene.from_level(level)
    setup = patrol_setup(scene)
    grid = scene.grid
    post = corridor_post(scene, 5, 0)
    detection = GuardDetection.of_level(scene.level)
    result = sneak_check(grid, setup.table, post, grid.flat(0, 0), grid.flat(10, 2), detection=detection)
    path, grade = result.path, result.grade
    assert path is not None and grade is not None
    data = sneak_data(result, grid)
    awareness = np.asarray(data["awareness"])[:, 0]
    # The meter fills on the post's cell and drains after: full, partial and empty bars all occur.
    assert (awareness == 0).any() and (awareness == 1).any() and ((awareness > 0.5) & (awareness < 1)).any()
    goal = np.asarray(grid.largest_component()).ravel()
    trace = patrol_trace(scene, setup.table, post, goal, start=path.start_tick, ticks=path.ticks, label="sneak")
    cells = [grid.unflat(int(cell)) for cell in path.cells]
    states = path_states(grade.meters, grade.in_view, grade.detected_at, 0.5)
    gif = tmp_path / "sneak.gif"
    options = GifOptions(size=300)
    frames = write_sneak_gif(gif, level, trace, cells, options=options, meters=grade.meters, states=states)
    assert frames == path.ticks + 1
    layout = SneakFrames(level, trace, size=300).layout
    scale = layout.scale
    radius = max(7, 0.45 * scale)
    # The post's disc is at its cell's centre (play area padded by 4 pixels); the bar sits above it.
    x = layout.left + 4 + 5.5 * scale
    y = layout.top + 4 + 1.5 * scale
    half, height = round(radius) + 1, max(5, round(0.6 * radius))
    left, top = round(x) - half, round(y - radius) - 4 - height
    inside = 2 * half - 2
    colours = {"white": COLOURS["white"], "orange": GUARD_COLOURS[3], "red": GUARD_COLOURS[0]}
    for tick, level_now in enumerate(awareness):
        image = iio.imread(gif, index=tick)[:, :, :3]
        assert tuple(image[top, left + half]) == COLOURS["outline"]
        assert tuple(image[top + height - 1, left + half]) == COLOURS["outline"]
        assert tuple(image[top + height // 2, left]) == COLOURS["outline"]
        row = image[top + height // 2, left + 1 : left + 1 + inside]
        filled = round(level_now * inside)
        fill = colours["red"] if level_now == 1 else colours["orange"] if level_now >= 0.5 else None
        if fill is not None:
            assert (row[:filled] == fill).all(), tick
        assert (row[filled:] == colours["white"]).all(), tick
        # The intruder: white while unseen, red once detected (the state of sneak.json's awareness).
        col, r = data["path"][tick]
        disc = tuple(image[layout.top + 4 + int((r + 0.5) * scale), layout.left + 4 + int((col + 0.5) * scale)])
        detected = data["detected_at"] is not None and tick >= data["detected_at"]
        if detected and (col, r) != (5, 1):
            assert disc == colours["red"], tick
        elif not detected and not (awareness[: tick + 1] > 0).any():
            assert disc == colours["white"], tick
