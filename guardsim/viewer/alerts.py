"""The viewer page of an alert episode (``guardsim alert --html``): the guards' walk as the trace, the
intruder, and the alert layers (each guard's state and meter, the contaminated set, the last known cell).

Downstream of :mod:`guardsim.alert`, which never imports the viewer. The colours and letters are the
alert GIF's (:mod:`guardsim.render.alert`), from the one palette.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.model import GUARD_STATES
from guardsim.alert.recorded import RecordedEpisode, recorded_episode
from guardsim.alert.trace import guard_trace
from guardsim.detection import intruder_state
from guardsim.kernels.steps import state_of
from guardsim.level import Level
from guardsim.patrol.model import Patrol
from guardsim.render.alert import CONTAMINATED_INDEX, HEARD_LETTER, LAST_KNOWN_INDEX, STATE_LETTERS
from guardsim.render.palette import PALETTE
from guardsim.scene import Scene
from guardsim.viewer.layers import AlertLayers, Intruder, Overlays
from guardsim.viewer.page import write_viewer
from guardsim.viewer.patrols import patrol_routes, watch_layers
from guardsim.vision.table import ViewTable

__all__ = ["ALERT_LAYERS", "alert_overlays", "write_alert_page", "write_alert_trace_page"]

#: Layers an alert page opens with: the routes, the cones, the contaminated set, the last known cell,
#: the intruder, each guard's meter and state, and the noises made (when there are any).
ALERT_LAYERS = ("route", "trail", "cone", "contaminated", "last-known", "intruder", "meters", "states", "noises")


def alert_overlays(
    scene: Scene,
    table: ViewTable,
    episode: AlertEpisode | RecordedEpisode,
    *,
    patrol: Patrol | None = None,
    suspicious: float = 0.5,
) -> Overlays:
    """The page layers of ``episode`` (the page's tick ``t`` is the episode's tick ``t``)."""
    grid = scene.grid
    record = episode.record
    ticks = len(record["cells"])
    guards = len(episode.modes)
    meters = np.asarray(record["awareness"], dtype=np.float64).reshape(ticks, guards)
    # The intruder while it is in the level (a sneak enters when its path starts; any leaves at its goal),
    # and whether some guard sees it.
    start = next((tick for tick, cell in enumerate(record["intruder"]) if cell is not None), 0)
    cells = []
    for cell in record["intruder"][start:]:
        if cell is None:
            break
        cells.append(int(cell))
    ticks_in = range(start, start + len(cells))
    in_view = [
        any(
            _sees(table, record["cells"][tick][guard], record["headings"][tick][guard], cell) for guard in range(guards)
        )
        for tick, cell in zip(ticks_in, cells, strict=True)
    ]
    detected_at = next((e.tick for e in episode.events if e.event == "detected"), None)
    states = [
        intruder_state(list(meters[tick]), seen, suspicious, detected_at is not None and tick >= detected_at)
        for tick, seen in zip(ticks_in, in_view, strict=True)
    ]
    goal = episode.intruder.goal
    intruder = Intruder(
        [grid.unflat(cell) for cell in cells],
        start,
        in_view=in_view,
        source=grid.centre(*grid.unflat(cells[0])) if cells else None,
        target=grid.centre(*grid.unflat(goal)) if goal >= 0 else None,
        label="intruder",
        states=states,
        suspicious=suspicious,
        detected_at=detected_at,
    )
    contaminated = np.zeros((ticks, grid.size), dtype=bool)
    for tick, found in enumerate(record["contaminated_cells"]):
        contaminated[tick, found] = True
    alert = AlertLayers(
        states=np.asarray([[GUARD_STATES.index(s) for s in row] for row in record["guard_states"]], dtype=np.uint8),
        state_names=GUARD_STATES,
        state_letters=[STATE_LETTERS[name] for name in GUARD_STATES],
        meters=meters,
        contaminated=contaminated,
        last_known=[int(cell) for cell in record["last_known"]],
        contaminated_colour=PALETTE[CONTAMINATED_INDEX],
        last_known_colour=PALETTE[LAST_KNOWN_INDEX],
        suspicious=suspicious,
        events=[(e.tick, e.guard, e.event) for e in episode.events],
        counts=[int(count) for count in record["contaminated"]],
        # The episode's own noises and hearing, as the alert GIF reads them.
        noises=[(int(tick), int(cell), float(radius)) for tick, cell, radius, _ in episode.noises if tick < ticks],
        heard=np.asarray(record["heard"], dtype=bool).reshape(ticks, guards) if record.get("heard") else None,
        heard_letter=HEARD_LETTER,
    )
    watch = episode.cameras.watch
    layers = None
    if watch is not None:
        # The page's tick t is the cameras' swing tick phase + t; their meters are drawn while the intruder is in.
        phase = episode.phase
        rolled = watch._replace(
            cameras=tuple(
                sight._replace(headings=np.roll(sight.headings, -(phase % len(sight.headings))))
                for sight in watch.cameras
            )
        )
        kept = record.get("camera_awareness")
        meters_in = None if not kept else np.asarray(kept, dtype=np.float64)[start : start + len(cells)]
        layers = watch_layers(rolled, grid, meters_in if cells else None)
    return Overlays(
        routes=() if patrol is None else patrol_routes(patrol, grid),
        intruder=intruder if cells else None,
        alert=alert,
        layers=ALERT_LAYERS if layers is None else (*ALERT_LAYERS, "light", "cameras"),
        watch=layers,
    )


def _sees(table: ViewTable, cell: int, heading: int, target: int) -> bool:
    seen = table.sees(int(state_of(cell, heading)))
    index = int(np.searchsorted(seen, target))
    return index < seen.size and int(seen[index]) == target


def write_alert_page(
    path: str | Path,
    scene: Scene,
    table: ViewTable,
    episode: AlertEpisode | RecordedEpisode,
    *,
    patrol: Patrol | None = None,
    suspicious: float = 0.5,
) -> None:
    """Write the viewer page of ``episode`` to ``path`` (atomically); ``patrol`` adds the guards' routes."""
    trace = guard_trace(scene, table, episode)
    overlays = alert_overlays(scene, table, episode, patrol=patrol, suspicious=suspicious)
    # In continuous motion the guards are drawn, and look, from their bodies' poses at each tick.
    poses = np.asarray(episode.record["poses"], dtype=np.float64) if "poses" in episode.record else None
    write_viewer(
        path, scene.level, trace, overlays=overlays, guard_poses=None if poses is None else poses.transpose(1, 0, 2)
    )


def write_alert_trace_page(
    path: str | Path,
    level: Level,
    data: dict[str, Any],
    *,
    patrol_path: str | None = None,
    source: str = "trace",
) -> RecordedEpisode:
    """Write the viewer page of a saved alert trace (``data``, :func:`~guardsim.alert.alert_trace_data`,
    read from ``source``) played on ``level``, with the vision and suspicious level it records; the
    patrol at ``patrol_path`` adds the guards' routes. The page has no search-area dots: a trace keeps the
    search area's size, not its cells (:mod:`guardsim.alert.recorded`). Returns the episode read back."""
    from guardsim.detection import GuardDetection
    from guardsim.patrol import read_patrol
    from guardsim.vision.table import view_table

    scene = Scene.from_level(level, **Scene.recorded_vision(data))
    episode = recorded_episode(data, scene.grid, source=source)
    patrol = None if patrol_path is None else read_patrol(patrol_path, scene.grid, level=level.name)
    suspicious = data.get("suspicious", GuardDetection.of_level(level).model.suspicious)
    write_alert_page(path, scene, view_table(scene.grid, scene.vision()), episode, patrol=patrol, suspicious=suspicious)
    return episode
