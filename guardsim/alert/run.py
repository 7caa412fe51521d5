"""Setting up and running alert episodes: one from given points, or many from seeded starts; their
traces as JSON and their summary per search strategy."""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.intruders import make_intruder, route_of_path
from guardsim.alert.model import AlertOutcome, AlertRules
from guardsim.alert.movement import ContinuousMovement, make_movement
from guardsim.detection import GuardDetection
from guardsim.detection.watch import level_watch
from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.kernels.distances import FAR, distances_from
from guardsim.motion.parameters import GuardMotion
from guardsim.patrol.model import Patrol
from guardsim.scene import Scene
from guardsim.sneak import FloorSight
from guardsim.vision.table import ViewTable, view_table

__all__ = [
    "DEFAULT_MAX_SECONDS",
    "AlertSummary",
    "alert_episode",
    "alert_trace_data",
    "plan_starts",
    "run_alerts",
    "summarise",
]

#: Seconds an alert episode may last when no limit is given.
DEFAULT_MAX_SECONDS = 300.0


def _shortest_path(grid: CoverageGrid, source: int, target: int) -> list[int]:
    field = distances_from(grid.neighbours, np.array([target], dtype=np.int64))
    if field[source] >= FAR:
        raise ArgumentError("the intruder's goal cannot be reached from its start")
    path, here = [source], source
    while here != target:
        here = min((int(n) for n in grid.neighbours[here] if n >= 0), key=lambda n: (field[n], n))
        path.append(here)
    return path


def alert_episode(
    scene: Scene,
    patrol: Patrol,
    *,
    intruder: str = "route",
    source: int,
    target: int = -1,
    route: Sequence[int] | None = None,
    search: str = "ripple",
    phase: int = 0,
    max_seconds: float = DEFAULT_MAX_SECONDS,
    table: ViewTable | None = None,
    rules: AlertRules | None = None,
    detection: GuardDetection | None = None,
    spotted: bool = False,
    motion: str | GuardMotion = "grid",
    gaits: Sequence[str] | None = None,
    distractions: Sequence[tuple[int, int, float]] = (),
) -> AlertEpisode:
    """An alert episode ready to :meth:`~AlertEpisode.step`: ``patrol``'s guards from lap tick ``phase``
    against an ``intruder`` entering at flat cell ``source`` and heading for ``target`` (-1: none).

    ``motion``: ``"grid"`` (a cell per tick), ``"continuous"`` (each guard a body in the scene's pymunk
    space walking at the level guard's speeds, looking from its pose every physics tick) or a
    :class:`~guardsim.motion.GuardMotion` (continuous, at those speeds); see
    :mod:`guardsim.alert.movement`. The decisions are made a grid tick at a time either way.

    A ``route`` intruder walks ``route`` (flat cells from ``source``) or else the shortest path to
    ``target``; a ``sneak`` intruder plans the fastest unseen path of the patrol's lap (the closest call
    when there is none) and enters the level at the tick that path starts (outside until then, unseen
    and out of reach), or at once when ``spotted``.

    ``gaits``: a route intruder's gait (``walk`` or ``sneak``) into each cell of ``route``;
    ``distractions``: noises away from the intruder, ``(tick, cell, radius in world units)``, that the
    guards who hear them investigate (see :class:`AlertEpisode`).
    """
    grid = scene.grid
    table = table if table is not None else view_table(grid, scene.vision())
    rules = rules if rules is not None else AlertRules.of_level(scene.level)
    detection = detection if detection is not None else GuardDetection.of_level(scene.level)
    wait = 0
    if intruder in ("route", "sneak") and target < 0 and route is None:
        raise ArgumentError(f"a {intruder} intruder needs a goal (or a route)")
    if intruder == "route" and route is None:
        route = _shortest_path(grid, source, target)
    if intruder == "sneak" and route is None:
        from guardsim.sneak import sneak_route

        heard = _lap_ears(grid, patrol, rules)
        sight = _lap_sight(grid, table, patrol, detection)
        path = sneak_route(sight, source, target, heard=heard, sneak_ticks=rules.sneak_ticks)
        if path is None:
            raise ArgumentError("the intruder's goal cannot be reached from its start")
        route, gaits = route_of_path(path.cells.tolist(), path.gaits)
        # Spotted, it is already in the level (seen at its entry); else it enters when its path starts.
        wait = 0 if spotted else (path.start_tick - phase) % int(patrol.period or 1)
    runner = make_intruder(
        intruder, grid.neighbours, source, goal=target, route=route, speed=rules.intruder_speed, wait_until=wait,
        gaits=gaits if intruder in ("route", "sneak") else None, sneak_ticks=rules.sneak_ticks,
        run_speed=rules.run_speed,
    )  # fmt: skip
    max_ticks = max(1, int(max_seconds / rules.dt + 1e-9))
    movement = make_movement(motion, scene, table, detection, dt=rules.dt, guards=patrol.guards)
    level = scene.level
    watch = level_watch(scene, detection.dt, gains=False) if level.cameras or not level.lit else None
    return AlertEpisode(
        grid,
        table,
        patrol,
        runner,
        rules=rules,
        detection=detection,
        search=search,
        phase=phase,
        max_ticks=max_ticks,
        spotted=spotted,
        movement=movement,
        watch=watch,
        distractions=distractions,
    )


