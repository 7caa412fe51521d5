"""Extra layers of the viewer page for patrols and sneaks, beside the trace it always draws.

A trace says where the guards were and what they had seen so far. A patrol page also needs what a trace
does not hold: each cell's worst unwatched gap (an :class:`IdlenessMap`), the lap the trace repeats and
what the team sees at each of its ticks (:class:`LapViews`, from which the page works out each cell's
idleness at the current tick), each guard's loop (:attr:`Overlays.routes`) and a sneaking player who is
not a guard (:class:`Intruder`, with the guards' awareness meters and its state at each tick). A sneak
page adds two more heat maps of the same kind (each cell's exposure and time to detection) and the safe
spots to outline (:class:`SafeSpot`). An alert page (``guardsim alert --html``) adds each guard's state and
meter at every tick, the contaminated set and the last known cell (:class:`AlertLayers`). These are plain
arrays; :mod:`guardsim.viewer.patrols` builds them from patrol and sneak results, :mod:`guardsim.viewer.alerts`
from an alert episode.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from guardsim.errors import GuardsimError
from guardsim.render.palette import COLOURS, GUARD_COLOURS
from guardsim.trace import Trace
from guardsim.viewer.packing import packed

__all__ = [
    "DEFAULT_LAPS",
    "IDLENESS_RAMP",
    "SAFE_COLOURS",
    "STATE_COLOURS",
    "AlertLayers",
    "IdlenessMap",
    "Intruder",
    "LapViews",
    "Overlays",
    "SafeSpot",
    "WatchLayers",
    "overlay_data",
]

#: Colour stops of every idleness layer and of its colour bar: matplotlib's viridis (as ``idleness.png``
#: draws), sampled at ninths; the page interpolates linearly between stops and rounds each channel.
IDLENESS_RAMP: tuple[tuple[float, tuple[int, int, int]], ...] = (
    (0.0, (68, 1, 84)),
    (0.125, (71, 45, 123)),
    (0.25, (59, 82, 139)),
    (0.375, (44, 114, 142)),
    (0.5, (33, 145, 140)),
    (0.625, (40, 174, 128)),
    (0.75, (94, 201, 98)),
    (0.875, (173, 220, 48)),
    (1.0, (253, 231, 37)),
)

#: Laps a patrol page's timeline spans unless the address asks for more (``#laps=N``).
DEFAULT_LAPS = 3

#: The intruder's states (its readout) and a meter bar's fill, as the sneak GIF draws them
#: (:data:`guardsim.render.sneak.STATE_INDEX`): white unseen, the walls' grey in view, orange suspicious,
#: red detected.
STATE_COLOURS: dict[str, tuple[int, int, int]] = {
    "unseen": COLOURS["white"],
    "in view": COLOURS["wall"],
    "suspicious": GUARD_COLOURS[3],
    "detected": GUARD_COLOURS[0],
}

#: A safe spot's outline: green where its rule holds, magenta where it is broken.
SAFE_COLOURS: dict[str, tuple[int, int, int]] = {"holds": (0, 200, 80), "broken": (255, 0, 255)}


@dataclass(frozen=True, eq=False)
class IdlenessMap:
    """A number per cell drawn as a heat map with a colour bar: patrol.json's ``idleness`` (each cell's
    worst gap) or sneak.json's ``longest_unseen``."""

    values: np.ndarray
    """``float (rows, cols)``; NaN where nothing is drawn (walls, cells outside the goal)."""
    unit: str = "ticks"
    """What the numbers count, shown under the colour bar (``"ticks"`` or ``"seconds"``)."""
    label: str = "worst gap"
    """What the numbers are, shown in the layer's toggle and the colour bar."""
    never: np.ndarray | None = None
    """``bool (rows, cols)``: cells never seen (or never detected), drawn apart (black) whatever their value."""
    top: float | None = None
    """The colour bar's top; ``None``: the largest value drawn (exposure, a fraction, runs to 1)."""
    never_text: str = "never seen"
    """What the black cells are, in the legend and a cell's readout."""


