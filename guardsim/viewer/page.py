"""The interactive episode viewer: one self-contained HTML page built from a trace.

The page carries the trace, not pictures: each cell's first-seen tick, its kind (goal, unreachable,
neither), every guard's path and headings, the wall rings and the vision simulated, packed as base64
typed arrays inside a JSON block. The page's own script (``viewer.js``, inlined) draws any tick from
that: a 512 x 512 episode stays near 2 MB. Nothing is fetched from the network.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.level import GuardSpec, Level
from guardsim.render.layout import VisionSettings
from guardsim.render.palette import COLOURS, GUARD_COLOURS, HEAT_RAMP, PALETTE, guard_index
from guardsim.trace import Trace
from guardsim.viewer.layers import Overlays, overlay_data
from guardsim.viewer.packing import packed
from guardsim.viewer.walls import rings_from_grid

__all__ = ["FIELD_BUDGET_BYTES", "build_page", "page_data", "write_viewer"]

#: Most bytes of D-field snapshots a page carries; longer episodes keep every k-th tick's field.
FIELD_BUDGET_BYTES = 1_500_000

#: Cell kinds in the page's ``kinds`` array: walls and the rest, goal floor, floor the guard fits on but
#: cannot reach, floor too tight to stand in (the palette's ``tight``, as in every picture).
_OTHER, _GOAL, _UNREACHABLE, _TIGHT = 0, 1, 2, 3


def _hex(colour: tuple[int, int, int]) -> str:
    return "#" + "".join(f"{channel:02x}" for channel in colour)


def _outline(level: Level) -> list[list[list[float]]]:
    """The floor's edges as rings: the boundary of the free area, so the cuts the importer makes to open
    an enclosing wall (two holes touching along a line) are not drawn as lines across the wall, as the
    GIF draws them not."""
    import shapely

    rings = []
    for part in shapely.get_parts(level.free_area()):
        for ring in (part.exterior, *part.interiors):
            rings.append([[float(x), float(y)] for x, y in list(ring.coords)[:-1]])
    return rings


def _field_snapshots(field: np.ndarray, steps: int, shape: tuple[int, int]) -> dict[str, Any]:
    """Snapshots of the planner's field (``(ticks, rows, cols)``, one per tick) within the byte budget."""
    if field.ndim != 3 or field.shape[1:] != shape or field.shape[0] < steps + 1:
        raise GuardsimError(
            f"the recorded field has shape {field.shape}, expected ({steps + 1}, {shape[0]}, {shape[1]}) "
            "(one grid per tick, the start included)"
        )
    per_tick = shape[0] * shape[1] * 4
    every = max(1, -(-per_tick * (steps + 1) // FIELD_BUDGET_BYTES))
    ticks = list(range(0, steps + 1, every))
    values = np.asarray(field[ticks], dtype=np.float64)
    finite = np.isfinite(values) & (values >= 0)
    top = float(values[finite].max()) if finite.any() else 1.0
    # Unreached or infinite entries become -1, drawn as no value.
    shipped = np.where(finite, values, -1.0).astype(np.float32)
    return {"ticks": ticks, "max": top, "data": packed(shipped, "f4")}


#: The intruder's colour: the GIF's (guard colour 6), which teams of up to five guards leave free.
_INTRUDER_COLOUR = GUARD_COLOURS[5]


def page_data(
    level: Level | None,
    trace: Trace,
    *,
    field: np.ndarray | None = None,
    overlays: Overlays | None = None,
    guard_poses: np.ndarray | None = None,
) -> dict[str, Any]:
    """Everything the page needs, as JSON-ready data.

    ``overlays`` adds a patrol's or a sneak's layers (see :mod:`guardsim.viewer.layers`). ``guard_poses``
    (``float (guards, ticks + 1, 3)``: ``x, y, facing degrees``) draws every guard and its cone where its
    body is (a team in continuous motion) instead of at its cell.

    With ``level`` ``None`` the walls are rebuilt from the trace's grid (see
    :func:`guardsim.viewer.walls.rings_from_grid`) and vision the trace does not record takes the
    default guard's.

    ``unseen_text`` holds each tick's ``unseen_percent`` formatted with one decimal by Python, so the
    page's readout is exactly the trace's figure (JavaScript's rounding of ties differs from Python's).
    """
    rows, cols = trace.shape
    kinds = np.where(trace.goal, _GOAL, np.where(trace.traversable, _UNREACHABLE, _OTHER))
    if level is not None:
        from guardsim.render.cells import tight_cells

        kinds[tight_cells(level, trace.traversable, trace.origin) & (kinds == _OTHER)] = _TIGHT
    vision = VisionSettings.of(level, trace) if level is not None else VisionSettings.of_guard(GuardSpec(), trace)
    rings = [list(ring) for ring in (level.outer, *level.holes)] if level is not None else rings_from_grid(trace)
    paths = trace.team_paths()
    data: dict[str, Any] = {
        "level": trace.level,
        "planner": trace.planner,
        "seed": trace.seed,
        "outcome": trace.outcome,
        "steps": trace.steps,
        "rows": rows,
        "cols": cols,
        "cell_size": trace.cell_size,
        "origin": list(trace.origin),
        "reachable": trace.reachable,
        "unreachable": trace.unreachable,
        "view_range": vision.view_range,
        "fov_degrees": vision.fov_degrees,
        "line_of_sight": trace.line_of_sight,
        "unseen_text": [f"{percent:.1f}" for percent in trace.unseen_percent],
        "first_seen": packed(trace.first_seen.ravel(), "i4"),
        "kinds": packed(kinds.ravel(), "u1"),
        "paths": [packed([row * cols + col for col, row in path], "i4") for path in paths],
        "headings": [packed(list(headings), "u1") for headings in trace.team_headings()],
        "rings": [[[float(x), float(y)] for x, y in ring] for ring in rings],
        "outline": _outline(level) if level is not None else None,
        "walls_from_grid": level is None,
        "colours": {
            name: _hex(COLOURS[name]) for name in ("wall", "free", "unseen", "unreachable", "tight", "outline", "cone")
        },
        "tight": int((kinds == _TIGHT).sum()),
        # The palette's heat ramp (away from the cone's yellow), the same as the GIF's and PNG's.
        "heat_ramp": [[fraction, list(colour)] for fraction, colour in HEAT_RAMP],
        "guard_colours": [_hex(GUARD_COLOURS[guard % len(GUARD_COLOURS)]) for guard in range(len(paths))],
    }
    poses = getattr(trace, "poses", None)
    if poses is not None:
        # Continuous motion: guard 0's recorded [x, y, heading_degrees] per tick, drawn instead of its cell.
        data["poses"] = packed(np.asarray(poses)[:, 1:4], "f4")
    if guard_poses is not None:
        data["guard_poses"] = [packed(np.asarray(poses, dtype=np.float64).ravel(), "f4") for poses in guard_poses]
    data["tick_hz"] = getattr(trace, "tick_hz", None)
    if field is not None:
        data["field"] = _field_snapshots(np.asarray(field), trace.steps, trace.shape)
    if overlays is not None:
        data.update(overlay_data(overlays, trace))
        data["colours"]["intruder"] = _hex(_INTRUDER_COLOUR)
        # Routes in each guard's dark shade (as the GIF's), dashed by layers.js, apart from its solid trail.
        data["route_colours"] = [_hex(PALETTE[guard_index(guard, dark=True)]) for guard in range(len(paths))]
    return data


def _asset(name: str) -> str:
    return resources.files("guardsim.viewer").joinpath(name).read_text(encoding="utf-8")


def build_page(
    level: Level | None,
    trace: Trace,
    *,
    field: np.ndarray | None = None,
    overlays: Overlays | None = None,
    guard_poses: np.ndarray | None = None,
) -> str:
    """The viewer page for ``trace`` as HTML text (self-contained: script and data inline).

    ``overlays`` adds a patrol's idleness, laps and routes, or a sneak's intruder.
    """
    document = page_data(level, trace, field=field, overlays=overlays, guard_poses=guard_poses)
    data = json.dumps(document, separators=(",", ":"))
    # Inside <script>, "</" would end the element early; JSON allows the escaped form.
    data = data.replace("</", "<\\/")
    title = f"{trace.level}: {trace.planner}, {trace.steps} ticks"
    page = _asset("template.html")
    page = page.replace("__TITLE__", _escape(title))
    page = page.replace("/*__DATA__*/", data)
    # layers.js defines the patrol layers viewer.js draws when the data has them.
    return page.replace("/*__SCRIPT__*/", _asset("layers.js") + "\n" + _asset("viewer.js"))


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def write_viewer(
    path: str | Path,
    level: Level | None,
    trace: Trace,
    *,
    field: np.ndarray | None = None,
    overlays: Overlays | None = None,
    guard_poses: np.ndarray | None = None,
) -> None:
    """Write the viewer page for ``trace`` to ``path`` (atomically).

    ``field`` defaults to the trace's recorded planner field (``trace.field``) when it has one;
    ``overlays`` adds a patrol's or a sneak's layers (:func:`guardsim.viewer.patrols.patrol_overlays`);
    ``guard_poses`` as :func:`page_data` takes it.
    """
    if field is None:
        field = getattr(trace, "field", None)
    write_text_atomic(path, build_page(level, trace, field=field, overlays=overlays, guard_poses=guard_poses))