_SIGHTS: dict[tuple[int, bytes, GuardDetection], tuple[ViewTable, FloorSight]] = {}
_SIGHTS_LOCK = threading.Lock()


def _lap_sight(grid: CoverageGrid, table: ViewTable, patrol: Patrol, detection: GuardDetection) -> FloorSight:
    """What the patrol sees over its lap, sparse and on the floor, as the sneak check reads it (the
    level's light and cameras left out: the intruder plans against the guards alone). A batch's episodes
    share one patrol, so the last one's is kept."""
    from guardsim.detection.sight import lap_sight
    from guardsim.sneak import check_sneak_size, floor_sight

    states = np.ascontiguousarray(patrol.states, dtype=np.int64)
    check_sneak_size(grid, states.shape[1])
    key = (id(table), hashlib.blake2b(states.tobytes(), digest_size=16).digest(), detection)
    with _SIGHTS_LOCK:
        kept = _SIGHTS.get(key)
    if kept is not None and kept[0] is table:
        return kept[1]
    sight = lap_sight(grid, table, states, detection.model, view_range=detection.view_range, dt=detection.dt)
    on_floor = floor_sight(sight, grid)
    del sight
    with _SIGHTS_LOCK:
        _SIGHTS.clear()
        _SIGHTS[key] = (table, on_floor)
    return on_floor


def _lap_ears(grid: CoverageGrid, patrol: Patrol, rules: AlertRules) -> np.ndarray | None:
    """Where and when the patrol hears each gait's step land (the sneak planner's ears), ``None`` when no
    walking step is ever heard (then walking is never worse than sneaking: the plan walks)."""
    from guardsim.detection.hearing import lap_hearing
    from guardsim.level.model import IntruderSpec

    if rules.walk_noise <= 0:
        return None
    ears = IntruderSpec(walk_noise=rules.walk_noise, sneak_ticks=rules.sneak_ticks, sneak_noise=rules.sneak_noise)
    heard = lap_hearing(grid.neighbours, patrol.states, ears, rules.cell_size)
    return heard if heard[0].any() else None


