"""``guardsim patrol --godot``: the scene loads in real Godot and its followers walk the planned routes.

Real Godot 3 (Debian's ``godot3-server``, which ``.ci/run`` installs) loads the exported scene, attaches
``examples/godot/guard_follow_godot3.gd`` to every ``PathFollow2D`` and seeks it through two periods;
the positions Godot reports must be route.json's (written in the same pixels) replayed by
:func:`guardsim.patrol.export.position_at`, which the patrol tests check against the patrol tick by tick.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest

from guardsim.patrol.export import position_at
from tests.common import SQUARE, STRIP, TWO_ROOMS, run, write_level

GODOT = shutil.which("godot3-server")
needs_godot = pytest.mark.skipif(GODOT is None, reason="Debian's godot3-server is not installed (.ci/run installs it)")
FOLLOW = Path(__file__).resolve().parent.parent / "examples" / "godot" / "guard_follow_godot3.gd"

WALKER = """extends SceneTree

func _init():
	var scene = load("{scene}").instance()
	root.add_child(scene)
	var file = File.new()
	file.open("{times}", File.READ)
	var times = parse_json(file.get_as_text())
	file.close()
	for path in scene.get_children():
		var follow = path.get_node("Follow")
		follow.set_script(load("{follow}"))
		follow.playing = false
		for t in times:
			follow.seek(t)
			print("POS ", path.get_meta("guard"), " ", t, " ", follow.position.x, " ", follow.position.y)
	quit()
