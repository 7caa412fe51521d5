"""The level format as a JSON Schema (draft 2020-12), shipped in the package for editors.

The schema covers what an editor can check as a file is typed: types, required and unknown keys and
number ranges. It agrees with :func:`guardsim.level.check_level_data` on those (``tests/test_schema.py``
checks it); geometry (simple rings, holes inside the outer ring, no overlaps, starts on the free area)
is only in the loader and ``guardsim validate``.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

__all__ = ["SCHEMA_FILE", "level_schema", "level_schema_text"]

#: The schema's file name inside the ``guardsim`` package.
SCHEMA_FILE = "level.schema.json"


def level_schema_text() -> str:
    """The schema as shipped, as text."""
    return resources.files("guardsim").joinpath(SCHEMA_FILE).read_text(encoding="utf-8")


def level_schema() -> dict[str, Any]:
    """The schema as a dictionary.

    Examples
    --------
    >>> schema = level_schema()
    >>> schema["$schema"], schema["required"]
    ('https://json-schema.org/draft/2020-12/schema', ['outer'])
    """
    return json.loads(level_schema_text())
