"""Reading map and level files safely: regular files only, a byte cap on what is read, bounded parsing.

Every importer and :func:`guardsim.importers.load_any` read through here, so that one set of rules holds
for every input: a FIFO, a device such as ``/dev/zero`` or a folder is refused in one line before any
byte is read (a FIFO is opened without blocking); ``max_file_bytes`` caps the bytes actually read, not
the size the file system reports; JSON numbers that are not finite, integers longer than
:data:`MAX_INTEGER_DIGITS` and nesting deeper than Python can parse are one-line errors with a line
and column; XML elements nested deeper than :data:`MAX_XML_DEPTH` are refused before anything walks them.
Library warnings (shapely, Pillow) raised while a map is converted are collected by :func:`quiet`
rather than printed, so an error stays one line.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import stat
import warnings
from collections.abc import Iterator
from typing import Any, cast
from xml.etree import ElementTree

from guardsim.errors import LevelError

__all__ = [
    "MAX_INTEGER_DIGITS",
    "MAX_XML_DEPTH",
    "display_name",
    "excerpt",
    "parse_json_bytes",
    "parse_xml_bytes",
    "quiet",
    "read_capped_bytes",
]

#: Longest JSON integer read (a tile id with its flag bits has 10 digits).
MAX_INTEGER_DIGITS = 20
#: Deepest XML element nesting read (a map, 60 nested group layers, an object and its points).
MAX_XML_DEPTH = 64


def display_name(path: str | os.PathLike[str]) -> str:
    """A file name safe to put in a one-line message: control characters (a newline) escaped.

    >>> display_name("a\\nb.tmx")
    'a\\\\nb.tmx'
    """
    text = os.fspath(path)
    return "".join(char if char.isprintable() else repr(char)[1:-1] for char in text)


def excerpt(value: Any, limit: int = 40) -> str:
    """``repr(value)`` cut to about ``limit`` characters, so an offending value never floods the line."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[: limit - 5]}...{text[-2:]}"


def read_capped_bytes(path: str | os.PathLike[str], *, max_file_bytes: int, kind: str = "map") -> bytes:
    """A regular file's bytes, reading at most ``max_file_bytes + 1`` of them.

    Raises :class:`LevelError` naming the file for a missing file, a folder, anything that is not a
    regular file (FIFO, device, socket), a read error, or more bytes than ``max_file_bytes``.
    """
    source = display_name(path)
    over = f"{source}: file is over the limit of {max_file_bytes} bytes (raise it with --max-file-bytes)"
    try:
        # O_NONBLOCK: opening a FIFO for reading must not wait for a writer; it is refused below.
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except FileNotFoundError:
        raise LevelError(f"{source}: no such file") from None
    except IsADirectoryError:
        raise LevelError(f"{source}: is a directory, not a {kind}") from None
    except (OSError, ValueError) as error:
        raise LevelError(f"{source}: cannot read: {getattr(error, 'strerror', None) or error}") from None
    try:
        info = os.fstat(descriptor)
        if stat.S_ISDIR(info.st_mode):
            raise LevelError(f"{source}: is a directory, not a {kind}")
        if not stat.S_ISREG(info.st_mode):
            raise LevelError(f"{source}: not a regular file (a device, FIFO or socket); guardsim reads only files")
        if info.st_size > max_file_bytes:
            raise LevelError(over.replace("file is over", f"file is {info.st_size} bytes, over"))
        chunks: list[bytes] = []
        remaining = max_file_bytes + 1
        while remaining > 0:
            chunk = os.read(descriptor, min(remaining, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            remaining -= len(chunk)
        if remaining <= 0:
            # The file grew, or its reported size was wrong: the cap holds on what was read.
            raise LevelError(over)
        return b"".join(chunks)
    except OSError as error:
        raise LevelError(f"{source}: cannot read: {error.strerror or error}") from None
    finally:
        os.close(descriptor)


def _location(text: str, pattern: str) -> str:
    match = re.search(pattern, text)
    if match is None:
        return ""
    line = text.count("\n", 0, match.start()) + 1
    column = match.start() - (text.rfind("\n", 0, match.start()) + 1) + 1
    return f"line {line} column {column}: "


class _BadNumber(Exception):
    def __init__(self, message: str, pattern: str) -> None:
        super().__init__(message)
        self.pattern = pattern


def _integer(text: str) -> int:
    if len(text.lstrip("-")) > MAX_INTEGER_DIGITS:
        raise _BadNumber(
            f"an integer of {len(text.lstrip('-'))} digits (at most {MAX_INTEGER_DIGITS} are read)",
            rf"-?\d{{{MAX_INTEGER_DIGITS + 1},}}",
        )
    return int(text)


def _float(text: str) -> float:
    value = float(text)
    if value != value or value in (float("inf"), float("-inf")):
        raise _BadNumber(f"the number {excerpt(text)} is too large", re.escape(text))
    return value


def _constant(text: str) -> Any:
    raise _BadNumber(f"{text} is not a number JSON allows", re.escape(text))


def parse_json_bytes(data: bytes, source: str) -> Any:
    """JSON text decoded as UTF-8, with the number and nesting rules of this module."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise LevelError(f"{source}: not UTF-8 text (byte {error.start})") from None
    try:
        return json.loads(text, parse_int=_integer, parse_float=_float, parse_constant=_constant)
    except json.JSONDecodeError as error:
        raise LevelError(f"{source}: line {error.lineno} column {error.colno}: not valid JSON: {error.msg}") from None
    except _BadNumber as error:
        raise LevelError(f"{source}: {_location(text, error.pattern)}not valid JSON: {error}") from None
    except RecursionError:
        raise LevelError(f"{source}: not valid JSON: nested too deeply") from None


def parse_xml_bytes(data: bytes, source: str, *, max_depth: int = MAX_XML_DEPTH) -> ElementTree.Element:
    """An XML document's root element; elements nested deeper than ``max_depth`` are refused."""
    depth = 0
    try:
        parser: ElementTree.XMLPullParser = ElementTree.XMLPullParser(events=("start", "end"))
        root: ElementTree.Element | None = None
        # Feed in slices so that a too-deep document is refused as soon as the depth is passed.
        for offset in range(0, max(len(data), 1), 1 << 16):
            parser.feed(data[offset : offset + (1 << 16)])
            events = cast("Iterator[tuple[str, ElementTree.Element]]", parser.read_events())
            for event, element in events:
                if event == "start":
                    depth += 1
                    root = element if root is None else root
                    if depth > max_depth:
                        raise LevelError(
                            f"{source}: <{excerpt(element.tag, 30)}> is nested {depth} elements deep; "
                            f"guardsim reads at most {max_depth} (flatten the group layers)"
                        )
                else:
                    depth -= 1
        parser.close()
    except ElementTree.ParseError as error:
        line, column = error.position
        raise LevelError(f"{source}: line {line} column {column + 1}: not well-formed XML") from None
    if root is None:
        raise LevelError(f"{source}: empty XML document")
    return root


@contextlib.contextmanager
def quiet(notes: list[str]) -> Iterator[None]:
    """Collect warnings raised inside the block into ``notes`` (one short phrase each) instead of stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    seen: set[str] = set()
    for item in caught:
        phrase = f"{item.category.__name__}: {str(item.message).splitlines()[0][:80] if str(item.message) else ''}"
        if phrase not in seen:
            seen.add(phrase)
            notes.append(f"library warning ({phrase})")