@dataclass(frozen=True, eq=False)
class LapViews:
    """The lap a periodic trace repeats: tick ``t`` of the page is tick ``t % period`` of the trace."""

    period: int
    """Ticks per lap; the trace must hold at least one lap."""
    seen: np.ndarray
    """``bool (period, cells)``: the cells some guard sees at each tick of the lap (a guard's own cell
    included). The page derives each cell's idleness at the current tick from it, in steady state."""
    laps: int = DEFAULT_LAPS
    """Laps the timeline spans by default."""


@dataclass(frozen=True, eq=False)
class Intruder:
    """A player sneaking through the patrol: drawn in its own colour, with no cone."""

    cells: Sequence[tuple[int, int]]
    """``(col, row)`` at each tick from :attr:`start_tick`."""
    start_tick: int
    """The page tick at which it enters."""
    in_view: Sequence[bool] = ()
    """Per tick of :attr:`cells`, whether a guard sees it then (a closest call's ticks); empty: never."""
    source: tuple[float, float] | None = None
    """The point it enters from (world units)."""
    target: tuple[float, float] | None = None
    """The point it must reach (world units)."""
    label: str = "intruder"
    meters: np.ndarray | None = None
    """``float (len(cells), guards)``: each guard's awareness meter after each tick of :attr:`cells` (a
    :class:`~guardsim.sneak.PathGrade`'s), drawn as a bar over each guard while the intruder is in."""
    states: Sequence[str] = ()
    """Per tick of :attr:`cells`, one of :data:`~guardsim.detection.INTRUDER_STATES`; empty: no readout."""
    suspicious: float = 0.5
    """The meter level at which a guard is suspicious (the bars turn orange)."""
    detected_at: int | None = None
    """The tick of :attr:`cells` at which a meter first fills, marked on the timeline."""


@dataclass(frozen=True, eq=False)
class SafeSpot:
    """A spot given as safe (``check --safe``), outlined on the page: green if it holds, else magenta."""

    cell: tuple[int, int]
    """``(col, row)``."""
    holds: bool
    label: str = ""
    """Shown in the legend and the cell's readout, e.g. ``"never seen"`` or ``"seen 12% of the lap"``."""


@dataclass(frozen=True, eq=False)
class WatchLayers:
    """A level's cameras and light on a sneak page: the light shaded over the floor, each camera's cone at
    every lap tick, and its meter over it while the intruder is in."""

    light: np.ndarray | None = None
    """``float (rows, cols)``: each cell's light, 0 to 1; ``None``: full light."""
    cameras: Sequence[tuple[tuple[float, float], np.ndarray, float, float]] = ()
    """Each camera: its position (world units), the degrees it faces at each tick of its swing, its field
    of view and its range."""
    meters: np.ndarray | None = None
    """``float (len(intruder cells), cameras)``: each camera's meter after each tick of the intruder's path."""


