"""What the design pages draw, as JSON: one analysis (:class:`guardsim.design.Analysis`) and its report.

Cells travel packed (base64 bytes, as on the episode viewer): each cell's kind and its exposure in
percent; routes, paths and spots as ``[col, row]`` lists. Positions the page prints are world units.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from guardsim.design.analysis import Analysis
from guardsim.grid import cell_of_state
from guardsim.render.palette import COLOURS, GUARD_COLOURS
from guardsim.viewer.packing import packed

__all__ = ["KINDS", "analysis_payload", "palette"]

#: Cell kinds in the payload: wall or outside, patrolled floor, floor the guards do not reach.
KINDS = {"wall": 0, "floor": 1, "other": 2}


def _cells(grid_cols: int, flat: np.ndarray) -> list[list[int]]:
    flat = np.asarray(flat, dtype=np.int64)
    return np.stack([flat % grid_cols, flat // grid_cols], axis=1).tolist()


def _route(cells: np.ndarray) -> np.ndarray:
    """A lap's cells with waits dropped and closed (back to its first cell)."""
    keep = np.concatenate([[True], cells[1:] != cells[:-1]])
    route = cells[keep]
    return np.concatenate([route, route[:1]]) if route.size > 1 else route


def analysis_payload(analysis: Analysis, report: dict[str, Any] | None = None) -> dict[str, Any]:
    """The JSON-ready drawing data of ``analysis``; ``report``: its report.json data (shown beside it)."""
    grid = analysis.scene.grid
    rows, cols = grid.shape
    kinds = np.where(grid.traversable.ravel(), KINDS["other"], KINDS["wall"])
    kinds[analysis.goal] = KINDS["floor"]
    watched = np.where(grid.traversable.ravel(), analysis.exposure, 0.0)
    # A cell seen for one tick of a long lap stays off 0: 0 is kept for the floor never watched.
    exposure = np.where(watched > 0, np.maximum(1, np.rint(100 * watched)), 0).astype(np.uint8)
    gaps = analysis.idleness.worst_gap
    routes = [_cells(cols, _route(np.asarray(cell_of_state(states)))) for states in analysis.patrol.states]
    pairs = []
    for pair in analysis.pairs:
        result = pair.sneak
        item: dict[str, Any] = {"from": list(pair.source), "to": list(pair.target), "outcome": pair.outcome}
        if pair.note:
            item["note"] = pair.note
        if result is not None and result.path is not None:
            item["path"] = _cells(cols, result.path.cells)
            item["start_tick"] = result.path.start_tick
            item["hiding"] = _cells(cols, np.array([spot.cell for spot in result.hiding_spots], dtype=np.int64))
        pairs.append(item)
    level = analysis.level
    return {
        "level": level.name,
        "shape": [rows, cols],
        "origin": list(grid.origin),
        "cell_size": grid.cell_size,
        "kinds": packed(kinds, "u1"),
        "exposure": packed(exposure, "u1"),
        "worst_gap": packed(np.where(gaps < 0, -1, gaps), "i4"),
        "safe": int(analysis.safe.sum()),
        "walls": {"outer": [list(p) for p in level.outer], "holes": [[list(p) for p in ring] for ring in level.holes]},
        "routes": routes,
        "pairs": pairs,
        "patrol": analysis.patrol_source,
        "period": analysis.patrol.ticks,
        "worst_idleness": analysis.idleness.worst_idleness,
        "mean_idleness": None if analysis.idleness.mean_idleness is None else round(analysis.idleness.mean_idleness, 1),
        "seconds": round(analysis.seconds, 3),
        "reused": list(analysis.reused),
        "report": report,
    }


def palette() -> dict[str, Any]:
    """The colours the page draws with (the pictures' palette)."""
    return {
        "colours": {name: list(value) for name, value in COLOURS.items()},
        "guards": [list(c) for c in GUARD_COLOURS],
    }
