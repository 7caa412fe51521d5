"""The design pages: a report's or a diff's analyses drawn in one offline file, and ``guardsim watch``'s
live page, a local server that re-analyses a level on each save and pushes the result to the page.

- :mod:`~guardsim.viewer.serve.payload`: an analysis as the page's JSON.
- :mod:`~guardsim.viewer.serve.page`: the page itself (``design.html`` and ``design.js``).
- :mod:`~guardsim.viewer.serve.app`: the server (starlette on uvicorn, watchfiles), ``guardsim[watch]``.
"""

from __future__ import annotations

from guardsim.viewer.serve.page import diff_table, live_page, static_page
from guardsim.viewer.serve.payload import analysis_payload

__all__ = ["analysis_payload", "diff_table", "live_page", "static_page"]
