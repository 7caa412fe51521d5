"""The example game (examples/game/stealth.py) played headless (SDL's dummy video driver) by a scripted
player: it walks down the right corridor into a guard's view, is detected and chased, runs up and
through the door into the storeroom's side, is lost, and waits while the guards search, give up and
walk back to their routes. The frame API itself: off-floor positions are one-line errors."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from guardsim.errors import GuardsimError

REPO = Path(__file__).resolve().parent.parent
GAME = REPO / "examples" / "game" / "stealth.py"

pytest.importorskip("pygame")
pytest.importorskip("pytmx")

#: The escape after detection: up the corridor, through its upper door, left along the top wall, down.
ESCAPE = [(28.5, 4.5), (24.5, 4.5), (24.5, 1.5), (12.5, 1.5), (12.5, 7.5)]


def _game() -> Any:
    spec = importlib.util.spec_from_file_location("stealth_example", GAME)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["stealth_example"] = module
    spec.loader.exec_module(module)
    return module


def _toward(position: tuple[float, float], goal: tuple[float, float]) -> set[str]:
    keys = set()
    if goal[0] > position[0] + 0.1:
        keys.add("right")
    if goal[0] < position[0] - 0.1:
        keys.add("left")
    if goal[1] > position[1] + 0.1:
        keys.add("down")
    if goal[1] < position[1] - 0.1:
        keys.add("up")
    return keys


def test_the_game_runs_headless_detected_chased_lost_gave_up(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    monkeypatch.setenv("SDL_AUDIODRIVER", "dummy")
    game = _game()
    plan = {"running": False, "waypoint": 0}

    def script(frame: int, summary: Any) -> set[str]:
        if not plan["running"]:
            plan["running"] = "detected" in summary.events
            return {"down"}
        while plan["waypoint"] < len(ESCAPE):
            keys = _toward(summary.player, ESCAPE[plan["waypoint"]])
            if keys:
                return keys
            plan["waypoint"] += 1
        return set()

    summary = game.play(script=script, frames=900, search_seconds=5.0)
    events = summary.events
    assert summary.frames == 900
    assert "captured" not in events
    first = {name: events.index(name) for name in ("detected", "lost", "gave_up", "back_on_route")}
    assert first["detected"] < first["lost"] < first["gave_up"] < first["back_on_route"], events
    assert {"chase", "search", "return"} <= summary.states
    assert plan["waypoint"] == len(ESCAPE)  # it got away along the whole escape


def test_the_frame_api_refuses_a_player_off_the_floor() -> None:
    import guardsim
    from guardsim.alert import GameGuards
    from guardsim.patrol.model import Patrol

    level = guardsim.load_level(str(REPO / "examples" / "game" / "warehouse.tmx"))
    scene = guardsim.Scene.from_level(level)
    post = Patrol(np.array([[scene.grid.flat(2, 2) * 4]]), period=1, strategy="loop")
    guards = GameGuards(scene, post, player=(28.5, 2.5))
    off = "not on the level's floor"
    cases: list[tuple[Any, str]] = [((0.5, 0.5), off), ((-3, 2), off), ((float("nan"), 1), off), (("a", 1), "pair")]
    for position, needle in cases:
        with pytest.raises(GuardsimError) as error:
            guards.frame(position, 1 / 60)
        assert str(error.value).startswith("position: ") and needle in str(error.value)
        assert "\n" not in str(error.value)
    with pytest.raises(GuardsimError, match=r"^dt: "):
        guards.frame((28.5, 2.5), -1.0)
    with pytest.raises(GuardsimError, match=r"^player: "):
        GameGuards(scene, post, player=(0.5, 0.5))


def test_the_players_noise_comes_from_its_speed() -> None:
    """A post guard facing west in a 10 x 3 room; the player walks east behind it (a cell a tick: walking,
    walk_noise 4) and is heard; at half that pace (sneaking, sneak_noise 0) it is not."""
    import guardsim
    from guardsim.alert import GameGuards
    from guardsim.patrol.model import Patrol

    level = guardsim.parse_level(
        {"outer": [[0, 0], [10, 0], [10, 3], [0, 3]], "guard": {"view_range": 3},
         "intruder": {"walk_noise": 4, "sneak_noise": 0, "sneak_ticks": 2}}
    )  # fmt: skip
    scene = guardsim.Scene.from_level(level)
    post = Patrol(np.array([[scene.grid.flat(3, 1) * 4 + 2]]), period=1, strategy="loop")
    heard = {}
    for pace, seconds in (("walk", 0.5), ("sneak", 1.0)):  # a grid tick is 0.5 s
        guards = GameGuards(scene, post, player=(5.5, 1.5))
        events = []
        for column in range(6, 10):
            for _ in range(int(seconds * 60)):
                events += [e.event for e in guards.frame((column + 0.5, 1.5), 1 / 60).events]
        heard[pace] = "heard" in events
    assert heard == {"walk": True, "sneak": False}