@dataclass(frozen=True, eq=False)
class AlertLayers:
    """An alert episode's own layers (``guardsim alert --html``), a row per tick of the trace: what each
    guard is doing, its meter, where the intruder may be and where it was last seen. The intruder
    itself is an :class:`Intruder` (from tick 0)."""

    states: np.ndarray
    """``int (ticks, guards)``: each guard's state, an index into :attr:`state_names`."""
    state_names: Sequence[str]
    """:data:`guardsim.alert.GUARD_STATES`."""
    state_letters: Sequence[str]
    """The letter drawn over a guard in each state (the alert GIF's, :data:`guardsim.render.alert.STATE_LETTERS`)."""
    meters: np.ndarray
    """``float (ticks, guards)``: each guard's awareness meter, drawn as a bar over it at every tick."""
    contaminated: np.ndarray
    """``bool (ticks, cells)``: the cells the intruder may be in (flat, row-major)."""
    last_known: Sequence[int]
    """Per tick, the flat cell the intruder was last seen in; -1 before any."""
    contaminated_colour: tuple[int, int, int]
    """The dots of the contaminated set (the alert GIF's)."""
    last_known_colour: tuple[int, int, int]
    """The cross at the last known cell (the alert GIF's)."""
    suspicious: float = 0.5
    """The meter level at which a guard is suspicious (its bar turns orange)."""
    events: Sequence[tuple[int, int, str]] = ()
    """``(tick, guard, event)``, marked on the timeline (guard -1: the intruder's own)."""
    counts: Sequence[int] | None = None
    """Per tick, the contaminated set's size as read out; ``None``: counted from :attr:`contaminated` (a
    page drawn from a trace knows the sizes, not the cells)."""
    noises: Sequence[tuple[int, int, float]] = ()
    """``(tick, flat cell, radius in world units)``: each noise made, drawn as a ring of its radius around
    the cell's centre at the tick it is made (the tick it lasts)."""
    heard: np.ndarray | None = None
    """``bool (ticks, guards)``: whether each guard is investigating a noise it heard (its letter is then
    :attr:`heard_letter`)."""
    heard_letter: str = "H"
    """The letter over a guard that heard a noise (the alert GIF's)."""


@dataclass(frozen=True, eq=False)
class Overlays:
    """Everything a patrol or sneak page shows beyond its trace; every part optional."""

    idleness: IdlenessMap | None = None
    laps: LapViews | None = None
    routes: Sequence[Sequence[tuple[float, float]]] = ()
    """Each guard's loop as a closed polyline of world points (the route.json waypoints), drawn in the
    guard's dark shade, dashed over white (apart from its solid trail), under the animation."""
    intruder: Intruder | None = None
    exposure: IdlenessMap | None = None
    """A sneak's exposure map (fraction of the lap each cell is seen), drawn like :attr:`idleness`."""
    detection_time: IdlenessMap | None = None
    """A sneak's time-to-detection map (ticks a player standing still lasts; ``never`` never detected)."""
    safe: Sequence[SafeSpot] = ()
    alert: AlertLayers | None = None
    """An alert episode's guard states, meters, contaminated set and last known cell."""
    layers: Sequence[str] = field(default=())
    """Layers shown when the page opens (empty: the page's usual ones); ``#layers=...`` overrides."""
    watch: WatchLayers | None = None
    """A level's cameras and light."""


