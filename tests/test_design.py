"""report, diff and check --baseline on two versions of a small level (tests/design_levels.py): a moved
wall opens a side passage round a posted guard. Exact outcomes, the picture decoded, exit codes."""

from __future__ import annotations

import itertools
import json
import re
import shutil
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner

import guardsim
from guardsim.cli import main
from guardsim.design import analyse, distinct_ways, path_distance_risk, report_of
from guardsim.design.diff import LevelDiff
from guardsim.level import parse_level
from guardsim.patrol import parse_patrol
from guardsim.render.diff import DIFF_COLOURS, diff_picture, panel_geometry
from tests.design_levels import ENTRY, GOAL, NEW, OLD, POST, write_versions

PAIR = [(ENTRY, GOAL)]
PAIR_ARGS = ["--from", "0.5,6.5", "--to", "19.5,6.5"]


@pytest.fixture(scope="module")
def versions(tmp_path_factory) -> tuple[Path, Path, Path]:
    return write_versions(tmp_path_factory.mktemp("design"))


@pytest.fixture(scope="module")
def found() -> LevelDiff:
    old, new = parse_level(OLD), parse_level(NEW)
    patrol_old = parse_patrol(POST, guardsim.Scene.from_level(old).grid)
    patrol_new = parse_patrol(POST, guardsim.Scene.from_level(new).grid)
    return guardsim.diff(old, new, patrol_old=patrol_old, patrol_new=patrol_new, pairs=PAIR)


def test_the_wall_closes_the_way_and_moving_it_opens_a_side_passage(found: LevelDiff) -> None:
    """Before: no undetected way (the closest call is caught in the hall), no way through; after: an
    unseen path round the guard, at least one way through, and a lower score."""
    before, after = found.pairs[0].before, found.pairs[0].after
    assert (before.outcome, before.ways, before.peak) == ("detected", 0, 1.0)
    assert after.outcome == "unseen" and after.ways >= 1 and after.peak == 0.0
    assert found.old_report.parts["caught"] == 1.0 and found.new_report.parts["caught"] == 0.0
    assert found.old_report.score > found.new_report.score
    # The unseen path keeps out of the guard's sight: its path-distance risk is below the caught path's.
    assert after.path_risk is not None and before.path_risk is not None and after.path_risk < before.path_risk


def test_safe_spots_lost_are_the_cells_the_guard_now_sees_through_the_gap(found: LevelDiff) -> None:
    """Every safe spot lost was never in view before and is in view after; the corridor beyond reach stays safe."""
    assert found.aligned and found.cells_added > 0 and found.cells_removed == 0
    assert (15.5, 2.5) in found.safe_lost
    grid = found.new.scene.grid
    for point in found.safe_lost:
        cell = grid.flat(*grid.cell_of(point))
        assert found.old.exposure[cell] == 0 and found.new.exposure[cell] > 0
    assert (10.5, 1.5) not in found.safe_lost and found.new.safe[grid.flat(10, 1)]


