"""The HTML viewer's page, without a browser: self-contained, small, carrying the trace exactly; the
`play --html` and `view` commands and their errors. The page in a real browser: tests/test_browser.py."""

from __future__ import annotations

import base64
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from guardsim import load_level
from guardsim.cli import main
from guardsim.errors import GuardsimError
from guardsim.trace import Trace
from guardsim.viewer import build_page, page_data
from guardsim.viewer.walls import rings_from_grid
from tests.common import write_level
from tests.pages import SQUARE, big_trace, page_json, patrol_pages


@pytest.fixture(scope="module")
def square_trace(tmp_path_factory) -> tuple[Path, Trace]:
    folder = tmp_path_factory.mktemp("viewer")
    out = folder / "trace.json"
    result = CliRunner().invoke(main, ["play", str(SQUARE), "--trace", str(out), "--html", str(folder / "p.html")])
    assert result.exit_code == 0, result.output
    return folder, Trace.from_data(json.loads(out.read_text()))





def test_page_is_self_contained(square_trace) -> None:
    """No external scripts, styles, images or fetches: the page works from disk, offline."""
    folder, _ = square_trace
    page = (folder / "p.html").read_text()
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "<script src" not in page and "<link" not in page
    assert "fetch(" not in page and "XMLHttpRequest" not in page and "import(" not in page
    assert 'id="tick-readout"' in page


