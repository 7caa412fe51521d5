"""The interactive episode viewer: one offline HTML page per trace (see ``docs/rendering.md``).

A patrol's or a sneak's page adds :class:`Overlays` (see ``docs/patrols.md``); build them from results
with :mod:`guardsim.viewer.patrols`. An alert episode's page: :mod:`guardsim.viewer.alerts` (``docs/alert.md``).
"""

from __future__ import annotations

from guardsim.viewer.layers import IdlenessMap, Intruder, LapViews, Overlays, SafeSpot
from guardsim.viewer.page import FIELD_BUDGET_BYTES, build_page, page_data, write_viewer

__all__ = [
    "FIELD_BUDGET_BYTES",
    "IdlenessMap",
    "Intruder",
    "LapViews",
    "Overlays",
    "SafeSpot",
    "build_page",
    "page_data",
    "write_viewer",
]
