"""`guardsim regress` against the committed references, on edited levels, and determinism across processes.

The references in ``renders/`` are regenerated with ``guardsim regress levels/ --update`` (see
``docs/regression.md``); these tests never write into the repository's ``renders/``.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest

from guardsim.regress import KEY_PERCENTS, REFERENCE_FRAME_SIZE, Tolerance, compare_frames
from tests.common import LEVELS, REPO, SQUARE_WITH_HOLE, assert_one_line_error, guardsim_command, run, write_level

RENDERS = REPO / "renders"
SQUARE = REPO / "levels" / "square.json"


def edited_square(folder: Path, shift: float = 3.0) -> Path:
    """A copy of the shipped square with its pillar moved ``shift`` units to the right."""
    data = json.loads(SQUARE.read_text(encoding="utf-8"))
    data["holes"][0] = [[x + shift, y] for x, y in data["holes"][0]]
    folder.mkdir(parents=True, exist_ok=True)
    return write_level(folder, data, "square.json")


def copied_references(folder: Path, *stems: str) -> Path:
    """A scratch copy of the committed references of ``stems``."""
    for stem in stems:
        shutil.copytree(RENDERS / stem, folder / stem)
    return folder


def test_shipped_levels_match_committed_references() -> None:
    """`guardsim regress levels/ --renders renders/` passes on a fresh clone: one ok line per level."""
    result = run("regress", REPO / "levels", "--renders", RENDERS)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert [line.split(": ok (")[0] for line in lines] == [str(path) for path in LEVELS]
    assert result.stderr == ""


def test_committed_references_are_small_and_complete() -> None:
    """Each shipped level has a manifest, a level snapshot, and per episode a trace and five PNG key frames."""
    for level_path in LEVELS:
        folder = RENDERS / level_path.stem
        manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
        assert manifest["frame_size"] == REFERENCE_FRAME_SIZE
        assert 1 <= len(manifest["episodes"]) <= 3
        for episode in manifest["episodes"]:
            assert (folder / f"{episode['name']}.trace.json").is_file()
            for percent in KEY_PERCENTS:
                frame = iio.imread(folder / f"{episode['name']}-{percent:03d}.png")
                # The play area is at most frame_size; the caption and legend bars come on top of it.
                assert max(frame.shape[:2]) <= 2 * REFERENCE_FRAME_SIZE
    assert sum(path.stat().st_size for path in RENDERS.rglob("*") if path.is_file()) < 1_000_000


@pytest.mark.parametrize("name", ["level-start", "seed0-episode0", "seed0-continuous"])
def test_play_options_rerun_the_stored_episode(tmp_path: Path, name: str) -> None:
    """The manifest's `play_options` make `guardsim play` write the stored trace, byte for byte."""
    manifest = json.loads((RENDERS / "square" / "manifest.json").read_text(encoding="utf-8"))
    [episode] = [episode for episode in manifest["episodes"] if episode["name"] == name]
    result = run("play", SQUARE, *episode["play_options"].split(), "--trace", tmp_path / "trace.json")
    assert result.exit_code == 0, result.output
    stored = RENDERS / "square" / f"{name}.trace.json"
    assert (tmp_path / "trace.json").read_bytes() == stored.read_bytes()


def test_edited_level_fails_with_one_line_and_a_diff_image(tmp_path: Path) -> None:
    """Moving the square's pillar: exit 1, one readable line (what differs, steps before -> after, diff path)."""
    level = edited_square(tmp_path / "levels")
    diffs = tmp_path / "diffs"
    result = run("regress", level, "--renders", RENDERS, "--diff-dir", diffs)
    assert result.exit_code == 1, result.output
    [line] = result.stdout.splitlines()
    diff_path = diffs / "square.diff.png"
    assert line.startswith(f"{level}: DIFFERS: level edited; level-start: path from tick ")
    assert "steps 685 -> " in line
    assert "seed0-episode0: " in line
    assert line.endswith(f"diff {diff_path}")
    assert result.stderr == ""
    image = iio.imread(diff_path)
    # Rows of reference | current | difference, each a stored frame's width with 4-pixel gaps.
    frame_width = iio.imread(RENDERS / "square" / "level-start-000.png").shape[1]
    assert image.shape[1] == 3 * frame_width + 2 * 4
    assert (image.reshape(-1, 3) == (255, 0, 255)).all(axis=1).any(), "no pixel highlighted as different"


