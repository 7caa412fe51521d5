"""fortify: on tiny levels the watchers it leaves are the fewest over its candidates (brute force over
subsets), every sealed proof holds under an independent breadth-first search over (lap tick, cell,
meters) of the level and patrol it writes, a keep-open pair keeps its slack, and bad input is one line."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from collections import deque
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.design.fortify import CameraShape, KeepOpen, fortify
from guardsim.design.fortify.candidates import candidate_gains, fortify_candidates, swing_ticks
from guardsim.detection import GuardDetection
from guardsim.detection.watch import lap_gains, level_watch
from guardsim.level import parse_level
from guardsim.patrol import read_patrol
from guardsim.scene import Scene
from guardsim.vision.table import view_table

ROOM = {"name": "room", "outer": [[0, 0], [7, 0], [7, 4], [0, 4]], "guard": {"view_range": 3}}
CORRIDOR = {"name": "corridor", "outer": [[0, 0], [8, 0], [8, 1], [0, 1]]}
DETECTED = 1.0 - 1e-9


def _way_through(
    neighbours: np.ndarray, gain: np.ndarray, fall: float, source: int, target: int, *, undetected: bool
) -> set[int]:
    """The entry ticks from which a player gets from ``source`` to ``target``: plain breadth-first search
    over (lap tick, cell, every watcher's meter), the meter rule written out here (rise by the gain in
    sight, fall by ``fall`` out of it, within [0, 1], full at 1 - 1e-9), no pruning but exact repeats."""
    watchers, lap, _ = gain.shape
    open_ticks = set()
    for entry in range(lap):

        def step(meters: tuple[float, ...], tick: int, cell: int) -> tuple[float, ...] | None:
            out = []
            for w in range(watchers):
                g = float(gain[w, tick, cell])
                if g > 0 and not undetected:
                    return None
                level = meters[w] + g if g > 0 else meters[w] - fall
                level = min(1.0, max(0.0, level))
                if level >= DETECTED:
                    return None
                out.append(level)
            return tuple(out)

        first = step((0.0,) * watchers, entry, source)
        if first is None:
            continue
        seen = {(entry, source, first)}
        queue = deque(seen)
        while queue:
            tick, cell, meters = queue.popleft()
            if cell == target:
                open_ticks.add(entry)
                break
            after = (tick + 1) % lap
            for other in [cell, *(int(n) for n in neighbours[cell] if n >= 0)]:
                moved = step(meters, after, other)
                if moved is None:
                    continue
                node = (after, other, tuple(round(m, 12) for m in moved))
                if node not in seen:
                    seen.add(node)
                    queue.append(node)
            assert len(seen) < 2_000_000
    return open_ticks


def _written_gains(folder: Path) -> tuple[Scene, np.ndarray, float]:
    """The watchers' gains over their joint lap, read back from the level and patrol fortify wrote."""
    level = parse_level(json.loads((folder / "level.json").read_text()))
    scene = Scene.from_level(level)
    detection = GuardDetection.of_level(level)
    watch = level_watch(scene, detection.dt) if level.cameras else None
    table = view_table(scene.grid, scene.vision())
    if (folder / "patrol.json").exists():
        patrol = read_patrol(str(folder / "patrol.json"), scene.grid)
        gains, _ = lap_gains(scene.grid, table, patrol.states, detection, watch)
        return scene, gains.gain, gains.fall
    assert watch is not None
    lap = int(np.lcm.reduce(watch.periods))
    gain = np.stack([g[np.arange(lap) % g.shape[0]] for g in watch.gains])
    return scene, gain, detection.model.fall(detection.dt)


def _cell(scene: Scene, point: tuple[float, float]) -> int:
    found = scene.grid.cell_of(point)
    assert found is not None
    return scene.grid.flat(*found)


def _run(args: Sequence[str]) -> Any:
    return CliRunner().invoke(main, ["fortify", *args])


