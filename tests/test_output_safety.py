"""Output safety: every file guardsim writes appears whole or not at all.

Outputs go to a hidden temporary file beside the target (``.NAME.XXXXXXXX.partSUFFIX``) that is renamed
onto it (:mod:`guardsim.files.output`). A run killed with SIGKILL cannot clean up, so it may leave that hidden
temporary file behind; it never leaves a broken target. These tests kill real ``guardsim`` processes.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import imageio.v3 as iio
import pytest

from tests.common import REPO, SQUARE_WITH_HOLE, assert_one_line_error, guardsim_command, run, write_level

#: Runs the real command line in a child that stops itself (SIGSTOP) at one audit event on the temporary
#: file of the output, so the parent can kill it at exactly that point: nothing is replaced or mocked.
PAUSING_CHILD = """
import os, signal, sys
event_wanted, marker = sys.argv[1], sys.argv[2]
def pause(event, args):
    if event == event_wanted and marker in os.fspath(args[0]) and (event != "open" or "w" in (args[1] or "")):
        os.kill(os.getpid(), signal.SIGSTOP)
sys.addaudithook(pause)
from guardsim.cli import main
main(sys.argv[3:], prog_name="guardsim")
"""


OPTIONS = {"out.gif": ("play", "--gif"), "out.json": ("play", "--trace"), "out.png": ("render", "--png")}


def old_output(folder: Path, target: str) -> bytes:
    """A valid ``target`` from a first run on a tiny level (``old.json``), to compare with after the kill."""
    level = write_level(folder, SQUARE_WITH_HOLE, "old.json")
    command, option = OPTIONS[target]
    assert run(command, level, option, folder / target).exit_code == 0
    return (folder / target).read_bytes()


def assert_old_output_intact(folder: Path, target: str, old: bytes) -> None:
    """The target still holds the old, valid output, and every other file left is a hidden temporary."""
    assert (folder / target).read_bytes() == old
    if target.endswith(".json"):
        assert (folder / target).read_text(encoding="utf-8").rstrip().endswith("}")
    else:
        assert iio.imread(folder / target, index=None).size > 0
    stray = set(os.listdir(folder)) - {"old.json", target}
    assert all(name.startswith(f".{target}.") and name.endswith(Path(target).suffix) for name in stray), stray


@pytest.mark.parametrize(
    ("target", "event"),
    [("out.gif", "open"), ("out.gif", "os.chmod"), ("out.json", "open"), ("out.png", "open")],
    ids=["gif-opened-for-writing", "gif-written-not-renamed", "trace-opened-for-writing", "png-opened-for-writing"],
)
def test_sigkill_mid_write_keeps_the_old_file(tmp_path: Path, target: str, event: str) -> None:
    """Kill -9 while the new output is being written (or written and not yet renamed): the target is the
    old valid file and the only leftover is the hidden temporary, which exists at that moment."""
    old = old_output(tmp_path, target)
    command, option = OPTIONS[target]
    child = subprocess.Popen(
        [
            sys.executable,
            "-c",
            PAUSING_CHILD,
            event,
            f".{target}.",
            command,
            str(REPO / "levels" / "square.json"),
            option,
            str(tmp_path / target),
            *(["--max-steps", "20"] if command == "play" else []),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        _, status = os.waitpid(child.pid, os.WUNTRACED)
        assert os.WIFSTOPPED(status), child.stderr.read() if child.stderr else status
        temporary = [name for name in os.listdir(tmp_path) if name.startswith(f".{target}.")]
        assert len(temporary) == 1, os.listdir(tmp_path)
    finally:
        child.kill()
        child.wait(timeout=60)
    assert child.returncode == -signal.SIGKILL
    assert_old_output_intact(tmp_path, target, old)


def test_sigkill_during_a_long_run_keeps_the_old_gif(tmp_path: Path) -> None:
    """The brief's scenario: a long `play --gif --stride 1` killed while it runs, at no chosen point."""
    old = old_output(tmp_path, "out.gif")
    child = subprocess.Popen(
        [
            *guardsim_command(),
            "play",
            str(REPO / "levels" / "king_snurre.json"),
            *("--gif", str(tmp_path / "out.gif"), "--max-frames", "2000", "--stride", "1"),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    # Kill it while the GIF is being written: once its temporary file exists, not after a guessed delay.
    temporary: list[str] = []
    for _ in range(60_000):
        temporary = [name for name in os.listdir(tmp_path) if name.startswith(".out.gif.")]
        if temporary or child.poll() is not None:
            break
        time.sleep(0.001)
    child.kill()
    child.wait(timeout=60)
    assert temporary, "the run never started writing the GIF"
    assert child.returncode == -signal.SIGKILL, "the run ended before it could be killed"
    assert_old_output_intact(tmp_path, "out.gif", old)


@pytest.mark.parametrize(
    ("command", "option", "name"),
    [("play", "--gif", "out.gif"), ("play", "--trace", "out.json"), ("render", "--png", "out.png")],
    ids=["play-gif", "play-trace", "render-png"],
)
def test_write_into_missing_folder_is_one_line(tmp_path: Path, command: str, option: str, name: str) -> None:
    """An output in a folder that does not exist: exit 2, one line naming the output and the folder."""
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    target = tmp_path / "missing" / name
    line = assert_one_line_error(run(command, level, option, target), target)
    assert f"folder {tmp_path / 'missing'} does not exist" in line
    assert not (tmp_path / "missing").exists()


def test_failed_run_leaves_the_old_output_and_no_temporary(tmp_path: Path) -> None:
    """A run that fails after the episode (too many frames) keeps the old GIF and leaves nothing behind."""
    old = old_output(tmp_path, "out.gif")
    level = tmp_path / "old.json"
    result = run("play", level, "--gif", tmp_path / "out.gif", "--stride", "1", "--max-frames", "2")
    assert result.exit_code == 2
    assert_old_output_intact(tmp_path, "out.gif", old)
    assert not [name for name in os.listdir(tmp_path) if name.startswith(".")]
