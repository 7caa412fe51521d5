"""Ears: a noise carries along the grid's traversable cells (round walls, not through them), the
intruder's gaits (a sneaking step takes ``sneak_ticks`` ticks), guards that hear investigate, and a
thrown bottle that pulls a post guard out of a doorway so that a route intruder gets through.

DOOR is a 12 x 5 level split by a wall at x = 6 with a one-cell door at (6, 2); a post guard stands in
the door facing west (view range 4, 90 degrees). The intruder waits at (5, 4), south-west of the door
and outside the guard's cone, then walks through the door to (11, 2).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.alert import alert_episode, alert_trace_data
from guardsim.alert.run import _shortest_path
from guardsim.cli import main
from guardsim.errors import LevelError
from guardsim.kernels.distances import FAR, distances_from
from guardsim.kernels.noise import heard_within, noise_steps
from guardsim.level import parse_level
from guardsim.patrol.model import Patrol
from tests.common import write_level
from tests.test_alert import setup

DOOR: dict[str, Any] = {
    "name": "doorway",
    "outer": [[0, 0], [12, 0], [12, 5], [0, 5]],
    "holes": [[[6, 0], [7, 0], [7, 2], [6, 2]], [[6, 3], [7, 3], [7, 5], [6, 5]]],
    "guard": {"view_range": 4, "fov_degrees": 90},
}
HIDE, GOAL = (5, 4), (11, 2)
WAIT = 6


def door_scene(**guard: Any) -> tuple[Any, Any, Patrol]:
    scene, table = setup(DOOR, **guard)
    grid = scene.grid
    post = Patrol(np.array([[grid.flat(6, 2) * 4 + 2]]), period=1, strategy="loop")
    return scene, table, post


def door_route(grid: Any) -> list[int]:
    """Wait at HIDE for WAIT ticks, then the shortest way through the door to GOAL."""
    route = [grid.flat(*HIDE)] * WAIT
    for waypoint in ((5, 2), (6, 2), GOAL):
        route += _shortest_path(grid, route[-1], grid.flat(*waypoint))[1:]
    return route


def test_noise_goes_round_walls_not_through() -> None:
    """Beside the door's wall, (5, 0) and (7, 0) are 2 cells apart but 6 steps round through the door: a
    radius of 5 is not heard there, 6 is; against a brute force (the breadth-first fill) everywhere."""
    scene, _, _ = door_scene()
    grid = scene.grid
    neighbours = grid.neighbours
    source, other = grid.flat(5, 0), grid.flat(7, 0)
    assert heard_within(neighbours, source, 5.0, 1.0, np.array([other])).tolist() == [False]
    assert heard_within(neighbours, source, 6.0, 1.0, np.array([other])).tolist() == [True]
    cells = np.flatnonzero(grid.traversable.ravel())
    for radius in (0.0, 1.0, 2.5, 7.0):
        for start in cells[::7]:
            steps = distances_from(neighbours, np.array([start]))[cells]
            expected = (steps < FAR) & (steps <= noise_steps(radius, grid.cell_size))
            assert heard_within(neighbours, int(start), radius, grid.cell_size, cells).tolist() == expected.tolist()


def test_a_thrown_bottle_pulls_the_post_guard_out_of_the_doorway() -> None:
    """Without the bottle the guard catches the intruder at the door; with a bottle thrown into the far
    corner (0, 0) at tick 2 (8 steps from the guard, noise 10) the guard hears it, walks off to
    investigate, and the intruder gets through undetected; a bottle of noise 5 is not heard."""
    scene, table, post = door_scene()
    grid = scene.grid
    route = door_route(grid)
    outcomes = {}
    for noise in (None, 5.0, 10.0):
        throws = [] if noise is None else [(2, grid.flat(0, 0), noise)]
        episode = alert_episode(
            scene, post, intruder="route", source=route[0], target=grid.flat(*GOAL), route=route, table=table,
            distractions=throws, max_seconds=60,
        )  # fmt: skip
        episode.run()
        outcomes[noise] = (episode.outcome, episode.tick, [(e.tick, e.event) for e in episode.events][:2])
    assert outcomes[None] == ("captured", 8, [(7, "noticed"), (8, "detected")])
    assert outcomes[5.0][0] == "captured"
    assert outcomes[10.0] == ("undetected_arrival", 13, [(2, "heard"), (13, "arrived")])


def test_walking_past_is_heard_and_sneaking_is_not() -> None:
    """A route intruder walks (or sneaks) along the door's far side past the post guard: with walk_noise
    3 the guard hears its steps within 3 steps of the door and investigates; sneaking with sneak_noise
    0 it hears nothing, and every sneaking step takes sneak_ticks ticks."""
    scene, table, post = door_scene()
    grid = scene.grid
    level = parse_level({**DOOR, "intruder": {"walk_noise": 3, "sneak_noise": 0, "sneak_ticks": 3}})
    from guardsim.alert import AlertRules

    rules = AlertRules.of_level(level)
    route = [grid.flat(c, 0) for c in range(11, 6, -1)]  # east of the wall, north of the door: out of sight
    heard = {}
    for gait in ("walk", "sneak"):
        episode = alert_episode(
            scene, post, intruder="route", source=route[0], target=route[-1], route=route, table=table, rules=rules,
            gaits=[gait] * len(route), max_seconds=30,
        )  # fmt: skip
        episode.run()
        heard[gait] = [e.tick for e in episode.events if e.event == "heard"]
        cells = episode.record["intruder"]
        moves = [t for t in range(1, len(cells)) if cells[t] != cells[t - 1]]
        if gait == "sneak":
            assert np.diff([0, *moves]).tolist() == [3] * (len(route) - 1), moves
        else:
            assert np.diff([0, *moves]).tolist() == [1] * (len(route) - 1)
    assert heard["walk"] and not heard["sneak"]
    # (7, 0), the fourth step's cell, is the first within 3 steps of the door's cell (6, 2) round the wall.
    assert heard["walk"][0] == 4


def test_noises_and_hearing_are_in_the_trace_and_the_gif(tmp_path: Path) -> None:
    import imageio.v3 as iio

    from guardsim.render.alert import write_alert_gif

    scene, table, post = door_scene()
    grid = scene.grid
    route = door_route(grid)
    episode = alert_episode(
        scene, post, intruder="route", source=route[0], target=grid.flat(*GOAL), route=route, table=table,
        distractions=[(2, grid.flat(0, 0), 10.0)], max_seconds=60,
    )  # fmt: skip
    episode.run()
    data = json.loads(json.dumps(alert_trace_data(episode, scene, search="ripple", intruder="route")))
    assert data["noises"] == [{"tick": 2, "position": [0.5, 0.5], "radius": 10.0, "source": "throw"}]
    assert data["heard"][0][2] and not data["heard"][0][1]
    gif = tmp_path / "ears.gif"
    write_alert_gif(gif, scene, table, episode, suspicious=0.5)
    frames = iio.imread(gif, index=None)
    # The ring is drawn at the throw's tick only: frames 2 and 3 differ where the ring is.
    assert frames.shape[0] == len(episode.record["cells"])
    assert (frames[2] != frames[1]).any()


# -- bad input ------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("keys", "needle"),
    [({"walk_noise": -1}, "intruder.walk_noise"), ({"sneak_noise": -0.5}, "intruder.sneak_noise"),
     ({"sneak_ticks": 0}, "intruder.sneak_ticks"), ({"sneak_ticks": 1001}, "intruder.sneak_ticks"),
     ({"sneak_ticks": 1.5}, "whole number"),
     ({"shout": 1}, "intruder.shout")],
)  # fmt: skip
def test_bad_intruder_keys_are_one_line_errors(keys: dict[str, Any], needle: str) -> None:
    with pytest.raises(LevelError) as error:
        parse_level({**DOOR, "intruder": keys})
    assert needle in str(error.value) and "\n" not in str(error.value)


def _patrol_file(folder: Path) -> Path:
    data = {
        "level": DOOR["name"], "cell_size": 1.0, "origin": [0.0, 0.0], "shape": [5, 12], "motion": "grid",
        "strategy": "loop", "period": 1, "guards": [{"loop": [[6, 2], [6, 2]], "headings": [2, 2]}],
    }  # fmt: skip
    path = folder / "patrol.json"
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize(
    ("items", "needle"),
    [([[5.5, 4.5], {"throw": [30, 0.5], "at": 1, "noise": 5}], "throw 30,0.5 lies outside the level"),
     ([[5.5, 4.5], {"throw": [6.5, 0.5], "at": 1, "noise": 5}], "throw 6.5,0.5 is in cell [6, 0]"),
     ([[5.5, 4.5], {"throw": [0.5, 0.5], "at": 1, "noise": -2}], "item 1: noise"),
     ([[5.5, 4.5], {"to": [5.5, 3.5], "gait": "run"}], "gait 'run' is not one the level allows"),
     ([[5.5, 4.5], {"to": [5.5, 3.5], "loud": True}], "item 1: a waypoint is")],
)  # fmt: skip
def test_bad_route_files_are_one_line_errors(tmp_path: Path, items: list[Any], needle: str) -> None:
    level = write_level(tmp_path, DOOR)
    route = tmp_path / "route.json"
    route.write_text(json.dumps(items))
    result = CliRunner().invoke(
        main,
        ["alert", str(level), "--patrol", str(_patrol_file(tmp_path)), "--intruder", "route", "--route", str(route)],
    )
    assert result.exit_code == 2, result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and needle in lines[0] and str(route) in lines[0], result.stderr


def test_cli_throw_gets_the_intruder_through(tmp_path: Path) -> None:
    """The doorway through the command line: the route file with and without its bottle."""
    level = write_level(tmp_path, DOOR)
    patrol = _patrol_file(tmp_path)
    waypoints: list[Any] = [[5.5, 4.5]] * WAIT + [[5.5, 3.5], [5.5, 2.5], [6.5, 2.5]]
    waypoints += [[c + 0.5, 2.5] for c in range(7, 12)]
    lines = {}
    for name, extra in (("quiet", []), ("bottle", [{"throw": [0.5, 0.5], "at": 1.0, "noise": 10}])):
        route = tmp_path / f"{name}.json"
        route.write_text(json.dumps(waypoints + extra))
        result = CliRunner().invoke(
            main, ["alert", str(level), "--patrol", str(patrol), "--intruder", "route", "--route", str(route)]
        )
        assert result.exit_code == 0, result.output
        lines[name] = result.stdout.strip().splitlines()[-1]
    assert "captured" in lines["quiet"]
    assert "undetected arrival" in lines["bottle"]
    bad = CliRunner().invoke(main, ["alert", str(level), "--patrol", str(patrol), "--walk-noise", "-1"])
    assert bad.exit_code == 2 and "Traceback" not in bad.output


# -- the page: noise rings and guards that heard --------------------------------------------------------


def _ears_page(folder: Path) -> tuple[Path, dict[str, Any], list[bool]]:
    """The doorway episode with its bottle, as the alert page; its data and guard 0's heard flags."""
    from guardsim.viewer.alerts import write_alert_page
    from tests.pages import page_json
    from tests.test_browser import CHROMIUM

    if CHROMIUM is None:
        pytest.skip("no chromium on PATH: install Debian's chromium (apt-get install -y chromium)")
    scene, table, post = door_scene()
    grid = scene.grid
    route = door_route(grid)
    episode = alert_episode(
        scene, post, intruder="route", source=route[0], target=grid.flat(*GOAL), route=route, table=table,
        distractions=[(2, grid.flat(0, 0), 10.0)], max_seconds=60,
    )  # fmt: skip
    episode.run()
    page = folder / "ears.html"
    write_alert_page(page, scene, table, episode, patrol=post)
    return page, page_json(page.read_text()), [bool(row[0]) for row in episode.record["heard"]]


