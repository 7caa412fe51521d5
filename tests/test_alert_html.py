"""``guardsim alert --html`` (issue 26, item 4): the alert episode in the viewer, with the guards' states
and meters, the intruder, the last known cell and the contaminated set as layers of the viewer page.

The page's data is checked against the episode's trace (``--trace``, written by the same command); then
the page runs in a real headless Chromium, as tests/test_browser.py runs the viewer: it loads without
script errors, the alert readout (computed from the arrays the layers draw) gives the trace's states,
intruder cell, last known cell and contaminated count at chosen ticks, and screenshots show the
contaminated dots, the last known cross and the intruder where the episode has them.

The episode: in the two-guard pillar room of tests/test_alert.py, a spotted route intruder walks from
(10, 6) to its goal at (11, 0) and leaves; the guards chase, lose it, search, give up and return.
"""

from __future__ import annotations

import base64
import html
import json
import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.alert import GUARD_STATES, alert_episode
from guardsim.cli import main
from guardsim.render.alert import CONTAMINATED_INDEX, LAST_KNOWN_INDEX, STATE_LETTERS
from guardsim.render.palette import PALETTE
from guardsim.viewer.alerts import ALERT_LAYERS
from tests.common import write_level
from tests.pages import page_json
from tests.test_alert import ROOM, ring_patrol, setup, write_patrol
from tests.test_browser import CHROMIUM, chromium, dump, element, geometry

ENTRY, GOAL = (4, 0), (7, 6)


class Episode:
    """The page, the trace the same command wrote, and the episode rerun here (for its cells)."""

    def __init__(self, folder: Path) -> None:
        level = write_level(folder, ROOM)
        scene, table = setup()
        patrol = write_patrol(folder, scene.grid)
        self.level_path, self.patrol_path = level, patrol
        self.page, self.trace_path = folder / "alert.html", folder / "trace.json"
        args = ["--intruder", "route", "--from", "4.5,0.5", "--to", "7.5,6.5", "--spotted"]
        outputs = ["--html", str(self.page), "--trace", str(self.trace_path)]
        result = CliRunner().invoke(main, ["alert", str(level), "--patrol", str(patrol), *args, *outputs])
        assert result.exit_code == 0, result.output
        assert f"wrote {self.page}" in result.stdout
        self.trace = json.loads(self.trace_path.read_text())
        self.data = page_json(self.page.read_text())
        grid = scene.grid
        self.episode = alert_episode(
            scene,
            ring_patrol(grid, guards=2),
            intruder="route",
            source=grid.flat(*ENTRY),
            target=grid.flat(*GOAL),
            spotted=True,
            table=table,
        )
        self.episode.run()
        assert self.episode.record["contaminated"] == self.trace["contaminated"]  # the same episode
        self.ticks = len(self.trace["contaminated"])

    def states(self, tick: int) -> list[str]:
        return [per_guard[tick] for per_guard in self.trace["guard_states"]]

    def chase_tick(self) -> int:
        """A tick with the intruder in the level and a guard chasing it."""
        return next(t for t in range(self.ticks) if "chase" in self.states(t) and self.trace["intruder_path"][t])

    def search_tick(self) -> int:
        """A tick of the search with several contaminated cells, the intruder gone."""
        return next(t for t in range(self.ticks) if "search" in self.states(t) and self.trace["contaminated"][t] >= 5)

    def return_tick(self) -> int:
        return next(t for t in range(self.ticks) if "return" in self.states(t))


@pytest.fixture(scope="module")
def alert_page(tmp_path_factory: pytest.TempPathFactory) -> Episode:
    return Episode(tmp_path_factory.mktemp("alert-page"))


def decoded(text: str, dtype: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(text), dtype=dtype)