"""


def _walk_in_godot(tmp_path: Path, scene: Path, times: list[float]) -> dict[int, list[tuple[float, float]]]:
    """Each guard's follower position at ``times``, as real Godot 3 reports it."""
    (tmp_path / "times.json").write_text(json.dumps(times))
    script = tmp_path / "walk.gd"
    script.write_text(WALKER.format(scene=scene, times=tmp_path / "times.json", follow=FOLLOW))
    (tmp_path / "project.godot").write_text("")
    assert GODOT is not None
    done = subprocess.run(
        [GODOT, "--no-window", "--path", str(tmp_path), "-s", str(script)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    errors = [line for line in done.stderr.splitlines() if "SCRIPT ERROR" in line or "Parse Error" in line]
    assert done.returncode == 0 and not errors, done.stdout + done.stderr
    walked: dict[int, list[tuple[float, float]]] = {}
    for line in done.stdout.splitlines():
        match = re.fullmatch(r"POS (\d+) \S+ (\S+) (\S+)", line.strip())
        if match:
            walked.setdefault(int(match[1]), []).append((float(match[2]), float(match[3])))
    return walked


def _export(tmp_path: Path, level: dict[str, Any], *options: str) -> tuple[Path, dict[str, Any]]:
    path = write_level(tmp_path, level)
    scene, route = tmp_path / "patrol.tscn", tmp_path / "route.json"
    args = ["patrol", str(path), "--out", str(tmp_path / "out"), "--export", str(route), "--godot", str(scene)]
    result = run(*args, "--godot-version", "3", "--units", "pixels", *options)
    assert result.exit_code == 0, result.output
    return scene, json.loads(route.read_text())


@needs_godot
@pytest.mark.parametrize(
    ("level", "options", "modes"),
    [
        (TWO_ROOMS, ["--guards", "2"], None),
        (STRIP, [], {"ping-pong"}),
        (TWO_ROOMS, ["--strategy", "staleness", "--laps", "1", "--pixels-per-unit", "16"], {"once"}),
        pytest.param(json.loads(SQUARE.read_text()), ["--guards", "2", "--clean"], {"loop"}, marks=pytest.mark.slow),
    ],
    ids=["two-rooms-team", "strip-ping-pong", "walked-once", "square-cleaned-team"],
)
def test_godot_walks_the_exported_route(
    tmp_path: Path, level: dict[str, Any], options: list[str], modes: set[str] | None
) -> None:
    scene, route = _export(tmp_path, level, *options)
    if modes is not None:
        assert {guard["loop_mode"] for guard in route["guards"]} == modes
    period = route["period_seconds"]
    span = 2 * period if period else route["guards"][0]["waypoints"][-1]["time"] + 1.0
    times = [round(0.125 * step, 3) for step in range(int(span / 0.125) + 1)]
    walked = _walk_in_godot(tmp_path, scene, times)
    assert sorted(walked) == list(range(1, len(route["guards"]) + 1))
    for number, guard in enumerate(route["guards"], start=1):
        assert len(walked[number]) == len(times)
        for seconds, got in zip(times, walked[number]):
            want = position_at(guard, seconds)
            # Godot bakes the curve every pixel; a follower cuts a corner by less than one.
            assert got == pytest.approx(want, abs=1.0), (number, seconds)


def test_godot_4_scene_says_what_the_godot_3_scene_says(tmp_path: Path) -> None:
    path = write_level(tmp_path, TWO_ROOMS)
    texts = {}
    for version in ("3", "4"):
        scene = tmp_path / f"patrol{version}.tscn"
        args = ["patrol", str(path), "--out", str(tmp_path / "out"), "--guards", "2", "--godot", str(scene)]
        result = run(*args, "--godot-version", version)
        assert result.exit_code == 0, result.output
        texts[version] = scene.read_text()
    four, three = texts["4"], texts["3"]
    assert four.startswith("[gd_scene load_steps=3 format=3]") and three.startswith("[gd_scene load_steps=3 format=2]")
    assert "rotates = false" in four and "rotate = false" in three
    # Two curves, three root metadata, eight metadata per guard.
    assert _contents(four) == _contents(three) and len(_contents(four)) == 2 + 3 + 2 * 8


def _numbers(value: str) -> list[float] | str:
    bare = re.sub(r"[A-Za-z]\w*", "", value)  # PackedFloat32Array, PoolRealArray
    return value if value.startswith('"') else [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", bare)]


def _contents(scene: str) -> list[tuple[str, list[float] | str]]:
    """The metadata and curve points of a scene, in order, whichever Godot format it is in."""
    found = []
    for line in scene.splitlines():
        match = re.fullmatch(r'metadata/(\w+) = (.*)|"(\w+)": (.*?),?', line)
        if match:
            name, value = (match[1], match[2]) if match[1] else (match[3], match[4])
            found.append((name, _numbers(value)))
    return found


def test_godot_options_are_checked(tmp_path: Path) -> None:
    path = write_level(tmp_path, STRIP)
    result = run("patrol", path, "--out", tmp_path / "o", "--godot", "x.tscn", "--godot-version", "2")
    assert result.exit_code == 2 and "'2' is not one of '4', '3'" in result.output
    result = run("patrol", path, "--out", tmp_path / "o", "--pixels-per-unit", "0", "--export", "r.json")
    assert result.exit_code == 2 and "--pixels-per-unit" in result.output


def test_the_pixel_scale_is_said_when_assumed(tmp_path: Path) -> None:
    # A hand-made level records no tile size: the Godot scene and a route in pixels use 32 px per unit,
    # and say so on one warning line; given --pixels-per-unit, or a route in world units only, nothing.
    path = write_level(tmp_path, STRIP)
    scene, route = tmp_path / "patrol.tscn", tmp_path / "route.json"
    base = ["patrol", str(path), "--out", str(tmp_path / "out"), "--godot", str(scene), "--export", str(route)]
    assumed = run(*base, "--units", "pixels")
    assert assumed.exit_code == 0, assumed.output
    warning = [line for line in assumed.stderr.splitlines() if "assumed" in line]
    assert warning == [
        f"guardsim: warning: {scene}, {route}: 32 pixels per world unit assumed ({path} records no tile_pixels); "
        "give --pixels-per-unit N, or --tiled-source MAP for the tiles of its Tiled map"
    ]
    chosen = run(*base, "--units", "pixels", "--pixels-per-unit", "16")
    assert chosen.exit_code == 0 and "assumed" not in chosen.stderr
    world = run("patrol", str(path), "--out", str(tmp_path / "out2"), "--export", str(route))
    assert world.exit_code == 0 and "assumed" not in world.stderr