def test_the_page_reads_out_the_noise_and_the_guard_that_heard(tmp_path: Path) -> None:
    """In real headless Chromium: at the bottle's tick the readout lists the noise (its cell and radius)
    and the guard as having heard it; the tick before, neither. The page's data holds the episode's own
    noises and hearing (the GIF's data)."""
    from tests.test_alert_html import attributes
    from tests.test_browser import dump, element

    page, data, heard = _ears_page(tmp_path)
    assert data["alert"]["noises"] == [[2, 0, 10.0]] and data["alert"]["heard_letter"] == "H"
    assert heard[2] and not heard[1]
    for tick in (1, 2):
        dom = dump(page, f"tick={tick}", tmp_path / "profile")
        assert element(dom, "errors") == "" and element(dom, "status") == "ready", tick
        readout = attributes(dom, "alert-readout")
        assert readout["data-noises"] == ("0,0,10" if tick == 2 else "")
        assert readout["data-heard"] == ("1" if heard[tick] else "0")
        assert ("(heard a noise)" in element(dom, "alert-readout")) == heard[tick]


@pytest.mark.slow
def test_the_page_draws_each_noise_as_a_ring_at_its_tick(tmp_path: Path) -> None:
    """With the noises layer alone, a ring of the noise's radius (10 cells) round the corner cell is drawn
    through the far room at the bottle's tick; the tick before and after, no ring."""
    import imageio.v3 as iio

    from tests.test_browser import chromium, dump, geometry

    page, data, _ = _ears_page(tmp_path)
    outline = tuple(int(data["colours"]["outline"][k : k + 2], 16) for k in (1, 3, 5))
    ring = {}
    for tick in (1, 2, 3):
        # Per tick: the readout above the canvas may wrap differently and move it.
        left, top, scale = geometry(dump(page, f"tick={tick}&layers=noises&scale=12", tmp_path / "profile"))
        shot = tmp_path / "shot.png"
        done = chromium(
            f"{page.as_uri()}#tick={tick}&layers=noises&scale=12", tmp_path / "profile", f"--screenshot={shot}"
        )
        assert done.returncode == 0
        image = iio.imread(shot)[:, :, :3].astype(int)
        rows, cols = np.mgrid[0 : 5 * scale, 8 * scale : 12 * scale]  # the far room, where no one stands
        near = np.abs(np.hypot(cols - scale / 2, rows - scale / 2) - 10 * scale)
        on = (image[top + rows, left + cols] == outline).all(axis=2)
        ring[tick] = (int((on & (near <= 2)).sum()), int((on & (near > 3)).sum()))
    # The level's own outline crosses the annulus (the same pixels at every tick): the ring adds the rest.
    assert ring[1] == ring[3] and ring[2][0] >= ring[1][0] + 30 and ring[2][1] == ring[1][1], ring