def test_the_episode_has_every_part_to_show(alert_page: Episode) -> None:
    """The chosen episode chases, searches with a contaminated set and returns: every layer has work."""
    states = {s for t in range(alert_page.ticks) for s in alert_page.states(t)}
    assert {"patrol", "chase", "search", "return"} <= states
    assert alert_page.trace["outcome"]["outcome"] == "escaped"
    assert alert_page.chase_tick() < alert_page.search_tick() < alert_page.return_tick()


def test_view_draws_the_saved_trace_as_alert_html_drew_the_episode(alert_page: Episode, tmp_path: Path) -> None:
    """``guardsim view TRACE --level --patrol`` writes the page ``alert --html`` wrote, from the trace
    alone: the same data but the search area's cells (a trace keeps their count, which the page reads
    out the same)."""
    page = tmp_path / "view.html"
    args = ["view", alert_page.trace_path, "--level", alert_page.level_path, "--patrol", alert_page.patrol_path]
    result = CliRunner().invoke(main, [*map(str, args), "--html", str(page)])
    assert result.exit_code == 0, result.output
    ticks = alert_page.ticks - 1
    assert result.stdout == f"alert room: alert episode, ripple search, {ticks} ticks, 2 guard(s) -> {page}\n"
    viewed, written = page_json(page.read_text()), dict(alert_page.data)
    assert decoded(viewed["alert"].pop("contaminated"), "u1").sum() == 0
    written["alert"] = {key: value for key, value in written["alert"].items() if key != "contaminated"}
    assert viewed == written
    # Without the level there is no grid to draw on: one line.
    missing = CliRunner().invoke(main, ["view", str(alert_page.trace_path), "--html", str(page)])
    assert missing.exit_code == 2
    assert missing.stderr == (
        f"guardsim: error: {alert_page.trace_path}: an alert episode's trace: give --level LEVEL, the level it "
        "was played on\n"
    )


