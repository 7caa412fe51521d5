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

__all__ = ["diff_table", "live_page", "static_page"]


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


def _value(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:g}"
    return html.escape(str(value))


def diff_table(data: dict[str, Any]) -> str:
    """The diff page's table (diff.json's figures, before and after) as HTML."""
    rows = [
        ("difficulty score", data["score"]),
        ("steps to cover", data["cover_steps"]),
        ("worst idleness", data["worst_idleness"]),
        ("mean idleness", data["mean_idleness"]),
        ("safe spots", data["safe_spots"]),
    ]
    out = ["<h2>What the edit changed</h2>"]
    out.append(
        f"<p>cells: {data['cells_added']} added, {data['cells_removed']} removed; safe spots: "
        f'{len(data["safe_gained"])} gained, <span id="safe-lost">{len(data["safe_lost"])}</span> lost</p>'
    )
    out.append("<table><tr><th>measure</th><th>before</th><th>after</th></tr>")
    out += [f"<tr><td>{name}</td><td>{_value(a)}</td><td>{_value(b)}</td></tr>" for name, (a, b) in rows]
    out.append(
        "</table><table><tr><th>from</th><th>to</th><th>outcome</th><th>ticks</th><th>slack</th>"
        "<th>risk</th><th>peak awareness</th><th>hiding gained</th><th>hiding lost</th></tr>"
    )
    for pair in data["pairs"]:
        cells = [
            " -> ".join(_value(v) for v in pair[key]) for key in ("outcome", "ticks", "slack", "risk", "peak_awareness")
        ]
        where = [",".join(f"{v:g}" for v in pair[key]) for key in ("from", "to")]
        out.append(
            "<tr>"
            + "".join(f"<td>{c}</td>" for c in [*where, *cells])
            + f"<td>{len(pair['hiding_gained'])}</td><td>{len(pair['hiding_lost'])}</td></tr>"
        )
    out.append("</table>")
    return "\n".join(out)
