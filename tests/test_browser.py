"""The viewer page in a real headless Chromium: it loads without JavaScript errors, `#tick=N` opens it at
tick N with the trace's readout, and a screenshot shows the unseen colour exactly at the cells the trace
says are unseen at that tick. Skipped only when no Chromium is installed (CI installs Debian's)."""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner

from guardsim.cli import main
from guardsim.render import COLOURS
from guardsim.trace import Trace
from guardsim.viewer import write_viewer
from tests.test_viewer import big_trace

CHROMIUM = next((path for path in map(shutil.which, ("chromium", "chromium-browser")) if path), None)
pytestmark = pytest.mark.skipif(
    CHROMIUM is None,
    reason="no chromium on PATH: install Debian's chromium (apt-get install -y chromium), as .ci/run does",
)

SQUARE = Path("levels/square.json")
WINDOW = "1100,900"


def chromium(url: str, profile: Path, *action: str) -> subprocess.CompletedProcess[str]:
    """Run headless Chromium on ``url`` with no network services, a throwaway profile and ``action``."""
    assert CHROMIUM is not None
    command = [
        CHROMIUM,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        "--force-color-profile=srgb",
        "--force-device-scale-factor=1",
        f"--user-data-dir={profile}",
        f"--window-size={WINDOW}",
        "--virtual-time-budget=5000",
        *action,
        url,
    ]
    return subprocess.run(command, capture_output=True, text=True, timeout=120)


def dump(page: Path, fragment: str, profile: Path) -> str:
    done = chromium(f"{page.as_uri()}#{fragment}", profile, "--dump-dom")
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def element(dom: str, element_id: str) -> str:
    """The text inside the element with ``element_id``."""
    found = re.search(rf'id="{element_id}"[^>]*>(.*?)</', dom, re.S)
    assert found is not None, element_id
    return html.unescape(found.group(1))


def geometry(dom: str) -> tuple[int, int, int]:
    found = re.search(r'id="canvas-geometry"[^>]*data-left="(\d+)" data-top="(\d+)" data-scale="(\d+)"', dom)
    assert found is not None
    return int(found.group(1)), int(found.group(2)), int(found.group(3))


@pytest.fixture(scope="module")
def square_page(tmp_path_factory) -> tuple[Path, Trace]:
    folder = tmp_path_factory.mktemp("browser")
    out, page = folder / "trace.json", folder / "square.html"
    result = CliRunner().invoke(main, ["play", str(SQUARE), "--trace", str(out), "--html", str(page)])
    assert result.exit_code == 0, result.output
    return page, Trace.from_data(json.loads(out.read_text()))


def test_page_loads_without_errors_and_reads_the_tick_from_the_url(square_page, tmp_path: Path) -> None:
    """For several N, #tick=N shows tick N and unseen_percent[N] with one decimal; no script errors."""
    page, trace = square_page
    for tick in (0, 1, trace.steps // 2, trace.steps):
        dom = dump(page, f"tick={tick}", tmp_path / "profile")
        assert element(dom, "errors") == ""
        assert element(dom, "status") == "ready"
        expected = f"tick {tick} / {trace.steps} \u00b7 {trace.unseen_percent[tick]:.1f}% unseen"
        assert element(dom, "tick-readout") == expected


def test_tick_past_the_end_is_clamped(square_page, tmp_path: Path) -> None:
    """#tick beyond the episode opens at its last tick."""
    page, trace = square_page
    dom = dump(page, "tick=999999", tmp_path / "profile")
    assert element(dom, "tick-readout").startswith(f"tick {trace.steps} / {trace.steps} ")


def test_screenshot_shows_unseen_exactly_where_the_trace_says(square_page, tmp_path: Path) -> None:
    """At a known tick with the coverage layer alone, every goal cell's centre pixel is the unseen
    colour if the trace says it is unseen at that tick and the seen floor colour if it is seen (apart
    from the cells under the start marker and the guard, which are always drawn)."""
    page, trace = square_page
    tick = trace.steps // 3
    fragment = f"tick={tick}&layers=coverage&scale=8"
    left, top, scale = geometry(dump(page, fragment, tmp_path / "profile"))
    assert scale == 8
    shot = tmp_path / "shot.png"
    done = chromium(f"{page.as_uri()}#{fragment}", tmp_path / "profile", f"--screenshot={shot}")
    assert done.returncode == 0, done.stderr[-2000:]
    image = iio.imread(shot)[:, :, :3]
    unseen = (trace.first_seen < 0) | (trace.first_seen > tick)
    rows, cols = np.nonzero(trace.goal)
    covered = np.zeros(len(rows), dtype=bool)
    for col, row in (trace.path[0], trace.path[tick]):
        covered |= (np.abs(cols - col) <= 2) & (np.abs(rows - row) <= 2)
    assert covered.sum() <= 50
    rows, cols = rows[~covered], cols[~covered]
    ys, xs = top + rows * scale + scale // 2, left + cols * scale + scale // 2
    pixels = image[ys, xs]
    is_unseen = (pixels == COLOURS["unseen"]).all(axis=1)
    is_seen = (pixels == COLOURS["free"]).all(axis=1)
    assert (is_unseen == unseen[rows, cols]).all()
    assert (is_seen == ~unseen[rows, cols]).all()
    assert 0 < unseen[rows, cols].sum() < len(rows)


def test_every_layer_and_a_team_draw_without_errors(tmp_path: Path) -> None:
    """All layers on, two guards and a planner field: the page still loads cleanly."""
    trace = big_trace(40, 50, 300, guards=2)
    field = np.random.default_rng(1).random((301, 40, 50)) * 30
    page = tmp_path / "team.html"
    write_viewer(page, None, trace, field=field)
    dom = dump(page, "tick=150&layers=coverage,trail,cone,heat,field", tmp_path / "profile")
    assert element(dom, "errors") == ""
    assert element(dom, "tick-readout") == f"tick 150 / 300 \u00b7 {trace.unseen_percent[150]:.1f}% unseen"


def readout_tick(dom: str) -> int:
    found = re.match(r"tick (\d+) / ", element(dom, "tick-readout"))
    assert found is not None
    return int(found.group(1))


def test_playback_advances_at_the_chosen_speed_and_stops_at_the_end(square_page, tmp_path: Path) -> None:
    """#play=1 plays from the tick given; in the same (virtual) time 60 ticks/s gets further than 15, and
    playing past the last tick stops there with the button back to Play."""
    page, trace = square_page
    slow = readout_tick(dump(page, "tick=10&play=1&speed=15", tmp_path / "profile"))
    fast = readout_tick(dump(page, "tick=10&play=1&speed=60", tmp_path / "profile"))
    assert 10 < slow < fast <= trace.steps
    assert fast - 10 > 2 * (slow - 10)
    dom = dump(page, f"tick={trace.steps - 5}&play=1&speed=60", tmp_path / "profile")
    assert readout_tick(dom) == trace.steps
    assert element(dom, "play") == "Play"
    assert element(dom, "errors") == ""