def test_page_data_is_the_trace(alert_page: Episode) -> None:
    """Per tick and guard the page carries the trace's state (with the GIF's letters) and meter, the
    intruder's cells while it is in, the last known cell, the contaminated cells (as many as the trace
    counts, exactly the episode's), and the GIF's colours from the one palette."""
    data, trace, ticks = alert_page.data, alert_page.trace, alert_page.ticks
    alert, cols = data["alert"], data["cols"]
    assert data["steps"] == ticks - 1 and alert["guards"] == 2
    assert alert["state_names"] == list(GUARD_STATES)
    assert alert["state_letters"] == [STATE_LETTERS[name] for name in GUARD_STATES]
    states = decoded(alert["states"], "u1").reshape(ticks, 2)
    assert [[GUARD_STATES[k] for k in states[:, g]] for g in range(2)] == trace["guard_states"]
    meters = decoded(alert["meters"], "<f4").reshape(ticks, 2)
    assert np.abs(meters.T - np.asarray(trace["awareness"])).max() < 1e-6
    known = decoded(alert["last_known"], "<i4")
    assert [None if c < 0 else [int(c) % cols, int(c) // cols] for c in known] == trace["last_known"]
    assert alert["contaminated_counts"] == trace["contaminated"]
    bits = decoded(alert["contaminated"], "u1").reshape(ticks, alert["contaminated_stride"])
    cells = np.unpackbits(bits, axis=1, bitorder="little")[:, : data["rows"] * cols]
    for tick in range(ticks):
        assert np.flatnonzero(cells[tick]).tolist() == alert_page.episode.record["contaminated_cells"][tick].tolist()
    path = decoded(data["intruder"]["path"], "<i4")
    inside = [cell for cell in trace["intruder_path"] if cell is not None]
    assert [[int(c) % cols, int(c) // cols] for c in path] == inside
    assert data["intruder"]["start"] == 0
    assert tuple(alert["contaminated_colour"]) == PALETTE[CONTAMINATED_INDEX]
    assert tuple(alert["last_known_colour"]) == PALETTE[LAST_KNOWN_INDEX]
    assert data["default_layers"] == list(ALERT_LAYERS)
    assert {"contaminated", "last-known", "meters", "states", "intruder"} <= set(ALERT_LAYERS)
    assert [[e["tick"], e["guard"], e["event"]] for e in trace["events"]] == alert["events"]


# -- In Chromium ----------------------------------------------------------------------------------

needs_chromium = pytest.mark.skipif(
    CHROMIUM is None,
    reason="no chromium on PATH: install Debian's chromium (apt-get install -y chromium), as .ci/run does",
)


def attributes(dom: str, element_id: str) -> dict[str, str]:
    """The attributes of the element with ``element_id``."""
    found = re.search(rf'<\w+ id="{element_id}"([^>]*)>', dom)
    assert found is not None, element_id
    return {name: html.unescape(value) for name, value in re.findall(r'([\w-]+)="([^"]*)"', found.group(1))}


def cell_text(cell: list[int] | None) -> str:
    return "" if cell is None else f"{cell[0]},{cell[1]}"


@needs_chromium
def test_page_loads_and_the_alert_readout_is_the_trace(alert_page: Episode, tmp_path: Path) -> None:
    """At the first tick, a chase, a search, a return and the last tick: no script errors, and the states,
    intruder cell, last known cell and contaminated count read back from the page are the trace's."""
    trace = alert_page.trace
    ticks = [0, alert_page.chase_tick(), alert_page.search_tick(), alert_page.return_tick(), alert_page.ticks - 1]
    for tick in ticks:
        dom = dump(alert_page.page, f"tick={tick}", tmp_path / "profile")
        assert element(dom, "errors") == "" and element(dom, "status") == "ready", tick
        assert element(dom, "tick-readout").startswith(f"tick {tick} / {alert_page.ticks - 1} "), tick
        readout = attributes(dom, "alert-readout")
        assert "hidden" not in readout
        assert readout["data-states"] == ",".join(alert_page.states(tick)), tick
        assert readout["data-intruder"] == cell_text(trace["intruder_path"][tick]), tick
        assert readout["data-last-known"] == cell_text(trace["last_known"][tick]), tick
        assert readout["data-contaminated"] == str(trace["contaminated"][tick]), tick
        text = element(dom, "alert-readout")
        assert text.startswith(f"guard 1 {alert_page.states(tick)[0]} \u00b7 guard 2 {alert_page.states(tick)[1]}")
        count = trace["contaminated"][tick]
        assert text.endswith(f"{count} {'cell' if count == 1 else 'cells'} contaminated")
        intruder = trace["intruder_positions"][tick]
        if intruder is not None:
            # In world units, as the command line takes a point.
            assert element(dom, "intruder-readout").startswith(f"intruder at {intruder[0]:g},{intruder[1]:g}: ")
        else:
            assert element(dom, "intruder-readout").startswith("intruder left the level at tick ")
    # Every alert layer has its toggle shown, and the timeline marks the detection and the give-ups.
    for layer in ("states", "contaminated", "last-known", "meters", "intruder", "route"):
        assert f'<label><input type="checkbox" data-layer="{layer}">' in dom, layer
    marks = dom.split('id="timeline-marks"')[1].split("</datalist>")[0]
    detected = next(e["tick"] for e in trace["events"] if e["event"] == "detected")
    assert f'<option value="{detected}">guard 1 detected' in marks
    assert "gave up" in marks and "back on route" in marks


def screenshot(page: Path, fragment: str, profile: Path) -> tuple[tuple[int, int, int], np.ndarray]:
    import imageio.v3 as iio

    dom = dump(page, fragment, profile)
    assert element(dom, "errors") == ""
    shot = profile.parent / "shot.png"
    done = chromium(f"{page.as_uri()}#{fragment}", profile, f"--screenshot={shot}")
    assert done.returncode == 0, done.stderr[-2000:]
    return geometry(dom), iio.imread(shot)[:, :, :3].astype(int)


def centres(image: np.ndarray, where: tuple[int, int, int], cells: np.ndarray) -> np.ndarray:
    """The centre pixel of each ``(col, row)``."""
    left, top, scale = where
    return image[top + cells[:, 1] * scale + scale // 2, left + cells[:, 0] * scale + scale // 2]


@pytest.mark.slow
@needs_chromium
def test_contaminated_dots_and_last_known_cross_are_drawn_where_the_episode_has_them(
    alert_page: Episode, tmp_path: Path
) -> None:
    """With the contaminated layer alone, the floor cells whose centre is the dots' colour are exactly the
    episode's contaminated cells at that tick; with the last known layer alone, the cross's colour is at
    the trace's last known cell."""
    tick = alert_page.search_tick()
    rows, cols = alert_page.data["rows"], alert_page.data["cols"]
    every = np.array([(c, r) for r in range(rows) for c in range(cols)])
    where, image = screenshot(alert_page.page, f"tick={tick}&layers=contaminated&scale=12", tmp_path / "profile")
    assert where[2] == 12
    dots = (centres(image, where, every) == PALETTE[CONTAMINATED_INDEX]).all(axis=1)
    expected = alert_page.episode.record["contaminated_cells"][tick]
    # Guards are always drawn, a guard's disc and facing mark over its cell and the one it faces: their
    # dots may be hidden; every other contaminated cell shows its dot, and no other cell has one.
    near = {(path[tick][0], path[tick][1]) for path in alert_page.trace["paths"]}
    under = {(c + dc) + (r + dr) * cols for c, r in near for dc, dr in ((0, 0), (1, 0), (-1, 0), (0, 1), (0, -1))}
    shown = [cell for cell in expected.tolist() if cell not in under]
    assert len(shown) >= len(expected) - 4
    assert [cell for cell in np.flatnonzero(dots).tolist() if cell not in under] == shown
    assert set(np.flatnonzero(dots).tolist()) <= set(expected.tolist())
    known = alert_page.trace["last_known"][tick]
    where, image = screenshot(alert_page.page, f"tick={tick}&layers=last-known&scale=12", tmp_path / "profile")
    cross = (centres(image, where, every) == PALETTE[LAST_KNOWN_INDEX]).all(axis=1)
    mark = known[1] * cols + known[0]
    assert cross[mark] and [cell for cell in np.flatnonzero(cross).tolist() if cell not in under | {mark}] == []


@pytest.mark.slow
@needs_chromium
def test_intruder_is_drawn_at_its_cell_and_leaves(alert_page: Episode, tmp_path: Path) -> None:
    """With the intruder layer alone: at a tick of the chase its disc (white unseen, black in view) covers
    the trace's intruder cell; once it has left, no disc is drawn, only its walk (at a tick with no guard on or beside that cell)."""
    trace = alert_page.trace
    tick = alert_page.chase_tick()
    col, row = trace["intruder_path"][tick]
    where, image = screenshot(alert_page.page, f"tick={tick}&layers=intruder&scale=12", tmp_path / "profile")
    pixel = tuple(centres(image, where, np.array([[col, row]]))[0])
    in_view = decoded(alert_page.data["intruder"]["in_view"], "u1")[tick] == 1
    assert pixel == ((0, 0, 0) if in_view else (255, 255, 255))
    # Gone: its last cell shows its walk (the intruder's colour), no disc (guards are always drawn: the
    # tick is one with no guard near that cell).
    gone = trace["intruder_path"].index(None)
    col, row = trace["intruder_path"][gone - 1]
    later = next(
        t for t in range(gone, alert_page.ticks)
        if all(abs(path[t][0] - col) + abs(path[t][1] - row) > 1 for path in trace["paths"])
    )  # fmt: skip
    where, image = screenshot(alert_page.page, f"tick={later}&layers=intruder&scale=12", tmp_path / "profile")
    pixel = tuple(centres(image, where, np.array([[col, row]]))[0])
    assert pixel == tuple(int(alert_page.data["colours"]["intruder"][k : k + 2], 16) for k in (1, 3, 5))
