"""The viewer page in a real headless Chromium: it loads without JavaScript errors, `#tick=N` opens it at
tick N with the trace's readout, and a screenshot shows the unseen colour exactly at the cells the trace
says are unseen at that tick. Skipped only when no Chromium is installed (CI installs Debian's)."""

from __future__ import annotations

import base64
import html
import itertools
import json
import math
import re
import shutil
import subprocess
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from click.testing import CliRunner

from guardsim import load_level
from guardsim.cli import main
from guardsim.render import COLOURS
from guardsim.trace import Trace
from guardsim.viewer import write_viewer
from tests.common import TWO_ROOMS
from tests.pages import CORRIDOR_POST, big_trace, page_json, patrol_pages

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


def timeline_marks(dom: str) -> str:
    """The inside of the timeline's datalist."""
    return dom.split('id="timeline-marks"')[1].split("</datalist>")[0]


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


# --- Patrol and sneak pages: laps, idleness layers, routes, the intruder; the continuous trail ---


def rgb_ramp(stops: list, fraction: float) -> tuple[int, int, int]:
    """The page's colour ramp (viewer.js ``ramp``), with JavaScript's Math.round."""
    fraction = min(1.0, max(0.0, fraction))
    for (f0, c0), (f1, c1) in itertools.pairwise(stops):
        if fraction <= f1:
            t = (fraction - f0) / (f1 - f0) if f1 > f0 else 0
            return tuple(math.floor(c0[k] + t * (c1[k] - c0[k]) + 0.5) for k in range(3))  # type: ignore[return-value]
    return tuple(stops[-1][1])


def view(page: Path, fragment: str, profile: Path) -> tuple[str, np.ndarray]:
    """The page's DOM and a screenshot (RGB) at ``fragment``."""
    dom = dump(page, fragment, profile)
    shot = profile.parent / "shot.png"
    done = chromium(f"{page.as_uri()}#{fragment}", profile, f"--screenshot={shot}")
    assert done.returncode == 0, done.stderr[-2000:]
    return dom, iio.imread(shot)[:, :, :3]