def test_update_rewrites_references_and_removes_the_diff(tmp_path: Path) -> None:
    """Default diff location is the reference folder; --update makes the edited level the reference."""
    renders = copied_references(tmp_path / "renders", "square")
    level = edited_square(tmp_path / "levels")
    failed = run("regress", level, "--renders", renders)
    assert failed.exit_code == 1
    assert (renders / "square" / "diff.png").is_file()
    updated = run("regress", level, "--renders", renders, "--update")
    assert updated.exit_code == 0, updated.output
    assert updated.stdout.startswith(f"{level}: references written to {renders / 'square'} (level-start ")
    assert not (renders / "square" / "diff.png").exists()
    assert not [path for path in (renders / "square").iterdir() if path.name.startswith(".")]
    passed = run("regress", level, "--renders", renders)
    assert passed.exit_code == 0, passed.output
    # The original level now differs from the updated references.
    assert run("regress", SQUARE, "--renders", renders).exit_code == 1


def test_new_level_needs_references_then_passes(tmp_path: Path) -> None:
    """A level without references fails (exit 1) until --update writes them; a level without a start
    gets only the batch episode."""
    data = {key: value for key, value in SQUARE_WITH_HOLE.items() if key != "guard"}
    level = write_level(tmp_path, data, "pillar.json")
    renders = tmp_path / "renders"
    renders.mkdir()
    missing = run("regress", level, "--renders", renders)
    assert missing.exit_code == 1
    assert missing.stdout == f"{level}: no references in {renders / 'pillar'} (write them with --update)\n"
    assert run("regress", level, "--renders", renders, "--update").exit_code == 0
    manifest = json.loads((renders / "pillar" / "manifest.json").read_text(encoding="utf-8"))
    assert [episode["name"] for episode in manifest["episodes"]] == ["seed0-episode0"]
    assert manifest["episodes"][0]["play_options"] == "--seed 0 --episode 0"
    assert run("regress", level, "--renders", renders).stdout.startswith(f"{level}: ok (seed0-episode0 ")


def test_stored_trace_tampered_names_the_first_tick(tmp_path: Path) -> None:
    """A reference trace whose path differs at one tick is reported as 'path from tick N'."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE, "pillar.json")
    renders = tmp_path / "renders"
    assert run("regress", level, "--renders", renders, "--update").exit_code == 0
    trace_path = renders / "pillar" / "level-start.trace.json"
    data = json.loads(trace_path.read_text(encoding="utf-8"))
    data["path"][3] = [5, 5]
    trace_path.write_text(json.dumps(data), encoding="utf-8")
    result = run("regress", level, "--renders", renders)
    assert result.exit_code == 1
    assert "level-start: path from tick 3, steps " in result.stdout
    assert "seed0-episode0 " in result.stdout


def test_shipped_continuous_case_replays_the_physics_walk() -> None:
    """The square's continuous reference is a walk of poses at game speeds, and regress passes on it."""
    manifest = json.loads((RENDERS / "square" / "manifest.json").read_text(encoding="utf-8"))
    [case] = [episode for episode in manifest["episodes"] if episode.get("motion") == "continuous"]
    stored = json.loads((RENDERS / "square" / f"{case['name']}.trace.json").read_text(encoding="utf-8"))
    assert stored["motion"] == "continuous" and stored["outcome"] == "covered"
    assert len(stored["poses"]) == len(stored["path"]) == case["steps"] + 1
    assert stored["tick_hz"] == case["tick_hz"]


