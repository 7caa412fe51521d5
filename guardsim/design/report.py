"""How hard a level is: measures with a source, and one difficulty score from 0 to 100 built from them.

Every part of the score is a number from 0 (easy) to 1 (hard), and the score is their weighted mean
times 100 (:data:`WEIGHTS`; the capture part counts only when alert episodes were run):

- ``caught``: share of entry-goal pairs with no undetected path (the player must be detected);
- ``tight``: 1 - slack / lap, averaged over the pairs (how few of the lap's ticks a player entering
  gets through from);
- ``straight``: 1 - direct / lap, averaged over the pairs, ``direct`` the lap ticks from which a player
  walking the fewest steps, never waiting, gets through unseen
  (:func:`~guardsim.design.measures.direct_entries`): how often the player cannot just walk across but
  must wait for a gap or go round (it does not saturate when a player who waits always gets through);
- ``risk``: path-distance risk of each pair's best path (:func:`~guardsim.design.measures.path_distance_risk`);
- ``peak``: the best path's peak awareness (how close a call it is);
- ``ways``: 1 - ways / :data:`~guardsim.design.measures.MAX_WAYS`, averaged over the pairs (fewer
  distinct ways through is harder);
- ``watched``: the share of the patrolled floor that some guard sees during the lap;
- ``unreadable``: turns and backtracks per move of the guards' laps (a hard-to-read patrol is harder to
  slip past), averaged over the guards;
- ``capture``: with ``alert`` episodes, the share of them in which the guards capture the intruder.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.design.analysis import Analysis, PairResult, Point, analyse
from guardsim.design.measures import (
    MAX_WAYS,
    GuardReadability,
    direct_entries,
    distinct_ways,
    path_distance_risk,
    readability,
)
from guardsim.errors import GuardsimError
from guardsim.grid import cell_of_state
from guardsim.level import Level
from guardsim.patrol import Patrol

__all__ = [
    "MAX_ALERT_EPISODES",
    "SOURCES",
    "WEIGHTS",
    "LevelReport",
    "PairReport",
    "formula",
    "report",
    "report_data",
    "report_of",
    "score_of",
]

#: Most alert episodes a report runs for its capture rate: ``alert --episodes``' own limit.
MAX_ALERT_EPISODES = 100_000

#: Weight of each part of the score.
WEIGHTS = {
    "caught": 25,
    "tight": 20,
    "straight": 20,
    "risk": 15,
    "peak": 10,
    "ways": 10,
    "watched": 10,
    "unreadable": 5,
    "capture": 15,
}


#: Where each part of the score comes from, as the page shows it.
SOURCES = {
    "caught": "the sneak check, undetected rule",
    "tight": "the sneak check's slack",
    "straight": "the straight walk: the fewest steps, never waiting, unseen",
    "risk": "path-distance risk, Tremblay, Torres and Verbrugge (FDG 2014)",
    "peak": "the detection model's meters on the best path",
    "ways": "distinct ways through (no shared corridor)",
    "watched": "the patrol's exposure: floor never watched",
    "unreadable": "turns and backtracks per move, after Zhang and Verbrugge (AIIDE 2018)",
    "capture": "guardsim alert's seeded episodes",
}


class PairReport(NamedTuple):
    """One entry-goal pair's measures."""

    source: Point
    target: Point
    outcome: str
    """``unseen``, ``undetected``, ``detected``, ``unreachable`` or ``unchecked`` (see
    :data:`guardsim.design.analysis.OUTCOMES`)."""
    ticks: int | None
    """Ticks of the best path (the fastest undetected one, else the closest call)."""
    slack: int
    """Lap ticks from which a player entering gets through undetected."""
    period: int
    peak: float | None
    """The best path's peak awareness (0 to 1)."""
    risk: float | None
    """The best path's meter risk (:attr:`guardsim.sneak.PathGrade.risk`)."""
    path_risk: float | None
    """The best path's path-distance risk (:func:`~guardsim.design.measures.path_distance_risk`)."""
    ways: int
    """Distinct undetected ways through (at most :data:`~guardsim.design.measures.MAX_WAYS`)."""
    direct: int = 0
    """Lap ticks from which a player walking the fewest steps, never waiting, gets through unseen
    (:func:`~guardsim.design.measures.direct_entries`)."""
    note: str = ""


