"""Nothing sits silent for more than 2 s: ``play``'s stage line, and the step lines of ``report``, ``diff``
and ``watch``'s analyses, which say again what they are doing while a step runs on (a big map's scene,
patrol or sneak check takes seconds)."""

from __future__ import annotations

import io
import json
import time
from pathlib import Path

import pytest

from guardsim.cli import design_common, progress
from guardsim.cli.design_common import StepLines
from tests.common import SQUARE_WITH_HOLE, run


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.fixture
def loud(monkeypatch: pytest.MonkeyPatch) -> None:
    """Progress on (the suite turns it off), with no quiet start and a tick as often as it may come."""
    monkeypatch.setenv("GUARDSIM_PROGRESS", "1")
    monkeypatch.setattr(progress, "QUIET_SECONDS", 0.0)
    monkeypatch.setattr(progress, "PLAIN_EVERY_SECONDS", 0.0)
    monkeypatch.setattr(design_common, "PLAIN_EVERY_SECONDS", 0.0)


def _level(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.json"
    path.write_text(json.dumps(SQUARE_WITH_HOLE), encoding="utf-8")
    return path


def test_a_long_step_is_said_again_with_its_time(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GUARDSIM_PROGRESS", "1")
    stream = io.StringIO()
    with StepLines(stream, is_step=lambda line: line.startswith("analysing: "), every=0.05) as steps:
        steps("analysing: the patrol")
        time.sleep(0.3)
        steps("analysis 1: 0.30 s")  # a result: the step is over
        after = stream.getvalue()
        time.sleep(0.2)
    lines = stream.getvalue().splitlines()
    assert lines[0] == "guardsim: analysing: the patrol"
    assert "guardsim: analysing: the patrol (0s)" in lines[1:-1] and lines[-1] == "guardsim: analysis 1: 0.30 s"
    assert stream.getvalue() == after


def test_a_step_redrawn_in_place_ends_its_line_before_the_next(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GUARDSIM_PROGRESS", "1")
    stream = _Terminal()
    with StepLines(stream, every=0.05) as steps:
        steps("planning the loop patrol")
        time.sleep(0.2)
        steps("sneak check")
    text = stream.getvalue()
    assert "\rguardsim: planning the loop patrol (0s)" in text
    assert text.endswith("\nguardsim: sneak check\n")


def test_no_tick_with_progress_off(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GUARDSIM_PROGRESS", "0")
    stream = io.StringIO()
    with StepLines(stream, every=0.01) as steps:
        steps("building the scene")
        time.sleep(0.1)
    assert stream.getvalue() == "guardsim: building the scene\n"


@pytest.mark.usefixtures("loud")
@pytest.mark.parametrize("command", ["report", "diff"])
def test_design_commands_tick_their_steps(tmp_path: Path, command: str, monkeypatch: pytest.MonkeyPatch) -> None:
    # On a tiny level every step ends within the clock's 10 ms: each is made to last 50 ms, so the clock
    # has a step to say again however fast the machine.
    said = StepLines.__call__

    def said_slowly(self: StepLines, line: str) -> None:
        said(self, line)
        time.sleep(0.05)

    monkeypatch.setattr(StepLines, "__call__", said_slowly)
    level = _level(tmp_path)
    levels = [level] if command == "report" else [level, level]
    result = run(command, *levels, "--from", "0.5,0.5", "--to", "5.5,5.5")
    assert result.exit_code == 0, result.output
    assert any(line.endswith("(0s)") and line.startswith("guardsim: ") for line in result.stderr.splitlines())


@pytest.mark.usefixtures("loud")
def test_play_keeps_a_stage_line(tmp_path: Path) -> None:
    result = run("play", _level(tmp_path), "--gif", tmp_path / "p.gif", "--trace", tmp_path / "p.json")
    assert result.exit_code == 0, result.output
    stages = {line.rsplit(" (", 1)[0] for line in result.stderr.splitlines()}
    assert {"guardsim: play: walking the episode", "guardsim: play: writing the GIF"} <= stages, result.stderr


def test_watch_ends_each_analysis_with_a_line(tmp_path: Path) -> None:
    # The report's last step ("counting the distinct ways through") was followed by nothing, so its line
    # would have ticked on while the page sat idle.
    import asyncio

    from guardsim.viewer.serve.app import LiveAnalyser

    lines: list[str] = []
    analyser = LiveAnalyser(
        str(_level(tmp_path)), patrol=None, guards=1, pairs=[((0.5, 0.5), (5.5, 5.5))], echo=lines.append
    )
    asyncio.run(analyser.run())
    steps = [k for k, line in enumerate(lines) if line.startswith("analysing: ")]
    assert steps and lines[-1].startswith("report 1: ") and steps[-1] < len(lines) - 1, lines


@pytest.mark.usefixtures("loud")
def test_alert_says_how_many_episodes_are_done_off_a_terminal(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Off a terminal the episodes' count (redrawn in place on one) is a stage line: a sneaking intruder's
    episode on a big map plans for seconds."""
    import guardsim.cli.alert as alert_command

    monkeypatch.setattr(alert_command, "PLAIN_EVERY_SECONDS", 0.0)
    level = _level(tmp_path)
    patrol = run("patrol", level, "--out", tmp_path / "p")
    assert patrol.exit_code == 0, patrol.output
    result = run(
        "alert", level, "--patrol", tmp_path / "p" / "patrol.json", "--episodes", "3", "--workers", "1",
        "--out", tmp_path / "a",
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    counts = {line.rsplit(" (", 1)[0] for line in result.stderr.splitlines()}
    assert {f"guardsim: alert: running the episodes {done}/3" for done in (0, 3)} <= counts, result.stderr
    assert "\r" not in result.stderr