def test_count_is_the_fewest_over_the_candidates_and_the_proof_holds(tmp_path: Path) -> None:
    level = parse_level(ROOM)
    pair = ((0.5, 0.5), (6.5, 3.5))
    result = fortify(level, None, [pair], candidates=10)
    document = result.document
    assert document["sealed"] and document["count"] == 2 and document["lower_bound"] == 2 and document["gap"] == 0
    # The candidate set, rebuilt with the same public functions: no subset of fewer watchers seals.
    scene = Scene.from_level(level)
    grid = scene.grid
    source, target = _cell(scene, pair[0]), _cell(scene, pair[1])
    detection = GuardDetection.of_level(level)
    swing = swing_ticks(1)
    pool = fortify_candidates(
        grid, [source], exclude=[source, target], near=[source, target], shape=CameraShape(), dt=detection.dt, swing=swing, cameras=True,
        posts=True, budget=10,
    )  # fmt: skip
    assert [w["candidate"] for w in document["watchers"]] and len(pool) == 10
    gains = candidate_gains(scene, view_table(grid, scene.vision()), pool, scene_options={}, swing=swing)
    lap = document["lap"]
    fall = detection.model.fall(detection.dt)

    def seals(subset: Sequence[int]) -> bool:
        if not subset:
            stacked = np.zeros((1, lap, grid.size))
        else:
            stacked = np.stack([gains[c][np.arange(lap) % gains[c].shape[0]] for c in subset])
        return not _way_through(grid.neighbours, stacked, fall, source, target, undetected=True)

    chosen = [w["candidate"] for w in document["watchers"]]
    assert seals(chosen)
    for size in range(document["count"]):
        assert not any(seals(subset) for subset in itertools.combinations(range(len(pool)), size)), size
    # The written level and patrol, read back, hold the proof: no entry tick of the joint lap gets through.
    out = tmp_path / "out"
    out.mkdir()
    from guardsim.design.fortify.outputs import write_fortify_outputs

    write_fortify_outputs(result, out)
    written, gain, written_fall = _written_gains(out)
    assert gain.shape[1] == lap
    assert _way_through(written.grid.neighbours, gain, written_fall, source, target, undetected=True) == set()
    proof = document["pairs"][0]["proof"]
    assert proof["no_path"] and proof["lap"] == lap and proof["entry_ticks"] == lap


def test_unseen_rule_seals_against_any_sighting_and_keep_open_keeps_its_slack(tmp_path: Path) -> None:
    level = parse_level(ROOM)
    sealed_pair = ((0.5, 0.5), (6.5, 0.5))
    keep = KeepOpen((0.5, 3.5), (6.5, 3.5), 2)
    result = fortify(level, None, [sealed_pair], keep_open=[keep], undetected=False, candidates=16)
    document = result.document
    assert document["sealed"] and document["rule"] == "unseen"
    kept = document["keep_open"][0]
    assert kept["kept"] and kept["slack"] >= 2 and kept["path"]["path"][0] == [0.5, 3.5]
    from guardsim.design.fortify.outputs import write_fortify_outputs

    write_fortify_outputs(result, tmp_path)
    scene, gain, fall = _written_gains(tmp_path)
    neighbours = scene.grid.neighbours
    source, target = _cell(scene, sealed_pair[0]), _cell(scene, sealed_pair[1])
    assert _way_through(neighbours, gain, fall, source, target, undetected=False) == set()
    still = _way_through(neighbours, gain, fall, _cell(scene, keep.source), _cell(scene, keep.target), undetected=False)
    assert len(still) == kept["slack"] >= keep.min_slack


def test_cli_in_process_seals_a_corridor(tmp_path: Path) -> None:
    level = tmp_path / "corridor.json"
    level.write_text(json.dumps(CORRIDOR))
    result = _run(
        [str(level), "--from", "0.5,0.5", "--to", "7.5,0.5", "--candidates", "8", "--out", str(tmp_path / "o")]
    )
    assert result.exit_code == 0, result.output
    document = json.loads((tmp_path / "o" / "fortify.json").read_text())
    assert document["sealed"] and document["count"] == 1 and document["pairs"][0]["proof"]["no_path"]


@pytest.mark.slow
def test_cli_writes_a_level_that_check_holds_to(tmp_path: Path) -> None:
    level = tmp_path / "corridor.json"
    level.write_text(json.dumps(CORRIDOR))
    out = tmp_path / "out"
    result = subprocess.run(
        [sys.executable, "-m", "guardsim.cli", "fortify", str(level), "--from", "0.5,0.5", "--to", "7.5,0.5",
         "--candidates", "8", "--out", str(out)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "corridor: sealed (undetected) with 1 watcher" in result.stdout
    for name in ("level.json", "fortify.json", "fortify.png"):
        assert (out / name).exists()
    assert not list(out.glob(".*part*"))
    args = ["check", str(out / "level.json"), "--sneak", "0.5,0.5", "7.5,0.5", "--expect", "detected"]
    if (out / "patrol.json").exists():
        args += ["--patrol", str(out / "patrol.json")]
    checked = CliRunner().invoke(main, args)
    assert checked.exit_code == 0, checked.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--from", "-3,0.5", "--to", "7.5,0.5"], "pair 1's entry -3,0.5 lies outside the level"),
        (["--from", "0.5,0.5", "--to", "4.5,2.5"], "pair 1's goal 4.5,2.5 lies outside the level"),
        (["--from", "0.5,0.5", "--to", "7.5,0.5", "--cameras", "0", "--posts", "0"], "a budget of 0 watchers"),
        (
            ["--from", "0.5,0.5", "--to", "7.5,0.5", "--keep-open", "0.5,0.5", "7.5,0.5"],
            "is also a pair to seal: it cannot be both",
        ),
        (["--from", "0.5,0.5"], "each --from needs its --to: 1 --from, 0 --to"),
        (["--from", "0.5,0.5", "--to", "7.5,0.5", "--max-rounds", "0"], "a budget of 0 rounds"),
    ],
    ids=["entry-off-level", "goal-off-level", "budget-0", "keep-open-is-sealed", "no-goal", "rounds-0"],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list[str], message: str) -> None:
    level = tmp_path / "corridor.json"
    level.write_text(json.dumps(CORRIDOR))
    result = _run([str(level), *args])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.output