class LevelReport(NamedTuple):
    """How hard a level is under a patrol."""

    level: str
    patrol: str
    period: int
    pairs: tuple[PairReport, ...]
    never_watched: float
    """Share of the patrolled floor no guard sees during the lap."""
    worst_idleness: int | None
    mean_idleness: float | None
    guards: tuple[GuardReadability, ...]
    capture_rate: float | None
    """Share of ``alert`` seeded episodes in which the intruder was captured; ``None`` when none were run."""
    alert_episodes: int
    parts: dict[str, float]
    """Each part of the score (0 easy to 1 hard), by :data:`WEIGHTS` name; parts that could not be
    measured (no pair, no alert episodes) are absent."""
    score: int
    """The difficulty, 0 to 100 (:func:`score_of`)."""


def score_of(parts: dict[str, float]) -> int:
    """The weighted mean of the parts given, times 100, rounded.

    >>> score_of({"caught": 1.0, "tight": 0.5})
    78
    """
    total = sum(WEIGHTS[name] for name in parts)
    return round(100 * sum(WEIGHTS[name] * value for name, value in parts.items()) / total) if total else 0


def formula(parts: dict[str, float] | None = None) -> str:
    """The score's formula over ``parts`` (all of them by default), as shown on the page.

    >>> formula({"caught": 1.0, "tight": 0.5})
    'score = 100 x (25 caught + 20 tight) / 45'
    """
    names = list(WEIGHTS) if parts is None else [name for name in WEIGHTS if name in parts]
    total = sum(WEIGHTS[name] for name in names)
    return f"score = 100 x ({' + '.join(f'{WEIGHTS[name]} {name}' for name in names)}) / {total}"


def _pair_report(analysis: Analysis, pair: PairResult, ways: bool) -> PairReport:
    result = pair.sneak
    period = analysis.patrol.ticks
    if result is None or result.path is None or result.grade is None:
        return PairReport(pair.source, pair.target, pair.outcome, None, 0, period, None, None, None, 0, 0, pair.note)
    path, grade = result.path, result.grade
    reach = analysis.detection.view_range
    reach = reach if np.isfinite(reach) else 8 * analysis.scene.grid.cell_size
    guard_cells = np.asarray(cell_of_state(analysis.patrol.states))
    risk = path_distance_risk(analysis.scene.grid, guard_cells, path.start_tick, path.cells, reach)
    count = 0
    gains = analysis.gains
    if ways and result.found and gains is not None and pair.source_cell is not None and pair.target_cell is not None:
        count = len(distinct_ways(analysis.scene.grid, gains, pair.source_cell, pair.target_cell, path.cells))
    direct = 0
    if pair.source_cell is not None and pair.target_cell is not None:
        direct = int(direct_entries(analysis.scene.grid, result.sight, pair.source_cell, pair.target_cell).sum())
    return PairReport(
        pair.source,
        pair.target,
        pair.outcome,
        path.ticks,
        result.slack,
        period,
        grade.peak,
        grade.risk,
        risk,
        count,
        direct,
    )


def _capture_rate(analysis: Analysis, episodes: int, seed: int) -> float:
    from guardsim.alert import run_alerts

    runs = run_alerts(
        analysis.scene,
        analysis.patrol,
        episodes=episodes,
        seed=seed,
        table=analysis.table,
        detection=analysis.detection,
    )
    outcomes = [episode.result() for episode in runs["ripple"]]
    return sum(outcome.captured_at is not None for outcome in outcomes) / episodes


