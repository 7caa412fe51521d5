"""Fortify: add cameras and guard posts to a level until no player gets through, and prove it.

The loop (see ``docs/fortify.md``):

1. Search each entry-goal pair exactly (the undetected label search of :mod:`guardsim.sneak.graded`, or
   the same search with every sighting detecting at once for the unseen rule) against the patrol, the
   level's own cameras and the watchers added so far, over their joint lap, from every entry tick.
2. If a pair has a way through, keep it as a counterexample; add the candidate
   (:mod:`~guardsim.design.fortify.candidates`) that catches the most counterexamples not caught yet, among
   those that leave every keep-open pair a way through from at least its ``min_slack`` entry ticks (on a
   tie, the one watching the most floor); repeat.
3. Once sealed, drop every watcher the seal does not need (each tried in the order added).
4. Then look for fewer: the smallest set of candidates that catches every counterexample found is a lower
   bound on any sealing placement (:mod:`~guardsim.design.fortify.cover`); when it is smaller than the
   placement, search against it: either it seals (the fewest watchers over the candidates) or it lets a
   new counterexample through, and the bound is computed again.

It ends sealed, each pair's proof being the search that found no path, or not sealed within the budget,
with the placement reached, the entry ticks still open and one way through.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.design.fortify.candidates import (
    DEFAULT_CANDIDATES,
    CameraShape,
    Candidate,
    candidate_gains,
    fortify_candidates,
    post_headings,
    post_states,
    swing_ticks,
)
from guardsim.design.fortify.cover import catches, disjoint_bound, min_hitting_set
from guardsim.detection.exposure import MAX_DENSE_NODES
from guardsim.detection.model import GuardDetection
from guardsim.detection.watch import MAX_JOINT_LAP, joint_lap, lap_gains, level_watch
from guardsim.errors import GuardsimError, LimitError
from guardsim.grid import CoverageGrid
from guardsim.level import Level
from guardsim.patrol.model import Patrol
from guardsim.scene import Scene
from guardsim.sneak.grade import unseen_reach
from guardsim.sneak.graded import entry_searches, undetected_search

__all__ = ["DEFAULT_ROUNDS", "MAX_TICK_SEARCHES", "Counterexample", "FortifyResult", "KeepOpen", "fortify"]

Point = tuple[float, float]
Progress = Callable[[str, int, int], None]

#: Entry ticks searched one by one to list a pair's open ticks in fortify.json (the undetected rule).
MAX_TICK_SEARCHES = 32
#: Searches rounds (one search of every open pair each) fortify may run when the caller gives no budget.
DEFAULT_ROUNDS = 64


class KeepOpen(NamedTuple):
    """A pair that must keep a way through: from ``source`` to ``target`` from at least ``min_slack`` entry
    ticks of the lap."""

    source: Point
    target: Point
    min_slack: int = 1


class Counterexample(NamedTuple):
    """A way through found during the loop."""

    pair: int
    """Index of the entry-goal pair."""
    start: int
    """Entry tick of the joint lap."""
    cells: np.ndarray
    """``int64 (ticks + 1,)``: flat cell at each tick."""
    round: int
    """Search round it was found in (0 first; pruning and the search for fewer watchers count on)."""


class FortifyResult(NamedTuple):
    """What :func:`fortify` found and made."""

    document: dict[str, Any]
    """fortify.json (``docs/fortify.md`` lists every key)."""
    level: Level
    """The level with the added cameras."""
    patrol: Patrol | None
    """The patrol's guards and then the posts, over their common lap (``None``: neither)."""
    posts: int
    """How many of :attr:`patrol`'s guards (the last ones) are posts."""
    scene: Scene
    watchers: tuple[Candidate, ...]
    """The watchers added, in the order added."""
    counterexamples: tuple[Counterexample, ...]
    ways_through: tuple[Counterexample | None, ...]
    """Per pair, a way through under the final placement (``None``: sealed)."""

    @property
    def sealed(self) -> bool:
        """Whether no pair has a way through."""
        return bool(self.document["sealed"])


class _Search(NamedTuple):
    found: bool
    start: int
    cells: np.ndarray
    expansions: int


