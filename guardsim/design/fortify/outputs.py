"""What ``guardsim fortify`` writes: the fortified level, the patrol with its posts and fortify.json (the
picture is drawn downstream, in :mod:`guardsim.pictures`); each through a temporary file renamed into place, so an interrupted run leaves no half file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from guardsim.design.fortify.loop import FortifyResult
from guardsim.files.output import write_text_atomic
from guardsim.level.writing import level_json_text, level_to_data

__all__ = ["fortify_patrol_data", "write_fortify_outputs"]


def fortify_patrol_data(result: FortifyResult) -> dict[str, Any] | None:
    """patrol.json of the patrol's guards and the posts (each marked ``"post": true``); ``None`` when
    there are neither."""
    from guardsim.patrol.format import patrol_data
    from guardsim.patrol.scoring import score_patrol
    from guardsim.vision.table import view_table

    patrol = result.patrol
    if patrol is None:
        return None
    scene = result.scene
    grid = scene.grid
    table = view_table(grid, scene.vision())
    score = score_patrol(table, patrol, grid.traversable.ravel())
    data = patrol_data(patrol, score, grid, level=result.level.name)
    for guard in data["guards"][patrol.guards - result.posts :]:
        guard["post"] = True
    return data


def write_fortify_outputs(result: FortifyResult, folder: Path | None) -> list[str]:
    """Write into ``folder`` level.json, patrol.json (when there are guards) and fortify.json; the paths
    written (the picture is :func:`guardsim.pictures.write_fortify_picture`). The level is written last of the files a check reads, so
    a folder holding it holds the rest."""
    written: list[str] = []
    if folder is not None:
        write_text_atomic(folder / "fortify.json", json.dumps(result.document, separators=(",", ":")) + "\n")
        written.append(str(folder / "fortify.json"))
        patrol = fortify_patrol_data(result)
        if patrol is not None:
            write_text_atomic(folder / "patrol.json", json.dumps(patrol, separators=(",", ":")) + "\n")
            written.append(str(folder / "patrol.json"))
        write_text_atomic(folder / "level.json", level_json_text(level_to_data(result.level)))
        written.append(str(folder / "level.json"))
    return written
