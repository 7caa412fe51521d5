"""Faults around the inputs: special files as outputs, a filesystem that fills up, a killed bench.

Each ends in a clear error (one line, exit 2), with no partial output and, for bench, nothing lost on
resume. These run real processes and, where the machine allows it (root), a real device node and a
real full filesystem (a 256 KB tmpfs); otherwise they are skipped, not faked.
"""

from __future__ import annotations

import contextlib
import os
import signal
import stat
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from guardsim.experiment import read_results
from tests.common import REPO, SQUARE_WITH_HOLE, guardsim_command, write_level

SQUARE = REPO / "levels" / "square.json"


def real_run(*args: str | Path, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*guardsim_command(), *map(str, args)], capture_output=True, text=True, timeout=timeout, check=False
    )


def test_trace_to_a_character_device_is_written_in_place(tmp_path: Path) -> None:
    """`play --trace NODE` with NODE a character device (a private /dev/null) writes into the device and
    leaves it a device: the atomic rename must never swap it for a regular file."""
    node = tmp_path / "null"
    try:
        os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    except PermissionError:
        pytest.skip("making a device node needs root")
    level = write_level(tmp_path, SQUARE_WITH_HOLE)
    result = real_run("play", level, "--trace", node)
    assert result.returncode == 0, result.stderr
    assert stat.S_ISCHR(node.stat().st_mode)
    assert {path.name for path in tmp_path.iterdir()} == {"null", "level.json"}


def test_output_to_a_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    """An output that is a FIFO would block the command (no reader) or be replaced: one line, exit 2."""
    fifo = tmp_path / "out.json"
    os.mkfifo(fifo)
    result = real_run("play", write_level(tmp_path, SQUARE_WITH_HOLE), "--trace", fifo, timeout=60)
    assert result.returncode == 2
    [line] = result.stderr.splitlines()
    assert line.startswith(f"guardsim: error: {fifo}: is a FIFO")
    assert stat.S_ISFIFO(fifo.stat().st_mode)


@contextlib.contextmanager
def small_filesystem(folder: Path, size: str = "256k") -> Iterator[Path]:
    """A tmpfs of ``size`` mounted at ``folder`` for the block (root only; skips otherwise)."""
    folder.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.decode().strip()}")
    try:
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], check=False)


def fill(folder: Path, leave: int) -> Path:
    """Fill the filesystem of ``folder`` until about ``leave`` bytes are free; returns the filler file."""
    filler = folder / "filler"
    free = os.statvfs(folder).f_bavail * os.statvfs(folder).f_frsize
    filler.write_bytes(b"\0" * max(0, free - leave))
    return filler


def test_bench_on_a_full_filesystem_is_one_line_and_resume_recovers(tmp_path: Path) -> None:
    """bench on a filesystem that fills up mid-run: exit 2 with one error line (no traceback), no partial
    row in results.csv; once there is room, the same command resumes and every episode is there once."""
    disk = tmp_path / "disk"
    with small_filesystem(disk):
        out = disk / "out"
        filler = fill(disk, leave=6000)
        command = (SQUARE, "--episodes", "60", "--workers", "1", "--no-bounds", "--out", out)
        full = real_run("bench", *command)
        assert full.returncode == 2, full.stderr
        assert "Traceback" not in full.stderr
        errors = [line for line in full.stderr.splitlines() if line.startswith("guardsim: error:")]
        assert len(errors) == 1 and "No space left on device" in errors[0], full.stderr
        results = out / "results.csv"
        if results.exists():
            assert results.read_bytes().endswith(b"\n") or results.stat().st_size == 0
        filler.unlink()
        resumed = real_run("bench", *command)
        assert resumed.returncode == 0, resumed.stderr
        records = read_results(results)
        assert sorted(record.episode for record in records) == list(range(60))


def test_regress_update_on_a_full_filesystem_leaves_no_partial_file(tmp_path: Path) -> None:
    """Writing references on a full filesystem: one error line, and no hidden temporary left behind."""
    disk = tmp_path / "disk"
    with small_filesystem(disk):
        fill(disk, leave=4000)
        level = write_level(tmp_path, SQUARE_WITH_HOLE, "room.json")
        result = real_run("regress", level, "--renders", disk / "renders", "--update")
        assert result.returncode == 2
        [line] = result.stderr.splitlines()
        assert "No space left on device" in line
        assert not [path for path in disk.rglob(".*") if ".part" in path.name]


def _session_processes(session: int) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == session and fields[0] != "Z":
            found.append(int(entry.name))
    return found


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_sigkill_of_bench_leaves_no_worker_running(tmp_path: Path) -> None:
    """SIGKILL of bench's main process: its pool workers (and the fork server) exit within seconds."""
    process = subprocess.Popen(
        [*guardsim_command(), "bench", str(SQUARE), "--episodes", "400", "--workers", "2", "--no-bounds",
         "--out", str(tmp_path / "out")],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 90
        while not (tmp_path / "out" / "results.csv").exists() or len(_session_processes(process.pid)) < 3:
            assert time.monotonic() < deadline, "bench never started its workers"
            time.sleep(0.2)
        os.kill(process.pid, signal.SIGKILL)
        deadline = time.monotonic() + 10
        while [pid for pid in _session_processes(process.pid) if pid != process.pid]:
            assert time.monotonic() < deadline, f"still running: {_session_processes(process.pid)}"
            time.sleep(0.2)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()
