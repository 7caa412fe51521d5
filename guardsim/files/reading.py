"""Reading what users hand guardsim, within limits: bytes, JSON, XML and the numbers inside them.

Everything guardsim reads from a file goes through here, upstream of every other module, so that each
way a file can be wrong ends the same way: one :class:`~guardsim.errors.GuardsimError` line that names
the file (made printable) and says what is wrong and where, quoting at most :data:`EXCERPT_CHARS`
characters of the offending value. The rules, each one a fault a fuzzing campaign found:

- only regular files are read (a FIFO would block forever, ``/dev/zero`` never ends), and the byte cap
  is enforced on the bytes actually read, not on ``st_size``;
- JSON and XML nesting is bounded before a recursive parser or walker sees it (``max_depth``);
- JSON's ``NaN``, ``Infinity``, numbers past float range and integers of more than
  :data:`MAX_INTEGER_DIGITS` digits are refused with their line and column;
- warnings a library prints while it works (shapely, Pillow) are captured and put in the one line
  (:func:`captured_warnings`).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import stat
import warnings
from collections.abc import Iterator
from typing import Any

import numpy as np

from guardsim.errors import GuardsimError, LevelError

__all__ = [
    "DEFAULT_MAX_DEPTH",
    "EXCERPT_CHARS",
    "MAX_INTEGER_DIGITS",
    "MAX_MAGNITUDE",
    "NumberError",
    "captured_warnings",
    "data_depth",
    "display_path",
    "excerpt",
    "finite_number",
    "json_depth",
    "json_type",
    "number_from_text",
    "parse_json",
    "quoted",
    "read_json_file",
    "read_limited_bytes",
    "read_text_file",
    "read_xml_root",
    "warning_note",
]

#: Deepest nesting of JSON arrays and objects, or XML elements, read; guardsim's formats need 5.
DEFAULT_MAX_DEPTH = 64
#: Longest excerpt of an offending value quoted in a message.
EXCERPT_CHARS = 80
#: Most digits of an integer in JSON (Python refuses to convert past 4,300; the value checks refuse far
#: smaller numbers, with their location).
MAX_INTEGER_DIGITS = 4000
#: Largest magnitude :func:`finite_number` accepts unless told otherwise: beyond it, sums and squares of
#: coordinates lose every fractional digit and soon overflow, so such a value is a mistake, not a level.
MAX_MAGNITUDE = 1e15


class NumberError(ValueError):
    """A value that is not a usable number; the message says why, without location (the caller adds it)."""


def display_path(path: str | os.PathLike[str]) -> str:
    """The path as it should appear in a one-line message: control characters (a newline in a file
    name) escaped, so that the message stays one line."""
    text = os.fspath(path)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    return text if text.isprintable() else text.encode("unicode_escape", "backslashreplace").decode("ascii")


def excerpt(value: Any, limit: int = EXCERPT_CHARS) -> str:
    """``value`` as JSON-like text on one line, elided in the middle past ``limit`` characters.

    Examples
    --------
    >>> excerpt([[1, 2]] * 40)
    '[[1,2],[1,2],[1,2],[1,2],[1,2],[1,2],[1,2],[1,2],[1,2],[ ... ,[1,2],[1,2],[1,2]] (241 characters)'
    >>> excerpt("a\\nb")
    '"a\\\\nb"'
    """
    try:
        text = json.dumps(value, separators=(",", ":"), ensure_ascii=False, default=repr)
    except (ValueError, RecursionError):  # a cycle, or nested past Python's stack
        text = repr(type(value).__name__)
    if not text.isprintable():
        text = text.encode("unicode_escape", "backslashreplace").decode("ascii")
    if len(text) <= limit:
        return text
    head = (limit - 5) * 3 // 4
    tail = limit - 5 - head
    return f"{text[:head]} ... {text[-tail:]} ({len(text)} characters)"


def quoted(text: str, limit: int = 40) -> str:
    """``repr(text)`` (control characters escaped), elided past ``limit`` characters.

    >>> quoted("north"), quoted("x" * 100, 20)
    ("'north'", "'xxxxxxxxxxxxxx...'")
    """
    shown = repr(text)
    return shown if len(shown) <= limit else shown[: limit - 4] + "...'"


def read_limited_bytes(
    path: str | os.PathLike[str],
    *,
    max_file_bytes: int,
    kind: str = "level file",
    error: type[GuardsimError] = LevelError,
) -> bytes:
    """A regular file's bytes, at most ``max_file_bytes`` of them, every failure a one-line ``error``.

    The file is opened without blocking (a FIFO must not hang the command) and refused unless it is a
    regular file; the cap counts the bytes read, so a file that grows or lies about its size (a device,
    ``/proc``) cannot pass it. ``kind`` names what a folder or device is not (``level file``, ``map``).
    """
    source = display_path(path)
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise error(f"{source}: no such file") from None
    except IsADirectoryError:
        raise error(f"{source}: is a directory, not a {kind}") from None
    except OSError as failure:
        raise error(f"{source}: cannot read: {failure.strerror or failure}") from None
    try:
        mode = os.fstat(descriptor).st_mode
        if stat.S_ISDIR(mode):
            raise error(f"{source}: is a directory, not a {kind}")
        if not stat.S_ISREG(mode):
            raise error(
                f"{source}: is {_file_type(mode)}, not a regular file; guardsim reads a {kind} only from a file"
            )
        chunks = []
        left = max_file_bytes + 1
        while left > 0:
            chunk = os.read(descriptor, min(left, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
    except OSError as failure:
        raise error(f"{source}: cannot read: {failure.strerror or failure}") from None
    finally:
        os.close(descriptor)
    data = b"".join(chunks)
    if len(data) > max_file_bytes:
        raise error(f"{source}: file is over the limit of {max_file_bytes} bytes (max_file_bytes)")
    return data


def _file_type(mode: int) -> str:
    for test, name in (
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "a special file"


def read_text_file(
    path: str | os.PathLike[str],
    *,
    max_file_bytes: int,
    kind: str = "level file",
    error: type[GuardsimError] = LevelError,
) -> str:
    """:func:`read_limited_bytes` decoded as UTF-8 (a byte-order mark is allowed)."""
    data = read_limited_bytes(path, max_file_bytes=max_file_bytes, kind=kind, error=error)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as failure:
        raise error(f"{display_path(path)}: not UTF-8 text (byte {failure.start})") from None


_JSON_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"', re.DOTALL)


def json_depth(text: str) -> int:
    """The deepest nesting of arrays and objects in JSON ``text`` (brackets inside strings ignored).

    Vectorised, so a 16 MB file costs well under a second, and never recursive.

    >>> json_depth('{"a": [[1], "]]]"]}')
    3
    """
    raw = _JSON_STRING.sub(b"", text.encode("utf-8", "surrogatepass"))
    codes = np.frombuffer(raw, dtype=np.uint8)
    steps = np.zeros(codes.shape, dtype=np.int32)
    steps[(codes == ord("[")) | (codes == ord("{"))] = 1
    steps[(codes == ord("]")) | (codes == ord("}"))] = -1
    return int(np.cumsum(steps).max(initial=0))


def data_depth(data: Any) -> int:
    """The deepest nesting of lists and dicts in parsed ``data`` (TOML's, whose parser takes no limit),
    walked without recursion.

    >>> data_depth({"a": [[1], {"b": 2}]})
    3
    """
    deepest, stack = 0, [(data, 1)]
    while stack:
        value, depth = stack.pop()
        children = value.values() if isinstance(value, dict) else value if isinstance(value, list) else None
        if children is None:
            continue
        deepest = max(deepest, depth)
        stack.extend((child, depth + 1) for child in children)
    return deepest


class _BadToken(ValueError):
    def __init__(self, token: str, why: str) -> None:
        super().__init__(why)
        self.token = token


def _parse_int(token: str) -> int:
    digits = len(token.lstrip("-"))
    if digits > MAX_INTEGER_DIGITS:
        raise _BadToken(token, f"an integer of {digits} digits (at most {MAX_INTEGER_DIGITS})")
    return int(token)


def _parse_float(token: str) -> float:
    value = float(token)
    if not math.isfinite(value):
        raise _BadToken(token, f"{excerpt(token, 30)} is beyond the range of a float")
    return value


def _parse_constant(token: str) -> float:
    raise _BadToken(token, f"{token} is not a JSON number")


def _line_column(text: str, index: int) -> str:
    line = text.count("\n", 0, index) + 1
    return f"line {line} column {index - (text.rfind(chr(10), 0, index) + 1) + 1}"


def parse_json(
    text: str,
    *,
    source: str,
    max_depth: int = DEFAULT_MAX_DEPTH,
    error: type[GuardsimError] = LevelError,
    allow_non_finite: bool = False,
) -> Any:
    """Decode JSON ``text`` read from ``source``, every failure one ``error`` line with its location.

    ``NaN``, ``Infinity`` and floats past the float range are refused unless ``allow_non_finite``, for a
    caller that checks every number itself and can say which field holds one (the level check).

    Examples
    --------
    >>> parse_json('{"x": [1, 2.5]}', source="a.json")
    {'x': [1, 2.5]}
    >>> parse_json('{"x": NaN}', source="a.json")
    Traceback (most recent call last):
    ...
    guardsim.errors.LevelError: a.json: not valid JSON: NaN is not a JSON number at line 1 column 7
    """
    depth = json_depth(text)
    if depth > max_depth:
        raise error(f"{source}: not valid JSON for guardsim: nested {depth} deep, over the limit of {max_depth}")
    try:
        if allow_non_finite:
            return json.loads(text, parse_int=_parse_int)
        return json.loads(text, parse_int=_parse_int, parse_float=_parse_float, parse_constant=_parse_constant)
    except json.JSONDecodeError as failure:
        raise error(
            f"{source}: not valid JSON: {failure.msg} at line {failure.lineno} column {failure.colno}"
        ) from None
    except _BadToken as failure:
        where = text.find(failure.token)
        located = f" at {_line_column(text, where)}" if where >= 0 else ""
        raise error(f"{source}: not valid JSON: {failure}{located}") from None
    except (ValueError, RecursionError) as failure:
        raise error(f"{source}: not valid JSON: {excerpt(str(failure))}") from None


def read_json_file(
    path: str | os.PathLike[str],
    *,
    max_file_bytes: int,
    max_depth: int = DEFAULT_MAX_DEPTH,
    kind: str = "level file",
    error: type[GuardsimError] = LevelError,
    allow_non_finite: bool = False,
) -> Any:
    """A regular file of at most ``max_file_bytes`` bytes decoded as JSON (see :func:`parse_json`)."""
    text = read_text_file(path, max_file_bytes=max_file_bytes, kind=kind, error=error)
    return parse_json(
        text, source=display_path(path), max_depth=max_depth, error=error, allow_non_finite=allow_non_finite
    )


def read_xml_root(
    data: bytes,
    *,
    source: str,
    max_depth: int = DEFAULT_MAX_DEPTH,
    error: type[GuardsimError] = LevelError,
) -> Any:
    """Parse XML ``data`` into an :class:`xml.etree.ElementTree.Element`, nesting bounded by ``max_depth``.

    The depth is checked as the parser streams, so a file of 3,000 nested groups is refused before any
    recursive walk over the tree. Document type declarations (the door to entity expansion) are refused.
    """
    from xml.etree import ElementTree

    if re.search(rb"<!DOCTYPE|<!ENTITY", data[:65536], re.IGNORECASE):
        raise error(f"{source}: XML with a document type declaration is not read")
    parser: Any = ElementTree.XMLPullParser(events=("start", "end"))
    depth = 0
    root = None
    try:
        for begin in range(0, len(data), 1 << 16):
            parser.feed(data[begin : begin + (1 << 16)])
            for event, element in parser.read_events():
                if event == "start":
                    depth += 1
                    root = element if root is None else root
                    if depth > max_depth:
                        raise error(f"{source}: XML nested over the limit of {max_depth} elements")
                else:
                    depth -= 1
        parser.close()
    except ElementTree.ParseError as failure:
        raise error(f"{source}: not valid XML: {excerpt(str(failure))}") from None
    if root is None:
        raise error(f"{source}: not valid XML: no element")
    return root


def finite_number(
    value: Any,
    *,
    positive: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
    magnitude: float = MAX_MAGNITUDE,
) -> float:
    """``value`` (an int or float from JSON, never a bool) as a finite float within bounds.

    Raises
    ------
    NumberError
        Saying what the value is instead (its excerpt, never the whole value); the caller adds where.

    Examples
    --------
    >>> finite_number(3)
    3.0
    >>> finite_number(float("nan"))
    Traceback (most recent call last):
    ...
    guardsim.files.reading.NumberError: must be a finite number, not nan
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise NumberError(f"must be a number, not {json_type(value)}")
    try:
        number = float(value)
    except OverflowError:
        raise NumberError(f"must be a number of at most {magnitude:g} in size, not {excerpt(value, 40)}") from None
    if not math.isfinite(number):
        raise NumberError(f"must be a finite number, not {number}")
    if abs(number) > magnitude:
        raise NumberError(f"must be a number of at most {magnitude:g} in size, not {number:g}")
    if positive and number <= 0:
        raise NumberError(f"must be positive, not {number:g}")
    if minimum is not None and number < minimum:
        raise NumberError(f"must be at least {minimum:g}, not {number:g}")
    if maximum is not None and number > maximum:
        raise NumberError(f"must be at most {maximum:g}, not {number:g}")
    return number


def number_from_text(
    text: str,
    *,
    integer: bool = False,
    positive: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
    magnitude: float = MAX_MAGNITUDE,
) -> float:
    """A number written as text (a header field, an option value), checked as :func:`finite_number`.

    Only ASCII digits count (``int("³")`` and ``float("１")`` would accept other scripts' digits).

    >>> number_from_text("12")
    12.0
    >>> number_from_text("nan")
    Traceback (most recent call last):
    ...
    guardsim.files.reading.NumberError: must be a finite number, not nan
    """
    stripped = text.strip()
    pattern = (
        r"[+-]?[0-9]+"
        if integer
        else r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?(?:nan|inf|infinity)"
    )
    if len(stripped) > 400 or not re.fullmatch(pattern, stripped, re.IGNORECASE):
        what = "a whole number" if integer else "a number"
        raise NumberError(f"must be {what}, not {excerpt(text, 40)}")
    if integer and len(stripped.lstrip("+-")) > 30:
        raise NumberError(f"must be a number of at most {magnitude:g} in size, not {excerpt(text, 40)}")
    return finite_number(float(stripped), positive=positive, minimum=minimum, maximum=maximum, magnitude=magnitude)


def json_type(value: Any) -> str:
    """How JSON would name the type of ``value``: ``a number``, ``a list``, ``null``..."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


@contextlib.contextmanager
def captured_warnings() -> Iterator[list[warnings.WarningMessage]]:
    """Collect the warnings raised in the block instead of letting them print (a library's warning on
    stderr would make an error two lines); see :func:`warning_note`."""
    with warnings.catch_warnings(record=True) as caught, np.errstate(all="ignore"):
        warnings.simplefilter("always")
        yield caught


def warning_note(caught: list[warnings.WarningMessage]) -> str:
    """The first captured warning as a clause to append to a one-line message, or ``""``.

    >>> import warnings
    >>> with captured_warnings() as caught:
    ...     warnings.warn("invalid value encountered", RuntimeWarning)
    >>> warning_note(caught)
    ' (RuntimeWarning: invalid value encountered)'
    """
    if not caught:
        return ""
    first = caught[0]
    more = f"; {len(caught) - 1} more warnings" if len(caught) > 1 else ""
    message = " ".join(str(first.message).split())
    return f" ({first.category.__name__}: {_short(message)}{more})"


def _short(text: str) -> str:
    return text if len(text) <= EXCERPT_CHARS else text[: EXCERPT_CHARS - 3] + "..."
