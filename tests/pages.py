"""Viewer pages the page tests (tests/test_viewer.py) and the browser tests (tests/test_browser.py) share:
the page's data block, a synthetic big episode, and patrol and sneak pages made by the real commands."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.trace import Trace
from tests.common import TWO_ROOMS, write_level

SQUARE = Path("levels/square.json")


def page_json(page: str) -> dict:
    """The data block of a page."""
    found = re.search(r'<script id="trace-data" type="application/json">(.*?)</script>', page, re.S)
    assert found is not None
    return json.loads(found.group(1))


def big_trace(rows: int = 512, cols: int = 512, steps: int = 30_000, guards: int = 1) -> Trace:
    """A synthetic episode on a 512 x 512 grid: random first-seen ticks, a long 4-connected walk."""
    rng = np.random.default_rng(0)
    first_seen = rng.integers(-1, steps, size=(rows, cols))
    moves = np.asarray([(1, 0), (0, 1), (-1, 0), (0, -1)])
    paths = []
    for _ in range(guards):
        position = np.asarray([cols // 2, rows // 2])
        path = [tuple(int(v) for v in position)]
        for step in rng.integers(0, 4, size=steps):
            position = np.clip(position + moves[step], 0, [cols - 1, rows - 1])
            path.append((int(position[0]), int(position[1])))
        paths.append(tuple(path))
    goal = np.ones((rows, cols), dtype=bool)
    unseen = [100.0 * float(((first_seen < 0) | (first_seen > t)).mean()) for t in range(0, steps + 1)]
    return Trace(
        level="big",
        planner="synthetic",
        seed=0,
        cell_size=1.0,
        origin=(0.0, 0.0),
        shape=(rows, cols),
        path=paths[0],
        headings=tuple(int(h) for h in rng.integers(0, 4, size=steps + 1)),
        unseen_percent=tuple(unseen),
        outcome="step_limit",
        reachable=rows * cols,
        unreachable=0,
        first_seen=first_seen,
        goal=goal,
        traversable=goal,
        guard_paths=tuple(paths) if guards > 1 else (),
        guard_headings=tuple(tuple(int(h) for h in rng.integers(0, 4, size=steps + 1)) for _ in paths)
        if guards > 1
        else (),
    )


CORRIDOR_POST = {"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}


def patrol_pages(folder: Path) -> Path:
    """`patrol --html --export` and `sneak --html` on Square (an unseen path exists), and `sneak --html`
    past a post in a one-cell corridor (caught: the closest call is in view for some ticks)."""
    runner = CliRunner()
    p, s, c = folder / "p", folder / "s", folder / "c"
    result = runner.invoke(main, ["patrol", str(SQUARE), "--out", str(p), "--html", "--export", str(p / "route.json")])
    assert result.exit_code == 0, result.output
    args = ["--from", "2.5,2.5", "--to", "57.5,57.5", "--out", str(s), "--html"]
    result = runner.invoke(main, ["sneak", str(SQUARE), "--patrol", str(p / "patrol.json"), *args])
    assert result.exit_code == 0 and "sneaks" in result.output, result.output
    level = write_level(folder, TWO_ROOMS, "corridor.json")
    (folder / "post.json").write_text(json.dumps(CORRIDOR_POST))
    args = ["--from", "0.5,0.5", "--to", "10.5,2.5", "--out", str(c), "--html"]
    result = runner.invoke(main, ["sneak", str(level), "--patrol", str(folder / "post.json"), *args])
    assert result.exit_code == 0 and "caught" in result.output, result.output
    return folder
