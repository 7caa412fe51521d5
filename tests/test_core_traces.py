"""Every field of today's traces keeps the value it had before the simulation core was rebuilt.

tests/data/before_core/ holds traces written by ``guardsim play`` before the change: every shipped level
with every planner from ``--seed 0``, and a two-guard ``tour`` from ``--seed 0 --episode 1``. New trace
fields may be added; every stored field must come out the same.
"""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import pytest

from guardsim import Scene, Simulation, load_level

DATA = Path(__file__).parent / "data" / "before_core"
LEVELS = Path(__file__).resolve().parents[1] / "levels"
STORED = sorted(DATA.glob("*.json.gz"))


def _case(path: Path) -> tuple[str, str, int]:
    name = path.name.removesuffix(".json.gz")
    level = next(stem for stem in ("square", "passages", "mgs_docks", "king_snurre") if name.startswith(stem + "-"))
    rest = name[len(level) + 1 :]
    guards = 2 if rest.endswith("-2guards") else 1
    return level, rest.removesuffix("-2guards"), guards


_SCENES: dict[str, Scene] = {}


@pytest.mark.parametrize("path", STORED, ids=[path.name.removesuffix(".json.gz") for path in STORED])
def test_trace_fields_unchanged(path: Path) -> None:
    level, planner, guards = _case(path)
    scene = _SCENES.setdefault(level, Scene.from_level(load_level(LEVELS / f"{level}.json")))
    simulation = Simulation(scene, planner, guards=guards)
    simulation.reset(seed=0, episode=1 if guards > 1 else None)
    now = json.loads(simulation.run().to_json())
    before = json.loads(gzip.decompress(path.read_bytes()))
    if planner == "tour" and guards == 1:
        assert now["covered"] and now["steps"] <= before["steps"]
        pytest.skip("tour improved in issue 15; its traces changed on purpose (checked: covered, never longer)")
    changed = [key for key in before if now.get(key) != before[key]]
    assert not changed, f"fields changed: {changed}"


def test_all_cases_stored() -> None:
    assert len(STORED) == 4 * 7
