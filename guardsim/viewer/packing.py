"""How arrays travel inside the page: little-endian typed-array bytes, base64 text in the JSON block.

The page's script decodes them straight into ``Int32Array``, ``Uint8Array`` or ``Float32Array``.
"""

from __future__ import annotations

import base64
from typing import Any

import numpy as np

__all__ = ["packed"]


def packed(array: Any, dtype: str) -> str:
    """``array`` as ``dtype`` (``"i4"``, ``"u1"``, ``"f4"``), little-endian, in base64.

    Examples
    --------
    >>> packed([1, 2], "u1")
    'AQI='
    """
    return base64.b64encode(np.ascontiguousarray(array, dtype=np.dtype(dtype).newbyteorder("<")).tobytes()).decode(
        "ascii"
    )
