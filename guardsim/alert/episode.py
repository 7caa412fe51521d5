"""One alert episode: patrolling guards with awareness meters against an intruder, tick by tick.

A tick, in order: the intruder moves; every guard moves by its state; every guard looks and its meter
is updated (the detection model); states change (see :mod:`guardsim.alert.model`); a detection
reaches the other guards ``radio_delay`` later; the contaminated set spreads by the intruder's reach
and loses every cell in view; a chasing guard within ``capture_radius`` captures.

**Rejoining the route.** A guard entering ``return`` at tick ``t`` picks the smallest ``k >= 1`` such that
it can walk to where its patrol puts it at tick ``t + k`` in at most ``k - 1`` steps (the tick to spare
turns it to the route's heading: a guard never takes a heading in the tick it steps another way), walks
there (waiting if early) and is exactly on its route, at the phase it would have reached had it never
left, from then on. A guard kept from its rejoining cell (see personal space) plans again.

**Game-guard rules** (what :mod:`guardsim.alert.invariants` checks on traces):

- *Running.* A chasing guard runs at ``chase_speed`` times walking: on the grid, chase tick ``k`` (from 1)
  takes ``floor(k * chase_speed) - floor((k - 1) * chase_speed)`` steps (1.5: one and two steps in turn),
  an extra step only straight on (a runner does not turn within a tick); in continuous motion the body
  walks that much faster.
- *Cutting off.* While a chasing guard sees the intruder, the chaser nearest it (in steps) follows it;
  every other chasing or searching guard runs for the first cell of the intruder's likely escape (from
  the last known cell away from the lead, straight on where it can) that it reaches no later than the
  intruder, or follows when it is within two cells of it.
- *Giving up.* The ``give_up_losses``-th time a guard loses sight of the intruder it chases, it
  searches and never chases that intruder again (it may still grow suspicious and investigate).
- *Searching.* Each searcher commits to one cell its strategy's field wants looked at (the field's
  bottom), the one with the fewest steps plus a cost per cell behind the last known cell (against the
  intruder's last seen direction of travel) and near another searcher's cell
  (:func:`guardsim.alert.steering.search_cell`), and keeps it until it is seen. A cell it can see by
  turning where it stands, it turns to look at rather than walks to.
- *Personal space.* A guard that is not chasing does not step within one cell (the same cell or a
  4-neighbour) of another guard unless one of the two cells is a corridor one cell wide; it takes the
  next best step or turns. Two guards that have stayed within one cell for :data:`STEP_ASIDE_TICKS`
  ticks anyway (one came to the other) part: the one not patrolling (or the higher numbered) steps
  away, and returns to its route if it was on it.
- *Radio.* A detection reaches the teammates ``radio_delay`` later only if by then some guard is still
  chasing or searching, the intruder has not left and the search area is not empty.

**Motion.** Where a guard is and what it sees is the movement's (:mod:`guardsim.alert.movement`): on the
grid, or as a body in the physics world. The decisions above are the same in both, a grid tick at a
time. Each guard keeps a *route clock*, the grid ticks on which it took a decision; its patrol and its
rejoining run on that clock. On the grid a guard decides every tick, so its clock is the tick; in
continuous motion a guard whose body is still catching up (turns take time) skips a decision, and its
clock stands still.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from guardsim.alert.intruders import Intruder
from guardsim.alert.invariants import corridor_cells
from guardsim.alert.model import AlertEvent, AlertOutcome, AlertRules, Event, GuardState
from guardsim.alert.movement import ContinuousMovement, GridMovement, Movement
from guardsim.alert.search import Contamination, make_search
from guardsim.alert.steering import cut_off_cell, escape_path, search_cell
from guardsim.detection import AwarenessMeter, GuardDetection
from guardsim.detection.watch import CameraAlarms, LevelWatch
from guardsim.errors import ArgumentError
from guardsim.grid import CoverageGrid
from guardsim.kernels.distances import FAR, distances_from
from guardsim.kernels.noise import heard_within
from guardsim.kernels.steps import cell_of_state, heading_of_state, state_of
from guardsim.patrol.model import Patrol
from guardsim.vision.table import ViewTable

__all__ = ["STEP_ASIDE_TICKS", "AlertEpisode"]

#: Ticks two guards may stay within one cell of each other before one steps aside.
STEP_ASIDE_TICKS = 5


def _contains(sorted_cells: np.ndarray, cell: int) -> bool:
    index = int(np.searchsorted(sorted_cells, cell))
    return index < sorted_cells.size and int(sorted_cells[index]) == cell


class AlertEpisode:
    """Guards walking ``patrol`` (from lap tick ``phase``) against ``intruder``; :meth:`step` advances a tick.

    ``spotted``: every guard that sees the intruder at tick 0 starts with a full meter (it is detected at
    once), as the experiments of docs/results.md start.

    ``movement``: where the guards are and what they see (:mod:`guardsim.alert.movement`); the grid's by
    default.

    ``distractions``: noises made away from the intruder, ``(tick, cell, radius in world units)``.

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
        distractions: Sequence[tuple[int, int, float]] = (),
    ) -> None:
        if patrol.period is None:
            raise ArgumentError("an alert episode needs a repeating patrol (its period is null)")
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
        self.modes = [GuardState.PATROL] * guards
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
        self.travel = -1
        """Heading number of the intruder's last seen direction of travel (-1: not known)."""
        self._losses = [0] * guards
        self._done_chasing = [False] * guards
        """Per guard: it lost the intruder ``give_up_losses`` times and chases it no more."""
        self._running = [0] * guards
        """Per guard: ticks it has run (chasing or cutting off) since it last started."""
        self._target = [-1] * guards
        """Per searcher: the cell it is committed to look at (-1: none)."""
        self._target_field: list[np.ndarray | None] = [None] * guards
        self._together = np.zeros((guards, guards), dtype=np.int64)
        """Consecutive ticks each pair of guards has been within one cell (outside corridors)."""
        self._corridor = corridor_cells(grid.traversable).ravel()
        self._distractions = sorted((int(t), int(c), float(r)) for t, c, r in distractions)
        self.noises: list[tuple[int, int, float, str]] = []
        """Every noise made: ``(tick, cell, radius in world units, "step" or "throw")``."""
        self._heard = [False] * guards
        """Per guard: it is investigating a noise."""
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
            "heard": [],
        }
        if isinstance(self.movement, ContinuousMovement):
            self.record.update({"poses": [], "awareness_peak": []})
        if self.cameras.meters:
            self.record["camera_awareness"] = []
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
        chased = GuardState.CHASE in self.modes
        alarmed = chased or GuardState.SEARCH in self.modes
        self.intruder.advance(self.tick, self.cells, chased, alarmed)
        if self.intruder.gone and not any(e.event == Event.ARRIVED for e in self.events):
            self.events.append(AlertEvent(self.tick, -1, Event.ARRIVED))
        made = len(self.noises)
        self._make_noises()
        self._move_guards()
        self.movement.follow(self.cells, self.headings)
        self._look_and_update()
        self._hear(self.noises[made:])
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
        guards = len(self.modes)
        deciding = [self.movement.ready(g) for g in range(guards)]
        searchers = {g: self.cells[g] for g, mode in enumerate(self.modes) if mode == GuardState.SEARCH and deciding[g]}
        fields = self.search.fields(searchers) if searchers else {}
        lead, cutters = self._chase_roles()
        chase_field: np.ndarray | None = None
        for guard, mode in enumerate(self.modes):
            if not deciding[guard]:
                continue
            self._clock[guard] += 1
            running = mode == GuardState.CHASE or guard in cutters
            if not running and self._running[guard]:
                self._running[guard] = 0
                self.movement.pace(guard, 1.0)
            if mode != GuardState.CHASE and self._crowded_for(guard) and self._step_aside(guard):
                if mode in (GuardState.PATROL, GuardState.RETURN):
                    self._enter_return(guard)
                self._target[guard] = -1
                continue
            if mode == GuardState.PATROL:
                state = self.patrol.state(guard, self._clock[guard] + self.phase)
                self.cells[guard], self.headings[guard] = int(cell_of_state(state)), int(heading_of_state(state))
            elif mode == GuardState.SUSPICIOUS:
                self.headings[guard] = self._facing(self.cells[guard], self._noticed[guard], self.headings[guard])
            elif mode == GuardState.INVESTIGATE:
                stepped = False
                if self.cells[guard] != self._noticed[guard]:
                    stepped = self._walk(guard, distances_from(self.neighbours, np.array([self._noticed[guard]])))
                else:
                    self.headings[guard] = (self.headings[guard] + 1) % 4
                if not stepped:
                    self._look[guard] += 1
                    if self._look[guard] >= 4:
                        self._enter_return(guard)
            elif mode == GuardState.SEARCH and (
                fields.get(guard) is None or tick - self._since[guard] >= self.rules.search_ticks
            ):
                self.events.append(AlertEvent(tick, guard, Event.GAVE_UP))
                if self._stats["gave_up"] is None:
                    self._stats["gave_up"] = tick
                self._target[guard] = -1
                self._enter_return(guard)
            elif running:
                if guard == lead or guard not in cutters:
                    if chase_field is None:
                        chase_field = distances_from(self.neighbours, np.array([self.last_known]))
                    field = chase_field
                else:
                    field = self._cut_off_field(guard, lead)
                self._run(guard, field)
            elif mode == GuardState.SEARCH:
                wanted = fields.get(guard)
                if wanted is not None:
                    self._search_step(guard, wanted)
            if self.modes[guard] == GuardState.RETURN:
                self._walk_back(guard)

    def _chase_roles(self) -> tuple[int, set[int]]:
        """The lead chaser (-1: none sees the intruder) and the guards cutting it off (see the module)."""
        if self.last_known < 0:
            return -1, set()
        seeing = [g for g, mode in enumerate(self.modes) if mode == GuardState.CHASE and self.in_sight[g]]
        if not seeing:
            return -1, set()
        field = distances_from(self.neighbours, np.array([self.last_known]))
        lead = min(seeing, key=lambda g: (int(field[self.cells[g]]), g))
        alarmed = {g for g, mode in enumerate(self.modes) if mode in (GuardState.CHASE, GuardState.SEARCH) and g != lead}
        return lead, alarmed

    def _run_steps(self, guard: int) -> int:
        """Steps ``guard`` runs this tick (see the module); one a decision in continuous motion."""
        self._running[guard] += 1
        if self._running[guard] == 1:
            self.movement.pace(guard, self.rules.chase_speed)
        if self.movement.name != "grid":
            return 1
        k, speed = self._running[guard], self.rules.chase_speed
        return math.floor(k * speed + 1e-9) - math.floor((k - 1) * speed + 1e-9)

    def _run(self, guard: int, field: np.ndarray) -> None:
        steps = self._run_steps(guard)
        if steps <= 0:
            return
        if not self._walk(guard, field):
            return
        for _ in range(steps - 1):
            cell, heading = self.cells[guard], self.headings[guard]
            ahead = int(self.neighbours[cell, heading])
            # An extra step only straight on, and only downhill: a runner does not turn within a tick.
            if ahead < 0 or field[ahead] >= field[cell] or self._best_direction(guard, field) != heading:
                return
            self.cells[guard] = ahead

    def _cut_off_field(self, guard: int, lead: int) -> np.ndarray:
        """The field to the cell of the intruder's likely escape ``guard`` reaches first (see
        :mod:`guardsim.alert.steering`); to the intruder itself when within two cells."""
        known = self.last_known
        own = distances_from(self.neighbours, np.array([self.cells[guard]]))
        if own[known] <= 2:
            return distances_from(self.neighbours, np.array([known]))
        away = distances_from(self.neighbours, np.array([self.cells[lead]]))
        path = escape_path(self.neighbours, known, self.travel, away)
        target = cut_off_cell(path, own, self.rules.chase_speed, self.rules.intruder_speed)
        return distances_from(self.neighbours, np.array([target]))

    def _search_step(self, guard: int, field: np.ndarray) -> None:
        """One tick of ``guard``'s search: to its committed cell, or turn to look at it (see the module)."""
        if self.search.name == "last-known":
            self._walk(guard, field)
            return
        target = self._target[guard]
        keep = target >= 0 and (
            field[target] == 0 or (self.search.name != "diffuse" and self.contamination.cells[target])
        )
        if not keep:
            target = self._choose_target(guard, field)
            self._target[guard] = target
            self._target_field[guard] = None if target < 0 else distances_from(self.neighbours, np.array([target]))
        target_field = self._target_field[guard]
        if target < 0 or target_field is None:
            self.headings[guard] = (self.headings[guard] + 1) % 4
            return
        cell = self.cells[guard]
        for heading in (self.headings[guard], *range(4)):
            if _contains(self.table.sees(state_of(cell, heading)), target):
                if heading != self.headings[guard]:
                    self.headings[guard] = heading
                    return
                break
        self._walk(guard, target_field)

    def _choose_target(self, guard: int, field: np.ndarray) -> int:
        goal = np.flatnonzero(field == 0)
        steps = distances_from(self.neighbours, np.array([self.cells[guard]]))[goal]
        claimed = [
            cell
            for other, cell in enumerate(self._target)
            if other != guard and cell >= 0 and self.modes[other] == GuardState.SEARCH
        ]
        return search_cell(
            goal, steps, self.grid.shape[1], last_known=self.last_known, travel=self.travel, claimed=claimed
        )

    def _best_direction(self, guard: int, field: np.ndarray) -> int:
        cell, heading = self.cells[guard], self.headings[guard]
        best, best_value = -1, 0
        for choice in range(5):
            direction = heading if choice == 0 else choice - 1
            there = int(self.neighbours[cell, direction])
            if there >= 0 and (best < 0 or field[there] < best_value):
                best, best_value = direction, field[there]
        return best

    def _walk(self, guard: int, field: np.ndarray) -> bool:
        """One step down ``field`` (the greedy step: ties keep the heading, then right, down, left, up),
        keeping personal space unless chasing; at its bottom, turn in place to look around. Whether it
        stepped."""
        cell, heading = self.cells[guard], self.headings[guard]
        here = field[cell]
        options = [
            direction
            for direction in (heading, 0, 1, 2, 3)
            if self.neighbours[cell, direction] >= 0 and field[self.neighbours[cell, direction]] < here
        ]
        options = sorted(dict.fromkeys(options), key=lambda d: (field[self.neighbours[cell, d]], d != heading, d))
        chasing = self.modes[guard] == GuardState.CHASE
        for direction in options:
            there = int(self.neighbours[cell, direction])
            if chasing or not self._crowds(guard, there):
                self.cells[guard], self.headings[guard] = there, direction
                return True
        # Kept from every step down (or at the bottom): turn in place, toward the way it wants to go.
        self.headings[guard] = options[0] if options and options[0] != heading else (heading + 1) % 4
        return False

    def _crowds(self, guard: int, cell: int) -> bool:
        """Whether ``cell`` lies within one cell of another guard (outside corridors one cell wide)."""
        if self._corridor[cell] or self._corridor[self.cells[guard]]:
            return False
        cols = self.grid.shape[1]
        row, col = divmod(cell, cols)
        for other, there in enumerate(self.cells):
            if other != guard and there >= 0:
                other_row, other_col = divmod(there, cols)
                if abs(row - other_row) + abs(col - other_col) <= 1 and not self._corridor[there]:
                    return True
        return False

    def _crowded_for(self, guard: int) -> bool:
        """Whether ``guard`` must step aside: it has stayed within one cell of another guard for
        :data:`STEP_ASIDE_TICKS` ticks and it is the one to yield (not patrolling while the other is, or
        the higher numbered)."""
        for other in range(len(self.modes)):
            if other == guard or self._together[guard, other] < STEP_ASIDE_TICKS:
                continue
            patrolling = self.modes[guard] == GuardState.PATROL, self.modes[other] == GuardState.PATROL
            if patrolling[0] != patrolling[1]:
                if not patrolling[0]:
                    return True
            elif guard > other or self.modes[other] == GuardState.CHASE:
                return True
        return False

    def _step_aside(self, guard: int) -> bool:
        """Step to the neighbour farthest (fewest-cells sense) from the nearest other guard, if that is
        farther than where it stands; whether it stepped."""
        cols = self.grid.shape[1]

        def room(cell: int) -> int:
            row, col = divmod(cell, cols)
            gaps = [
                abs(row - there // cols) + abs(col - there % cols)
                for other, there in enumerate(self.cells)
                if other != guard and there >= 0
            ]
            return min(gaps, default=FAR)

        cell = self.cells[guard]
        best, best_room = -1, room(cell)
        for direction in range(4):
            there = int(self.neighbours[cell, direction])
            if there >= 0 and room(there) > best_room:
                best, best_room = direction, room(there)
        if best < 0:
            return False
        self.cells[guard], self.headings[guard] = int(self.neighbours[cell, best]), best
        self._together[guard, :] = 0
        self._together[:, guard] = 0
        return True

    def _enter_return(self, guard: int) -> None:
        self.modes[guard] = GuardState.RETURN
        here, clock = self.cells[guard], self._clock[guard]
        steps = distances_from(self.neighbours, np.array([here]))
        for k in range(1, 2 * self.patrol.ticks + self.grid.size + 2):
            cell = int(cell_of_state(self.patrol.state(guard, clock + k + self.phase)))
            if steps[cell] <= k - 1:
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
        if clock >= rejoin_tick:
            if self.cells[guard] != cell:  # kept from it (personal space): plan again from here
                self._enter_return(guard)
                return
            state = self.patrol.state(guard, clock + self.phase)
            self.cells[guard], self.headings[guard] = int(cell_of_state(state)), int(heading_of_state(state))
            self.modes[guard] = GuardState.PATROL
            self._rejoin[guard] = None
            self.events.append(AlertEvent(self.tick, guard, Event.BACK_ON_ROUTE))
        elif self.cells[guard] != cell:
            self._walk(guard, field)

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
        chasing_before = GuardState.CHASE in self.modes
        alarms = self.cameras.look(self.phase + tick, intruder)
        for camera in alarms:
            # The alarm tells every guard where the intruder is now, as a guard's detection tells its team.
            self.events.append(AlertEvent(tick, camera, Event.ALARM))
            self.last_known = intruder
            self._stats["detected"] = tick if self._stats["detected"] is None else self._stats["detected"]
            self._radio_at = tick
        for guard, mode in enumerate(self.modes):
            meter, seen = self.meters[guard], self.in_sight[guard]
            if look.spotted[guard] and not self._done_chasing[guard]:
                self._saw_at(intruder)
                if mode != GuardState.CHASE:
                    self._enter_chase(guard, chasing_before)
            elif mode == GuardState.CHASE:
                self.modes[guard] = GuardState.SEARCH
                self._since[guard] = tick
                self._target[guard] = -1
                self._losses[guard] += 1
                self._done_chasing[guard] = self._losses[guard] >= self.rules.give_up_losses
                self.events.append(AlertEvent(tick, guard, Event.LOST))
                if self._stats["lost"] is None:
                    self._stats["lost"] = tick
            elif mode == GuardState.PATROL and meter.suspicious:
                self.modes[guard] = GuardState.SUSPICIOUS
                self._noticed[guard], self._rising[guard] = intruder, 0
                self._left_route = True
                self.events.append(AlertEvent(tick, guard, Event.NOTICED))
            elif mode == GuardState.SUSPICIOUS:
                if meter.level <= 0:
                    self._enter_return(guard)
                elif seen:
                    self._noticed[guard] = intruder
                    self._rising[guard] += 1
                    if self._rising[guard] >= 2:
                        self.modes[guard], self._look[guard] = GuardState.INVESTIGATE, 0
                else:
                    self._rising[guard] = 0
            elif mode == GuardState.INVESTIGATE and seen:
                self._noticed[guard] = intruder
        # The radio reaches the others only while the alarm is real: a camera's alarm this tick, or someone
        # still chasing or searching with the intruder still here and somewhere left to search.
        live = any(mode in (GuardState.CHASE, GuardState.SEARCH) for mode in self.modes) and not self.intruder.gone
        real = bool(alarms) or (live and (self.contamination.count > 0 or GuardState.CHASE in self.modes))
        if self._radio_at == tick and real:
            for guard, mode in enumerate(self.modes):
                if mode in (GuardState.PATROL, GuardState.SUSPICIOUS, GuardState.INVESTIGATE, GuardState.RETURN):
                    self.modes[guard], self._since[guard], self._rejoin[guard] = GuardState.SEARCH, tick, None
                    self._left_route = True
                    self.events.append(AlertEvent(tick, guard, Event.JOINED))
        if self.last_known >= 0:
            if alarms or any(self.in_sight[g] and self.modes[g] == GuardState.CHASE for g in range(len(self.modes))):
                self.contamination.seed(self.last_known)  # in sight: exactly where it is
                self.search.start(self.last_known, self.travel)
                self._target = [-1] * len(self.modes)
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
                alarmed = mode == GuardState.CHASE or (mode == GuardState.SEARCH and self.meters[guard].detected)
                if alarmed and self.movement.distance(guard, intruder) <= self.rules.capture_radius + 1e-9:
                    self.events.append(AlertEvent(tick, guard, Event.CAPTURED))
                    self._stats["captured"] = tick
                    self.outcome, self.done = "captured", True
                    break

    def _make_noises(self) -> None:
        """This tick's noises: the intruder's steps where they landed, and the distractions due."""
        rules = self.rules
        for cell, gait in self.intruder.landed:
            radius = rules.sneak_noise if gait == "sneak" else rules.walk_noise
            if radius > 0:
                self.noises.append((self.tick, int(cell), radius, "step"))
        while self._distractions and self._distractions[0][0] <= self.tick:
            tick, cell, radius = self._distractions.pop(0)
            if tick == self.tick and radius > 0:
                self.noises.append((tick, cell, radius, "throw"))

    def _hear(self, noises: list[tuple[int, int, float, str]]) -> None:
        """Guards within a noise's reach (along the grid) that are not chasing or searching investigate
        the cell they heard; their meters are untouched."""
        self._heard = [heard and self.modes[g] == GuardState.INVESTIGATE for g, heard in enumerate(self._heard)]
        for _, cell, radius, _ in noises:
            hears = heard_within(self.neighbours, cell, radius, self.rules.cell_size, np.array(self.cells))
            for guard in np.flatnonzero(hears).tolist():
                if self.modes[guard] in (GuardState.CHASE, GuardState.SEARCH):
                    continue  # already alarmed: it hunts by sight and the radio
                self.modes[guard], self._noticed[guard], self._look[guard] = GuardState.INVESTIGATE, cell, 0
                self._rejoin[guard] = None
                self._heard[guard] = True
                self._left_route = True
                self.events.append(AlertEvent(self.tick, guard, Event.HEARD))

    def _saw_at(self, cell: int) -> None:
        """The intruder is seen at ``cell``: the last known cell and its direction of travel."""
        before = self.last_known
        if before >= 0 and cell != before:
            cols = self.grid.shape[1]
            (row, col), (new_row, new_col) = divmod(before, cols), divmod(cell, cols)
            dx, dy = new_col - col, new_row - row
            self.travel = (0 if dx > 0 else 2) if abs(dx) >= abs(dy) else (1 if dy > 0 else 3)
        self.last_known = cell

    def _enter_chase(self, guard: int, chasing_before: bool) -> None:
        tick = self.tick
        first = self._stats["detected"] is None
        self.modes[guard] = GuardState.CHASE
        self._rejoin[guard] = None
        self._left_route = True
        self.events.append(AlertEvent(tick, guard, Event.DETECTED))
        if not chasing_before and GuardState.CHASE not in [m for g, m in enumerate(self.modes) if g != guard]:
            self._stats["detections"] += 1
            if self._stats["lost"] is not None and self._stats["reacquired"] is None:
                self._stats["reacquired"] = tick
        if first:
            self._stats["detected"] = tick
        if self._radio_at < tick:
            self._radio_at = tick + self.rules.radio_ticks

    def _reach(self) -> int:
        speed = self.rules.intruder_speed
        walking = math.floor(self.tick * speed + 1e-9) - math.floor((self.tick - 1) * speed + 1e-9)
        # A running evader may have covered more this tick: the guards, who chased it, know it may run.
        return max(walking, self.intruder.ran)

    # -- ending and recording ---------------------------------------------------------------------

    def _finish(self) -> None:
        if self.done:
            return
        if GuardState.SEARCH in self.modes:
            self._stats["searching"] += 1
        calm = all(mode == GuardState.PATROL for mode in self.modes)
        if self.intruder.gone and self._stats["detected"] is None:
            self.outcome, self.done = "undetected_arrival", True
        elif self._stats["detected"] is not None and calm:
            self._stats["back"] = self.tick
            self.outcome, self.done = ("escaped" if self.intruder.gone else "hidden"), True
        elif self.tick >= self.max_ticks:
            self.done = True

    def _record(self) -> None:
        self._count_together()
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
        if "camera_awareness" in record:
            record["camera_awareness"].append([round(level, 4) for level in self.cameras.levels()])
        record["intruder"].append(self.intruder.cell if self.intruder.present else None)
        record["contaminated"].append(self.contamination.count)
        record["contaminated_cells"].append(np.flatnonzero(self.contamination.cells).astype(np.int32))
        record["last_known"].append(self.last_known)
        record["heard"].append(list(self._heard))

    def _count_together(self) -> None:
        cols = self.grid.shape[1]
        guards = len(self.modes)
        # Where the guards are (in continuous motion the bodies, which may lag their decided cells).
        cells, _ = self.movement.recorded()
        for first in range(guards):
            for second in range(first + 1, guards):
                a, b = cells[first], cells[second]
                if a < 0 or b < 0:
                    self._together[first, second] = self._together[second, first] = 0
                    continue
                near = (
                    abs(a // cols - b // cols) + abs(a % cols - b % cols) <= 1
                    and not (self._corridor[a] or self._corridor[b])
                    and not (self.modes[first] == GuardState.CHASE and self.modes[second] == GuardState.CHASE)
                )
                count = self._together[first, second] + 1 if near else 0
                self._together[first, second] = self._together[second, first] = count

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