def test_entry_in_a_wall_and_a_pair_with_no_path_are_refused(tmp_path: Path) -> None:
    two_rooms = {
        "name": "two rooms",
        "outer": [[0, 0], [9, 0], [9, 3], [0, 3]],
        "holes": [[[4, 0], [5, 0], [5, 3], [4, 3]]],
    }
    level = tmp_path / "two.json"
    level.write_text(json.dumps(two_rooms))
    walled = _run([str(level), "--from", "4.5,1.5", "--to", "8.5,1.5"])
    assert walled.exit_code == 2 and "pair 1's entry 4.5,1.5 is in cell [4, 1]" in walled.output
    apart = _run([str(level), "--from", "0.5,1.5", "--to", "8.5,1.5"])
    assert (
        apart.exit_code == 2 and "pair 1's goal 8.5,1.5 cannot be reached from its entry 0.5,1.5 at all" in apart.output
    )


@pytest.mark.slow
def test_same_bytes_whatever_the_worker_count() -> None:
    level = parse_level(ROOM)
    pairs = [((0.5, 0.5), (6.5, 3.5))]
    one = fortify(level, None, pairs, candidates=10, workers=1).document
    two = fortify(level, None, pairs, candidates=10, workers=2).document
    assert json.dumps(one) == json.dumps(two)


@pytest.mark.slow
def test_same_bytes_on_a_real_dask_cluster() -> None:
    """Candidates evaluated on a two-process local Dask cluster (on 127.0.0.1): the same document."""
    distributed = pytest.importorskip("distributed")
    level = parse_level(ROOM)
    pairs = [((0.5, 0.5), (6.5, 3.5))]
    one = fortify(level, None, pairs, candidates=10, workers=1).document
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None, host="127.0.0.1"
    ) as cluster:  # fmt: skip
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        dask = fortify(level, None, pairs, candidates=10, scheduler=cluster.scheduler_address).document
    assert json.dumps(one) == json.dumps(dask)


def test_a_post_in_patrol_json_turns_in_place_and_stays_on_one_cell() -> None:
    from guardsim.errors import PatrolError
    from guardsim.patrol.format import parse_patrol

    grid = Scene.from_level(parse_level(CORRIDOR)).grid
    post = {"loop": [[3, 0]] * 5, "headings": [0, 1, 2, 3, 0], "post": True}
    patrol = parse_patrol({"shape": [1, 8], "guards": [post]}, grid)
    assert patrol.period == 4 and patrol.headings(0) == [0, 1, 2, 3]
    with pytest.raises(PatrolError, match="a guard standing still keeps its heading"):
        parse_patrol({"shape": [1, 8], "guards": [{**post, "post": False}]}, grid)
    with pytest.raises(PatrolError, match="a post stands on one cell"):
        parse_patrol({"shape": [1, 8], "guards": [{**post, "loop": [[3, 0], [4, 0], [3, 0], [3, 0], [3, 0]]}]}, grid)


def test_a_lap_too_long_for_the_searches_is_refused_before_any_work(monkeypatch: pytest.MonkeyPatch) -> None:
    # A 256 x 256 city's 8,826-tick lap passed 20 GB before the search's own label limit stopped it.
    from guardsim.design.fortify import loop
    from guardsim.errors import LimitError

    level = parse_level(ROOM)
    cells = Scene.from_level(level).grid.size
    monkeypatch.setattr(loop, "MAX_DENSE_NODES", cells - 1)
    with pytest.raises(LimitError, match=rf"\(lap tick, cell\): {cells} nodes \({cells} cells x a 1-tick lap\), over"):
        fortify(level, None, [((0.5, 0.5), (6.5, 3.5))], candidates=4)
