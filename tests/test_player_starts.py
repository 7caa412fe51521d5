"""Player starts: kept by the level, the default --from of ``guardsim sneak``; one coordinate system labelled."""

from __future__ import annotations

import json
from pathlib import Path

from guardsim.level import level_to_data, parse_level
from tests.common import TWO_ROOMS, assert_one_line_error, import_map, run, write_level

# 10 x 8 tiles of 16 px; ground on rows 1..6 and columns 2..9 only (the level is cropped to it), a
# wall object, and a player start at tile (3.5, 2.5).
GROUND = ",\n".join(",".join("1" if col >= 2 and 1 <= row <= 6 else "0" for col in range(10)) for row in range(8))
TMX = f"""<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" renderorder="right-down" width="10" height="8" tilewidth="16"
     tileheight="16" infinite="0" nextlayerid="3" nextobjectid="3">
 <tileset firstgid="1" name="ground" tilewidth="16" tileheight="16" tilecount="1" columns="1">
  <image source="ground.png" width="16" height="16"/>
 </tileset>
 <layer id="1" name="Ground" width="10" height="8">
  <data encoding="csv">
{GROUND}
  </data>
 </layer>
 <objectgroup id="2" name="Objects">
  <object id="1" name="wall" x="96" y="48" width="32" height="32"/>
  <object id="2" name="PlayerStart" x="56" y="40"><point/></object>
 </objectgroup>
</map>
"""


def _map(tmp_path: Path) -> Path:
    path = tmp_path / "map.tmx"
    path.write_text(TMX, encoding="utf-8")
    return path


def test_a_player_start_is_kept_by_the_level_and_its_file(tmp_path: Path) -> None:
    imported = import_map(_map(tmp_path))
    assert imported.player_starts == ((3.5, 2.5),)
    assert imported.level.player_starts == ((3.5, 2.5),) and not imported.level.starts
    # The grid is cropped to the ground and says where it sits; world units stay the map's tiles.
    assert "Tiled map 10 x 8 -> 8 x 6 grid at (2, 1)" in imported.summary()
    data = level_to_data(imported.level)
    assert data["player_starts"] == [[3.5, 2.5]]
    assert parse_level(json.loads(json.dumps(data)), source="again.json").player_starts == ((3.5, 2.5),)


def test_a_player_start_in_a_wall_is_one_line_naming_it(tmp_path: Path) -> None:
    level = write_level(tmp_path, {**TWO_ROOMS, "player_starts": [[1.5, 0.5], [-4, 0.5]]})
    result = run("validate", level)
    assert result.exit_code != 0
    assert "player_starts point 1 (-4, 0.5): start lies outside the level" in result.output


def test_sneak_starts_at_the_player_start_unless_told(tmp_path: Path) -> None:
    path = _map(tmp_path)
    assert run("patrol", path, "--out", tmp_path / "p").exit_code == 0
    args = ["sneak", path, "--patrol", tmp_path / "p" / "patrol.json", "--to", "8.5,5.5", "--out", tmp_path / "s"]
    result = run(*args)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("from the level's player start (3.5, 2.5)")
    data = json.loads((tmp_path / "s" / "sneak.json").read_text())
    # sneak.json's cells count from the cropped grid's origin, which it names.
    assert data["origin"] == [2.0, 1.0] and data["cell_size"] == 1.0 and data["from"] == [3.5, 2.5]
    assert data["path"][0] == [1, 1]


def test_sneak_without_from_on_a_level_with_no_player_start_is_one_line(tmp_path: Path) -> None:
    level = write_level(tmp_path, TWO_ROOMS)
    assert run("patrol", level, "--out", tmp_path / "p").exit_code == 0
    result = run("sneak", level, "--patrol", tmp_path / "p" / "patrol.json", "--to", "10.5,0.5")
    assert_one_line_error(result, level)
    assert "marks no player start: give --from X,Y" in result.output


def test_one_alert_episode_enters_at_the_player_start_unless_told(tmp_path: Path) -> None:
    path = _map(tmp_path)
    assert run("patrol", path, "--out", tmp_path / "p").exit_code == 0
    args = ["alert", path, "--patrol", tmp_path / "p" / "patrol.json", "--intruder", "route", "--to", "8.5,5.5"]
    result = run(*args, "--trace", tmp_path / "alert.json", "--max-seconds", "5")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("from the level's player start (3.5, 2.5)")
    trace = json.loads((tmp_path / "alert.json").read_text())
    # The intruder's first cell is the start's cell, counted from the cropped grid's origin (2, 1).
    assert trace["intruder_path"][0] == [1, 1]