def _seen_runs(seen: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each cell's runs of seen lap ticks, ``[start, end]`` inclusive, as CSR arrays (cell-major):
    ``offsets`` (cells + 1), ``starts``, ``ends``."""
    period, cells = seen.shape
    padded = np.zeros((period + 2, cells), dtype=np.int8)
    padded[1:-1] = seen
    # Transposed, nonzero lists the changes cell by cell, in tick order within a cell.
    change = np.diff(padded, axis=0).T
    start_cell, starts = np.nonzero(change == 1)
    _, ends = np.nonzero(change == -1)
    offsets = np.concatenate([[0], np.cumsum(np.bincount(start_cell, minlength=cells))])
    return offsets, starts, ends - 1


def _worst_idleness(offsets: np.ndarray, starts: np.ndarray, ends: np.ndarray, period: int) -> np.ndarray:
    """``int64 (cells,)``: each cell's largest idleness over the lap, taken cyclically; -1 when never seen.

    Idleness climbs by one each unseen tick, so its largest value is the longest unseen run.
    """
    cells = offsets.size - 1
    worst = np.full(cells, -1, dtype=np.int64)
    counts = np.diff(offsets)
    has = counts > 0
    if not has.any():
        return worst
    first, last = offsets[:-1][has], offsets[1:][has] - 1
    worst[has] = starts[first] + period - ends[last] - 1
    inner = np.ones(starts.size, dtype=bool)
    inner[offsets[1:][has] - 1] = False  # a cell's last run has no next run within the lap
    owner = np.repeat(np.arange(cells), counts)
    gaps = np.zeros(starts.size, dtype=np.int64)
    gaps[inner] = starts[np.flatnonzero(inner) + 1] - ends[inner] - 1
    np.maximum.at(worst, owner[inner], gaps[inner])
    return worst


def _idleness_data(layer: IdlenessMap, shape: tuple[int, int], name: str = "idleness") -> dict[str, Any]:
    values = np.asarray(layer.values, dtype=np.float64)
    if values.shape != shape:
        raise GuardsimError(f"the {name} layer has shape {values.shape}, expected the trace's grid {shape}")
    never = np.zeros(shape, dtype=bool) if layer.never is None else np.asarray(layer.never, dtype=bool)
    if never.shape != shape:
        raise GuardsimError(
            f"the {name} layer's never cells have shape {never.shape}, expected the trace's grid {shape}"
        )
    drawn = np.isfinite(values) & ~never
    if (values[drawn] < 0).any():
        raise GuardsimError(f"the {name} layer has negative values (give NaN where nothing is drawn)")
    top = float(values[drawn].max()) if drawn.any() else 0.0
    return {
        # NaN (nothing drawn) travels as -1: the layers' values are never negative.
        "values": packed(np.where(drawn, values, -1.0), "f4"),
        "never": packed(never.ravel(), "u1"),
        "max": top if layer.top is None else float(layer.top),
        "unit": layer.unit,
        "label": layer.label,
        "never_text": layer.never_text,
    }


def _laps_data(laps: LapViews, trace: Trace) -> dict[str, Any]:
    seen = np.asarray(laps.seen, dtype=bool)
    cells = trace.shape[0] * trace.shape[1]
    if laps.period < 1 or seen.shape != (laps.period, cells):
        raise GuardsimError(
            f"the lap's views have shape {seen.shape}, expected ({laps.period}, {cells}) (one row per lap tick)"
        )
    if trace.steps < laps.period:
        raise GuardsimError(f"the trace holds {trace.steps} ticks, less than one lap of {laps.period}")
    offsets, starts, ends = _seen_runs(seen)
    worst = _worst_idleness(offsets, starts, ends, laps.period)[trace.goal.ravel()]
    return {
        "period": laps.period,
        "laps": max(1, laps.laps),
        "offsets": packed(offsets, "i4"),
        "starts": packed(starts, "i4"),
        "ends": packed(ends, "i4"),
        # The animated layer's colour bar runs from 0 to the largest idleness a goal cell reaches.
        "max": int(worst.max()) if worst.size and worst.max() > 0 else 0,
    }


def _intruder_data(intruder: Intruder, shape: tuple[int, int], guards: int) -> dict[str, Any]:
    rows, cols = shape
    cells = list(intruder.cells)
    if not cells:
        raise GuardsimError("the intruder's path is empty")
    if any(not (0 <= col < cols and 0 <= row < rows) for col, row in cells):
        raise GuardsimError(f"the intruder's path leaves the trace's grid of {cols} x {rows} cells")
    in_view = list(intruder.in_view) or [False] * len(cells)
    if len(in_view) != len(cells):
        raise GuardsimError(f"the intruder has {len(in_view)} in-view flags for {len(cells)} ticks of path")
    from guardsim.detection.model import INTRUDER_STATES  # here: a plain trace's page needs no detection

    data: dict[str, Any] = {
        "path": packed([row * cols + col for col, row in cells], "i4"),
        "start": int(intruder.start_tick),
        "in_view": packed(in_view, "u1"),
        "ticks_in_view": int(sum(in_view)),
        "from": None if intruder.source is None else [float(v) for v in intruder.source],
        "to": None if intruder.target is None else [float(v) for v in intruder.target],
        "label": intruder.label,
        "suspicious": float(intruder.suspicious),
        "detected_at": intruder.detected_at,
        "state_names": list(INTRUDER_STATES),
        "state_colours": {name: list(colour) for name, colour in STATE_COLOURS.items()},
    }
    if intruder.meters is not None:
        meters = np.asarray(intruder.meters, dtype=np.float64)
        if meters.ndim != 2 or meters.shape != (len(cells), guards):
            raise GuardsimError(
                f"the intruder's meters have shape {meters.shape}, expected ({len(cells)}, {guards}): "
                "a row per tick of its path, a column per guard"
            )
        # The peak: the first tick at which the highest meter is highest.
        highest = meters.max(axis=1) if guards else np.zeros(len(cells))
        step = int(np.argmax(highest))
        data["guards"] = guards
        data["meters"] = packed(meters.ravel(), "f4")
        data["peak"] = {"step": step, "value": float(highest[step])}
    if intruder.states:
        if len(intruder.states) != len(cells):
            raise GuardsimError(f"the intruder has {len(intruder.states)} states for {len(cells)} ticks of path")
        unknown = sorted(set(intruder.states) - set(INTRUDER_STATES))
        if unknown:
            raise GuardsimError(f"unknown intruder state {unknown[0]!r} (known: {', '.join(INTRUDER_STATES)})")
        data["states"] = packed([INTRUDER_STATES.index(state) for state in intruder.states], "u1")
    return data


def _safe_data(spots: Sequence[SafeSpot], shape: tuple[int, int]) -> list[dict[str, Any]]:
    rows, cols = shape
    if any(not (0 <= spot.cell[0] < cols and 0 <= spot.cell[1] < rows) for spot in spots):
        raise GuardsimError(f"a safe spot lies off the trace's grid of {cols} x {rows} cells")
    return [{"cell": [int(v) for v in spot.cell], "holds": bool(spot.holds), "label": spot.label} for spot in spots]


def _alert_data(alert: AlertLayers, trace: Trace) -> dict[str, Any]:
    guards = len(trace.team_paths())
    ticks = trace.steps + 1
    cells = trace.shape[0] * trace.shape[1]
    states = np.asarray(alert.states)
    meters = np.asarray(alert.meters, dtype=np.float64)
    contaminated = np.asarray(alert.contaminated, dtype=bool)
    for name, array, shape in (
        ("guard states", states, (ticks, guards)),
        ("meters", meters, (ticks, guards)),
        ("contaminated cells", contaminated, (ticks, cells)),
    ):
        if array.shape != shape:
            raise GuardsimError(f"the alert's {name} have shape {array.shape}, expected {shape} (a row per tick)")
    if len(alert.last_known) != ticks:
        raise GuardsimError(f"the alert has {len(alert.last_known)} last known cells for {ticks} ticks")
    if len(alert.state_letters) != len(alert.state_names):
        raise GuardsimError("the alert needs one letter per guard state")
    if states.size and not (states.min() >= 0 and states.max() < len(alert.state_names)):
        raise GuardsimError("the alert's guard states index past its state names")
    if any(not -1 <= cell < cells for cell in alert.last_known):
        raise GuardsimError(f"a last known cell lies off the trace's grid of {cells} cells")
    heard = np.zeros((ticks, guards), dtype=bool) if alert.heard is None else np.asarray(alert.heard, dtype=bool)
    if heard.shape != (ticks, guards):
        raise GuardsimError(f"the alert's heard flags have shape {heard.shape}, expected {(ticks, guards)}")
    if any(not (0 <= cell < cells and 0 <= tick < ticks) for tick, cell, _ in alert.noises):
        raise GuardsimError("a noise lies off the trace's grid or its ticks")
    return {
        "guards": guards,
        "states": packed(states.ravel(), "u1"),
        "state_names": list(alert.state_names),
        "state_letters": list(alert.state_letters),
        "meters": packed(meters.ravel(), "f4"),
        # A bit per cell, little-endian within each byte; each tick's row starts on a byte.
        "contaminated": packed(np.packbits(contaminated, axis=1, bitorder="little").ravel(), "u1"),
        "contaminated_stride": (cells + 7) // 8,
        "contaminated_counts": [int(count) for count in (contaminated.sum(axis=1) if alert.counts is None else alert.counts)],
        "last_known": packed(list(alert.last_known), "i4"),
        "contaminated_colour": list(alert.contaminated_colour),
        "last_known_colour": list(alert.last_known_colour),
        "suspicious": float(alert.suspicious),
        "events": [[int(tick), int(guard), str(event)] for tick, guard, event in alert.events],
        "noises": [[int(tick), int(cell), float(radius)] for tick, cell, radius in alert.noises],
        "heard": packed(heard.ravel().astype(np.uint8), "u1"),
        "heard_letter": alert.heard_letter,
        "state_colours": {name: list(colour) for name, colour in STATE_COLOURS.items()},
    }


def overlay_data(overlays: Overlays, trace: Trace) -> dict[str, Any]:
    """The page-data keys of ``overlays`` (JSON-ready), checked against ``trace``'s grid.

    Raises
    ------
    GuardsimError
        When a layer's shape does not match the trace.
    """
    data: dict[str, Any] = {"ramp": [[stop, list(colour)] for stop, colour in IDLENESS_RAMP]}
    if overlays.idleness is not None:
        data["idleness"] = _idleness_data(overlays.idleness, trace.shape)
    if overlays.laps is not None:
        data["laps"] = _laps_data(overlays.laps, trace)
    if overlays.routes:
        data["routes"] = [[[float(x), float(y)] for x, y in route] for route in overlays.routes]
    if overlays.intruder is not None:
        data["intruder"] = _intruder_data(overlays.intruder, trace.shape, len(trace.team_paths()))
    if overlays.exposure is not None:
        data["exposure"] = _idleness_data(overlays.exposure, trace.shape, "exposure")
    if overlays.detection_time is not None:
        data["detection_time"] = _idleness_data(overlays.detection_time, trace.shape, "time-to-detection")
    if overlays.safe:
        data["safe"] = _safe_data(overlays.safe, trace.shape)
        data["safe_colours"] = {name: list(colour) for name, colour in SAFE_COLOURS.items()}
    if overlays.alert is not None:
        data["alert"] = _alert_data(overlays.alert, trace)
    if overlays.layers:
        data["default_layers"] = list(overlays.layers)
    if overlays.watch is not None:
        data["watch"] = _watch_data(overlays.watch, trace.shape)
    return data


def _watch_data(watch: WatchLayers, shape: tuple[int, int]) -> dict[str, Any]:
    from guardsim.render.palette import DARK_ALPHA, WATCH_COLOURS

    data: dict[str, Any] = {
        "camera_colour": list(WATCH_COLOURS["camera"]),
        "dark_colour": list(WATCH_COLOURS["dark"]),
        "dark_alpha": DARK_ALPHA,
        "cameras": [
            {
                "position": [float(p[0]), float(p[1])],
                "headings": packed(np.asarray(headings), "f4"),
                "ticks": len(headings),
                "fov": float(fov),
                "range": float(reach),
            }
            for p, headings, fov, reach in watch.cameras
        ],
    }
    if watch.light is not None:
        light = np.asarray(watch.light, dtype=np.float64)
        if light.shape != shape:
            raise GuardsimError(f"the light map has shape {light.shape}, the trace's grid {shape}")
        data["light"] = packed(light.ravel(), "f4")
    if watch.meters is not None:
        meters = np.asarray(watch.meters, dtype=np.float64)
        if meters.ndim != 2 or meters.shape[1] != len(watch.cameras):
            raise GuardsimError(
                f"the cameras' meters have shape {meters.shape}, expected (ticks, {len(watch.cameras)})"
            )
        data["meters"] = packed(meters.ravel(), "f4")
    return data
