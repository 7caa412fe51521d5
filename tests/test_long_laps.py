"""Patrols whose laps are long: read back whatever their length (the reader bounds only the states it
unrolls, in bytes), and the commands that build arrays over every (tick, cell) refuse up front, naming
the limit to raise, while the sneak check and alert's sneaking intruder read the lap sparse."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import guardsim.patrol.format as patrol_format
import guardsim.patrol.scoring as scoring
import guardsim.sneak as sneak_module
from guardsim.detection import GuardDetection
from guardsim.errors import LimitError, PatrolError
from guardsim.grid import CoverageGrid
from guardsim.patrol import parse_patrol, seen_timeline
from guardsim.sneak import sneak_check
from tests.common import TWO_ROOMS, run, scene_from, write_level

REPO = Path(__file__).resolve().parent.parent
# ../shared beside the clone (CI), or beside the folder of worktrees.
MAPS = next(
    (base / "shared" / "maps" / "movingai" for base in (REPO.parent, REPO.parent.parent) if (base / "shared").is_dir()),
    REPO.parent / "shared" / "maps" / "movingai",
)
#: Ticks the guard of :func:`_waiting_loop` stands still before walking its ring: a lap over 20 000 ticks.
WAIT = 20_500


def _waiting_loop(wait: int) -> dict[str, list[list[int]] | list[int]]:
    """A guard standing at [0, 0] facing up for ``wait`` ticks, then walking a 2 x 2 ring back there."""
    loop = [[0, 0]] * (wait + 1) + [[1, 0], [1, 1], [0, 1], [0, 0]]
    return {"loop": loop, "headings": [3] * (wait + 1) + [0, 1, 2, 3]}


def _ring_grid() -> CoverageGrid:
    """A 2 x 2 grid, every cell floor (neighbours right, down, left, up)."""
    neighbours = np.array([[1, 2, -1, -1], [-1, 3, 0, -1], [3, -1, -1, 0], [-1, -1, 2, 1]])
    return CoverageGrid((0.0, 0.0), 1.0, np.ones((2, 2), dtype=bool), neighbours)


def test_a_lap_over_twenty_thousand_ticks_is_read_back() -> None:
    patrol = parse_patrol({"shape": [2, 2], "guards": [_waiting_loop(WAIT)]}, _ring_grid())
    assert patrol.period == WAIT + 4 and patrol.states.shape == (1, WAIT + 4)


def test_laps_repeating_together_over_the_bytes_limit_are_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    guards = [_waiting_loop(3), _waiting_loop(4)]  # laps of 7 and 8 ticks: 56 together, 2 guards: 896 bytes
    grid = _ring_grid()
    assert parse_patrol({"shape": [2, 2], "guards": guards}, grid).period == 56
    monkeypatch.setattr(patrol_format, "MAX_UNROLLED_BYTES", 800)
    with pytest.raises(PatrolError) as error:
        parse_patrol({"shape": [2, 2], "guards": guards}, grid, source="p.json")
    message = str(error.value)
    assert message.startswith("p.json: guards: the laps' lengths [7, 8] repeat together only every 56 ticks")
    assert "guardsim.patrol.format.MAX_UNROLLED_BYTES" in message and "\n" not in message


def test_a_dense_timeline_over_its_limit_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    scene = scene_from(TWO_ROOMS)
    table = scene.view_table()
    states = np.zeros((1, 40), dtype=np.int64)
    assert seen_timeline(table, states, scene.grid.size).shape == (40, scene.grid.size)
    monkeypatch.setattr(scoring, "MAX_TIMELINE_BYTES", 39 * scene.grid.size)
    with pytest.raises(LimitError, match="MAX_TIMELINE_BYTES"):
        seen_timeline(table, states, scene.grid.size)


def test_the_sneak_limit_is_stated_in_memory(monkeypatch: pytest.MonkeyPatch) -> None:
    """Counted over the floor cells (the searches hold rows for those alone), refused before any work."""
    scene = scene_from(TWO_ROOMS)
    grid = scene.grid
    patrol = parse_patrol({"shape": list(grid.shape), "guards": [_waiting_loop(10)]}, grid)
    floor = int(grid.traversable.sum())
    assert floor < grid.size
    monkeypatch.setattr(sneak_module, "MAX_SNEAK_NODES", 14 * floor - 1)
    with pytest.raises(LimitError) as error:
        sneak_check(
            grid, scene.view_table(), patrol, grid.flat(0, 0), grid.flat(10, 2),
            detection=GuardDetection.of_level(scene.level),
        )  # fmt: skip
    message = str(error.value)
    assert f"{14 * floor} (floor cell, lap tick) nodes ({floor} floor cells x a 14-tick lap)" in message
    assert " GB, over the limit of " in message and "guardsim.sneak.MAX_SNEAK_NODES" in message
    # Alert's sneaking intruder plans with the same searches, under the same limit.
    from guardsim.alert.run import alert_episode

    with pytest.raises(LimitError, match="MAX_SNEAK_NODES"):
        alert_episode(scene, patrol, intruder="sneak", source=grid.flat(0, 0), target=grid.flat(10, 2))


def test_sneak_and_alert_run_on_a_long_lap(tmp_path: Path) -> None:
    """The lap of 20 504 ticks is read back; `sneak --undetected` and a sneaking intruder's alert episodes
    answer on it (the intruder plans over the sparse sight)."""
    level = write_level(tmp_path, TWO_ROOMS)
    patrol = tmp_path / "patrol.json"
    patrol.write_text(json.dumps({"shape": [3, 11], "guards": [_waiting_loop(WAIT)]}), encoding="utf-8")
    ends = ["--from", "2.5,2.5", "--to", "10.5,0.5"]
    sneak = run("sneak", level, "--patrol", patrol, *ends, "--undetected", "--out", tmp_path / "s")
    assert sneak.exit_code == 0, sneak.output
    found = json.loads((tmp_path / "s" / "sneak.json").read_text(encoding="utf-8"))
    assert found["period"] == WAIT + 4 and found["found"]
    alert = run("alert", level, "--patrol", patrol, "--intruder", "sneak", *ends, "--out", tmp_path / "a")
    assert alert.exit_code == 0, alert.output
    [outcome] = json.loads((tmp_path / "a" / "alert.json").read_text(encoding="utf-8"))["outcomes"]["ripple"]
    # Entering at lap tick 0 on the unseen path the sneak check finds, it arrives unseen when that path does.
    assert outcome["outcome"] == "undetected_arrival" and found["start_tick"] == 0
    assert outcome["ticks"] == len(found["path"]) - 1


@pytest.mark.slow
def test_a_512_map_patrolled_by_4_guards_is_usable_afterwards(tmp_path: Path) -> None:
    """AR0603SR (512 x 512): a 4-guard patrol, read back by `sneak --undetected` (over the floor's rows)
    and by alert's batch (about 50 s, 1 GB)."""
    level = MAPS / "AR0603SR.map"
    if not level.exists():
        pytest.skip(f"{level} is not here")
    patrol = run("patrol", level, "--guards", "4", "--out", tmp_path / "p")
    assert patrol.exit_code == 0, patrol.output
    written = tmp_path / "p" / "patrol.json"
    period = json.loads(written.read_text(encoding="utf-8"))["period"]
    sneak = run(
        "sneak", level, "--patrol", written, "--from", "133.5,20.5", "--to", "245.5,510.5", "--undetected",
        "--out", tmp_path / "s",
    )  # fmt: skip
    assert sneak.exit_code == 0, sneak.output
    found = json.loads((tmp_path / "s" / "sneak.json").read_text(encoding="utf-8"))
    assert found["period"] == period and found["found"] and found["path"][0] == [133, 20]
    alert = run("alert", level, "--patrol", written, "--episodes", "2", "--workers", "1", "--out", tmp_path / "a")
    assert alert.exit_code == 0, alert.output
    assert len(json.loads((tmp_path / "a" / "alert.json").read_text(encoding="utf-8"))["outcomes"]["ripple"]) == 2