def cell_pixels(image: np.ndarray, dom: str, cells: np.ndarray) -> np.ndarray:
    """The centre pixel of each ``(col, row)`` in ``cells``."""
    left, top, scale = geometry(dom)
    return image[top + cells[:, 1] * scale + scale // 2, left + cells[:, 0] * scale + scale // 2].astype(int)


def away_from(cells: np.ndarray, *points: tuple[int, int], reach: int = 2) -> np.ndarray:
    """Which ``cells`` lie more than ``reach`` cells from every point (guards and markers are drawn there)."""
    keep = np.ones(len(cells), dtype=bool)
    for col, row in points:
        keep &= (np.abs(cells[:, 0] - col) > reach) | (np.abs(cells[:, 1] - row) > reach)
    return keep


def page_data_of(page: Path) -> dict:

    return page_json(page.read_text())


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> Path:

    return patrol_pages(tmp_path_factory.mktemp("patrol-pages"))


@pytest.mark.slow
def test_patrol_timeline_plays_several_laps_and_tick_period_plus_k_is_lap_tick_k(pages: Path, tmp_path: Path) -> None:
    """The timeline spans three laps, marked where each begins; #tick=period+k reads 'lap 2 / 3 · lap
    tick k' and draws exactly what tick k draws, and not what tick k+7 draws (the guard has moved)."""
    page = pages / "p" / "patrol.html"
    period = page_data_of(page)["laps"]["period"]
    k = 100
    fragment = "scale=8&layers=idleness,route,trail,cone&tick="
    dom, later = view(page, fragment + str(period + k), tmp_path / "profile")
    assert element(dom, "errors") == ""
    assert f"tick {period + k} / {3 * period} \u00b7 lap 2 / 3 \u00b7 lap tick {k} / {period} \u00b7" in element(
        dom, "tick-readout"
    )
    left, top, scale = geometry(dom)
    rows, cols = page_data_of(page)["rows"], page_data_of(page)["cols"]
    box = (slice(top, top + rows * scale), slice(left, left + cols * scale))
    dom_first, first = view(page, fragment + str(k), tmp_path / "profile")
    assert geometry(dom_first) == (left, top, scale)
    _, moved = view(page, fragment + str(k + 7), tmp_path / "profile")
    assert (later[box] == first[box]).all()
    assert (later[box] != moved[box]).any()
    marks = {int(v) for v in re.findall(r'<option value="(\d+)">', timeline_marks(dom))}
    assert marks == {period, 2 * period}
    dom = dump(page, f"tick={10 * period}", tmp_path / "profile")
    assert element(dom, "tick-readout").startswith(f"tick {3 * period} / {3 * period} ")
    dom = dump(
        page,
        f"tick={4 * period + 3}&laps=5&layers=coverage,trail,cone,heat,idleness,idle-now,route",
        tmp_path / "profile",
    )
    assert element(dom, "errors") == ""
    assert f"lap 5 / 5 \u00b7 lap tick 3 / {period}" in element(dom, "tick-readout")


def test_idleness_layer_has_the_colour_bars_colours_and_holes(pages: Path, tmp_path: Path) -> None:
    """With the worst-gap layer alone, every goal cell's pixel is the ramp colour of its value over the
    colour bar's range, and the bar shows that colour where the value lies on it; null cells show the
    floor or the wall, not a heat colour."""
    page = pages / "p" / "patrol.html"
    data = page_data_of(page)
    rows, cols = data["rows"], data["cols"]
    values = np.frombuffer(base64.b64decode(data["idleness"]["values"]), dtype="<f4").reshape(rows, cols)
    top_value = data["idleness"]["max"]
    dom, image = view(page, "tick=0&layers=idleness&scale=8", tmp_path / "profile")
    assert element(dom, "bar-label") == "worst gap" and element(dom, "bar-unit") == "ticks"
    assert float(element(dom, "bar-max")) == top_value
    path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")
    guard = (int(path[0] % cols), int(path[0] // cols))
    rr, cc = np.nonzero(values >= 0)
    cells = np.stack([cc, rr], axis=1)
    cells = cells[away_from(cells, guard)]
    pixels = cell_pixels(image, dom, cells)
    expected = np.array([rgb_ramp(data["ramp"], float(values[r, c]) / top_value) for c, r in cells])
    assert (pixels == expected).all()
    assert len(np.unique(expected, axis=0)) > 20
    bar_left = int(re.search(r'data-bar-left="(\d+)"', dom).group(1))  # type: ignore[union-attr]
    bar_top = int(re.search(r'data-bar-top="(\d+)"', dom).group(1))  # type: ignore[union-attr]
    for c, r in cells[:: max(1, len(cells) // 40)]:
        x = bar_left + 1 + round(float(values[r, c]) / top_value * 255)
        bar = image[bar_top + 1 + 7, x].astype(int)
        assert np.abs(bar - np.array(rgb_ramp(data["ramp"], float(values[r, c]) / top_value))).max() <= 3
    rr, cc = np.nonzero(values < 0)
    holes = np.stack([cc, rr], axis=1)
    holes = holes[away_from(holes, guard)]
    hole_pixels = cell_pixels(image, dom, holes)
    floor_or_wall = (hole_pixels == COLOURS["free"]).all(axis=1) | (hole_pixels == COLOURS["wall"]).all(axis=1)
    assert len(holes) > 0 and floor_or_wall.all()


def test_never_seen_cells_are_drawn_apart(pages: Path, tmp_path: Path) -> None:
    """Past the corridor post, the hiding-spot layer draws the never-seen cells black and the others in
    the ramp's colours."""
    page = pages / "c" / "sneak.html"
    data = page_data_of(page)
    rows, cols = data["rows"], data["cols"]
    never = np.frombuffer(base64.b64decode(data["idleness"]["never"]), dtype=np.uint8).reshape(rows, cols) == 1
    values = np.frombuffer(base64.b64decode(data["idleness"]["values"]), dtype="<f4").reshape(rows, cols)
    dom, image = view(page, "tick=0&layers=idleness&scale=20", tmp_path / "profile")
    assert element(dom, "errors") == ""
    rr, cc = np.nonzero(never)
    pixels = cell_pixels(image, dom, np.stack([cc, rr], axis=1))
    assert len(pixels) > 0 and (pixels == 0).all()
    rr, cc = np.nonzero(values >= 0)
    cells = np.stack([cc, rr], axis=1)
    cells = cells[away_from(cells, (5, 1), reach=0)]
    pixels = cell_pixels(image, dom, cells)
    assert len(cells) > 0 and (pixels != 0).any(axis=1).all()


def _steady_idleness(seen: np.ndarray, tau: int) -> np.ndarray:
    """Each cell's ticks since last seen at lap tick ``tau``, the lap repeating for ever; -1 if never."""
    period = seen.shape[0]
    two = np.concatenate([seen, seen])
    ticks = np.arange(2 * period)[:, None]
    last = np.where(two[: period + tau + 1], ticks[: period + tau + 1], -1).max(axis=0)
    return np.where(seen.any(axis=0), period + tau - last, -1)


def test_idleness_now_is_the_ticks_since_each_cell_was_last_seen(pages: Path, tmp_path: Path) -> None:
    """At page tick period+k the animated layer colours each goal cell by its idleness at lap tick k, as
    replayed here from the patrol's own views (steady state: the lap repeats), over the bar's range."""
    from guardsim.patrol import read_patrol, seen_timeline
    from guardsim.scene import Scene
    from guardsim.vision.table import view_table

    page = pages / "p" / "patrol.html"
    data = page_data_of(page)
    rows, cols, period = data["rows"], data["cols"], data["laps"]["period"]
    scene = Scene.from_level(load_level(SQUARE))
    patrol = read_patrol(pages / "p" / "patrol.json", scene.grid)
    seen = seen_timeline(view_table(scene.grid, scene.vision()), patrol.states, scene.grid.size)
    k = 300
    idle = _steady_idleness(seen, k).reshape(rows, cols)
    dom, image = view(page, f"tick={period + k}&layers=idle-now&scale=8", tmp_path / "profile")
    assert element(dom, "bar-label") == "idleness now"
    assert element(dom, "bar-max") == str(data["laps"]["max"])
    kinds = np.frombuffer(base64.b64decode(data["kinds"]), dtype=np.uint8).reshape(rows, cols)
    path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")
    guards = [(int(path[t] % cols), int(path[t] // cols)) for t in (0, k)]
    rr, cc = np.nonzero(kinds == 1)
    cells = np.stack([cc, rr], axis=1)
    cells = cells[away_from(cells, *guards)]
    pixels = cell_pixels(image, dom, cells)
    expected = np.array([rgb_ramp(data["ramp"], idle[r, c] / data["laps"]["max"]) for c, r in cells])
    assert (pixels == expected).all()
    assert (idle[cells[:, 1], cells[:, 0]] == 0).any() and (idle[cells[:, 1], cells[:, 0]] > 300).any()


def test_each_guards_loop_is_drawn_as_a_closed_dashed_polyline(pages: Path, tmp_path: Path) -> None:
    """With the route layer, the cell centres along every straight run between two waypoints are the
    guard's dark route colour or the white between its dashes, both often (dashed, unlike the solid
    trail); without it they are neither."""
    page = pages / "p" / "patrol.html"
    data = page_data_of(page)
    cols = data["cols"]
    path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")
    start = (int(path[0] % cols), int(path[0] // cols))
    along = []
    route = data["routes"][0]
    for (x0, y0), (x1, y1) in itertools.pairwise(route):
        c0, r0, c1, r1 = int(x0), int(y0), int(x1), int(y1)
        steps = max(abs(c1 - c0), abs(r1 - r0))
        along += [(c0 + (c1 - c0) * i // steps, r0 + (r1 - r0) * i // steps) for i in range(1, steps)]
    # A waypoint's cell is a corner, where the dashes of two runs meet at any phase (a run that turns back
    # passes its own corner cell mid-run): only cells strictly between corners are checked.
    corners = {(int(x), int(y)) for x, y in route}
    cells = np.asarray([cell for cell in along if cell not in corners])
    cells = cells[away_from(cells, start)]
    assert len(cells) > 100
    colour = tuple(int(data["route_colours"][0][i : i + 2], 16) for i in (1, 3, 5))
    dom, image = view(page, "tick=0&layers=route&scale=8", tmp_path / "profile")
    pixels = cell_pixels(image, dom, cells)
    dark, gap = (pixels == colour).all(axis=1), (pixels == (255, 255, 255)).all(axis=1)
    assert (dark | gap).all()
    assert 0.4 < dark.mean() < 0.8 and gap.mean() > 0.2
    dom, image = view(page, "tick=0&layers=trail&scale=8", tmp_path / "profile")
    pixels = cell_pixels(image, dom, cells)
    assert ((pixels == colour).all(axis=1) | (pixels == (255, 255, 255)).all(axis=1)).mean() < 0.05


def test_the_cone_stands_out_over_the_heat_map(pages: Path, tmp_path: Path) -> None:
    """Over the worst-gap layer, each cell well inside the guard's cone is the heat colour of its value
    under a white wash, far (> 80 in RGB) from that heat colour, including cells at the yellow top of the
    ramp, where the GIF's yellow tint would vanish; cells outside the cone keep their heat colour."""
    from guardsim.patrol import read_patrol, seen_timeline
    from guardsim.scene import Scene
    from guardsim.vision.table import view_table

    page = pages / "p" / "patrol.html"
    data = page_data_of(page)
    rows, cols = data["rows"], data["cols"]
    values = np.frombuffer(base64.b64decode(data["idleness"]["values"]), dtype="<f4").reshape(rows, cols)
    top_value = data["idleness"]["max"]
    scene = Scene.from_level(load_level(SQUARE))
    patrol = read_patrol(pages / "p" / "patrol.json", scene.grid)
    seen = seen_timeline(view_table(scene.grid, scene.vision()), patrol.states, scene.grid.size)
    path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")

    def inside_cone(k: int) -> tuple[tuple[int, int], np.ndarray, np.ndarray]:
        """The guard's cell at tick k, what it sees, and the goal cells well inside its cone."""
        guard = (int(path[k] % cols), int(path[k] // cols))
        now = seen[k].reshape(rows, cols)
        # Cells whose eight neighbours are seen too lie inside the drawn cone, clear of its edge.
        padded = np.pad(now, 1)
        inner = np.ones_like(now)
        for dr in range(3):
            for dc in range(3):
                inner &= padded[dr : dr + rows, dc : dc + cols]
        rr, cc = np.nonzero(inner & (values >= 0))
        cells = np.stack([cc, rr], axis=1)
        return guard, now, cells[away_from(cells, guard)]

    # The first tick whose cone holds more than 10 such cells, one of them at the yellow top of the ramp.
    k = next(
        k
        for k in range(len(seen))
        if len(inside_cone(k)[2]) > 10
        and (values[inside_cone(k)[2][:, 1], inside_cone(k)[2][:, 0]] / top_value > 0.9).any()
    )
    guard, now, cells = inside_cone(k)
    dom, image = view(page, f"tick={k}&layers=idleness,cone&scale=8", tmp_path / "profile")
    assert element(dom, "errors") == ""
    heat = np.array([rgb_ramp(data["ramp"], float(values[r, c]) / top_value) for c, r in cells])
    assert (values[cells[:, 1], cells[:, 0]] / top_value > 0.9).any()
    pixels = cell_pixels(image, dom, cells)
    assert (np.linalg.norm(pixels - heat, axis=1) > 80).all()
    assert (np.abs(pixels - (0.5 * heat + 0.5 * 255)) <= 2).all()
    padded = np.pad(now, 3)
    near = np.zeros_like(now)
    for dr in range(7):
        for dc in range(7):
            near |= padded[dr : dr + rows, dc : dc + cols]
    rr, cc = np.nonzero(~near & (values >= 0))
    outside = np.stack([cc, rr], axis=1)
    start = (int(path[0] % cols), int(path[0] // cols))  # its start is marked by a square
    outside = outside[away_from(outside, guard, start)]
    heat = np.array([rgb_ramp(data["ramp"], float(values[r, c]) / top_value) for c, r in outside])
    assert len(outside) > 100 and (cell_pixels(image, dom, outside) == heat).all()


def test_the_intruder_has_no_cone_and_is_marked_while_in_view(pages: Path, tmp_path: Path) -> None:
    """Past the corridor post: as it enters, the intruder is a white disc with floor all round it (no cone
    of its own) while the post's cone tints the corridor; at a tick in view it is black, ringed red, and
    the readout says so."""
    page = pages / "c" / "sneak.html"
    data = page_data_of(page)
    intruder = data["intruder"]
    cols = data["cols"]
    path = np.frombuffer(base64.b64decode(intruder["path"]), dtype="<i4")
    in_view = np.frombuffer(base64.b64decode(intruder["in_view"]), dtype=np.uint8)
    fragment = "layers=cone,intruder&scale=20&tick="
    dom, image = view(page, fragment + str(intruder["start"]), tmp_path / "profile")
    assert element(dom, "errors") == "" and element(dom, "intruder-readout").endswith(": unseen")
    left, top, scale = geometry(dom)
    col, row = int(path[0] % cols), int(path[0] // cols)
    x, y = left + col * scale + scale // 2, top + row * scale + scale // 2
    assert tuple(image[y, x]) == (255, 255, 255)
    around = [(x + dx, y + dy) for dx, dy in ((30, 0), (0, 30), (30, 30), (40, 10), (10, 40))]
    assert all(tuple(image[py, px]) == COLOURS["free"] for px, py in around)
    assert tuple(image[top + scale + scale // 2, left + 7 * scale + scale // 2]) != COLOURS["free"]
    step = int(np.flatnonzero(in_view)[0])
    dom, image = view(page, fragment + str(intruder["start"] + step), tmp_path / "profile")
    assert element(dom, "intruder-readout").endswith(": IN VIEW")
    # The timeline marks where the intruder enters, where it comes into view and where it arrives.
    marks = {int(v) for v in re.findall(r'<option value="(\d+)">', timeline_marks(dom))}
    assert {intruder["start"], intruder["start"] + step, intruder["start"] + len(path) - 1} <= marks
    col, row = int(path[step] % cols), int(path[step] // cols)
    x, y = left + col * scale + scale // 2, top + row * scale + scale // 2
    assert tuple(image[y, x]) == (0, 0, 0)
    radius = max(7, 0.45 * scale)
    red = image[y - 2 : y + 3, x + round(radius) + 3 : x + round(radius) + 6].reshape(-1, 3).astype(int)
    assert ((red[:, 0] > 200) & (red[:, 1] < 90) & (red[:, 2] < 90)).any()


def test_the_square_sneak_page_plays_the_intruders_walk(pages: Path, tmp_path: Path) -> None:
    """sneak.html on Square: the intruder is not in before its start tick, walks unseen and arrives."""
    page = pages / "s" / "sneak.html"
    intruder = page_data_of(page)["intruder"]
    ticks = len(np.frombuffer(base64.b64decode(intruder["path"]), dtype="<i4")) - 1
    dom = dump(page, f"tick={intruder['start'] + 5}", tmp_path / "profile")
    assert element(dom, "errors") == ""
    assert element(dom, "intruder-readout") == f"intruder tick 5 / {ticks}: unseen"
    dom = dump(page, f"tick={intruder['start'] + ticks}", tmp_path / "profile")
    assert element(dom, "intruder-readout") == f"intruder arrived after {ticks} ticks, 0 in view"


def test_continuous_trail_passes_through_the_poses_not_the_cell_centres(tmp_path: Path) -> None:
    """A guard walking along y = 5.9 (row 5, whose centres are at y = 5.5): the trail covers the pixels
    of its poses and leaves the cell-centre line bare. The speed menu says which speed is game time."""
    ticks = 36
    xs = 2.5 + 0.5 * np.arange(ticks + 1)
    poses = np.stack([np.arange(ticks + 1) / 30, xs, np.full(ticks + 1, 5.9), np.zeros(ticks + 1)], axis=1)
    free = np.ones((12, 24), dtype=bool)
    trace = Trace(
        level="walk",
        planner="synthetic",
        seed=0,
        cell_size=1.0,
        origin=(0.0, 0.0),
        shape=(12, 24),
        path=tuple((int(x), 5) for x in xs),
        headings=(0,) * (ticks + 1),
        unseen_percent=(50.0,) * (ticks + 1),
        outcome="step_limit",
        reachable=int(free.sum()),
        unreachable=0,
        first_seen=np.zeros((12, 24), dtype=int),
        goal=free,
        traversable=free,
        motion="continuous",
        tick_hz=30.0,
        poses=poses,
    )
    page = tmp_path / "walk.html"
    write_viewer(page, None, trace)
    dom, image = view(page, f"tick={ticks}&layers=trail&scale=10", tmp_path / "profile")
    assert element(dom, "errors") == ""
    assert ">30 ticks/s (real time)<" in dom and ">60 ticks/s (\u00d72)<" in dom
    left, top, scale = geometry(dom)
    xs_px = left + np.arange(5 * scale, 15 * scale)
    on_poses = image[top + 59, xs_px].astype(int)
    on_centres = image[top + 55, xs_px].astype(int)
    assert (on_centres == COLOURS["free"]).all(axis=1).all()
    # The oldest stretch fades towards the floor, as the GIF's does; it stays red over the floor's white.
    reddish = (on_poses[:, 0] > on_poses[:, 1] + 20) & (on_poses[:, 0] > on_poses[:, 2] + 20)
    assert reddish.all()


def test_cell_readout_gives_a_cells_worst_gap_and_idleness_now(pages: Path, tmp_path: Path) -> None:
    """#cell=COL,ROW (or the pointer) reads out the cell's worst gap from patrol.json and its idleness
    at the current lap tick as replayed from the patrol's views."""
    from guardsim.patrol import read_patrol, seen_timeline
    from guardsim.scene import Scene
    from guardsim.vision.table import view_table

    page = pages / "p" / "patrol.html"
    patrol_json = json.loads((pages / "p" / "patrol.json").read_text())
    period = patrol_json["period"]
    scene = Scene.from_level(load_level(SQUARE))
    patrol = read_patrol(pages / "p" / "patrol.json", scene.grid)
    seen = seen_timeline(view_table(scene.grid, scene.vision()), patrol.states, scene.grid.size)
    rows, cols = patrol_json["shape"]
    # Lap ticks early, mid and late in whatever period the patrol has (it follows tour's walk).
    for k, (col, row) in ((17, (30, 40)), (period // 2, (5, 55)), (period - 10, (50, 8))):
        idle = _steady_idleness(seen, k).reshape(rows, cols)[row, col]
        dom = dump(page, f"tick={2 * period + k}&cell={col},{row}", tmp_path / "profile")
        worst = patrol_json["idleness"][row][col]
        assert (
            element(dom, "cell-readout")
            == f"{col + 0.5:g},{row + 0.5:g} (cell [{col}, {row}]): worst gap {worst} ticks \u00b7 idle now {idle} ticks"
        )


# --- Sneak pages under the detection model: meters, the intruder's state, the peak, exposure, time to
# detection, safe spots ---

#: Slow detection past the corridor post, so the intruder goes unseen, in view, suspicious, detected.
SLOW_DETECTION = ["--detect-near", "1", "--detect-far", "2", "--suspicious", "0.6"]


@pytest.fixture(scope="module")
def detection_page(tmp_path_factory) -> tuple[Path, dict]:
    """`sneak --html` past the corridor post with slow detection and two safe spots (one never seen,
    one in the post's view): the page and its sneak.json."""
    from tests.common import write_level

    folder = tmp_path_factory.mktemp("detection-page")
    level = write_level(folder, TWO_ROOMS, "corridor.json")
    (folder / "post.json").write_text(json.dumps(CORRIDOR_POST))
    args = ["--from", "0.5,0.5", "--to", "10.5,2.5", "--out", str(folder / "c"), "--html", *SLOW_DETECTION]
    args += ["--safe", "0.5,2.5", "--safe", "6.5,1.5"]
    result = CliRunner().invoke(main, ["sneak", str(level), "--patrol", str(folder / "post.json"), *args])
    assert result.exit_code == 0 and "caught" in result.output, result.output
    return folder / "c" / "sneak.html", json.loads((folder / "c" / "sneak.json").read_text())


def meter_colour(level: float, suspicious: float, colours: dict) -> tuple[int, int, int]:
    """A meter bar's fill colour: red full, orange from the suspicious level, the walls' grey below."""
    name = "detected" if level >= 1 else "suspicious" if level >= suspicious else "in view"
    return tuple(colours[name])  # type: ignore[return-value]


@pytest.mark.slow
def test_sneak_page_shows_each_guards_meter_and_the_intruders_state(detection_page, tmp_path: Path) -> None:
    """At ticks unseen, in view, suspicious, detected and draining: a bar over the post, framed in the
    outline colour, is filled from the left by sneak.json's ``awareness`` at that tick (in the colour of
    its level) and white beyond; the state beside the readout is the one sneak.json's meters give (shown
    in the state's colour, with the highest meter); once the intruder has arrived the bar is gone."""
    from guardsim.detection import intruder_state

    page, sneak = detection_page
    data = page_data_of(page)
    intruder = data["intruder"]
    awareness = np.asarray(sneak["awareness"])
    assert np.abs(decoded_f4(intruder["meters"]) - awareness.ravel()).max() < 1e-6
    in_view = np.frombuffer(base64.b64decode(intruder["in_view"]), dtype=np.uint8) == 1
    cols = data["cols"]
    guard_path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")
    states = [
        intruder_state(
            list(awareness[t]), bool(in_view[t]), 0.6, sneak["detected_at"] is not None and t >= sneak["detected_at"]
        )
        for t in range(len(awareness))
    ]
    assert {"unseen", "in view", "suspicious", "detected"} <= set(states)
    wanted = {states.index(name) for name in ("unseen", "in view", "suspicious", "detected")}
    ticks = sorted(wanted | {len(awareness) - 2})
    scale = 40
    radius = max(7, 0.45 * scale)
    half, height = round(radius) + 1, max(5, round(0.6 * radius))
    for step in ticks:
        tick = intruder["start"] + step
        dom, image = view(page, f"tick={tick}&layers=meters&scale={scale}", tmp_path / "profile")
        assert element(dom, "errors") == ""
        found = re.search(
            r'id="intruder-state" data-state="([^"]+)" style="background: rgb\((\d+), (\d+), (\d+)\)', dom
        )
        assert found is not None
        assert found.group(1) == states[step]
        assert tuple(int(found.group(k)) for k in (2, 3, 4)) == tuple(intruder["state_colours"][states[step]])
        assert element(dom, "intruder-state") == f"{states[step]} \u00b7 awareness {awareness[step].max():.2f}"
        left, top, _ = geometry(dom)
        cell = int(guard_path[tick % len(guard_path)])
        x, y = left + (cell % cols + 0.5) * scale, top + (cell // cols + 0.5) * scale
        x0, y0 = round(x) - half, round(y - radius) - 4 - height
        outline = tuple(int(data["colours"]["outline"][i : i + 2], 16) for i in (1, 3, 5))
        assert tuple(image[y0, x0 + half]) == outline and tuple(image[y0 + height // 2, x0]) == outline
        inside = 2 * half - 2
        row = image[y0 + height // 2, x0 + 1 : x0 + 1 + inside].astype(int)
        level = float(awareness[step, 0])
        filled = round(level * inside)
        assert (row[:filled] == meter_colour(level, 0.6, intruder["state_colours"])).all(), step
        assert (row[filled:] == 255).all(), step
    # Past the arrival no bar is drawn: the bar's frame is floor or cone, not the outline colour.
    end = intruder["start"] + len(awareness)
    dom, image = view(page, f"tick={end}&layers=meters&scale={scale}", tmp_path / "profile")
    assert readout_tick(dom) == end
    assert element(dom, "intruder-state") == ""
    assert tuple(image[y0, x0 + half]) != outline


def decoded_f4(text: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(text), dtype="<f4").astype(float)


def test_sneak_timeline_marks_the_peak_awareness_and_the_detection(detection_page, tmp_path: Path) -> None:
    """The timeline marks the first tick of the highest meter in sneak.json's ``awareness`` and its
    ``detected_at``, named; a page whose meters never rise (Square, unseen) marks no peak."""
    page, sneak = detection_page
    data = page_data_of(page)
    awareness = np.asarray(sneak["awareness"])
    peak = int(np.argmax(awareness.max(axis=1)))
    start = data["intruder"]["start"]
    dom = dump(page, "tick=0", tmp_path / "profile")
    named = dict(re.findall(r'<option value="(\d+)">([^<]+)</option>', timeline_marks(dom)))
    assert named[str(start + peak)].startswith(f"peak awareness {awareness.max():.2f}")
    assert "detected" in named[str(start + sneak["detected_at"])].split(", ")
    assert len(named) == len({peak, sneak["detected_at"]})


def test_square_sneak_page_marks_no_peak(pages: Path, tmp_path: Path) -> None:
    page = pages / "s" / "sneak.html"
    dom = dump(page, "tick=0", tmp_path / "profile")
    assert element(dom, "errors") == ""
    assert not re.findall(r'<option value="\d+">[^<]+</option>', timeline_marks(dom))


def heat_layer_check(
    page: Path, sneak: dict, key: str, page_key: str, layer: str, tmp_path: Path
) -> tuple[np.ndarray, np.ndarray]:
    """With the layer ``layer`` alone: the page's ``page_key`` equals sneak.json's ``key``; every drawn cell (away
    from the guard) has the ramp colour of its value over the colour bar's range, which the bar shows at
    that value; cells with no value are floor or wall. Returns the values and the never cells."""
    data = page_data_of(page)
    info = data[page_key]
    rows, cols = data["rows"], data["cols"]
    values = decoded_f4(info["values"]).reshape(rows, cols)
    never = np.frombuffer(base64.b64decode(info["never"]), dtype=np.uint8).reshape(rows, cols) == 1
    expected = np.array([[np.nan if v is None else v for v in row] for row in sneak[key]], dtype=float)
    drawn = values >= 0
    assert (np.isfinite(expected) == drawn).all()
    assert np.abs(values[drawn] - expected[drawn]).max() < 1e-6
    dom, image = view(page, f"tick=0&layers={layer}&scale=8", tmp_path / "profile")
    assert element(dom, "errors") == ""
    assert element(dom, "bar-label") == info["label"] and element(dom, "bar-unit") == info["unit"]
    top_value = info["max"]
    path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")
    guard = (int(path[0] % cols), int(path[0] // cols))
    rr, cc = np.nonzero(drawn)
    cells = np.stack([cc, rr], axis=1)
    cells = cells[away_from(cells, guard)]
    pixels = cell_pixels(image, dom, cells)
    colours = np.array([rgb_ramp(data["ramp"], float(values[r, c]) / top_value) for c, r in cells])
    assert len(cells) > 100 and (pixels == colours).all()
    assert len(np.unique(colours, axis=0)) > 5
    bar_left = int(re.search(r'data-bar-left="(\d+)"', dom).group(1))  # type: ignore[union-attr]
    bar_top = int(re.search(r'data-bar-top="(\d+)"', dom).group(1))  # type: ignore[union-attr]
    for c, r in cells[:: max(1, len(cells) // 40)]:
        bar = image[bar_top + 8, bar_left + 1 + round(float(values[r, c]) / top_value * 255)].astype(int)
        assert np.abs(bar - np.array(rgb_ramp(data["ramp"], float(values[r, c]) / top_value))).max() <= 3
    rr, cc = np.nonzero(never)
    if len(rr):
        black = cell_pixels(image, dom, np.stack([cc, rr], axis=1)[away_from(np.stack([cc, rr], axis=1), guard)])
        assert (black == 0).all()
    rr, cc = np.nonzero(~drawn & ~never)
    holes = np.stack([cc, rr], axis=1)
    hole_pixels = cell_pixels(image, dom, holes[away_from(holes, guard)])
    assert ((hole_pixels == COLOURS["free"]).all(axis=1) | (hole_pixels == COLOURS["wall"]).all(axis=1)).all()
    return values, never


def test_exposure_layer_has_the_colour_bars_colours(pages: Path, tmp_path: Path) -> None:
    """Square's sneak page, exposure alone: each floor cell is the ramp colour of sneak.json's
    ``exposure`` on a bar from 0 to 1 (a fraction of the lap); walls are holes."""
    page = pages / "s" / "sneak.html"
    sneak = json.loads((pages / "s" / "sneak.json").read_text())
    values, never = heat_layer_check(page, sneak, "exposure", "exposure", "exposure", tmp_path)
    assert page_data_of(page)["exposure"]["max"] == 1 and not never.any()
    assert 0 < values.max() <= 1


def test_time_to_detection_layer_marks_never_detected_cells_black(pages: Path, tmp_path: Path) -> None:
    """Square's sneak page, time to detection alone: each cell sneak.json gives a number is the ramp
    colour of it over the bar's range (0 to the largest); floor cells it gives null (never detected) are
    black, and the cell readout says so."""
    page = pages / "s" / "sneak.html"
    sneak = json.loads((pages / "s" / "sneak.json").read_text())
    data = page_data_of(page)
    sneak_never = np.array(
        [
            [lasts is None and seen is not None for lasts, seen in zip(row, exposure_row)]
            for row, exposure_row in zip(sneak["time_to_detection"], sneak["exposure"])
        ]
    )
    values, never = heat_layer_check(page, sneak, "time_to_detection", "detection_time", "detection-time", tmp_path)
    assert (never == sneak_never).all() and never.any()
    assert data["detection_time"]["max"] == np.nanmax(np.where(values >= 0, values, np.nan))
    row, col = (int(v) for v in np.argwhere(never)[0])
    dom = dump(page, f"tick=0&cell={col},{row}", tmp_path / "profile")
    assert "time to detection never detected" in element(dom, "cell-readout")


def test_safe_spots_are_outlined_green_where_they_hold(detection_page, tmp_path: Path) -> None:
    """--safe 0.5,2.5 (never seen: holds) and --safe 6.5,1.5 (in the post's view: broken): each cell is
    ringed just outside its edges in the colour of its verdict, its centre is not, and its readout says
    why."""
    page, sneak = detection_page
    data = page_data_of(page)
    scale = 40
    dom, image = view(page, f"tick=0&layers=safe&scale={scale}", tmp_path / "profile")
    assert element(dom, "errors") == ""
    left, top, _ = geometry(dom)
    for col, row in ((0, 2), (6, 1)):
        holds = sneak["exposure"][row][col] == 0
        ring = tuple(data["safe_colours"]["holds" if holds else "broken"])
        x0, y0 = left + col * scale, top + row * scale
        assert tuple(image[y0 - 1, x0 + scale // 2]) == ring
        assert tuple(image[y0 + scale // 2, x0 + scale]) == ring
        assert tuple(image[y0 + scale // 2, x0 + scale // 2]) != ring
        cell = element(dump(page, f"tick=0&cell={col},{row}", tmp_path / "profile"), "cell-readout")
        assert cell.endswith("safe spot holds: never seen" if holds else "safe spot broken: seen 100% of the lap")
    assert {spot["holds"] for spot in data["safe"]} == {True, False}
