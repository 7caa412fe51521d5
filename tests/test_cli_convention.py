"""One command-line convention, as a user meets it: every picture option takes a file name (a bare
``--gif``/``--html`` on patrol and sneak still writes into ``--out DIR``)."""

from __future__ import annotations

import json
from pathlib import Path

import imageio.v3 as iio
import pytest

from tests.common import SPLIT_ROOMS, TWO_ROOMS, assert_one_line_error, run, write_level

#: A guard posted in the middle of the corridor, facing east.
POST = {"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}


@pytest.fixture(scope="module")
def two_rooms(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    folder = tmp_path_factory.mktemp("rooms")
    level = write_level(folder, TWO_ROOMS)
    patrol = folder / "post.json"
    patrol.write_text(json.dumps(POST))
    return level, patrol


def _sneak(level: Path, patrol: Path, *more: str | Path) -> list[str | Path]:
    return ["sneak", level, "--patrol", patrol, "--from", "0.5,0.5", "--to", "10.5,2.5", *more]


def test_sneak_pictures_take_a_file_name_and_need_no_out_folder(tmp_path: Path, two_rooms: tuple[Path, Path]) -> None:
    level, patrol = two_rooms
    gif, page = tmp_path / "pictures" / "walk.gif", tmp_path / "walk.html"
    gif.parent.mkdir()
    result = run(*_sneak(level, patrol, "--gif", gif, "--html", page))
    assert result.exit_code == 0, result.output
    assert result.stdout.rstrip().endswith(f"-> {gif}, {page}")
    assert sorted(path.name for path in tmp_path.rglob("*") if path.is_file()) == ["walk.gif", "walk.html"]
    frames = iio.imread(gif, index=None)
    # One frame per tick of the closest call (0 to 10, 2 takes at least 12 steps), each the same size.
    assert frames.ndim == 4 and frames.shape[0] >= 13
    assert page.read_text().startswith("<!DOCTYPE html>")


def test_a_bare_picture_option_writes_its_old_name_into_the_out_folder(
    tmp_path: Path, two_rooms: tuple[Path, Path]
) -> None:
    level, patrol = two_rooms
    named, bare = tmp_path / "named.gif", tmp_path / "out"
    assert run(*_sneak(level, patrol, "--gif", named)).exit_code == 0
    result = run(*_sneak(level, patrol, "--out", bare, "--gif"))
    assert result.exit_code == 0, result.output
    assert result.stdout.rstrip().endswith(f"-> {bare / 'sneak.json'}, {bare / 'hiding.png'}, {bare / 'sneak.gif'}")
    assert (bare / "sneak.gif").read_bytes() == named.read_bytes()


def test_a_bare_picture_option_without_an_out_folder_is_one_line(tmp_path: Path, two_rooms: tuple[Path, Path]) -> None:
    level, patrol = two_rooms
    line = assert_one_line_error(run(*_sneak(level, patrol, "--html")), "--html FILE")
    assert line == "guardsim: error: --html FILE: give a file name (a bare --html writes into the --out folder)"
    assert list(tmp_path.iterdir()) == []


def test_patrol_pictures_take_a_file_name(tmp_path: Path, two_rooms: tuple[Path, Path]) -> None:
    level, _ = two_rooms
    out, gif, page = tmp_path / "out", tmp_path / "lap.gif", tmp_path / "lap.html"
    result = run("patrol", level, "--out", out, "--gif", gif, "--html", page)
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[-1].endswith(f"-> {out / 'patrol.json'}, {out / 'idleness.png'}, {gif}, {page}")
    assert sorted(path.name for path in out.iterdir()) == ["idleness.png", "patrol.json"]
    data = json.loads((out / "patrol.json").read_text())
    # One frame per tick of the lap, tick 0 included.
    assert iio.imread(gif, index=None).shape[0] == data["period"] + 1
    assert page.read_text().startswith("<!DOCTYPE html>")


def test_a_picture_named_outside_an_existing_folder_is_refused_before_any_work(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    out, gif = tmp_path / "out", tmp_path / "missing" / "lap.gif"
    line = assert_one_line_error(run("patrol", level, "--out", out, "--gif", gif), gif)
    assert "does not exist" in line
    assert not out.exists()


def test_a_gif_named_as_another_format_is_refused(tmp_path: Path, two_rooms: tuple[Path, Path]) -> None:
    level, patrol = two_rooms
    result = run(*_sneak(level, patrol, "--gif", tmp_path / "walk.png"))
    assert result.exit_code == 2
    assert "ends in '.png', but a GIF is written: name it .gif" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_patrol_takes_start_like_play_and_watches_the_area_it_is_in(tmp_path: Path) -> None:
    """Split rooms: the level's guard starts in the left room; ``--start`` in the right room patrols that
    one instead (idleness is given only for the cells reachable from the start)."""
    level = write_level(tmp_path, SPLIT_ROOMS)

    def watched_columns(*more: str) -> set[int]:
        out = tmp_path / "-".join(more or ("default",))
        result = run("patrol", level, "--out", out, *more)
        assert result.exit_code == 0, result.output
        rows = json.loads((out / "patrol.json").read_text())["idleness"]
        return {col for row in rows for col, value in enumerate(row) if value is not None}

    assert watched_columns() == {0, 1, 2}
    assert watched_columns("--start", "5.5,1.5") == {3, 4, 5}
    line = assert_one_line_error(run("patrol", level, "--out", tmp_path / "x", "--start", "9,1"), level)
    assert line.endswith("start (9, 1) lies outside the level")


@pytest.mark.parametrize(
    "rule", [(), ("--undetected", "--suspicious", "0.3", "--fov", "120")], ids=["unseen", "undetected"]
)
def test_view_draws_a_sneak_json_again_as_sneak_html_drew_it(
    tmp_path: Path, two_rooms: tuple[Path, Path], rule: tuple[str, ...]
) -> None:
    """``view sneak.json --level`` runs the check again as sneak.json records it (its patrol, vision,
    detection keys) and writes the very page ``sneak --html`` wrote."""
    level, patrol = two_rooms
    out, page, again = tmp_path / "out", tmp_path / "sneak.html", tmp_path / "again.html"
    assert run(*_sneak(level, patrol, "--out", out, "--html", page, *rule)).exit_code == 0
    result = run("view", out / "sneak.json", "--level", level, "--html", again)
    assert result.exit_code == 0, result.output
    data = json.loads((out / "sneak.json").read_text())
    assert result.stdout == f"corridor: sneak from lap tick {data['start_tick']}, {data['ticks']} ticks -> {again}\n"
    assert again.read_bytes() == page.read_bytes()


def test_view_of_a_sneak_json_names_what_is_missing_or_changed(tmp_path: Path, two_rooms: tuple[Path, Path]) -> None:
    level, patrol = two_rooms
    out = tmp_path / "out"
    assert run(*_sneak(level, patrol, "--out", out)).exit_code == 0
    sneak_json, page = out / "sneak.json", tmp_path / "again.html"
    line = assert_one_line_error(run("view", sneak_json, "--html", page), sneak_json)
    assert line.endswith("a sneak check's sneak.json: give --level LEVEL, the level it checked")
    # The guard moved to a corner since: the check run again finds another answer, and says so.
    moved = tmp_path / "moved.json"
    moved.write_text(json.dumps({**POST, "guards": [{"loop": [[10, 0]], "headings": [3]}]}))
    line = assert_one_line_error(
        run("view", sneak_json, "--level", level, "--patrol", moved, "--html", page), sneak_json
    )
    assert line.endswith("finds another path: the level or the patrol changed since")
    assert not page.exists()


def test_patrol_setup_and_plan_refuse_with_a_named_error(tmp_path: Path) -> None:
    """What a Python caller can get wrong is a PatrolError (a GuardsimError the command line prints in one
    line), not a bare ValueError."""
    from guardsim.errors import PatrolError
    from guardsim.patrol import patrol_setup, plan_patrol
    from guardsim.scene import Scene
    from tests.common import level_from

    scene = Scene.from_level(level_from(TWO_ROOMS))
    with pytest.raises(PatrolError, match="at least one guard"):
        patrol_setup(scene, 0)
    with pytest.raises(PatrolError, match="unknown strategy 'lawnmower'; known: loop, "):
        plan_patrol(patrol_setup(scene, 1), "lawnmower")


def test_a_sneak_picture_in_a_missing_folder_is_refused_before_the_search(
    tmp_path: Path, two_rooms: tuple[Path, Path]
) -> None:
    level, patrol = two_rooms
    page = tmp_path / "missing" / "walk.html"
    line = assert_one_line_error(run(*_sneak(level, patrol, "--out", tmp_path / "out", "--html", page)), page)
    assert line.endswith(f"folder {page.parent} does not exist")
    assert not (tmp_path / "out").exists()


#: The guard of POST walking two cells and stopping (period null), and the post walked in continuous motion.
WALKED = {"shape": [3, 11], "period": None, "guards": [{"loop": [[5, 1], [6, 1]], "headings": [0, 0]}]}
CONTINUOUS = {**POST, "motion": "continuous"}


@pytest.mark.parametrize(
    ("command", "extra"),
    [
        ("sneak", ["--from", "0.5,0.5", "--to", "10.5,2.5"]),
        ("fortify", ["--from", "0.5,0.5", "--to", "10.5,2.5"]),
        ("alert", []),
    ],
    ids=["sneak", "fortify", "alert"],
)
@pytest.mark.parametrize(
    ("patrol", "problem"), [(WALKED, "period null"), (CONTINUOUS, "motion 'continuous'")], ids=["walked", "continuous"]
)
def test_a_patrol_that_does_not_repeat_on_the_grid_is_one_line_naming_it(
    tmp_path: Path, command: str, extra: list[str], patrol: dict[str, object], problem: str
) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    path = tmp_path / "patrol.json"
    path.write_text(json.dumps(patrol))
    line = assert_one_line_error(run(command, level, "--patrol", path, *extra), path)
    assert line == (
        f"guardsim: error: {path}: {command} needs a repeating grid-motion patrol (from guardsim patrol); "
        f"this one has {problem}"
    )


def test_each_import_option_is_written_once_and_read_everywhere(tmp_path: Path) -> None:
    """The fields of ImportOptions are the flags of every command that takes a map, and load_level's keywords."""
    import dataclasses

    import click

    from guardsim.cli.importing import import_command
    from guardsim.cli.validate import validate
    from guardsim.importers.options import ImportOptions, option_form

    flags = [option_form(field).flag for field in dataclasses.fields(ImportOptions)]
    assert flags[:3] == ["--cell-size", "--threshold", "--spawn-tile"] and len(flags) == 11
    # The shared stack keeps the order the help has always listed: import options, --strict, the limits.
    stack = [*flags, "--strict", "--max-cells", "--max-vertices", "--max-file-bytes"]
    for command in (import_command, validate):
        options = [opt for param in command.params if isinstance(param, click.Option) for opt in param.opts]
        assert [opt for opt in options if opt in stack] == stack, command.name
    # A check written beside its field reaches the command line as a bad parameter (click's exit 2).
    result = run("import", "map.tmj", "--out", tmp_path / "level.json", "--wall-class", " ")
    assert result.exit_code == 2 and "expected a class name, got an empty text" in result.output
