"""The design page: one self-contained HTML file that draws analyses (``design.js``, inlined).

``report --html`` and ``diff --html`` write it with their analyses inside; ``guardsim watch`` serves it
with none and sends each analysis as a server-sent event.
"""

from __future__ import annotations

import html
import json
from importlib import resources
from typing import Any

from guardsim.viewer.serve.payload import palette

__all__ = ["live_page", "static_page"]


def _block(data: Any) -> str:
    # Inside <script>, only "</" can end the block early.
    return json.dumps(data, separators=(",", ":")).replace("</", "<\\/")


def _page(title: str, payloads: list[dict[str, Any]], diff_html: str | None, live: bool, status: str) -> str:
    template = resources.files("guardsim.viewer.serve").joinpath("design.html").read_text(encoding="utf-8")
    script = resources.files("guardsim.viewer.serve").joinpath("design.js").read_text(encoding="utf-8")
    parts = {
        "__TITLE__": html.escape(title),
        "__STATUS__": html.escape(status),
        "__PALETTE__": _block(palette()),
        "__PAYLOADS__": _block(payloads),
        "__DIFF__": _block(diff_html),
        "__LIVE__": "true" if live else "false",
        "__SCRIPT__": script,
    }
    for key, value in parts.items():
        template = template.replace(key, value)
    return template


def static_page(title: str, payloads: list[dict[str, Any]], diff_html: str | None = None) -> str:
    """A page of one analysis (a report) or two (a diff: before, after, their difference, and the diff's
    table given as HTML)."""
    return _page(title, payloads, diff_html, False, "")


def live_page(title: str) -> str:
    """The page ``guardsim watch`` serves: it draws each analysis the server sends."""
    return _page(title, [], None, True, "waiting for the first analysis")