def test_the_picture_shows_the_lost_safe_spots(found: LevelDiff) -> None:
    """Decoded picture: three panels; at each lost safe spot the difference panel has the lost colour,
    and at a wall cell the wall colour."""
    image = diff_picture(found)
    scale, corners = panel_geometry(found)
    assert len(corners) == 3
    left, top = corners[2]
    assert image.shape == (top + 9 * scale + 8, left + 20 * scale + 8, 3)
    grid = found.new.scene.grid
    for point in found.safe_lost:
        col, row = grid.cell_of(point)
        y, x = top + row * scale + scale // 2, left + col * scale + scale // 2
        assert tuple(image[y, x]) == DIFF_COLOURS["safe_lost"]
    assert tuple(image[top + 3 * scale + scale // 2, left + 5 * scale + scale // 2]) == guardsim.render.COLOURS["wall"]


def test_diff_command_prints_writes_and_draws(versions, tmp_path: Path) -> None:
    old, new, post = versions
    png, page, data = tmp_path / "d.png", tmp_path / "d.html", tmp_path / "d.json"
    args = ["diff", str(old), str(new), "--patrol-old", str(post), "--patrol-new", str(post), *PAIR_ARGS]
    result = CliRunner().invoke(main, [*args, "--png", str(png), "--html", str(page), "--json", str(data)])
    assert result.exit_code == 0, result.output
    assert "0.5,6.5 -> 19.5,6.5: detected -> unseen" in result.output
    written = json.loads(data.read_text())
    assert written["pairs"][0]["outcome"] == ["detected", "unseen"] and [15.5, 2.5] in written["safe_lost"]
    assert iio.imread(png).ndim == 3
    block = re.search(r'<script id="diff-data" type="application/json">(.*?)</script>', page.read_text(), re.S)
    assert block is not None
    assert f'id="safe-lost">{len(written["safe_lost"])}</span> lost' in json.loads(block.group(1))


def test_diff_needs_both_patrols_or_neither(versions) -> None:
    old, new, post = versions
    result = CliRunner().invoke(main, ["diff", str(old), str(new), "--patrol-old", str(post)])
    assert result.exit_code == 2 and "--patrol-new" in result.output


def test_check_baseline_fails_on_the_moved_wall_and_passes_on_a_copy(versions, tmp_path: Path) -> None:
    """One line per broken margin (outcome and safe spots), exit 1; an unchanged copy: exit 0."""
    old, new, post = versions
    copy = tmp_path / "copy.json"
    shutil.copy(old, copy)
    runner = CliRunner()
    args = ["--baseline", str(old), "--patrol", str(post), "--sneak", "0.5,6.5", "19.5,6.5", "--expect", "caught"]
    result = runner.invoke(main, ["check", str(new), *args])
    assert result.exit_code == 1, result.output
    broken = [line for line in result.stdout.splitlines() if "broken: baseline" in line]
    assert [line.split("broken: ")[1].split(":")[0] for line in broken] == [
        "baseline outcome",
        "baseline safe",
        "baseline score",
    ]
    assert "detected -> unseen" in broken[0]
    relaxed = runner.invoke(
        main, ["check", str(new), "--baseline", str(old), "--patrol", str(post), "--max-worse", "safe=10"]
    )
    assert "broken: baseline safe" not in relaxed.stdout
    result = runner.invoke(main, ["check", str(copy), *args])
    assert result.exit_code == 0, result.output


def test_check_baseline_margin_errors_are_one_line(versions) -> None:
    old, new, _ = versions
    result = CliRunner().invoke(main, ["check", str(new), "--baseline", str(old), "--max-worse", "safety=1"])
    assert result.exit_code == 2
    assert result.output.strip().count("\n") == 0 and "unknown margin 'safety'" in result.output
    result = CliRunner().invoke(main, ["check", str(new), "--max-worse", "safe=1"])
    assert result.exit_code == 2 and "give --baseline OLD" in result.output


def test_report_command_gives_the_score_with_its_formula(versions, tmp_path: Path) -> None:
    old, _, post = versions
    out, page = tmp_path / "r.json", tmp_path / "r.html"
    args = ["report", str(old), "--patrol", str(post), *PAIR_ARGS, "--json", str(out), "--html", str(page)]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    data = json.loads(out.read_text())
    assert data["pairs"][0]["outcome"] == "detected" and data["formula"].startswith("score = 100 x (25 caught")
    weights, parts = data["weights"], data["parts"]
    assert data["score"] == round(100 * sum(weights[k] * parts[k] for k in parts) / sum(weights.values()))
    assert f"difficulty {data['score']}/100" in result.output
    assert set(data["sources"]) == set(parts) and "Tremblay" in data["sources"]["risk"]
    assert data["formula"] in page.read_text()


def test_report_input_errors_are_one_line(versions) -> None:
    old, _, _ = versions
    result = CliRunner().invoke(main, ["report", str(old), "--from", "0.5,6.5"])
    assert result.exit_code == 2 and "each --from needs its --to" in result.output
    result = CliRunner().invoke(main, ["report", str(old), "--patrol", str(old)])
    errors = [line for line in result.output.splitlines() if line.startswith("guardsim: error:")]
    assert result.exit_code == 2 and len(errors) == 1 and "Traceback" not in result.output


def test_capture_rate_counts_captured_episodes() -> None:
    """With --alert N the capture part is the share of N seeded episodes captured, in [0, 1], and the
    same seed gives the same rate."""
    analysis = analyse(
        parse_level(OLD), patrol=parse_patrol(POST, guardsim.Scene.from_level(parse_level(OLD)).grid), pairs=PAIR
    )
    first = report_of(analysis, alert=3, seed=4, ways=False)
    again = report_of(analysis, alert=3, seed=4, ways=False)
    assert first.capture_rate is not None and 0.0 <= first.capture_rate <= 1.0
    assert first.capture_rate == again.capture_rate and first.parts["capture"] == first.capture_rate
    assert first.capture_rate * 3 == round(first.capture_rate * 3)


def test_ways_share_no_corridor(found: LevelDiff) -> None:
    """Each way after the first avoids every earlier way's cells and their 4-neighbours (away from the
    endpoints), and every way is a walk of 4-neighbours or waits from entry to goal."""
    analysis = found.new
    pair = analysis.pairs[0]
    grid = analysis.scene.grid
    ways = distinct_ways(grid, analysis.gains, pair.source_cell, pair.target_cell)
    assert ways
    for way in ways:
        assert way[0] == pair.source_cell and way[-1] == pair.target_cell
        for a, b in itertools.pairwise(way):
            assert a == b or b in grid.neighbours[a]


def test_path_distance_risk_is_zero_out_of_reach_and_one_on_the_guard() -> None:
    grid = guardsim.Scene.from_level(parse_level(OLD)).grid
    guard = np.array([[grid.flat(13, 6)]])
    assert path_distance_risk(grid, guard, 0, np.array([grid.flat(13, 6)] * 3), reach=5.5) == 1.0
    assert path_distance_risk(grid, guard, 0, np.array([grid.flat(0, 6), grid.flat(0, 7)]), reach=5.5) == 0.0


@pytest.mark.slow
def test_report_ranks_the_shipped_levels() -> None:
    """One loop guard on each shipped level (the default): a player who waits always gets through unseen,
    so the levels are told apart by how often the straight walk is seen, the ways through and the guard's
    loop: Passages 12 < Square 13 < MGS Docks 14 < King Snurre's Hall 18 (docs/design.md)."""
    found = {
        name: guardsim.report(guardsim.load_level(f"levels/{name}.json"))
        for name in ("passages", "square", "mgs_docks", "king_snurre")
    }
    assert {name: report.score for name, report in found.items()} == {
        "passages": 12,
        "square": 13,
        "mgs_docks": 14,
        "king_snurre": 18,
    }
    pairs = {name: report.pairs[0] for name, report in found.items()}
    assert {name: (pair.outcome, pair.slack, pair.period) for name, pair in pairs.items()} == {
        "passages": ("unseen", 474, 474),
        "square": ("unseen", 384, 384),
        "mgs_docks": ("unseen", 434, 434),
        "king_snurre": ("unseen", 492, 492),
    }
    assert {name: (pair.direct, pair.ways) for name, pair in pairs.items()} == {
        "passages": (451, 3),
        "square": (352, 3),
        "mgs_docks": (379, 3),
        "king_snurre": (440, 1),
    }


def test_the_straight_walk_counts_the_entry_ticks_of_brute_force() -> None:
    """A guard seeing 3 units all round paces the hall's second row: brute force over its lap and every
    shortest walk from (0, 7) to (19, 8) (along row 7, one step down, along row 8): an entry tick counts
    exactly when one of them is unseen at every tick. The posted guard of the side-passage level sees the
    whole straight walk at every tick: the straight part is 1 though a way round exists."""
    from guardsim.design import direct_entries
    from guardsim.detection import GuardDetection
    from guardsim.detection.watch import lap_sight_of
    from guardsim.vision.table import view_table

    level = parse_level({**NEW, "guard": {**NEW["guard"], "view_range": 3.0}})
    scene = guardsim.Scene.from_level(level)
    grid = scene.grid
    there = [[col, 5] for col in range(2, 18)]
    loop = [*there, *there[-2::-1]]
    headings = [2] + [0] * 15 + [2] * 15
    pace = parse_patrol({"shape": [9, 20], "guards": [{"loop": loop, "headings": headings}]}, grid)
    sight, _ = lap_sight_of(grid, view_table(grid, scene.vision()), pace.states, GuardDetection.of_level(level), None)
    found = direct_entries(grid, sight, grid.flat(0, 7), grid.flat(19, 8))
    seen = sight.dense_seen()
    expected = np.zeros(sight.period, dtype=bool)
    for down in range(1, 21):
        cells = [grid.flat(k, 7) if k < down else grid.flat(k - 1, 8) for k in range(21)]
        for entry in range(sight.period):
            if not any(seen[(entry + k) % sight.period, cell] for k, cell in enumerate(cells)):
                expected[entry] = True
    assert np.array_equal(found, expected) and 0 < found.sum() < sight.period
    posted = parse_level(NEW)
    found_posted = report_of(analyse(posted, patrol=parse_patrol(POST, grid), pairs=PAIR))
    assert found_posted.parts["straight"] == 1.0 and found_posted.pairs[0].outcome == "unseen"


def test_a_lap_over_the_sneak_limit_is_unchecked_and_its_exposure_counted_in_slices(monkeypatch) -> None:
    """Over the size limit the pairs are 'unchecked' (no failed analysis), the exposure counted a slice of
    the lap at a time equals the one from the detection model's gains, and the report leaves the pair's
    parts out of the score."""
    import guardsim.design.analysis as analysis_module
    import guardsim.sneak as sneak_module

    level = parse_level(NEW)
    post = parse_patrol(
        {
            "shape": [9, 20],
            "guards": [{"loop": [[13, 6], [14, 6], [15, 6], [14, 6], [13, 6]], "headings": [2, 0, 0, 2, 2]}],
        },
        guardsim.Scene.from_level(level).grid,
    )
    whole = analyse(level, patrol=post, pairs=PAIR)
    monkeypatch.setattr(analysis_module, "MAX_DENSE_NODES", 10)
    monkeypatch.setattr(analysis_module, "EXPOSURE_SLICE", 3)
    monkeypatch.setattr(sneak_module, "MAX_SNEAK_NODES", 10)
    sliced = analyse(level, patrol=post, pairs=PAIR)
    assert sliced.gains is None and whole.gains is not None
    assert np.array_equal(sliced.exposure, whole.exposure)
    assert sliced.pairs[0].outcome == "unchecked" and "not checked" in sliced.pairs[0].note
    found = report_of(sliced)
    assert "caught" not in found.parts and found.pairs[0].outcome == "unchecked"


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None, reason="no chromium on PATH: apt-get install -y chromium")
def test_the_report_and_diff_pages_draw_in_chromium(versions, tmp_path: Path) -> None:
    """Real headless Chromium: the report page shows the score of report.json and draws the level; the
    diff page draws both versions and their difference."""
    import subprocess

    old, new, post = versions
    runner = CliRunner()
    data, page, diff_page = tmp_path / "r.json", tmp_path / "r.html", tmp_path / "d.html"
    args = ["report", str(old), "--patrol", str(post), *PAIR_ARGS, "--json", str(data), "--html", str(page)]
    assert runner.invoke(main, args).exit_code == 0
    args = ["diff", str(old), str(new), "--patrol-old", str(post), "--patrol-new", str(post), *PAIR_ARGS]
    assert runner.invoke(main, [*args, "--html", str(diff_page)]).exit_code == 0

    def dom(path: Path) -> str:
        done = subprocess.run(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={tmp_path / 'profile'}",
             "--virtual-time-budget=3000", "--dump-dom", path.as_uri()],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr[-2000:]
        return done.stdout

    shown = dom(page)
    assert f'<span id="score">{json.loads(data.read_text())["score"]}</span>' in shown
    assert re.search(r'<canvas id="level" width="(\d+)"', shown) is not None
    shown = dom(diff_page)
    for name in ("before", "after", "difference"):
        found = re.search(rf'<canvas id="{name}" width="(\d+)" height="(\d+)"', shown)
        assert found is not None and int(found.group(1)) > 0, name
    assert 'id="safe-lost">4</span>' in shown


def test_an_edit_reuses_the_sight_away_from_it_and_changes_nothing_else() -> None:
    """Re-analysing the moved wall from the old analysis: the view table is reused away from the edit
    and equals the one built whole, and every result equals a fresh analysis's."""
    from guardsim.vision.table import build_view_table

    old, new = parse_level(OLD), parse_level(NEW)
    post = parse_patrol(POST, guardsim.Scene.from_level(new).grid)
    fresh = analyse(new, patrol=post, pairs=PAIR)
    again = analyse(new, patrol=post, pairs=PAIR, reuse=analyse(old, patrol=post, pairs=PAIR))
    assert again.reused == ("sight away from the edit",) and fresh.reused == ()
    whole = build_view_table(fresh.scene.grid, fresh.scene.vision())
    assert all(np.array_equal(a, b) for a, b in zip(again.table, whole))
    assert np.array_equal(again.exposure, fresh.exposure) and again.pairs[0].outcome == fresh.pairs[0].outcome
    assert np.array_equal(again.pairs[0].sneak.path.cells, fresh.pairs[0].sneak.path.cells)


@pytest.mark.parametrize("sliced", [False, True], ids=["dense lap", "lap in slices"])
def test_every_reuse_gives_the_bytes_of_a_fresh_analysis(monkeypatch, sliced: bool) -> None:
    """A chain of edits analysed as ``watch`` does (each from the last): a wall moved, a detection key
    changed, the key changed back. Each step reuses what its edit left (the sight away from the wall; the
    scene, the planned patrol, the exposure and the unseen reach for a key) and its report.json and page
    data are byte for byte those of a fresh analysis of the same level."""
    import dataclasses

    import guardsim.design.analysis as analysis_module
    from guardsim.design import report_data
    from guardsim.viewer.serve.payload import analysis_payload

    if sliced:
        monkeypatch.setattr(analysis_module, "MAX_DENSE_NODES", 10)
    old, new = parse_level(OLD), parse_level(NEW)
    keyed = dataclasses.replace(new, guard=dataclasses.replace(new.guard, detect_near=2.0, detect_far=4.0))
    expected = [
        ("sight away from the edit",),
        ("scene", "patrol", *(("exposure",) if sliced else ()), "unseen reach"),
        ("scene", "patrol", *(("exposure",) if sliced else ()), "unseen reach"),
    ]

    def data(analysis) -> str:
        payload = analysis_payload(analysis, report_data(report_of(analysis)))
        del payload["seconds"], payload["reused"]
        return json.dumps(payload, sort_keys=True)

    last = analyse(old, planner="cover", pairs=PAIR)
    for level, reused in zip((new, keyed, new), expected, strict=True):
        last = analyse(level, planner="cover", pairs=PAIR, reuse=last)
        assert last.reused == reused
        assert data(last) == data(analyse(level, planner="cover", pairs=PAIR))
    assert last.pairs[0].outcome == "unseen"


def test_a_sneak_memo_gives_a_sweep_back_only_for_equal_inputs() -> None:
    """The kept backward sweep comes back for equal neighbours, seen bits, lap length and target (from the
    earlier memo too, counted as a hit), and for nothing else: not another target, not another lap length
    with the same words of bits, not one seen bit more."""
    from guardsim.sneak import SneakMemo
    from guardsim.sneak.sweep import Sweep

    grid = guardsim.Scene.from_level(parse_level(NEW)).grid
    neighbours = np.asarray(grid.neighbours)
    bits = np.zeros((grid.size, 2), dtype=np.uint64)
    found = Sweep(-1, -1, bits.copy(), np.zeros(grid.size, dtype=bool), 0)
    earlier = SneakMemo()
    earlier.keep(neighbours, bits, 100, 7, found)
    memo = SneakMemo(earlier)
    assert memo.find(neighbours.copy(), bits.copy(), 100, 7) is found and memo.hits == 1
    seen = bits.copy()
    seen[3, 1] = 1
    assert memo.find(neighbours, bits, 100, 8) is None and memo.find(neighbours, bits, 101, 7) is None
    assert memo.find(neighbours, seen, 100, 7) is None
    memo.forget_earlier()
    assert memo.find(neighbours, bits, 100, 7) is found and memo.hits == 1


@pytest.mark.parametrize("period", [1, 63, 64, 65, 130])
def test_the_straight_walk_on_random_sight_is_brute_force(period: int) -> None:
    """Random seen ticks on a small room round a pillar, laps of lengths round the 64-tick words: the
    entry ticks are those of some walk of the fewest steps, found by trying every such walk."""
    from guardsim.design import direct_entries
    from guardsim.detection.sight import LapSight
    from guardsim.kernels.distances import distances_from

    grid = guardsim.Scene.from_level(
        parse_level({"outer": [[0, 0], [6, 0], [6, 4], [0, 4]], "holes": [[[2, 1], [4, 1], [4, 3], [2, 3]]]})
    ).grid
    rng = np.random.default_rng(period)
    words = (period + 63) // 64
    seen = np.zeros((grid.size, words * 64), dtype=bool)
    seen[:, :period] = rng.random((grid.size, period)) < 0.1
    bits = np.packbits(seen, axis=1, bitorder="little").view(np.uint64)
    nothing = np.zeros(0, dtype=np.int64)
    sight = LapSight(period, np.zeros(grid.size + 1, dtype=np.int64), nothing, nothing, np.zeros(0), bits, 1, 0.1,
                     np.zeros((1, period), dtype=np.int64), 0.1)  # fmt: skip
    neighbours = np.asarray(grid.neighbours)
    source, target = grid.flat(0, 0), grid.flat(5, 3)
    from_source = distances_from(neighbours, np.array([source]))
    steps = int(from_source[target])

    def walks(cell: int) -> list[list[int]]:
        if cell == target:
            return [[cell]]
        ahead = [n for n in neighbours[cell] if n >= 0 and from_source[n] == from_source[cell] + 1]
        return [[cell, *rest] for n in ahead for rest in walks(int(n))]

    every = [walk for walk in walks(source) if len(walk) == steps + 1]
    expected = [
        any(not any(seen[cell, (entry + k) % period] for k, cell in enumerate(walk)) for walk in every)
        for entry in range(period)
    ]
    assert len(every) > 1 and direct_entries(grid, sight, source, target).tolist() == expected
