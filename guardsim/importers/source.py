"""How the importers read their files: :mod:`guardsim.files.reading`'s rules, with the limits maps need.

Every map, tileset and template is read with :func:`guardsim.files.reading.read_limited_bytes` (regular files
only, the byte cap counted on the bytes read), decoded with :func:`guardsim.files.reading.parse_json` (no
``NaN``, no absurd integers, bounded nesting) or :func:`guardsim.files.reading.read_xml_root` (bounded
nesting, no document type declarations). This module adds only what maps need on top: the nesting
limits of Tiled's group layers, JSON from bytes, and library warnings collected as summary notes.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from typing import Any
from xml.etree import ElementTree

from guardsim.errors import LevelError
from guardsim.files.reading import (
    captured_warnings,
    display_path,
    parse_json,
    quoted,
    read_limited_bytes,
    read_xml_root,
    warning_note,
)
from guardsim.files.reading import excerpt as json_excerpt

__all__ = [
    "MAX_JSON_DEPTH",
    "MAX_XML_DEPTH",
    "display_name",
    "excerpt",
    "parse_json_bytes",
    "parse_xml_bytes",
    "quiet",
    "read_capped_bytes",
]

#: Deepest XML nesting read: a map, 50 nested group layers, an object and its shape.
MAX_XML_DEPTH = 60
#: Deepest JSON nesting read: each Tiled JSON group layer nests two levels (a list and an object).
MAX_JSON_DEPTH = 120

#: A path as it should appear in a one-line message (control characters escaped).
display_name = display_path


def excerpt(value: Any, limit: int = 40) -> str:
    """A short quoted excerpt of an offending value: ``'name'`` for text, JSON-like for the rest."""
    return quoted(value, limit) if isinstance(value, str) else json_excerpt(value, limit)


def read_capped_bytes(path: str | os.PathLike[str], *, max_file_bytes: int, kind: str = "map") -> bytes:
    """A regular file's bytes, at most ``max_file_bytes`` of them (:func:`guardsim.files.reading.read_limited_bytes`)."""
    return read_limited_bytes(path, max_file_bytes=max_file_bytes, kind=kind)


def parse_json_bytes(data: bytes, source: str) -> Any:
    """JSON from a map's bytes (UTF-8, a byte-order mark allowed), every failure one located line."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise LevelError(f"{source}: not UTF-8 text (byte {error.start})") from None
    return parse_json(text, source=source, max_depth=MAX_JSON_DEPTH)


def parse_xml_bytes(data: bytes, source: str) -> ElementTree.Element:
    """The root element of a map's XML, nesting bounded by :data:`MAX_XML_DEPTH`."""
    root: ElementTree.Element = read_xml_root(data, source=source, max_depth=MAX_XML_DEPTH)
    return root


@contextlib.contextmanager
def quiet(notes: list[str]) -> Iterator[None]:
    """Collect the warnings raised inside the block into ``notes`` (one phrase) instead of stderr."""
    with captured_warnings() as caught:
        yield
    if caught:
        notes.append(f"library warning{warning_note(caught)}")
