"""The results folder of a batch: ``run.json`` (the options), ``results.csv`` (one row per episode).

Rows are appended and flushed as episodes finish, so a killed run loses at most the line it was writing;
:func:`read_results` drops such a half-written last line so that its episode runs again. A finished run
rewrites the CSV atomically in :attr:`EpisodeRecord.sort_key` order, so the file does not depend on the
order in which workers finished.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import stat
from collections.abc import Collection, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TextIO

from guardsim.errors import OutputError
from guardsim.experiment.episodes import CSV_COLUMNS, EpisodeRecord
from guardsim.files.output import write_text_atomic
from guardsim.files.reading import display_path, excerpt, read_json_file, read_limited_bytes

__all__ = [
    "ERRORS_NAME",
    "RESULTS_NAME",
    "RUN_NAME",
    "ResultsFile",
    "append_record",
    "append_traceback",
    "appending_results",
    "check_run_options",
    "prepare_folder",
    "read_results",
    "write_results_sorted",
]

#: File names inside the output folder.
RESULTS_NAME = "results.csv"
RUN_NAME = "run.json"
#: The full traceback of every episode that raised, appended as they arrive.
ERRORS_NAME = "errors.log"
#: Largest run.json read (one holds the options and a digest per level).
MAX_RUN_BYTES = 4 * 1024 * 1024
#: Largest results.csv read: about 40 million rows.
MAX_RESULTS_BYTES = 4 * 1024 * 1024 * 1024


def prepare_folder(folder: Path) -> None:
    """Create the output folder (and its parents) if needed."""
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{folder}: exists and is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"{folder}: cannot create folder: {error.strerror or error}") from None


def check_run_options(folder: Path, options: dict[str, Any]) -> None:
    """Record ``options`` in ``run.json``, or check that the folder's earlier run had the same ones.

    Raises
    ------
    OutputError
        If the folder holds results of a run with other options, or results without ``run.json``.
    """
    run_path = folder / RUN_NAME
    if not run_path.exists():
        if (folder / RESULTS_NAME).exists():
            raise OutputError(f"{folder / RESULTS_NAME}: found without {RUN_NAME}; use another output folder")
        try:
            text = json.dumps(options, indent=2, allow_nan=False)
        except ValueError:  # a NaN option would make a run.json its own resume refuses
            raise OutputError(f"{run_path}: options hold a number that is not finite") from None
        write_text_atomic(run_path, text + "\n")
        return
    earlier = read_json_file(run_path, max_file_bytes=MAX_RUN_BYTES, kind="run.json", error=OutputError)
    if earlier != options:
        raise OutputError(f"{run_path}: {folder} holds a run with other options ({_difference(earlier, options)}); "
                          "use another output folder, or delete this one to start again")  # fmt: skip


def _difference(earlier: Any, now: dict[str, Any]) -> str:
    """The first option that differs, as ``name: X there, Y here``."""
    if not isinstance(earlier, dict):
        return "not a run.json written by guardsim bench"
    for name in sorted(set(earlier) | set(now), key=str):
        if name not in earlier or name not in now:
            there = _short(earlier[name]) if name in earlier else "not set"
            here = _short(now[name]) if name in now else "not set"
            return f"{_clip(str(name), 40)}: {there} there, {here} here"
        if earlier[name] != now[name]:
            return f"{name}: {_short(earlier[name])} there, {_short(now[name])} here"
    return ""


def _short(value: Any) -> str:
    text = json.dumps(value, separators=(",", ":"))
    return text if len(text) <= 60 else text[:57] + "..."


def read_results(path: Path, expected: Collection[tuple[str, str, int, int]] | None = None) -> list[EpisodeRecord]:
    """The rows of a results file, dropping (from the file too) a half-written last line.

    A run killed while writing a row leaves a last line without its newline; that episode is then
    missing from the returned rows and runs again. With ``expected`` (the keys of the batch's
    episodes), a row of an episode outside the batch, or a second row of one episode, is refused: it
    would be counted among the batch's results.

    Raises
    ------
    OutputError
        If another ``guardsim bench`` is appending to the file, the header is not guardsim's, a
        complete row does not parse, or a row is not one of ``expected`` or repeats an earlier one.
    """
    if not path.exists() and not path.is_symlink():
        return []
    source = display_path(path)
    _require_regular(path)
    try:
        with path.open("a", encoding="utf-8") as stream:
            _lock(stream)  # a run appending right now would make the half line below whole again
        data = read_limited_bytes(path, max_file_bytes=MAX_RESULTS_BYTES, kind="results file", error=OutputError)
        complete = data[: data.rfind(b"\n") + 1]
        if len(complete) < len(data):
            os.truncate(path, len(complete))
        text = complete.decode("utf-8")
    except OSError as error:
        raise OutputError(f"{source}: cannot read: {error.strerror or error}") from None
    except UnicodeDecodeError as error:
        raise OutputError(f"{source}: not UTF-8 text (byte {error.start})") from None
    rows = csv.reader(io.StringIO(text, newline=""))
    header = next(rows, None)
    if header is None:
        return []
    if tuple(header) != CSV_COLUMNS and tuple(header) != CSV_COLUMNS[: CSV_COLUMNS.index("motion")]:
        raise OutputError(f"{source}: line 1 is not the header of guardsim bench results; use another output folder")
    records = []
    seen: dict[tuple[str, str, int, int], int] = {}
    wanted = set(expected) if expected is not None else None
    try:
        for row in rows:
            where = f"{source}: line {rows.line_num}"
            try:
                record = EpisodeRecord.from_row(row)
            except ValueError as error:
                raise OutputError(f"{where}: {_clip(str(error))}; fix or delete that line") from None
            if wanted is not None and record.key not in wanted:
                raise OutputError(
                    f"{where}: episode {record.episode} of {_clip(record.planner)} on {excerpt(record.level_file, 60)} "
                    f"(seed {record.seed}) is not part of this batch; fix or delete that line"
                )
            earlier = seen.setdefault(record.key, rows.line_num)
            if earlier != rows.line_num:
                raise OutputError(f"{where}: repeats the episode of line {earlier}; delete one of the two lines")
            records.append(record)
    except csv.Error as error:
        raise OutputError(f"{source}: line {rows.line_num}: not CSV: {error}; fix or delete that line") from None
    return records


def _require_regular(path: Path) -> None:
    """Refuse a results file that exists and is not a regular file (opening a FIFO to append blocks)."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return
    except OSError as error:
        raise OutputError(f"{display_path(path)}: cannot read: {error.strerror or error}") from None
    if not stat.S_ISREG(mode):
        raise OutputError(f"{display_path(path)}: is not a regular file; use another output folder")


