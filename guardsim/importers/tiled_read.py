"""Reading Tiled maps (TMX and Tiled JSON) with pytiled-parser, inside guardsim's input limits.

pytiled-parser (the Arcade project's Tiled reader) turns layers, objects,
properties and tilesets (with tile classes and collision shapes) into typed objects. guardsim calls it
part by part rather than through ``pytiled_parser.parse_map``, because of what that entry point does not
do for untrusted files:

* it opens files itself, with no byte cap and no guard against a FIFO or ``/dev/zero``; here every map,
  tileset and template is read through :func:`guardsim.importers.source.read_capped_bytes` first;
* it inflates zlib/gzip tile data with no cap, and stores tiles as nested Python lists, so a 20 KB file
  can become gigabytes: tile data is decoded here (:func:`~guardsim.importers.tiled_data.decode_tile_data`),
  after the declared size has been checked against ``max_cells``;
* it reads ``<data encoding="hex">`` as base64, and recurses once per group layer: encodings are
  checked, and groups are walked here without recursion under a depth cap;
* it raises ``KeyError``/``ValueError``/``AttributeError`` with no file or place, and requires every
  attribute recent Tiled versions write (old maps without ``infinite`` or ``tilecount`` fail): each part
  is given Tiled's documented defaults (:mod:`~guardsim.importers.tiled_defaults`), and any exception
  becomes one :class:`LevelError` naming the file, the layer and the object;
* it prints to stdout when a template brings a tileset the map lacks, and its JSON template merge lets
  the template override the instance (a resized instance gets the template's size): templates are
  merged here (:mod:`~guardsim.importers.tiled_templates`) and handed over as plain objects.

Used as-is: the TMX and JSON parsers of layers (their names, properties, offsets, visibility, class),
objects (every shape), properties (typed) and tilesets (tile classes, properties,
collision shapes). :mod:`~guardsim.importers.tiled_tmx` and :mod:`~guardsim.importers.tiled_json` walk
each format; :mod:`~guardsim.importers.tiled_parts` is what they share.
"""

from __future__ import annotations

import os
from pathlib import Path

from guardsim.importers.source import parse_json_bytes, parse_xml_bytes, read_capped_bytes
from guardsim.importers.tiled_data import TiledMap
from guardsim.importers.tiled_json import JsonReader
from guardsim.importers.tiled_tmx import TmxReader
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES

__all__ = ["read_tiled"]


def read_tiled(
    path: str | os.PathLike[str],
    *,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    max_cells: int = DEFAULT_MAX_CELLS,
    cells_per_tile: float = 1.0,
) -> TiledMap:
    """Read a TMX or Tiled JSON map (told apart by content) with its external tilesets and templates.

    ``max_cells`` (with ``cells_per_tile``, the level cells one tile becomes) caps the tiles a layer may
    declare, checked before any tile data is decoded.
    """
    data = read_capped_bytes(path, max_file_bytes=max_file_bytes)
    # Told apart by content; with no content to tell by (an empty file), by the name's suffix.
    if data.lstrip()[:1] == b"<" or (not data.strip() and str(path).lower().endswith((".tmx", ".tsx", ".tx"))):
        tmx = TmxReader(Path(path), max_file_bytes, max_cells, cells_per_tile)
        return tmx.read(parse_xml_bytes(data, tmx.source))
    reader = JsonReader(Path(path), max_file_bytes, max_cells, cells_per_tile)
    return reader.read(parse_json_bytes(data, reader.source))
