"""The results folder of a batch: ``run.json`` (the options), ``results.csv`` (one row per episode).

Rows are appended and flushed as episodes finish, so a killed run loses at most the line it was writing;
:func:`read_results` drops such a half-written last line so that its episode runs again. A finished run
rewrites the CSV atomically in :attr:`EpisodeRecord.sort_key` order, so the file does not depend on the
order in which workers finished.
"""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TextIO

from guardsim.errors import OutputError
from guardsim.experiment.episodes import CSV_COLUMNS, EpisodeRecord
from guardsim.output import write_text_atomic

__all__ = [
    "RESULTS_NAME",
    "RUN_NAME",
    "append_record",
    "appending_results",
    "check_run_options",
    "prepare_folder",
    "read_results",
    "write_results_sorted",
]

#: File names inside the output folder.
RESULTS_NAME = "results.csv"
RUN_NAME = "run.json"


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
            raise OutputError(f"{folder / RESULTS_NAME}: found without {RUN_NAME}; use another --out")
        write_text_atomic(run_path, json.dumps(options, indent=2) + "\n")
        return
    try:
        earlier = json.loads(run_path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise OutputError(f"{run_path}: cannot read: {error}") from None
    if earlier != options:
        raise OutputError(f"{run_path}: {folder} holds a run with other options ({_difference(earlier, options)}); "
                          "use another --out, or delete the folder to start again")  # fmt: skip


def _difference(earlier: Any, now: dict[str, Any]) -> str:
    """The first option that differs, as ``name: X there, Y here``."""
    if not isinstance(earlier, dict):
        return "not a run.json written by guardsim bench"
    for name in sorted(set(earlier) | set(now)):
        if earlier.get(name) != now.get(name):
            return f"{name}: {_short(earlier.get(name))} there, {_short(now.get(name))} here"
    return ""


def _short(value: Any) -> str:
    text = json.dumps(value, separators=(",", ":"))
    return text if len(text) <= 60 else text[:57] + "..."


def read_results(path: Path) -> list[EpisodeRecord]:
    """The rows of a results file, dropping (from the file too) a half-written last line.

    A run killed while writing a row leaves a last line without its newline; that episode is then
    missing from the returned rows and runs again.

    Raises
    ------
    OutputError
        If another ``guardsim bench`` is appending to the file, the header is not guardsim's, or a
        complete row does not parse.
    """
    if not path.exists():
        return []
    try:
        with path.open("a", encoding="utf-8") as stream:
            _lock(stream)  # a run appending right now would make the half line below whole again
        data = path.read_bytes()
        complete = data[: data.rfind(b"\n") + 1]
        if len(complete) < len(data):
            os.truncate(path, len(complete))
        text = complete.decode("utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise OutputError(f"{path}: cannot read: {error}") from None
    rows = csv.reader(io.StringIO(text, newline=""))
    header = next(rows, None)
    if header is None:
        return []
    if tuple(header) != CSV_COLUMNS:
        raise OutputError(f"{path}: line 1 is not the header of guardsim bench results; use another --out")
    records = []
    for row in rows:
        try:
            records.append(EpisodeRecord.from_row(row))
        except ValueError as error:
            raise OutputError(f"{path}: line {rows.line_num}: {error}; fix or delete that line") from None
    return records


@contextmanager
def appending_results(path: Path) -> Iterator[TextIO]:
    """Open the results file for appending rows, writing the header first if the file is new or empty."""
    try:
        stream = path.open("a", encoding="utf-8", newline="")
    except OSError as error:
        raise OutputError(f"{path}: cannot write: {error.strerror or error}") from None
    with stream:
        _lock(stream)
        if stream.tell() == 0:
            _write(stream, _csv_text([list(CSV_COLUMNS)]))
        yield stream


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


def append_record(stream: TextIO, record: EpisodeRecord) -> None:
    """Append one row in a single write and flush it, so a kill leaves whole rows and at most one part."""
    _write(stream, _csv_text([record.to_row()]))


def _write(stream: TextIO, text: str) -> None:
    try:
        stream.write(text)
        stream.flush()
    except OSError as error:
        raise OutputError(f"{stream.name}: cannot write: {error.strerror or error}") from None


def write_results_sorted(path: Path, records: Iterable[EpisodeRecord]) -> None:
    """Rewrite the results file atomically: header, then one row per episode in sort order."""
    ordered = sorted(records, key=lambda record: record.sort_key)
    write_text_atomic(path, _csv_text([list(CSV_COLUMNS), *(record.to_row() for record in ordered)]))


def _csv_text(rows: list[list[str]]) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(rows)
    return buffer.getvalue()
