"""What ``guardsim fortify`` writes: the fortified level, the patrol with its posts and fortify.json (the
picture is drawn downstream, in :mod:`guardsim.pictures`); each through a temporary file renamed into place, so an interrupted run leaves no half file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from guardsim.design.fortify.loop import FortifyResult
from guardsim.files.output import write_text_atomic
from guardsim.level.writing import level_json_text, level_to_data

__all__ = ["fortify_patrol_data", "fortify_summary", "write_fortify_outputs"]


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


def fortify_summary(result: FortifyResult) -> str:
    """The answer in one line: sealed with which watchers and how close to the lower bound, or which pair
    is still open and when."""
    document = result.document
    added = (
        ", ".join(f"{w['kind']} at ({w['position'][0]:g}, {w['position'][1]:g})" for w in document["watchers"])
        or "nothing"
    )
    bound = "unknown" if document["lower_bound"] is None else str(document["lower_bound"])
    count = document["count"]
    if result.sealed:
        return (
            f"sealed ({document['rule']}) with {count} watcher{'' if count == 1 else 's'} ({added}); lower bound "
            f"{bound}, gap {document['gap']}; {document['search_rounds']} search rounds, joint lap {document['lap']} ticks"
        )
    open_pairs = [pair for pair in document["pairs"] if not pair["sealed"]]
    first = open_pairs[0]
    return (
        f"not sealed: {document['reason']}; {len(open_pairs)} pair{'' if len(open_pairs) == 1 else 's'} still open "
        f"(from ({first['from'][0]:g}, {first['from'][1]:g}): entry ticks {_ticks(first['open_entry_ticks'])} of "
        f"{document['lap']}); {count} watcher{'' if count == 1 else 's'} placed ({added}); lower bound {bound}"
    )


def _ticks(ticks: list[int]) -> str:
    shown = ", ".join(str(tick) for tick in ticks[:8])
    return shown + (f" and {len(ticks) - 8} more" if len(ticks) > 8 else "")
