"""Two versions of a small level for the design tests (report, diff, check --baseline, watch).

A 20 x 9 room: a hall below, a corridor above, a wall between them. One guard is posted in the hall at
(13.5, 6.5), seeing all round to 5.5 units, and a player it sees is caught at once. Before the edit the
wall runs to the right-hand side, so the corridor is a dead end open only at the left: a player going
from (0.5, 6.5) to (19.5, 6.5) must cross the hall in the guard's sight, and the corridor's right end
is never watched. The edit moves the wall's right end to x = 14: the corridor becomes a side passage
round the guard, and the guard now sees up through the gap into what were safe spots.
"""

from __future__ import annotations

import json
from pathlib import Path

BASE = {
    "name": "Side passage",
    "cell_size": 1.0,
    "outer": [[0, 0], [20, 0], [20, 9], [0, 9]],
    "guard": {"start": [13.5, 6.5], "fov_degrees": 360, "view_range": 5.5, "detect_near": 0, "detect_far": 0},
}
OLD = {**BASE, "holes": [[[1, 3], [20, 3], [20, 4], [1, 4]]]}
NEW = {**BASE, "holes": [[[1, 3], [14, 3], [14, 4], [1, 4]]]}
POST = {"shape": [9, 20], "guards": [{"loop": [[13, 6]], "headings": [0]}]}
ENTRY, GOAL = (0.5, 6.5), (19.5, 6.5)


def write_versions(folder: Path) -> tuple[Path, Path, Path]:
    """old.json, new.json and post.json in ``folder``."""
    paths = folder / "old.json", folder / "new.json", folder / "post.json"
    for path, data in zip(paths, (OLD, NEW, POST)):
        path.write_text(json.dumps(data), encoding="utf-8")
    return paths
