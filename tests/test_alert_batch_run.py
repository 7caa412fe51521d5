"""A batch of alert episodes from Python, as ``guardsim alert`` runs it (guardsim.alert.batch_run): the
options checked, the starts drawn, the episodes run, and a folder resumed from its traces."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from guardsim import plan_alert_batch, run_alert_batch
from guardsim.alert.batch_run import alert_run_options, write_alert_json
from guardsim.alert.intruders import read_route_cells
from guardsim.errors import GuardsimError
from tests.test_alert import ring_patrol, setup


def test_a_route_file_becomes_cells_and_a_jump_is_refused(tmp_path: Path) -> None:
    scene, _ = setup()
    grid = scene.grid
    walk = tmp_path / "walk.json"
    walk.write_text(json.dumps([[1.5, 1.5], [2.5, 1.5], {"to": [2.5, 2.5], "gait": "sneak"}]))
    cells = read_route_cells(str(walk), grid, dt=0.5)
    assert cells.cells == [grid.flat(1, 1), grid.flat(2, 1), grid.flat(2, 2)]
    assert cells.gaits == ["walk", "walk", "sneak"]
    jump = tmp_path / "jump.json"
    jump.write_text(json.dumps([[1.5, 1.5], [3.5, 1.5]]))
    with pytest.raises(GuardsimError, match=r"jump.json: point 1 is not a 4-neighbour of point 0"):
        read_route_cells(str(jump), grid, dt=0.5)


def test_one_episode_needs_an_entry_and_a_batch_draws_its_own() -> None:
    scene, _ = setup()
    patrol = ring_patrol(scene.grid)
    with pytest.raises(GuardsimError, match="one episode needs --from"):
        plan_alert_batch(scene, patrol, intruder="still")
    batch = plan_alert_batch(scene, patrol, intruder="evader", search="all", episodes=3, seed=2)
    assert len(batch.tasks) == 3 * len(batch.searches) == 12
    # Every strategy plays the same drawn starts.
    starts = {name: [(t.phase, t.source, t.target) for t in batch.tasks if t.search == name] for name in batch.searches}
    assert len({tuple(s) for s in starts.values()}) == 1
    again = plan_alert_batch(scene, patrol, intruder="evader", episode=1, seed=2)
    assert (again.tasks[0].phase, again.tasks[0].source, again.tasks[0].target) == starts["ripple"][1]


def test_a_folder_resumes_from_its_traces(tmp_path: Path) -> None:
    scene, _ = setup()
    patrol = ring_patrol(scene.grid)
    level = tmp_path / "level.json"
    level.write_text("{}")
    batch = plan_alert_batch(scene, patrol, intruder="evader", episodes=3, seed=5, spotted=True, trace=True)
    options = alert_run_options(batch, str(level), str(level), None, None, None, episodes=3)
    first = run_alert_batch(batch, folder=tmp_path, options=options, workers=1)
    assert first.done_before == 0 and first.lost == 0 and len(first.outcomes) == 3
    assert sorted(path.name for path in tmp_path.glob("ripple-*.json")) == [f"ripple-{k:04d}.json" for k in range(3)]
    told: list[int] = []
    second = run_alert_batch(batch, folder=tmp_path, options=options, workers=1, starting=lambda *a: told.append(1))
    assert second.done_before == 3 and not told
    assert second.runs(batch) == first.runs(batch)
    path = write_alert_json(tmp_path, batch, second, patrol="p.json", intruder="evader", seed=5)
    summary = json.loads(path.read_text())
    assert summary["episodes"] == 3 and [row["search"] for row in summary["summary"]] == ["ripple"]
    with pytest.raises(GuardsimError, match="other options"):
        run_alert_batch(batch, folder=tmp_path, options={**options, "seed": 6}, workers=1)