def alert_trace_data(
    episode: AlertEpisode,
    scene: Scene,
    *,
    search: str,
    intruder: str,
    index: int | None = None,
    seed: int | None = None,
) -> dict[str, Any]:
    """The episode's trace as JSON data: per tick each guard's cell, heading, state and meter, the
    intruder's cell and position, the contaminated count, and the events. ``phase`` (the lap tick the
    guards start at) and ``goal`` (the world position the intruder heads for, ``null`` for none) say how
    it started, and ``los``, ``fov``, ``view_range`` (``null``: unlimited) and ``suspicious`` what it
    saw with; an episode of a seeded batch also records its ``episode`` number and the batch's ``seed``
    (``guardsim alert --seed S --episode K`` runs it again). In continuous motion the
    cell is the one the body is in and the heading the nearest heading number. ``noises``: every noise
    made (tick, world position, radius, ``step`` or ``throw``); ``heard``: per guard and tick, whether it
    is investigating a noise. In continuous motion the trace adds
    ``motion``, the speeds, ``poses`` (per guard, ``[t, x, y, heading_degrees]`` at the end of each
    tick) and ``awareness_peak`` (per guard, the highest meter level during each tick)."""
    grid = scene.grid
    record = episode.record
    guards = len(episode.modes)

    def cell_pair(cell: int) -> list[int]:
        col, row = grid.unflat(cell)
        return [col, row]

    intruder_path = [None if cell is None else cell_pair(cell) for cell in record["intruder"]]
    data: dict[str, Any] = {
        "format": "guardsim alert trace",
        "level": scene.level.name,
        "cell_size": grid.cell_size,
        "origin": list(grid.origin),
        "shape": list(grid.shape),
        "dt": episode.rules.dt,
        "search": search,
        "intruder": intruder,
        "phase": episode.phase,
        # The vision and the suspicious level the episode ran with, so that its page can be drawn again.
        **scene.vision_record(),
        "suspicious": episode.detection.model.suspicious,
        "goal": None if episode.intruder.goal < 0 else list(grid.centre(*grid.unflat(episode.intruder.goal))),
        "outcome": episode.result()._asdict(),
        "paths": [[cell_pair(tick[g]) for tick in record["cells"]] for g in range(guards)],
        "headings": [[tick[g] for tick in record["headings"]] for g in range(guards)],
        "guard_states": [[tick[g] for tick in record["guard_states"]] for g in range(guards)],
        "awareness": [[tick[g] for tick in record["awareness"]] for g in range(guards)],
        "intruder_path": intruder_path,
        "intruder_positions": [None if cell is None else list(grid.centre(*cell)) for cell in intruder_path],
        "contaminated": record["contaminated"],
        "last_known": [None if cell < 0 else cell_pair(cell) for cell in record["last_known"]],
        "events": [{"tick": e.tick, "guard": e.guard, "event": e.event} for e in episode.events],
        "noises": [
            {"tick": tick, "position": list(grid.centre(*grid.unflat(cell))), "radius": radius, "source": source}
            for tick, cell, radius, source in episode.noises
        ],
        "heard": [[tick[g] for tick in record["heard"]] for g in range(guards)],
    }
    if index is not None and seed is not None:
        data.update(episode=index, seed=seed)
    movement = episode.movement
    if isinstance(movement, ContinuousMovement):
        motion = movement.motion
        data["motion"] = "continuous"
        data.update(move_speed=motion.move_speed, turn_speed=motion.turn_speed, tick_hz=motion.tick_hz)
        data["paths"] = [
            [None if tick[g] < 0 else cell_pair(tick[g]) for tick in record["cells"]] for g in range(guards)
        ]
        data["poses"] = [
            [
                [round(tick * episode.rules.dt, 6), *(round(v, 6) for v in poses[g])]
                for tick, poses in enumerate(record["poses"])
            ]
            for g in range(guards)
        ]
        data["awareness_peak"] = [[tick[g] for tick in record["awareness_peak"]] for g in range(guards)]
    return data


class AlertSummary(NamedTuple):
    """One search strategy over many episodes (means over the episodes where the moment happened)."""

    search: str
    episodes: int
    detected: int
    captured: int
    capture_rate: float
    """Captures per episode with a detection."""
    time_to_capture: float | None
    """Seconds from the first detection to the capture."""
    searching: float
    reacquire: float | None
    back_on_route: float | None
    """Seconds from the first detection until every guard is back on its route."""
    detections: float


def _mean(values: list[float]) -> float | None:
    return round(float(np.mean(values)), 3) if values else None


def summarise(search: str, outcomes: Sequence[AlertOutcome]) -> AlertSummary:
    """The table row of ``search`` over ``outcomes``."""
    detected = [o for o in outcomes if o.detected_at is not None]
    captured = [o for o in detected if o.captured_at is not None]
    return AlertSummary(
        search,
        len(outcomes),
        len(detected),
        len(captured),
        round(len(captured) / len(detected), 3) if detected else 0.0,
        _mean(
            [o.captured_at - o.detected_at for o in captured if o.captured_at is not None and o.detected_at is not None]
        ),
        _mean([o.searching for o in detected]) or 0.0,
        _mean([o.reacquired_after for o in detected if o.reacquired_after is not None]),
        _mean(
            [
                o.back_on_route_at - o.detected_at
                for o in detected
                if o.back_on_route_at is not None and o.detected_at is not None
            ]
        ),
        _mean([float(o.detections) for o in detected]) or 0.0,
    )


