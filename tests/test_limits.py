"""Size limits through the command line: over a limit is one error line (exit 2) naming the option that
raises it; at the limit, the same command succeeds.

Limits: grid cells (``--max-cells``), vertices (``--max-vertices``) and file size (``--max-file-bytes``) on
every command that loads a level, and GIF frames (``--max-frames``, with ``--stride``) on ``play``.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from guardsim.render import FRAME_CEILING
from tests.common import SQUARE_WITH_HOLE, assert_one_line_error, run, write_level

#: The 6 x 6 room with a pillar at cell size 0.5: a 12 x 12 grid, 8 vertices.
LEVEL = {**SQUARE_WITH_HOLE, "cell_size": 0.5}
CELLS, VERTICES = 12 * 12, 8


def outputs(command: str, folder: Path) -> list[str]:
    """The options that make ``command`` write into ``folder``."""
    return {
        "play": ["--gif", str(folder / "out.gif")],
        "render": ["--png", str(folder / "out.png")],
        "regress": ["--renders", str(folder / "renders"), "--update"],
    }[command]


@pytest.mark.parametrize("command", ["play", "render", "regress"])
@pytest.mark.parametrize("option", ["--max-cells", "--max-vertices", "--max-file-bytes"])
def test_level_limits_refuse_with_one_line_and_can_be_raised(tmp_path: Path, command: str, option: str) -> None:
    """One below the level's size: exit 2, one line naming the file, the size and the option; at it: exit 0."""
    path = write_level(tmp_path, LEVEL)
    size = {"--max-cells": CELLS, "--max-vertices": VERTICES, "--max-file-bytes": path.stat().st_size}[option]
    refused = run(command, path, option, str(size - 1), *outputs(command, tmp_path))
    line = assert_one_line_error(refused, path)
    assert f"over the limit of {size - 1}" in line
    assert option in line
    assert not (tmp_path / "out.gif").exists() and not (tmp_path / "out.png").exists()
    accepted = run(command, path, option, str(size), *outputs(command, tmp_path))
    assert accepted.exit_code == 0, accepted.output


def test_frame_limit_refuses_with_one_line_and_can_be_raised(tmp_path: Path) -> None:
    """`--stride 1` needs one frame per tick plus the start: one fewer allowed is one line naming both
    options; exactly enough writes the GIF."""
    path = write_level(tmp_path, LEVEL)
    first = run("play", path, "--trace", tmp_path / "trace.json")
    assert first.exit_code == 0, first.output
    frames = json.loads((tmp_path / "trace.json").read_text(encoding="utf-8"))["steps"] + 1
    gif = tmp_path / "out.gif"
    refused = run("play", path, "--gif", gif, "--stride", "1", "--max-frames", str(frames - 1))
    assert refused.exit_code == 2
    [line] = refused.stderr.splitlines()
    assert line == (
        f"guardsim: error: {frames} frames at stride 1 is over the limit of {frames - 1} "
        "(raise --stride or --max-frames)"
    )
    assert not gif.exists()
    accepted = run("play", path, "--gif", gif, "--stride", "1", "--max-frames", str(frames))
    assert accepted.exit_code == 0, accepted.output
    assert gif.is_file()


def test_frame_ceiling_names_the_option(tmp_path: Path) -> None:
    """Past the hard ceiling on frames, the one line names --max-frames and the ceiling."""
    path = write_level(tmp_path, LEVEL)
    refused = run("play", path, "--gif", tmp_path / "out.gif", "--max-frames", str(FRAME_CEILING + 1))
    assert refused.exit_code == 2
    assert refused.stderr == (
        f"guardsim: error: --max-frames must be from 1 to {FRAME_CEILING} (the GIF ceiling), not {FRAME_CEILING + 1}\n"
    )


def test_cells_limit_raised_past_memory_is_one_line(tmp_path: Path) -> None:
    """A level spanning 1e15 units is refused by the default cells limit; with the limit raised past any
    machine's memory, the allocation fails and that too is one line with exit 2, not a traceback."""
    path = write_level(tmp_path, {"outer": [[0, 0], [1e15, 0], [1e15, 1e15], [0, 1e15]]}, "huge.json")
    refused = run("play", path, "--gif", tmp_path / "out.gif")
    assert "--max-cells" in assert_one_line_error(refused, path)
    unbounded = run("play", path, "--gif", tmp_path / "out.gif", "--max-cells", str(10**31))
    assert unbounded.exit_code == 2
    assert unbounded.stderr == f"guardsim: error: {path}: out of memory; lower --max-cells or --max-vertices\n"
    assert "Traceback" not in unbounded.output
