"""What ``guardsim sneak`` writes as data: sneak.json. Its pictures are drawn downstream
(:func:`guardsim.pictures.write_sneak_pictures`)."""

from __future__ import annotations

import json
import os

from guardsim.files.output import write_text_atomic

__all__ = ["write_sneak_json"]


def write_sneak_json(path: str | os.PathLike[str], data: dict[str, object]) -> None:
    """Write ``data`` (:func:`guardsim.sneak.sneak_data`) as compact JSON, atomically."""
    write_text_atomic(path, json.dumps(data, separators=(",", ":")) + "\n")