def _seeded_points(
    scene: Scene, patrol: Patrol, generator: np.random.Generator, *, table: ViewTable | None = None, phase: int = 0
) -> tuple[int, int]:
    """An entry and a goal on the guards' area, drawn apart (at least a third of the area's diameter).

    With ``table``, the entry is drawn among the cells some guard sees at lap tick ``phase``, at least 3
    cells from it (any seen cell when there is none; any cell when no guard sees one)."""
    grid = scene.grid
    label = grid.component_labels[int(patrol.states[0, 0]) // 4]
    cells = np.flatnonzero(grid.component_labels == label)
    pool = cells
    if table is not None:
        seen: set[int] = set()
        near: set[int] = set()
        cols = grid.shape[1]
        for guard in range(patrol.guards):
            state = patrol.state(guard, phase)
            row, col = divmod(state // 4, cols)
            for cell in table.sees(state).tolist():
                (seen if (cell // cols - row) ** 2 + (cell % cols - col) ** 2 >= 9 else near).add(cell)
        chosen = seen or near
        if chosen:
            pool = np.array(sorted(chosen), dtype=np.int64)
    source = int(pool[generator.integers(pool.size)])
    far = distances_from(grid.neighbours, np.array([source], dtype=np.int64))[cells]
    apart = cells[far >= max(1, int(far.max()) // 3)]
    return source, int(apart[generator.integers(apart.size)])


def plan_starts(
    scene: Scene,
    patrol: Patrol,
    *,
    episodes: int = 1,
    seed: int = 0,
    source: int | None = None,
    target: int | None = None,
    spotted: bool = False,
    phase: int | None = None,
    table: ViewTable | None = None,
) -> list[tuple[int, int, int]]:
    """``(lap tick, entry, goal)`` of episodes ``0 .. episodes - 1``: the patrol phase given or seeded,
    and the entry and goal given or drawn (see :func:`_seeded_points`), in order from one generator of
    ``seed``; every search strategy plays the same starts. With ``spotted``, a drawn entry lies in some
    guard's view at the start."""
    if spotted and table is None:
        table = view_table(scene.grid, scene.vision())
    generator = np.random.default_rng(seed)
    starts = []
    for _ in range(episodes):
        if source is not None and target is not None and phase is not None:
            starts.append((phase, source, target))
            continue
        lap = int(generator.integers(int(patrol.period or 1))) if phase is None else phase
        drawn = _seeded_points(scene, patrol, generator, table=table if spotted else None, phase=lap)
        starts.append((lap, drawn[0] if source is None else source, drawn[1] if target is None else target))
    return starts


def run_alerts(
    scene: Scene,
    patrol: Patrol,
    *,
    intruder: str = "evader",
    searches: Sequence[str] = ("ripple",),
    episodes: int = 1,
    seed: int = 0,
    source: int | None = None,
    target: int | None = None,
    max_seconds: float = DEFAULT_MAX_SECONDS,
    rules: AlertRules | None = None,
    detection: GuardDetection | None = None,
    spotted: bool = False,
    phase: int | None = None,
    route: Sequence[int] | None = None,
    table: ViewTable | None = None,
    motion: str | GuardMotion = "grid",
    gaits: Sequence[str] | None = None,
    distractions: Sequence[tuple[int, int, float]] = (),
) -> dict[str, list[AlertEpisode]]:
    """Episodes ``0 .. episodes - 1`` of each search strategy, the same starts for every strategy
    (:func:`plan_starts`), run here one after the other. With ``spotted``, a drawn entry lies in some
    guard's view at the start and that guard detects the intruder at tick 0 (see :class:`AlertEpisode`).
    ``route``: a route intruder's path (from ``source``); ``motion``, ``gaits`` and ``distractions``:
    :func:`alert_episode`'s.
    :mod:`guardsim.alert.batch` runs the same episodes on worker processes or a Dask cluster."""
    table = table if table is not None else view_table(scene.grid, scene.vision())
    starts = plan_starts(
        scene, patrol, episodes=episodes, seed=seed, source=source, target=target, spotted=spotted, phase=phase,
        table=table,
    )  # fmt: skip
    out: dict[str, list[AlertEpisode]] = {}
    for name in searches:
        runs = []
        for lap, entry, goal in starts:
            episode = alert_episode(
                scene,
                patrol,
                intruder=intruder,
                source=entry,
                target=-1 if intruder == "still" else goal,
                route=route,
                search=name,
                phase=lap,
                max_seconds=max_seconds,
                table=table,
                rules=rules,
                detection=detection,
                spotted=spotted,
                motion=motion,
                gaits=gaits,
                distractions=distractions,
            )
            episode.run()
            runs.append(episode)
        out[name] = runs
    return out