def test_page_carries_the_trace_exactly(square_trace) -> None:
    """First-seen ticks, cell kinds, path and headings decode to the trace's; each readout figure is
    the trace's unseen_percent with one decimal, as Python formats it."""
    _, trace = square_trace
    data = page_json(build_page(load_level(SQUARE), trace))
    rows, cols = trace.shape
    first_seen = np.frombuffer(base64.b64decode(data["first_seen"]), dtype="<i4").reshape(rows, cols)
    assert (first_seen == trace.first_seen).all()
    kinds = np.frombuffer(base64.b64decode(data["kinds"]), dtype=np.uint8).reshape(rows, cols)
    assert ((kinds == 1) == trace.goal).all()
    path = np.frombuffer(base64.b64decode(data["paths"][0]), dtype="<i4")
    assert [(int(i % cols), int(i // cols)) for i in path] == list(trace.path)
    assert list(np.frombuffer(base64.b64decode(data["headings"][0]), dtype=np.uint8)) == list(trace.headings)
    assert data["unseen_text"] == [f"{p:.1f}" for p in trace.unseen_percent]
    assert (data["view_range"], data["fov_degrees"]) == (trace.view_range, trace.fov_degrees)


def test_readout_text_rounds_ties_as_python_does() -> None:
    """12.25 is '12.2' in Python (JavaScript's toFixed gives '12.3'); the page sends Python's text."""
    trace = big_trace(8, 8, 3)
    fields = {name: getattr(trace, name) for name in trace.__dataclass_fields__}
    tied = Trace(**{**fields, "unseen_percent": (12.25, 0.05, 99.95, 100.0)})
    text = page_data(None, tied)["unseen_text"]
    assert text == [f"{v:.1f}" for v in (12.25, 0.05, 99.95, 100.0)]


@pytest.mark.slow
def test_page_for_a_512_by_512_episode_is_under_5_mb() -> None:
    """A 512 x 512 grid and a 30,000-tick walk by two guards fit in well under 5 MB."""
    page = build_page(None, big_trace(guards=2))
    assert len(page.encode()) < 5_000_000


def test_field_layer_is_carried_within_its_budget() -> None:
    """A recorded planner field becomes snapshots (every k-th tick) inside the byte budget."""
    trace = big_trace(64, 64, 400)
    field = np.arange(401 * 64 * 64, dtype=np.float64).reshape(401, 64, 64) % 97
    field[:, 0, 0] = np.inf
    data = page_data(None, trace, field=field)["field"]
    assert data["ticks"][0] == 0 and len(data["ticks"]) * 64 * 64 * 4 <= 1_500_000
    values = np.frombuffer(base64.b64decode(data["data"]), dtype="<f4").reshape(len(data["ticks"]), 64, 64)
    assert values[0, 0, 0] == -1 and values[1, 3, 3] == field[data["ticks"][1], 3, 3]
    with pytest.raises(GuardsimError, match="expected"):
        page_data(None, trace, field=field[:, :10])


def test_walls_from_the_grid_outline_the_blocked_cells(square_trace) -> None:
    """Without the level, the walls drawn are the grid's blocked cells: the box and the pillar (inflated
    by the cells the guard could not stand on)."""
    _, trace = square_trace
    rings = rings_from_grid(trace)
    assert rings[0] == [(0.0, 0.0), (60.0, 0.0), (60.0, 60.0), (0.0, 60.0)]
    xs = [x for ring in rings[1:] for x, _ in ring]
    assert min(xs) <= 20 and max(xs) >= 30


def test_view_writes_the_page_from_a_saved_trace(square_trace, tmp_path: Path) -> None:
    """`guardsim view TRACE --html OUT` writes the page; with --level, the level's own walls."""
    folder, trace = square_trace
    out = tmp_path / "view.html"
    result = CliRunner().invoke(main, ["view", str(folder / "trace.json"), "--html", str(out)])
    assert result.exit_code == 0, result.output
    assert "walls rebuilt from the trace's grid" in result.output
    assert page_json(out.read_text())["walls_from_grid"] is True
    result = CliRunner().invoke(main, ["view", str(folder / "trace.json"), "--html", str(out), "--level", str(SQUARE)])
    assert result.exit_code == 0, result.output
    data = page_json(out.read_text())
    assert data["walls_from_grid"] is False and len(data["rings"]) == 2
    assert data["unseen_text"] == [f"{p:.1f}" for p in trace.unseen_percent]


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("{not json", "trace.json"),
        ('{"level": 3}', "not a guardsim trace"),
    ],
    ids=["broken-json", "not-a-trace"],
)
def test_view_refuses_bad_traces_in_one_line(tmp_path: Path, content: str, message: str) -> None:
    """A broken or foreign trace file is one error line naming it, exit 2, no traceback."""
    path = tmp_path / "trace.json"
    path.write_text(content)
    result = CliRunner().invoke(main, ["view", str(path), "--html", str(tmp_path / "out.html")])
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1 and message in result.stderr
    assert not (tmp_path / "out.html").exists()


def test_view_refuses_a_level_the_trace_was_not_played_on(square_trace, tmp_path: Path) -> None:
    """--level naming another level is one error line, exit 2."""
    folder, _ = square_trace
    other = write_level(tmp_path, {"name": "other", "outer": [[0, 0], [4, 0], [4, 4], [0, 4]]})
    result = CliRunner().invoke(
        main, ["view", str(folder / "trace.json"), "--html", str(tmp_path / "o.html"), "--level", str(other)]
    )
    assert result.exit_code == 2
    assert "is not the one" in result.stderr and result.stderr.count("\n") == 1


def test_view_runs_as_a_real_process(square_trace, tmp_path: Path) -> None:
    """The installed command, in its own process, writes the page."""
    folder, _ = square_trace
    out = tmp_path / "sub.html"
    command = [sys.executable, "-c", "from guardsim.cli import main; main()", "view", str(folder / "trace.json")]
    done = subprocess.run([*command, "--html", str(out)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert out.read_text().startswith("<!DOCTYPE html>")


# --- Patrol and sneak pages (guardsim.viewer.layers, guardsim.viewer.patrols) ---







@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> Path:
    return patrol_pages(tmp_path_factory.mktemp("pages"))


def decoded(text: str, dtype: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(text), dtype=np.dtype(dtype).newbyteorder("<"))


def test_seen_runs_give_each_cells_worst_idleness_as_brute_force() -> None:
    """The page's run-length views decode to the seen ticks, and the largest idleness they give equals
    the longest unseen run over three laps walked tick by tick (random laps, cells never seen too)."""
    from guardsim.viewer.layers import _seen_runs, _worst_idleness

    rng = np.random.default_rng(1)
    for _ in range(300):
        period, cells = int(rng.integers(1, 12)), int(rng.integers(1, 6))
        seen = rng.random((period, cells)) < rng.random()
        offsets, starts, ends = _seen_runs(seen)
        worst = _worst_idleness(offsets, starts, ends, period)
        for cell in range(cells):
            rebuilt = np.zeros(period, dtype=bool)
            for run in range(offsets[cell], offsets[cell + 1]):
                rebuilt[starts[run] : ends[run] + 1] = True
            assert (rebuilt == seen[:, cell]).all()
            best, last = -1 if not seen[:, cell].any() else 0, None
            for tick, value in enumerate(np.tile(seen[:, cell], 3)):
                if value:
                    last = tick
                elif last is not None and tick >= period:
                    best = max(best, tick - last)
            assert worst[cell] == best


def test_patrol_page_carries_idleness_laps_and_routes(pages: Path) -> None:
    """patrol.html holds patrol.json's idleness grid (nulls as holes), the lap, each guard's loop as the
    route.json waypoints, and an animated layer whose largest idleness is the patrol's worst."""
    patrol = json.loads((pages / "p" / "patrol.json").read_text())
    route = json.loads((pages / "p" / "route.json").read_text())
    data = page_json((pages / "p" / "patrol.html").read_text())
    rows, cols = patrol["shape"]
    values = decoded(data["idleness"]["values"], "f4").reshape(rows, cols)
    expected = np.array([[-1 if v is None else v for v in row] for row in patrol["idleness"]], dtype=float)
    assert (values == expected).all()
    assert (values < 0).any() and (values >= 0).any()
    assert data["idleness"]["unit"] == "ticks" and data["idleness"]["max"] == patrol["worst_idleness"]
    assert not decoded(data["idleness"]["never"], "u1").any()
    assert data["laps"]["period"] == patrol["period"] and data["laps"]["laps"] >= 2
    assert data["laps"]["max"] == patrol["worst_idleness"]
    assert data["routes"] == [[[w["x"], w["y"]] for w in guard["waypoints"]] for guard in route["guards"]]
    assert all(loop[0] == loop[-1] for loop in data["routes"])
    assert "intruder" not in data and data["default_layers"] == ["idleness", "route", "trail", "cone"]
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", (pages / "p" / "patrol.html").read_text())


def test_sneak_page_draws_the_intruder_apart_from_the_guards(pages: Path) -> None:
    """sneak.html keeps the patrol's guards only; the intruder travels as its own path from its start
    tick, with from/to points; in view nowhere on an unseen path, and for exactly the closest call's
    ticks in view past the post. Its heat map is the hiding spots, never-seen cells marked."""
    for folder, guards in (("s", 1), ("c", 1)):
        answer = json.loads((pages / folder / "sneak.json").read_text())
        data = page_json((pages / folder / "sneak.html").read_text())
        cols = data["cols"]
        assert len(data["paths"]) == guards
        intruder = data["intruder"]
        path = decoded(intruder["path"], "i4")
        assert [[int(i % cols), int(i // cols)] for i in path] == answer["path"]
        assert intruder["start"] == answer["start_tick"]
        assert (intruder["from"], intruder["to"]) == (answer["from"], answer["to"])
        in_view = decoded(intruder["in_view"], "u1")
        assert int(in_view.sum()) == answer["ticks_in_view"] == intruder["ticks_in_view"]
        assert data["laps"]["period"] == answer["period"]
        assert data["laps"]["laps"] * answer["period"] >= answer["start_tick"] + answer["ticks"]
        hiding = np.array([[-1 if v is None else v for v in row] for row in answer["longest_unseen"]], dtype=float)
        never = decoded(data["idleness"]["never"], "u1").reshape(hiding.shape).astype(bool)
        assert int(never.sum()) == answer["never_seen_cells"]
        values = decoded(data["idleness"]["values"], "f4").reshape(hiding.shape)
        assert (values[~never] == hiding[~never]).all()
    assert decoded(page_json((pages / "c" / "sneak.html").read_text())["intruder"]["in_view"], "u1").any()


def test_layers_that_do_not_fit_the_trace_are_refused(square_trace) -> None:
    """A layer of the wrong shape is a library error naming what is wrong, not a broken page."""
    from guardsim.viewer.layers import IdlenessMap, Intruder, LapViews, Overlays

    _, trace = square_trace
    rows, cols = trace.shape
    cases = [
        (Overlays(idleness=IdlenessMap(np.zeros((rows, cols + 1)))), "idleness layer has shape"),
        (Overlays(laps=LapViews(10, np.zeros((9, rows * cols), dtype=bool))), "lap's views have shape"),
        (
            Overlays(laps=LapViews(trace.steps + 1, np.zeros((trace.steps + 1, rows * cols), dtype=bool))),
            "less than one lap",
        ),
        (Overlays(intruder=Intruder([(cols, 0)], 0)), "leaves the trace's grid"),
        (Overlays(intruder=Intruder([(0, 0), (1, 0)], 0, in_view=[True])), "1 in-view flags for 2 ticks"),
    ]
    for overlays, message in cases:
        with pytest.raises(GuardsimError, match=message):
            page_data(None, trace, overlays=overlays)
