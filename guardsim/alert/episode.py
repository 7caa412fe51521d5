"""One alert episode: patrolling guards with awareness meters against an intruder, tick by tick.

A tick, in order: the intruder moves; every guard moves by its state; every guard looks and its meter
is updated (the detection model); states change (see :mod:`guardsim.alert.model`); a detection
reaches the other guards ``radio_delay`` later; the contaminated set spreads by the intruder's reach
and loses every cell in view; a chasing guard within ``capture_radius`` captures.

**Rejoining the route.** A guard entering ``return`` at tick ``t`` picks the smallest ``k >= 1`` such that
it can walk to where its patrol puts it at tick ``t + k`` in at most ``k`` steps, walks there (waiting if
early) and is exactly on its route, at the phase it would have reached had it never left, from then on.

**Motion.** Where a guard is and what it sees is the movement's (:mod:`guardsim.alert.movement`): on the
grid, or as a body in the physics world. The decisions above are the same in both, a grid tick at a
time. Each guard keeps a *route clock*, the grid ticks on which it took a decision; its patrol and its
rejoining run on that clock. On the grid a guard decides every tick, so its clock is the tick; in
continuous motion a guard whose body is still catching up (turns take time) skips a decision, and its
clock stands still.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from guardsim.alert.intruders import Intruder
from guardsim.alert.model import AlertEvent, AlertOutcome, AlertRules
from guardsim.alert.movement import ContinuousMovement, GridMovement, Movement
from guardsim.alert.search import Contamination, make_search
from guardsim.detection import AwarenessMeter, GuardDetection
from guardsim.detection.watch import CameraAlarms, LevelWatch
from guardsim.grid import CoverageGrid
from guardsim.kernels.distances import distances_from
from guardsim.kernels.steps import cell_of_state, greedy_step, heading_of_state
from guardsim.patrol.model import Patrol
from guardsim.vision.table import ViewTable

__all__ = ["AlertEpisode"]


class AlertEpisode:
    """Guards walking ``patrol`` (from lap tick ``phase``) against ``intruder``; :meth:`step` advances a tick.

    ``spotted``: every guard that sees the intruder at tick 0 starts with a full meter (it is detected at
    once), as the experiments of docs/results.md start.

    ``movement``: where the guards are and what they see (:mod:`guardsim.alert.movement`); the grid's by
    default.

    The per-tick record (:attr:`record`) is what :func:`guardsim.alert.trace.alert_trace_data` writes.
    """

    def __init__(
        self,
        grid: CoverageGrid,
        table: ViewTable,
        patrol: Patrol,
        intruder: Intruder,
        *,
        rules: AlertRules,
        detection: GuardDetection,
        search: str = "ripple",
        phase: int = 0,
        max_ticks: int = 600,
        spotted: bool = False,
        movement: Movement | None = None,
        watch: LevelWatch | None = None,
    ) -> None:
        if patrol.period is None:
            raise ValueError("an alert episode needs a repeating patrol (its period is null)")
        self.grid, self.table, self.patrol, self.intruder = grid, table, patrol, intruder
        self.rules, self.detection = rules, detection
        self.neighbours = np.ascontiguousarray(grid.neighbours, dtype=np.int64)
        self.search = make_search(search, self.neighbours)
        self.phase = int(phase)
        self.max_ticks = int(max_ticks)
        self.contamination = Contamination(self.neighbours)
        guards = patrol.guards
        self.movement: Movement = movement if movement is not None else GridMovement(grid, table, detection, guards)
        self.cameras = CameraAlarms(watch, detection, guards)
        if watch is not None and watch.dark and isinstance(self.movement, GridMovement | ContinuousMovement):
            self.movement.light = watch.light
        self.tick = 0
        self._clock = [0] * guards
        """Per guard: its route clock (see the module)."""
        self.modes = ["patrol"] * guards
        self.meters = [AwarenessMeter(detection.model, detection.view_range) for _ in range(guards)]
        self.cells = [0] * guards
        self.headings = [0] * guards
        self.events: list[AlertEvent] = []
        self.last_known = -1
        self.done = False
        self.outcome = "time_limit"
        self._noticed = [-1] * guards
        self._rising = [0] * guards
        self._look = [0] * guards
        self._since = [0] * guards
        self._rejoin: list[tuple[int, int, int, np.ndarray] | None] = [None] * guards
        """Per guard in ``return``: the tick it decided, the tick and cell it rejoins at, the field there."""
        self._radio_at = -1
        self._left_route = False
        self._stats: dict[str, Any] = {"detected": None, "captured": None, "lost": None, "reacquired": None}
        self._stats.update({"gave_up": None, "back": None, "detections": 0, "searching": 0})
        self.seen_now: np.ndarray = np.zeros(0, dtype=np.int32)
        self.in_sight = [False] * guards
        self.record: dict[str, list[Any]] = {
            "cells": [],
            "headings": [],
            "guard_states": [],
            "awareness": [],
            "intruder": [],
            "contaminated": [],
            "last_known": [],
            "contaminated_cells": [],
        }
        if isinstance(self.movement, ContinuousMovement):
            self.record.update({"poses": [], "awareness_peak": []})
        for guard in range(guards):
            state = patrol.state(guard, self.phase)
            self.cells[guard], self.headings[guard] = int(cell_of_state(state)), int(heading_of_state(state))
        self.movement.follow(self.cells, self.headings)
        for guard in range(guards):
            if spotted and intruder.present and self.movement.sees_at_start(guard, intruder.cell):
                meter = self.meters[guard]
                meter.level = meter.peak = 1.0  # the experiments' "detected mid-level": the meter starts full
        self._look_and_update()
        self._record()

    # -- one tick ---------------------------------------------------------------------------------

    def step(self) -> None:
        """Advance one tick."""
        if self.done:
            return
        self.tick += 1
        chased = "chase" in self.modes
        alarmed = chased or "search" in self.modes
        self.intruder.advance(self.tick, self.cells, chased, alarmed)
        if self.intruder.gone and not any(e.event == "arrived" for e in self.events):
            self.events.append(AlertEvent(self.tick, -1, "arrived"))
        self._move_guards()
        self.movement.follow(self.cells, self.headings)
        self._look_and_update()
        self._record()
        self._finish()
        if self.done:
            self.movement.close()

    def run(self) -> AlertOutcome:
        """Step until the episode ends; its outcome."""
        while not self.done:
            self.step()
        return self.result()

    def close(self) -> None:
        """Give back what the movement took from the scene (continuous motion: the guards' bodies in its
        space), as the end of the episode does; for an episode left unfinished."""
        self.movement.close()

    def _move_guards(self) -> None:
        tick = self.tick
        chase_field: np.ndarray | None = None
        deciding = [self.movement.ready(g) for g in range(len(self.modes))]
        searchers = {g: self.cells[g] for g, mode in enumerate(self.modes) if mode == "search" and deciding[g]}
        fields = self.search.fields(searchers) if searchers else {}
        for guard, mode in enumerate(self.modes):
            if not deciding[guard]:
                continue
            self._clock[guard] += 1
            if mode == "patrol":
                state = self.patrol.state(guard, self._clock[guard] + self.phase)
                self.cells[guard], self.headings[guard] = int(cell_of_state(state)), int(heading_of_state(state))
            elif mode == "suspicious":
                self.headings[guard] = self._facing(self.cells[guard], self._noticed[guard], self.headings[guard])
            elif mode == "investigate":
                if self.cells[guard] == self._noticed[guard]:
                    self._look[guard] += 1
                    self.headings[guard] = (self.headings[guard] + 1) % 4
                    if self._look[guard] >= 4:
                        self._enter_return(guard)
                else:
                    self._walk(guard, distances_from(self.neighbours, np.array([self._noticed[guard]])))
            elif mode == "chase":
                if chase_field is None:
                    chase_field = distances_from(self.neighbours, np.array([self.last_known]))
                self._walk(guard, chase_field)
            elif mode == "search":
                field = fields.get(guard)
                if field is None or tick - self._since[guard] >= self.rules.search_ticks:
                    self.events.append(AlertEvent(tick, guard, "gave_up"))
                    if self._stats["gave_up"] is None:
                        self._stats["gave_up"] = tick
                    self._enter_return(guard)
                else:
                    self._walk(guard, field)
            if self.modes[guard] == "return":
                self._walk_back(guard)

    def _walk(self, guard: int, field: np.ndarray) -> None:
        """One step down ``field``; at its bottom, turn in place to look around."""
        cell = self.cells[guard]
        direction = greedy_step(field, self.neighbours[cell], self.headings[guard])
        if direction >= 0 and field[self.neighbours[cell, direction]] < field[cell]:
            self.cells[guard] = int(self.neighbours[cell, direction])
            self.headings[guard] = direction
        else:
            self.headings[guard] = (self.headings[guard] + 1) % 4

    def _enter_return(self, guard: int) -> None:
        self.modes[guard] = "return"
        here, clock = self.cells[guard], self._clock[guard]
        steps = distances_from(self.neighbours, np.array([here]))
        for k in range(1, 2 * self.patrol.ticks + self.grid.size + 1):
            cell = int(cell_of_state(self.patrol.state(guard, clock + k + self.phase)))
            if steps[cell] <= k:
                self._rejoin[guard] = (
                    clock,
                    clock + k,
                    cell,
                    distances_from(self.neighbours, np.array([cell])),
                )
                return
        raise RuntimeError("no tick of the patrol is reachable")  # the route lies in the guard's area

    def _walk_back(self, guard: int) -> None:
        plan = self._rejoin[guard]
        if plan is None:
            return
        entered, rejoin_tick, cell, field = plan
        clock = self._clock[guard]
        if clock <= entered:  # the first step back comes the tick after the decision
            return
        if self.cells[guard] != cell:
            self._walk(guard, field)
        if clock >= rejoin_tick:
            state = self.patrol.state(guard, clock + self.phase)
            self.cells[guard], self.headings[guard] = int(cell_of_state(state)), int(heading_of_state(state))
            self.modes[guard] = "patrol"
            self._rejoin[guard] = None
            self.events.append(AlertEvent(self.tick, guard, "back_on_route"))

    def _facing(self, cell: int, target: int, heading: int) -> int:
        """The heading that looks most directly toward ``target`` (``heading`` when there is none)."""
        if target < 0 or target == cell:
            return heading
        cols = self.grid.shape[1]
        (row, col), (to_row, to_col) = divmod(cell, cols), divmod(target, cols)
        dx, dy = to_col - col, to_row - row
        if abs(dx) >= abs(dy):
            return 0 if dx > 0 else 2
        return 1 if dy > 0 else 3

    # -- looking ----------------------------------------------------------------------------------

    def _look_and_update(self) -> None:
        tick = self.tick
        intruder = self.intruder.cell if self.intruder.present else -1
        look = self.movement.look(tick, intruder, self.meters)
        self.in_sight = list(look.seen)
        self.seen_now = look.cells
        chasing_before = "chase" in self.modes
        alarms = self.cameras.look(self.phase + tick, intruder)
        for camera in alarms:
            # The alarm tells every guard where the intruder is now, as a guard's detection tells its team.
            self.events.append(AlertEvent(tick, camera, "alarm"))
            self.last_known = intruder
            self._stats["detected"] = tick if self._stats["detected"] is None else self._stats["detected"]
            self._radio_at = tick
        for guard, mode in enumerate(self.modes):
            meter, seen = self.meters[guard], self.in_sight[guard]
            if look.spotted[guard]:
                self.last_known = intruder
                if mode != "chase":
                    self._enter_chase(guard, chasing_before)
            elif mode == "chase":
                self.modes[guard] = "search"
                self._since[guard] = tick
                self.events.append(AlertEvent(tick, guard, "lost"))
                if self._stats["lost"] is None:
                    self._stats["lost"] = tick
            elif mode == "patrol" and meter.suspicious:
                self.modes[guard] = "suspicious"
                self._noticed[guard], self._rising[guard] = intruder, 0
                self._left_route = True
                self.events.append(AlertEvent(tick, guard, "noticed"))
            elif mode == "suspicious":
                if meter.level <= 0:
                    self._enter_return(guard)
                elif seen:
                    self._noticed[guard] = intruder
                    self._rising[guard] += 1
                    if self._rising[guard] >= 2:
                        self.modes[guard], self._look[guard] = "investigate", 0
                else:
                    self._rising[guard] = 0
            elif mode == "investigate" and seen:
                self._noticed[guard] = intruder
        if self._radio_at == tick:
            for guard, mode in enumerate(self.modes):
                if mode in ("patrol", "suspicious", "investigate", "return"):
                    self.modes[guard], self._since[guard], self._rejoin[guard] = "search", tick, None
                    self._left_route = True
                    self.events.append(AlertEvent(tick, guard, "joined"))
        if self.last_known >= 0:
            if alarms or any(self.in_sight[g] and self.modes[g] == "chase" for g in range(len(self.modes))):
                self.contamination.seed(self.last_known)  # in sight: exactly where it is
                self.search.start(self.last_known)
            else:
                cleared = self.seen_now
                if intruder >= 0 and any(self.in_sight):
                    # A guard whose meter rose this tick saw something there: not a cell to mark clear.
                    cleared = cleared[cleared != intruder]
                self.contamination.spread(self._reach())
                self.contamination.clear(cleared)
                self.search.observe(self.contamination, cleared)
        if intruder >= 0:
            for guard, mode in enumerate(self.modes):
                # A guard that lost sight at arm's length (the cone turned away) still grabs.
                alarmed = mode == "chase" or (mode == "search" and self.meters[guard].detected)
                if alarmed and self.movement.distance(guard, intruder) <= self.rules.capture_radius + 1e-9:
                    self.events.append(AlertEvent(tick, guard, "captured"))
                    self._stats["captured"] = tick
                    self.outcome, self.done = "captured", True
                    break

    def _enter_chase(self, guard: int, chasing_before: bool) -> None:
        tick = self.tick
        first = self._stats["detected"] is None
        self.modes[guard] = "chase"
        self._rejoin[guard] = None
        self._left_route = True
        self.events.append(AlertEvent(tick, guard, "detected"))
        if not chasing_before and "chase" not in [m for g, m in enumerate(self.modes) if g != guard]:
            self._stats["detections"] += 1
            if self._stats["lost"] is not None and self._stats["reacquired"] is None:
                self._stats["reacquired"] = tick
        if first:
            self._stats["detected"] = tick
        if self._radio_at < tick:
            self._radio_at = tick + self.rules.radio_ticks

    def _reach(self) -> int:
        speed = self.rules.intruder_speed
        return math.floor(self.tick * speed + 1e-9) - math.floor((self.tick - 1) * speed + 1e-9)

    # -- ending and recording ---------------------------------------------------------------------

    def _finish(self) -> None:
        if self.done:
            return
        if "search" in self.modes:
            self._stats["searching"] += 1
        calm = all(mode == "patrol" for mode in self.modes)
        if self.intruder.gone and self._stats["detected"] is None:
            self.outcome, self.done = "undetected_arrival", True
        elif self._stats["detected"] is not None and calm:
            self._stats["back"] = self.tick
            self.outcome, self.done = ("escaped" if self.intruder.gone else "hidden"), True
        elif self.tick >= self.max_ticks:
            self.done = True

    def _record(self) -> None:
        record = self.record
        cells, headings = self.movement.recorded()
        record["cells"].append(cells)
        record["headings"].append(headings)
        if isinstance(self.movement, ContinuousMovement):
            movement = self.movement
            record["poses"].append([movement.pose(guard) for guard in range(len(self.modes))])
            record["awareness_peak"].append([round(peak, 4) for peak in movement.peaks])
        record["guard_states"].append(list(self.modes))
        record["awareness"].append([round(m.level, 4) for m in self.meters])
        record["intruder"].append(self.intruder.cell if self.intruder.present else None)
        record["contaminated"].append(self.contamination.count)
        record["contaminated_cells"].append(np.flatnonzero(self.contamination.cells).astype(np.int32))
        record["last_known"].append(self.last_known)

    def result(self) -> AlertOutcome:
        """The episode's outcome so far."""
        dt, stats = self.rules.dt, self.stats_seconds()
        return AlertOutcome(
            self.outcome,
            self.tick,
            round(self.tick * dt, 6),
            stats["detected"],
            stats["captured"],
            round(self._stats["searching"] * dt, 6),
            None
            if stats["reacquired"] is None or stats["lost"] is None
            else round(stats["reacquired"] - stats["lost"], 6),
            stats["gave_up"],
            stats["back"],
            int(self._stats["detections"]),
        )

    @property
    def route_clocks(self) -> list[int]:
        """Per guard: the grid ticks on which it took a decision, the clock its patrol runs on (see the
        module); each is :attr:`tick` in grid motion."""
        return list(self._clock)

    def stats_seconds(self) -> dict[str, float | None]:
        """The episode's moments in seconds."""
        dt = self.rules.dt
        keys = ("detected", "captured", "lost", "reacquired", "gave_up", "back")
        return {k: None if self._stats[k] is None else round(self._stats[k] * dt, 6) for k in keys}
