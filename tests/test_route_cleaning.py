"""``guardsim patrol --clean``: jogs and spurs taken out of exported routes only where nothing is lost."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from guardsim.motion.sight import pose_visible_cells
from guardsim.patrol.cleaning import clean_routes, guard_poses, route_period
from tests.common import TWO_ROOMS, run, scene_from, write_level

ROOM = {"name": "room", "outer": [[0, 0], [12, 0], [12, 4], [0, 4]], "guard": {"start": [0.5, 0.5], "radius": 0.3}}
# A thin wall the straight leg from (0.5, 0.5) to (11.5, 1.5) would graze, clear of the staircase.
LEDGE = {**ROOM, "holes": [[[3, 1.0], [5, 1.0], [5, 1.1], [3, 1.1]]]}


def _point(x: float, y: float, time: float) -> dict[str, Any]:
    return {"x": x, "y": y, "tick": time * 2, "time": time, "heading": 0.0, "wait": 0.0}


def _staircase() -> dict[str, Any]:
    """A loop along the room with a one-cell jog halfway along its top run."""
    corners = [(0.5, 0.5), (6.5, 0.5), (6.5, 1.5), (11.5, 1.5), (11.5, 3.5), (0.5, 3.5), (0.5, 0.5)]
    time, points = 0.0, []
    for index, (x, y) in enumerate(corners):
        if index:
            time += abs(x - corners[index - 1][0]) + abs(y - corners[index - 1][1])
        points.append(_point(x, y, time / 2.0))
    return {"loop_mode": "loop", "period": points[-1]["time"], "phase": 0.0, "waypoints": points}


@pytest.mark.parametrize(("level", "jogs"), [(ROOM, 1), (LEDGE, 0)], ids=["open", "ledge-in-the-way"])
def test_a_jog_is_taken_out_only_where_the_guard_fits(level: dict[str, Any], jogs: int) -> None:
    scene = scene_from(level)
    route = _staircase()
    goal = scene.grid.traversable.ravel().copy()
    [cleaned], [report] = clean_routes(scene, [route], goal, speed=2.0, tolerance=10.0)
    assert report is not None and report.jogs == jogs and report.spurs == 0
    places = [(p["x"], p["y"]) for p in cleaned["waypoints"]]
    assert ((6.5, 0.5) in places) == (jogs == 0) and ((6.5, 1.5) in places) == (jogs == 0)
    # Retimed at the same speed: a straight leg is shorter than the staircase it replaces.
    assert cleaned["period"] == pytest.approx(cleaned["waypoints"][-1]["time"])
    assert (cleaned["period"] < route["period"]) == (jogs > 0)
    for a, b in zip(cleaned["waypoints"], cleaned["waypoints"][1:]):
        leg = np.hypot(b["x"] - a["x"], b["y"] - a["y"])
        assert b["time"] - a["time"] - a["wait"] == pytest.approx(leg / 2.0, abs=1e-5)


def test_a_spur_is_cut_and_its_waits_kept() -> None:
    scene = scene_from(ROOM)
    points = [_point(0.5, 0.5, 0), _point(11.5, 0.5, 5.5), _point(11.5, 3.5, 7), _point(11.5, 0.5, 8.5), _point(0.5, 0.5, 14)]
    points[1]["wait"] = 1.0
    points[3]["wait"] = 2.0
    for point in points[2:]:
        point["time"] += 1.0
    points[4]["time"] += 2.0
    route = {"loop_mode": "loop", "period": points[-1]["time"], "phase": 0.0, "waypoints": points}
    goal = scene.grid.traversable.ravel().copy()
    [cleaned], [report] = clean_routes(scene, [route], goal, speed=2.0, tolerance=10.0)
    assert report is not None and report.spurs == 1
    assert [(p["x"], p["y"], p["wait"]) for p in cleaned["waypoints"]] == [(0.5, 0.5, 0.0), (11.5, 0.5, 3.0), (0.5, 0.5, 0.0)]


def test_cleaned_team_routes_still_see_every_cell_with_the_reference_vision(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    route_path = tmp_path / "route.json"
    args = ["patrol", level, "--out", tmp_path / "o", "--guards", "2", "--export", route_path, "--clean"]
    result = run(*args)
    assert result.exit_code == 0, result.output
    assert "route 1 cleaned:" in result.output
    data = json.loads(route_path.read_text())
    scene = scene_from(TWO_ROOMS)
    seen = np.zeros(scene.grid.size, dtype=bool)
    for guard in data["guards"]:
        assert guard["period"] == pytest.approx(route_period(guard))
        for x, y, heading in guard_poses(guard, data["seconds_per_tick"]).tolist():
            assert scene.world.fits((x, y), scene.level.guard.radius)
            seen[pose_visible_cells(scene.world, scene.grid, scene.cone, x, y, heading)] = True
    patrol = json.loads((tmp_path / "o" / "patrol.json").read_text())
    reachable = np.array([[value is not None for value in row] for row in patrol["idleness"]]).ravel()
    assert seen[reachable].all()