def report_of(
    analysis: Analysis,
    *,
    alert: int = 0,
    seed: int = 0,
    ways: bool = True,
    progress: Callable[[str], None] | None = None,
) -> LevelReport:
    """The report of an analysis already made (:func:`~guardsim.design.analysis.analyse`); ``ways=False``
    leaves the distinct ways uncounted (and out of the score)."""
    if not 0 <= alert <= MAX_ALERT_EPISODES:
        raise GuardsimError(f"alert: {alert} episodes; from 0 to {MAX_ALERT_EPISODES}")
    tell = progress or (lambda line: None)
    if ways and analysis.pairs:
        tell("counting the distinct ways through")
    pairs = tuple(_pair_report(analysis, pair, ways) for pair in analysis.pairs)
    if alert > 0:
        tell(f"running {alert} seeded alert episode(s)")
    goal = analysis.goal
    floor = int(goal.sum())
    never = float((analysis.safe.sum()) / floor) if floor else 0.0
    guards = tuple(readability(analysis.patrol))
    capture = _capture_rate(analysis, alert, seed) if alert > 0 else None
    parts: dict[str, float] = {}
    checked = [pair for pair in pairs if pair.outcome not in ("unreachable", "unchecked")]
    if checked:
        parts["caught"] = float(np.mean([pair.outcome == "detected" for pair in checked]))
        parts["tight"] = float(np.mean([1 - pair.slack / pair.period for pair in checked]))
        parts["straight"] = float(np.mean([1 - pair.direct / pair.period for pair in checked]))
        parts["risk"] = float(np.mean([pair.path_risk or 0.0 for pair in checked]))
        parts["peak"] = float(np.mean([pair.peak or 0.0 for pair in checked]))
        if ways:
            parts["ways"] = float(np.mean([1 - pair.ways / MAX_WAYS for pair in checked]))
    if floor:
        parts["watched"] = 1.0 - never
    parts["unreadable"] = float(np.mean([guard.complexity for guard in guards]))
    if capture is not None:
        parts["capture"] = capture
    parts = {name: round(value, 4) for name, value in parts.items()}
    score = analysis.idleness
    return LevelReport(
        analysis.level.name,
        analysis.patrol_source,
        analysis.patrol.ticks,
        pairs,
        never,
        score.worst_idleness,
        score.mean_idleness,
        guards,
        capture,
        alert,
        parts,
        score_of(parts),
    )


def report(
    level: Level,
    patrol: Patrol | str | None = None,
    *,
    guards: int = 1,
    pairs: Sequence[tuple[Point, Point]] | None = None,
    alert: int = 0,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> LevelReport:
    """How hard ``level`` is under ``patrol`` (a :class:`~guardsim.patrol.Patrol` or a patrol.json path;
    ``None``: the loop patrol of ``guards`` guards), for the entry-goal ``pairs`` (world units; ``None``:
    :func:`~guardsim.design.analysis.default_pairs`), with ``alert`` seeded alert episodes for the
    capture rate (0: none).

    Examples
    --------
    A room with a pillar and one guard on its loop: the player gets round unseen, two ways (either side).

    >>> from guardsim.level import parse_level
    >>> room = parse_level({"outer": [[0, 0], [16, 0], [16, 10], [0, 10]], "holes": [[[6, 3], [10, 3], [10, 7], [6, 7]]],
    ...                     "guard": {"start": [8.5, 1.5], "view_range": 4}})
    >>> found = report(room, pairs=[((0.5, 5.5), (15.5, 5.5))])
    >>> found.pairs[0].outcome, found.pairs[0].ways, found.score
    ('unseen', 2, 30)
    """
    analysis = analyse(level, patrol=patrol, guards=guards, pairs=pairs, seed=seed, progress=progress)
    return report_of(analysis, alert=alert, seed=seed, progress=progress)


def report_data(found: LevelReport) -> dict[str, Any]:
    """report.json: the report as JSON-ready data, with the formula."""
    return {
        "level": found.level,
        "patrol": found.patrol,
        "period": found.period,
        "score": found.score,
        "formula": formula(found.parts),
        "weights": {name: WEIGHTS[name] for name in found.parts},
        "sources": {name: SOURCES[name] for name in found.parts},
        "parts": found.parts,
        "never_watched": round(found.never_watched, 4),
        "worst_idleness": found.worst_idleness,
        "mean_idleness": None if found.mean_idleness is None else round(found.mean_idleness, 2),
        "capture_rate": found.capture_rate,
        "alert_episodes": found.alert_episodes,
        "guards": [{**guard._asdict(), "complexity": round(guard.complexity, 4)} for guard in found.guards],
        "pairs": [
            {
                "from": list(pair.source),
                "to": list(pair.target),
                "outcome": pair.outcome,
                "ticks": pair.ticks,
                "slack": pair.slack,
                "direct": pair.direct,
                "period": pair.period,
                "peak_awareness": None if pair.peak is None else round(pair.peak, 4),
                "risk": None if pair.risk is None else round(pair.risk, 4),
                "path_distance_risk": None if pair.path_risk is None else round(pair.path_risk, 4),
                "ways": pair.ways,
                **({"note": pair.note} if pair.note else {}),
            }
            for pair in found.pairs
        ],
    }