def test_update_in_continuous_motion_then_overrides_and_tampered_poses(tmp_path: Path) -> None:
    """`--update --motion continuous` stores continuous episodes that later runs re-play without the
    option; another turning speed differs by field and tick; a pose moved with the cells unchanged is
    'poses from tick N'; speeds with --motion grid are refused."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE, "pillar.json")
    renders = tmp_path / "renders"
    written = run("regress", level, "--renders", renders, "--update", "--motion", "continuous", "--tick-hz", "10")
    assert written.exit_code == 0, written.output
    manifest = json.loads((renders / "pillar" / "manifest.json").read_text(encoding="utf-8"))
    for episode in manifest["episodes"]:
        assert (episode["motion"], episode["tick_hz"]) == ("continuous", 10.0)
        assert episode["play_options"].endswith("--motion continuous --tick-hz 10")
        assert "move_speed" not in episode  # the level's (or the default) speed, read at each re-play
    passed = run("regress", level, "--renders", renders)
    assert passed.exit_code == 0, passed.output
    slower = run("regress", level, "--renders", renders, "--turn-speed", "45")
    assert slower.exit_code == 1
    assert "turn_speed 180.0 -> 45.0" in slower.stdout and "path from tick " in slower.stdout
    as_grid = run("regress", level, "--renders", renders, "--motion", "grid")
    assert "motion continuous -> grid" in as_grid.stdout
    trace_path = renders / "pillar" / "level-start.trace.json"
    data = json.loads(trace_path.read_text(encoding="utf-8"))
    data["poses"][5][1] += 0.01
    trace_path.write_text(json.dumps(data), encoding="utf-8")
    moved = run("regress", level, "--renders", renders)
    assert moved.exit_code == 1
    assert "level-start: poses from tick 5, steps " in moved.stdout
    refused = run("regress", level, "--renders", renders, "--motion", "grid", "--move-speed", "3")
    assert refused.exit_code == 2 and "continuous-motion parameters" in refused.output


@pytest.mark.parametrize(
    ("change", "fragment"),
    [
        ({"motion": "teleport"}, 'episodes[0].motion: must be one of grid, continuous, not "teleport"'),
        ({"move_speed": 3}, 'episodes[0]: move_speed is a continuous-motion parameter; add "motion": "continuous"'),
        ({"motion": "continuous", "tick_hz": -5}, "episodes[0].tick_hz: must be a positive number"),
        ({"motion": "continuous", "turn_speed": "fast"}, "episodes[0].turn_speed: must be a positive number"),
    ],
    ids=["unknown-motion", "speed-on-grid-episode", "negative-rate", "speed-not-a-number"],
)
def test_bad_motion_in_a_manifest_is_one_line(tmp_path: Path, change: dict, fragment: str) -> None:
    """A manifest episode's motion or speed that is wrong is one line naming the manifest, exit 2."""
    folder = copied_references(tmp_path / "renders", "square") / "square"
    manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    manifest["episodes"][0].update(change)
    (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    line = assert_one_line_error(run("regress", SQUARE, "--renders", folder.parent), folder / "manifest.json")
    assert fragment in line


@pytest.mark.parametrize(
    ("damage", "fragment"),
    [
        ("short", "poses: must be a list of one [t, x, y, heading] per tick of the path"),
        ("not-finite", "poses[2]: must be [t, x, y, heading] of finite numbers"),
        ("no-poses", "a continuous trace needs poses"),
    ],
)
def test_damaged_continuous_reference_trace_is_one_line(tmp_path: Path, damage: str, fragment: str) -> None:
    """A stored continuous trace whose poses the renderer could not read is refused before drawing."""
    folder = copied_references(tmp_path / "renders", "square") / "square"
    trace_path = folder / "seed0-continuous.trace.json"
    data = json.loads(trace_path.read_text(encoding="utf-8"))
    if damage == "short":
        data["poses"] = data["poses"][:-1]
    elif damage == "not-finite":
        data["poses"][2][1] = None
    else:
        del data["poses"]
    trace_path.write_text(json.dumps(data), encoding="utf-8")
    line = assert_one_line_error(run("regress", SQUARE, "--renders", folder.parent), trace_path)
    assert fragment in line


@pytest.mark.parametrize("channel_change", [20, 200], ids=["within-channel-tolerance", "over-it"])
def test_frame_tolerance(channel_change: int) -> None:
    """A pixel differs only past the channel tolerance; a frame only past the fraction of differing pixels."""
    reference = np.zeros((100, 100, 3), dtype=np.uint8)
    few, many = reference.copy(), reference.copy()
    few[:2, :2] += np.uint8(channel_change)  # 4 pixels: 0.04 %
    many[:10, :10] += np.uint8(channel_change)  # 100 pixels: 1 %
    tolerance = Tolerance()
    expected = 0.0 if channel_change <= tolerance.channel else 1.0
    assert compare_frames(reference, few, tolerance) == (expected * 0.0004, channel_change)
    assert compare_frames(reference, many, tolerance) == (expected * 0.01, channel_change)
    assert compare_frames(reference, reference[:50], tolerance) == (1.0, 255)


def test_folders_expand_and_duplicate_names_are_refused(tmp_path: Path) -> None:
    """A folder means its *.json files; two levels with one file name would share references: exit 2."""
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        write_level(tmp_path / folder, SQUARE_WITH_HOLE, "room.json")
    result = run("regress", tmp_path / "a", tmp_path / "b", "--renders", RENDERS)
    assert_one_line_error(result, tmp_path / "b" / "room.json")
    assert "same file name" in result.stderr
    (tmp_path / "empty").mkdir()
    assert_one_line_error(run("regress", tmp_path / "empty", "--renders", RENDERS), tmp_path / "empty")


@pytest.mark.parametrize(
    ("damage", "fragment"),
    [
        ("manifest-not-json", "manifest.json: not valid JSON"),
        ("manifest-bad-episode", "episodes[0].name: must be"),
        ("frame-missing", "level-start-050.png: missing (listed in"),
        ("frame-not-png", "level-start-050.png: not a PNG image"),
    ],
)
def test_damaged_references_are_bad_input(tmp_path: Path, damage: str, fragment: str) -> None:
    """A reference that cannot be read is one error line and exit 2, and the other levels still run."""
    renders = copied_references(tmp_path / "renders", "square", "passages")
    folder = renders / "square"
    if damage == "manifest-not-json":
        (folder / "manifest.json").write_text("{", encoding="utf-8")
    elif damage == "manifest-bad-episode":
        manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
        manifest["episodes"][0]["name"] = "../escape"
        (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    elif damage == "frame-missing":
        (folder / "level-start-050.png").unlink()
    else:
        (folder / "level-start-050.png").write_bytes(b"not a png")
    result = run("regress", SQUARE, REPO / "levels" / "passages.json", "--renders", renders)
    assert result.exit_code == 2
    assert result.stdout.startswith(f"{REPO / 'levels' / 'passages.json'}: ok (")
    [error, count] = result.stderr.splitlines()
    assert error.startswith(f"guardsim: error: {folder}")
    assert fragment in error
    assert count == "guardsim regress: 1 invalid of 2 levels"


def test_bad_level_and_missing_renders_folder_are_bad_input(tmp_path: Path) -> None:
    """A level that does not load, or a --renders folder that does not exist: one line, exit 2."""
    missing_level = tmp_path / "nope.json"
    assert_one_line_error(run("regress", missing_level, "--renders", RENDERS), missing_level)
    bad = write_level(tmp_path, {"outer": [[0, 0], [1, 0]]}, "bad.json")
    result = run("regress", bad, "--renders", RENDERS)
    assert result.exit_code == 2
    assert result.stderr.splitlines()[0].startswith(f"guardsim: error: {bad}: outer: ring has 2 distinct points")
    line = assert_one_line_error(run("regress", SQUARE, "--renders", tmp_path / "none"), tmp_path / "none")
    assert "--update" in line


@pytest.mark.slow
def test_real_process_regress_and_byte_identical_play(tmp_path: Path) -> None:
    """Real processes: `guardsim regress` passes on one shipped level, and two `guardsim play` runs with the
    same level, seed and options write the same trace and the same GIF, byte for byte."""
    regress = subprocess.run(
        [*guardsim_command(), "regress", str(SQUARE), "--renders", str(RENDERS)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert regress.returncode == 0, regress.stderr
    assert regress.stdout.startswith(f"{SQUARE}: ok (level-start 685 steps")
    outputs = []
    for run_number in (1, 2):
        gif, trace = tmp_path / f"run{run_number}.gif", tmp_path / f"run{run_number}.json"
        play = subprocess.run(
            [
                *guardsim_command(),
                "play",
                str(REPO / "levels" / "passages.json"),
                *("--seed", "3", "--episode", "2", "--max-frames", "30", "--gif", str(gif), "--trace", str(trace)),
            ],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        assert play.returncode == 0, play.stderr
        outputs.append((gif.read_bytes(), trace.read_bytes()))
    assert outputs[0][1] == outputs[1][1]
    assert outputs[0][0] == outputs[1][0]
    assert iio.imread(outputs[0][0], index=None, extension=".gif").shape[0] == 30