def _point_cell(grid: CoverageGrid, point: Point, option: str) -> int:
    cell = grid.cell_of(point)
    where = f"{option} {point[0]:g},{point[1]:g}"
    if cell is None:
        raise GuardsimError(f"{where} lies outside the level")
    if not grid.traversable[cell[1], cell[0]]:
        raise GuardsimError(f"{where} is in cell [{cell[0]}, {cell[1]}], a wall or too tight for the player")
    return grid.flat(*cell)


class _Fortress:
    """The searches against a placement: the base watchers (patrol, level cameras) and chosen candidates."""

    def __init__(
        self, grid: CoverageGrid, base: np.ndarray, gains: list[np.ndarray], lap: int, fall: float, undetected: bool
    ):
        self.grid = grid
        self.base = base
        self.gains = gains
        self.lap = lap
        self.fall = fall
        self.undetected = undetected
        self.neighbours = np.ascontiguousarray(grid.neighbours, dtype=np.int64)

    def watcher_gains(self, chosen: Sequence[int]) -> np.ndarray:
        """``float64 (watchers, lap, cells)``: the base's and the chosen candidates' gains over the lap."""
        ticks = np.arange(self.lap)
        rows = [self.base[:, ticks % self.base.shape[1]]] + [
            self.gains[c][ticks % self.gains[c].shape[0]][None] for c in chosen
        ]
        gains = np.concatenate(rows, axis=0)
        if gains.shape[0] == 0:
            # Nobody watches: one watcher who sees nothing keeps the search's shapes.
            gains = np.zeros((1, self.lap, self.grid.size), dtype=np.float64)
        return np.ascontiguousarray(gains)

    def _rule_gains(self, chosen: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        gains = self.watcher_gains(chosen)
        seen = np.asarray((gains > 0).any(axis=0))
        if not self.undetected:
            # Unseen: any sighting catches, as a meter filled at once.
            gains = np.where(seen, np.inf, 0.0)[None]
        return gains, seen

    def search(self, chosen: Sequence[int], source: int, target: int) -> _Search:
        gains, seen = self._rule_gains(chosen)
        found = undetected_search(self.neighbours, gains, self.fall, source, target, seen=seen)
        if found.found < 0:
            return _Search(False, -1, np.zeros(0, dtype=np.int64), found.labels)
        start, cells = found.path()
        return _Search(True, start, cells, found.labels)

    def open_ticks(
        self, chosen: Sequence[int], source: int, target: int, *, enough: int | None = None, most: int | None = None
    ) -> tuple[np.ndarray, bool]:
        """``bool (lap,)``: the entry ticks from which a way through exists, and whether every tick was
        decided. Under the undetected rule a tick no unseen path leaves from takes a search of its own: they
        stop once ``enough`` ticks are open, or after ``most`` searches (the rest counted closed)."""
        gains, seen = self._rule_gains(chosen)
        reach = unseen_reach(self.neighbours, seen, target)
        known = reach[:, source].copy()
        if not self.undetected:
            return known, True
        goal = reach.copy()
        goal[:, target] = True
        phases = np.flatnonzero(~known)
        step = 16
        for begin in range(0, phases.size, step):
            if enough is not None and known.sum() >= enough:
                return known, False
            if most is not None and begin >= most:
                return known, False
            chunk = phases[begin : begin + step]
            known[chunk] = entry_searches(self.neighbours, gains, self.fall, source, goal, chunk, seen=seen)
        return known, True


def fortify(
    level: Level,
    patrol: Patrol | None,
    pairs: Sequence[tuple[Point, Point]],
    *,
    cameras: int = 8,
    posts: int = 8,
    keep_open: Sequence[KeepOpen] = (),
    undetected: bool = True,
    camera: CameraShape | None = None,
    candidates: int = DEFAULT_CANDIDATES,
    max_rounds: int = DEFAULT_ROUNDS,
    max_lap: int = MAX_JOINT_LAP,
    scene_options: dict[str, Any] | None = None,
    patrol_name: str = "patrol",
    workers: int = 1,
    scheduler: str | None = None,
    progress: Progress | None = None,
) -> FortifyResult:
    """Place cameras and guard posts on ``level`` until no player gets from any entry to its goal.

    Parameters
    ----------
    level, patrol
        The level (its own cameras and light count) and the guards already on it (a repeating grid
        patrol, or ``None`` for none).
    pairs
        ``(entry, goal)`` points in world units.
    cameras, posts
        The most cameras and posts to add.
    keep_open
        Pairs that must keep a way through (:class:`KeepOpen`).
    undetected
        Seal against undetected paths (a meter must fill); ``False``: against unseen ones (any sighting).
    camera
        The candidate cameras' cone (:class:`~guardsim.design.fortify.candidates.CameraShape`).
    candidates
        How many candidates to consider (:mod:`~guardsim.design.fortify.candidates`).
    max_rounds
        How many search rounds (each searching every open pair) to run at most.
    scene_options
        Keywords of :meth:`Scene.from_level` (line of sight, field of view, view range).
    patrol_name
        The patrol's file or name, as errors give it.
    workers, scheduler
        Where the candidates' gains are computed (:func:`guardsim.experiment.executors.make_executor`);
        the result is the same bytes either way.
    progress
        Called with ``(what, done, total)`` as the loop goes.

    Raises
    ------
    GuardsimError
        An entry or goal outside the floor, a pair with no path at all, a keep-open pair equal to a pair
        to seal, a budget of 0.
    PatrolError
        When ``patrol`` does not repeat or does not move in grid motion.
    LimitError
        When the joint lap is over ``max_lap`` or a search over its limits.

    Examples
    --------
    A corridor 8 cells long with no guard: one watcher seals it.

    >>> from guardsim import parse_level
    >>> level = parse_level({"outer": [[0, 0], [8, 0], [8, 1], [0, 1]]})
    >>> result = fortify(level, None, [((0.5, 0.5), (7.5, 0.5))], candidates=8)
    >>> result.sealed, result.document["count"], result.document["lower_bound"]
    (True, 1, 1)
    """
    options = dict(scene_options or {})
    shape = camera or CameraShape()
    if cameras < 0 or posts < 0:
        raise GuardsimError(f"cameras={cameras}, posts={posts}: each must be 0 or more")
    if cameras + posts == 0:
        raise GuardsimError("cameras=0 and posts=0: a budget of 0 watchers cannot fortify anything")
    if max_rounds < 1:
        raise GuardsimError(f"max_rounds={max_rounds}: a budget of 0 rounds cannot fortify anything")
    if candidates < 1:
        raise GuardsimError(f"candidates={candidates}: a budget of 0 candidates cannot fortify anything")
    if not pairs:
        raise GuardsimError("pairs is empty: no entry-goal pair to seal")
    if patrol is not None:
        patrol.require_repeating_grid(patrol_name, "fortify")
    report = progress or (lambda _what, _done, _total: None)
    report("building the scene", 0, 0)
    scene = Scene.from_level(level, **options)
    grid = scene.grid
    cells = [
        (_point_cell(grid, a, f"--from: pair {n + 1}'s entry"), _point_cell(grid, b, f"--to: pair {n + 1}'s goal"))
        for n, (a, b) in enumerate(pairs)
    ]
    labels = grid.component_labels
    for n, ((a, b), (source, target)) in enumerate(zip(pairs, cells)):
        if labels[source] != labels[target]:
            raise GuardsimError(
                f"pair {n + 1}'s goal {b[0]:g},{b[1]:g} cannot be reached from its entry {a[0]:g},{a[1]:g} at all"
            )
    open_cells = [
        (
            _point_cell(grid, k.source, f"keep-open pair {n + 1}'s entry"),
            _point_cell(grid, k.target, f"keep-open pair {n + 1}'s goal"),
        )
        for n, k in enumerate(keep_open)
    ]
    for n, (keep, (source, target)) in enumerate(zip(keep_open, open_cells)):
        where = (
            f"keep-open pair {n + 1} ({keep.source[0]:g},{keep.source[1]:g} to {keep.target[0]:g},{keep.target[1]:g})"
        )
        if (source, target) in cells:
            raise GuardsimError(f"{where} is also a pair to seal: it cannot be both")
        if labels[source] != labels[target]:
            raise GuardsimError(f"{where}: no path at all between them")
        if keep.min_slack < 0:
            raise GuardsimError(f"{where}: min_slack {keep.min_slack} must be 0 or more")

    from guardsim.vision.table import view_table

    detection = GuardDetection.of_level(scene.level)
    dt = detection.dt
    watch = level_watch(scene, dt, max_lap=max_lap) if level.cameras or not level.lit else None
    # The searches below hold arrays over every (lap tick, cell), each watcher's too: refuse up front, before
    # the view table, a level whose lap alone is over the dense limit (a 256 x 256 city passed 20 GB before
    # its search did).
    lap_ticks = joint_lap(1 if patrol is None else int(patrol.states.shape[1]), watch, max_lap=max_lap)
    if lap_ticks * grid.size > MAX_DENSE_NODES:
        raise LimitError(
            f"fortify's searches hold arrays over every (lap tick, cell): {lap_ticks * grid.size} nodes ({grid.size} "
            f"cells x a {lap_ticks}-tick lap), over the limit of {MAX_DENSE_NODES}; a shorter patrol lap or a "
            "smaller level fits"
        )
    report("computing the view table", 0, 0)
    table = view_table(grid, scene.vision())
    if patrol is not None:
        base_gains, _ = lap_gains(grid, table, patrol.states, detection, watch, max_lap=max_lap)
        base = base_gains.gain
    elif watch is not None and watch.cameras:
        own = joint_lap(1, watch, max_lap=max_lap)
        base = np.stack([gain[np.arange(own) % gain.shape[0]] for gain in watch.gains])
    else:
        base = np.zeros((0, 1, grid.size), dtype=np.float64)
    swing = swing_ticks(int(base.shape[1]))
    lap = math.lcm(int(base.shape[1]), swing)
    if lap > max_lap:
        raise LimitError(
            f"the joint lap of the watchers' {base.shape[1]} ticks and the candidates' {swing}-tick turn is "
            f"{lap} ticks, over the limit of {max_lap} (raise it with --max-lap)"
        )
    fall = detection.model.fall(dt)

    pool = fortify_candidates(
        grid, [source for source, _ in cells], exclude=[cell for pair in cells + open_cells for cell in pair], near=[cell for pair in cells for cell in pair], shape=shape, dt=dt, swing=swing, cameras=cameras > 0, posts=posts > 0,
        budget=candidates,
    )  # fmt: skip
    report(f"computing the gains of {len(pool)} candidates", 0, len(pool))
    gains = candidate_gains(
        scene, table, pool, scene_options=options, swing=swing, workers=workers, scheduler=scheduler
    )
    fortress = _Fortress(grid, base, gains, lap, fall, undetected)
    kinds = [0 if candidate.kind == "camera" else 1 for candidate in pool]
    watching = [float((gain > 0).sum()) / gain.shape[0] for gain in gains]
    caps = [cameras, posts]

    paths: list[Counterexample] = []
    caught: list[frozenset[int]] = []
    rounds: list[dict[str, Any]] = []
    chosen: list[int] = []
    searches = 0

    def seal_searches(placement: Sequence[int], round_number: int) -> list[Counterexample]:
        nonlocal searches
        found = []
        for index, (source, target) in enumerate(cells):
            searches += 1
            result = fortress.search(placement, source, target)
            if result.found:
                found.append(Counterexample(index, result.start, result.cells, round_number))
        return found

    def add_paths(found: list[Counterexample]) -> None:
        for path in found:
            paths.append(path)
            caught.append(
                frozenset(np.flatnonzero(catches(gains, path.start, path.cells, fall, undetected=undetected)).tolist())
            )

    def keeps_open(placement: Sequence[int]) -> bool:
        return all(
            int(fortress.open_ticks(placement, source, target, enough=keep.min_slack)[0].sum()) >= keep.min_slack
            for keep, (source, target) in zip(keep_open, open_cells)
        )

    reason: str | None = None
    sealed = False
    used = 0
    while True:
        if used >= max_rounds:
            reason = f"the budget of {max_rounds} search rounds ran out"
            break
        report(f"round {used + 1}: searching {len(cells)} pair{'s' if len(cells) != 1 else ''}", used, max_rounds)
        found = seal_searches(chosen, used)
        used += 1
        if not found:
            sealed = True
            break
        add_paths(found)
        if any(not caught[-1 - n] for n in range(len(found))):
            reason = "a way through that no candidate catches (more candidates or another camera cone may)"
            break
        hit = set(chosen)
        uncaught = [members for members in caught if hit.isdisjoint(members)]
        counts = [sum(1 for kind_index in (kinds[c] for c in chosen) if kind_index == k) for k in range(2)]
        scores: dict[int, int] = {}
        for members in uncaught:
            for candidate in members:
                if counts[kinds[candidate]] < caps[kinds[candidate]]:
                    scores[candidate] = scores.get(candidate, 0) + 1
        # Ties go to the candidate watching the most floor over its turn, then the lowest index.
        order = sorted(scores, key=lambda c: (-scores[c], -watching[c], c))
        pick = next((c for c in order if not keep_open or keeps_open([*chosen, c])), None)
        if pick is None:
            reason = "no candidate left within the budget ({} cameras, {} posts) catches the new way through{}".format(
                cameras, posts, " and keeps the keep-open pairs open" if keep_open and order else ""
            )
            break
        chosen.append(pick)
        rounds.append({
            "round": len(rounds) + 1,
            "open_pairs": sorted({path.pair for path in found}),
            "added": _watcher_data(grid, pool[pick], pick),
            "catches": scores[pick],
        })  # fmt: skip

    pruned: list[int] = []
    bound: int | None = None
    bound_kind = "disjoint counterexamples"
    if sealed:
        for candidate in list(chosen):
            trial = [c for c in chosen if c != candidate]
            report(f"pruning: without watcher {chosen.index(candidate) + 1} of {len(chosen)}", 0, 0)
            extra = seal_searches(trial, used)
            used += 1
            if not extra:
                chosen = trial
                pruned.append(candidate)
            else:
                add_paths(extra)
        while used < max_rounds:
            report(f"looking for fewer than {len(chosen)} watchers", used, max_rounds)
            smaller, finished = min_hitting_set(caught, kinds, caps, below=len(chosen))
            if not finished:
                break
            if smaller is None:
                bound, bound_kind = len(chosen), "fewest over the candidates"
                break
            extra = seal_searches(smaller, used)
            used += 1
            if extra:
                add_paths(extra)
                continue
            if keep_open and not keeps_open(smaller):
                bound, bound_kind = len(smaller), "hitting set of the counterexamples"
                break
            chosen = smaller
            bound, bound_kind = len(chosen), "fewest over the candidates"
            break
    if bound is None:
        bound = disjoint_bound(caught)
        if bound > len(caught):
            bound_kind = "none: a way through no candidate catches"

    report("writing the proof", 0, 0)
    proofs: list[dict[str, Any]] = []
    ways: list[Counterexample | None] = []
    for index, (source, target) in enumerate(cells):
        result = fortress.search(chosen, source, target)
        if not result.found:
            ways.append(None)
            proofs.append(
                {
                    "sealed": True,
                    "proof": {"no_path": True, "expansions": result.expansions, "lap": lap, "entry_ticks": lap},
                }
            )
            continue
        way = Counterexample(index, result.start, result.cells, used)
        ways.append(way)
        ticks, complete = fortress.open_ticks(chosen, source, target, most=MAX_TICK_SEARCHES)
        proofs.append({
            "sealed": False, "open_entry_ticks": np.flatnonzero(ticks).tolist(), "all_ticks_searched": complete,
            "way_through": _path_data(grid, way),
        })  # fmt: skip
    keep_data = []
    for keep, (source, target) in zip(keep_open, open_cells):
        ticks, complete = fortress.open_ticks(chosen, source, target, most=MAX_TICK_SEARCHES)
        slack = int(ticks.sum())
        result = fortress.search(chosen, source, target)
        entry = {
            "from": list(keep.source), "to": list(keep.target), "min_slack": keep.min_slack, "slack": slack,
            "all_ticks_searched": complete,
            "kept": slack >= keep.min_slack,
            "path": _path_data(grid, Counterexample(-1, result.start, result.cells, used)) if result.found else None,
        }  # fmt: skip
        if slack < keep.min_slack:
            entry["message"] = (
                f"keep-open pair {keep.source[0]:g},{keep.source[1]:g} to {keep.target[0]:g},{keep.target[1]:g} cannot "
                f"be kept: a way through from {slack} entry ticks, fewer than its min_slack {keep.min_slack}"
            )
        keep_data.append(entry)

    watchers = tuple(pool[c] for c in chosen)
    new_cameras = tuple(candidate.camera for candidate in watchers if candidate.camera is not None)
    fortified = dataclasses.replace(level, cameras=tuple(level.cameras) + new_cameras)
    post_cells = [candidate.cell for candidate in watchers if candidate.kind == "post"]
    combined = _combined_patrol(patrol, post_cells, swing)
    guards = 0 if patrol is None else patrol.guards
    count = len(chosen)
    # The last round may add the watcher that seals every pair and leave no round to search it: the
    # proof searches above are exact, so the placement is sealed all the same (not pruned).
    proved = all(way is None for way in ways)
    document: dict[str, Any] = {
        "level": level.name,
        "rule": "undetected" if undetected else "unseen",
        "sealed": proved,
        "reason": None if proved else reason,
        "cell_size": grid.cell_size,
        "origin": list(grid.origin),
        "lap": lap,
        "count": count,
        "lower_bound": bound if bound <= len(caught) else None,
        "bound": bound_kind,
        "gap": (count - bound) if proved and bound <= len(caught) else None,
        "budget": {"cameras": cameras, "posts": posts, "rounds": max_rounds, "candidates": candidates},
        "candidates": {
            "cameras": sum(1 for c in pool if c.kind == "camera"),
            "posts": sum(1 for c in pool if c.kind == "post"),
            "camera": {
                "fov_degrees": shape.fov_degrees,
                "view_range": shape.view_range,
                "sweep": shape.sweep,
                "swing_ticks": swing if shape.sweep > 0 else 1,
            },
            "post": {"turn_ticks": swing, "headings": post_headings(swing).tolist()},
        },
        "watchers": [
            {
                **_watcher_data(grid, candidate, index),
                **({"guard": guards + post_cells.index(candidate.cell)} if candidate.kind == "post" else {}),
            }
            for candidate, index in zip(watchers, chosen)
        ],
        "rounds": rounds,
        "search_rounds": used,
        "searches": searches,
        "pruned": [_watcher_data(grid, pool[c], c) for c in pruned],
        "counterexamples": [
            {
                **_path_data(grid, path),
                "pair": path.pair,
                "round": path.round + 1,
                "caught_by": [chosen.index(c) for c in sorted(members) if c in chosen],
            }
            for path, members in zip(paths, caught)
        ],
        "pairs": [{"from": list(a), "to": list(b), **proof} for (a, b), proof in zip(pairs, proofs)],
        "keep_open": keep_data,
    }
    return FortifyResult(document, fortified, combined, len(post_cells), scene, watchers, tuple(paths), tuple(ways))


def _watcher_data(grid: CoverageGrid, candidate: Candidate, index: int) -> dict[str, Any]:
    data: dict[str, Any] = {"kind": candidate.kind, "candidate": index, "position": list(candidate.position(grid))}
    if candidate.camera is not None:
        data["heading"] = candidate.camera.heading
        data["sweep"] = candidate.camera.sweep
    return data


def _path_data(grid: CoverageGrid, path: Counterexample) -> dict[str, Any]:
    return {
        "start_tick": path.start,
        "ticks": int(path.cells.size) - 1,
        "path": [list(grid.centre(*grid.unflat(int(cell)))) for cell in path.cells],
    }


def _combined_patrol(patrol: Patrol | None, post_cells: Sequence[int], swing: int) -> Patrol | None:
    """The patrol's guards then the posts, over their common lap."""
    if patrol is None and not post_cells:
        return None
    laps = [] if patrol is None else [patrol.states]
    if post_cells:
        laps.append(post_states(post_cells, swing))
    common = math.lcm(*(states.shape[1] for states in laps))
    states = np.concatenate([states[:, np.arange(common) % states.shape[1]] for states in laps])
    return Patrol(states, common, "evaluate" if patrol is None else patrol.strategy)
