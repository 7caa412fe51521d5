"""Statistics of a batch per level and planner: ``summary.json`` and the table printed at the end.

Everything here is deterministic: the wall-time columns of the rows are left out, so the summary of a
batch is the same file whatever ran it.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.experiment.episodes import EpisodeRecord
from guardsim.trace import OUTCOMES

__all__ = [
    "ALL_OUTCOMES",
    "MOTION_COLUMNS",
    "GroupSummary",
    "Statistics",
    "describe",
    "format_table",
    "summarise",
    "summary_json",
]

#: Outcomes counted per group: the simulation's, and ``error`` for an episode that raised.
ALL_OUTCOMES = (*OUTCOMES, "error")


class Statistics(NamedTuple):
    """Five-number summary and mean of a sample. Quartiles interpolate linearly (numpy's default)."""

    count: int  # type: ignore[assignment]  # the field shadows tuple.count, as the summary's JSON names it
    mean: float
    median: float
    q1: float
    """First quartile (25th percentile)."""
    q3: float
    """Third quartile (75th percentile)."""
    min: float
    """Smallest value (an ``int`` for a sample of integers)."""
    max: float
    """Largest value (an ``int`` for a sample of integers)."""


def describe(values: Sequence[float]) -> Statistics | None:
    """:class:`Statistics` of ``values``, rounded to 3 decimals; ``None`` for no values.

    Examples
    --------
    >>> describe([4, 1, 3, 2])
    Statistics(count=4, mean=2.5, median=2.5, q1=1.75, q3=3.25, min=1, max=4)
    >>> describe([1.25, 2.0])
    Statistics(count=2, mean=1.625, median=1.625, q1=1.438, q3=1.812, min=1.25, max=2.0)
    """
    if not values:
        return None
    array = np.asarray(values, dtype=np.float64)
    q1, median, q3 = (round(float(value), 3) for value in np.percentile(array, [25, 50, 75]))
    integers = all(isinstance(value, (int, np.integer)) for value in values)
    low, high = ((int(limit) if integers else round(float(limit), 3)) for limit in (min(values), max(values)))
    return Statistics(len(values), round(float(array.mean()), 3), median, q1, q3, low, high)


class GroupSummary(NamedTuple):
    """The episodes of one level with one planner."""

    level: str
    """Level name."""
    level_file: str
    planner: str
    guards: int
    """Guards in the team."""
    episodes: int
    """Rows in the group, errors included."""
    outcomes: dict[str, int]
    """Count per outcome, every one of :data:`ALL_OUTCOMES` present."""
    steps: Statistics | None
    """Steps of the episodes that did not raise (those stopped by the step limit count with the limit);
    a team's makespan."""
    t90: Statistics | None
    """T90 of the episodes that reached 90 % coverage."""
    total_moves: Statistics | None
    """Moves summed over the guards, of the episodes that did not raise."""
    bound_ratio: Statistics | None
    """``steps / best_bound`` of the episodes with a positive bound (one guard only: ``None`` for a team).
    Episodes stopped by the step limit count with the limit, as in :attr:`steps`."""
    motion: dict[str, Statistics] | None = None
    """Statistics of each motion column of the rows that have it (:data:`MOTION_COLUMNS`: game seconds,
    T50/T90/T99 seconds, distance, turning, turns; on the grid only the steps-based ones)."""

    def to_data(self) -> dict[str, Any]:
        """The JSON-ready dictionary."""
        data = self._asdict()
        for name in ("steps", "t90", "total_moves", "bound_ratio"):
            data[name] = data[name]._asdict() if data[name] is not None else None
        data["motion"] = {name: stats._asdict() for name, stats in (self.motion or {}).items()}
        return data


def summarise(records: Iterable[EpisodeRecord]) -> list[GroupSummary]:
    """One :class:`GroupSummary` per ``(level_file, planner, guards)``, in that order."""
    groups: dict[tuple[str, str, int], list[EpisodeRecord]] = {}
    for record in records:
        groups.setdefault((record.level_file, record.planner, record.guards), []).append(record)
    summaries = []
    for (level_file, planner, guards), members in sorted(groups.items()):
        outcomes = dict.fromkeys(ALL_OUTCOMES, 0)
        for record in members:
            outcomes[record.outcome] = outcomes.get(record.outcome, 0) + 1
        summaries.append(
            GroupSummary(
                level=members[0].level,
                level_file=level_file,
                planner=planner,
                guards=guards,
                episodes=len(members),
                outcomes=outcomes,
                steps=describe([record.steps for record in members if record.steps is not None]),
                t90=describe([record.t90 for record in members if record.t90 is not None]),
                total_moves=describe([record.total_moves for record in members if record.total_moves is not None]),
                bound_ratio=describe(
                    [ratio for ratio in (record.bound_ratio for record in members) if ratio is not None]
                ),
                motion=_motion_statistics(members),
            )
        )
    return summaries


#: The numeric motion columns summarised per group.
MOTION_COLUMNS = ("game_seconds", "t50_s", "t90_s", "t99_s", "distance", "turning_degrees", "in_place_s", "turns",
                  "u_turns", "turns_per_minute")  # fmt: skip


def _motion_statistics(members: Sequence[EpisodeRecord]) -> dict[str, Statistics]:
    found = {
        name: describe([v for v in (getattr(r, name) for r in members) if v is not None]) for name in MOTION_COLUMNS
    }
    return {name: stats for name, stats in found.items() if stats is not None}


def summary_json(groups: Sequence[GroupSummary], run: dict[str, Any]) -> str:
    """The text of ``summary.json``: the run's options and one entry per group."""
    return json.dumps({"run": run, "groups": [group.to_data() for group in groups]}, indent=2) + "\n"


def format_table(groups: Sequence[GroupSummary]) -> str:
    """The summary as an aligned text table, one line per level and planner.

    The columns after ``other`` are steps (median, quartiles, range, mean), the median T90 and the median
    of steps / best lower bound (``-`` for teams); in continuous motion, the medians of game seconds, T90
    in seconds, turns per minute, seconds turning in place, turns and U-turns; with a team, also the
    median of the moves summed over its guards.
    """
    teams = any(group.guards > 1 for group in groups)
    # Motion medians once a group walked continuously (the grid's turns are in summary.json).
    continuous = any("game_seconds" in (group.motion or {}) for group in groups)
    shown = ("game_seconds", "t90_s", "turns_per_minute", "in_place_s", "turns", "u_turns") if continuous else ()
    names = {
        "game_seconds": "seconds med",
        "t90_s": "T90 s med",
        "turns_per_minute": "turns/min med",
        "in_place_s": "in place s med",
        "turns": "turns med",
        "u_turns": "U-turns med",
    }
    header = ("level", "planner", "episodes", "covered", "other", "median", "q1", "q3", "min", "max", "mean",
              "T90 med", "steps/bound med", *(names[name] for name in shown), *(("moves med",) if teams else ()))  # fmt: skip
    lines = [header]
    for group in groups:
        steps, t90, ratio = group.steps, group.t90, group.bound_ratio
        other = ", ".join(f"{count} {name}" for name, count in group.outcomes.items() if count and name != "covered")
        lines.append((
            group.level, group.planner, str(group.episodes), str(group.outcomes["covered"]), other or "-",
            *(_number(getattr(steps, name, None)) for name in ("median", "q1", "q3", "min", "max", "mean")),
            _number(t90.median if t90 else None),
            f"{ratio.median:.2f}" if ratio else "-",
            *(_number(stats.median if (stats := (group.motion or {}).get(name)) else None) for name in shown),
            *((_number(group.total_moves.median if group.total_moves else None),) if teams else ()),
        ))  # fmt: skip
    widths = [max(len(line[column]) for line in lines) for column in range(len(header))]
    left = {0, 1, 4}
    return "\n".join(
        "  ".join(cell.ljust(width) if column in left else cell.rjust(width)
                  for column, (cell, width) in enumerate(zip(line, widths))).rstrip()
        for line in lines
    )  # fmt: skip


def _number(value: float | None) -> str:
    if value is None:
        return "-"
    return f"{value:g}" if float(value).is_integer() else f"{value:.1f}"