def _clip(text: str, limit: int = 100) -> str:
    """``text`` on one line, cut to ``limit`` characters."""
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


@contextmanager
def appending_results(path: Path) -> Iterator[ResultsFile]:
    """Open the results file for appending rows, writing the header first if the file is new or empty."""
    _require_regular(path)
    try:
        descriptor = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | getattr(os, "O_NONBLOCK", 0), 0o666)
    except OSError as error:
        raise OutputError(f"{display_path(path)}: cannot write: {error.strerror or error}") from None
    results = ResultsFile(path, descriptor)
    try:
        results.lock()
        if os.fstat(descriptor).st_size == 0:
            results.write(_csv_text([list(CSV_COLUMNS)]))
        yield results
    finally:
        os.close(descriptor)


class ResultsFile:
    """``results.csv`` open for appending: each row goes out in one unbuffered write, and a write that
    fails (a full disk) is cut back to the last whole row before the error is raised, so the file never
    holds a partial line."""

    def __init__(self, path: Path, descriptor: int) -> None:
        self.path = path
        self.name = display_path(path)
        self.descriptor = descriptor

    def lock(self) -> None:
        """Refuse a second ``guardsim bench`` appending to the same file (it would write each row twice)."""
        try:
            import fcntl
        except ImportError:  # not POSIX: no advisory locks, run one command per folder
            return
        try:
            fcntl.flock(self.descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise OutputError(f"{self.name}: another guardsim bench is writing to this folder") from None

    def write(self, text: str) -> None:
        """Append ``text`` whole, or raise :class:`OutputError` leaving the file as it was."""
        data = text.encode("utf-8")
        size = os.fstat(self.descriptor).st_size
        try:
            written = 0
            while written < len(data):
                written += os.write(self.descriptor, data[written:])
        except OSError as error:
            with contextlib.suppress(OSError):
                os.ftruncate(self.descriptor, size)
            raise OutputError(f"{self.name}: cannot write: {error.strerror or error}") from None


def _lock(stream: TextIO) -> None:
    """Refuse a second ``guardsim bench`` appending to the same file (it would write each row twice)."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no advisory locks, run one command per folder
        return
    try:
        fcntl.flock(stream.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        raise OutputError(f"{stream.name}: another guardsim bench is writing to this folder") from None


def append_record(stream: ResultsFile, record: EpisodeRecord) -> None:
    """Append one row in a single write, so a kill leaves whole rows and a full disk none of the row."""
    stream.write(_csv_text([record.to_row()]))


def append_traceback(folder: Path, record: EpisodeRecord, trace_text: str) -> None:
    """Append the traceback of an episode that raised to ``errors.log``, under a line naming the episode."""
    header = (
        f"=== {record.level_file} planner {record.planner} seed {record.seed} episode {record.episode}: "
        f"{record.error}\n"
    )
    path = folder / ERRORS_NAME
    try:
        with path.open("a", encoding="utf-8") as log:
            log.write(header + trace_text.rstrip("\n") + "\n\n")
    except OSError as error:
        raise OutputError(f"{display_path(path)}: cannot write: {error.strerror or error}") from None


def write_results_sorted(path: Path, records: Iterable[EpisodeRecord]) -> None:
    """Rewrite the results file atomically: header, then one row per episode in sort order."""
    ordered = sorted(records, key=lambda record: record.sort_key)
    write_text_atomic(path, _csv_text([list(CSV_COLUMNS), *(record.to_row() for record in ordered)]))


def _csv_text(rows: list[list[str]]) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(rows)
    return buffer.getvalue()
