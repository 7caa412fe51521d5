"""The interactive episode viewer: one offline HTML page per trace (see ``docs/rendering.md``)."""

from __future__ import annotations

from guardsim.viewer.page import FIELD_BUDGET_BYTES, build_page, page_data, write_viewer

__all__ = ["FIELD_BUDGET_BYTES", "build_page", "page_data", "write_viewer"]
