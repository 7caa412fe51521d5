"""Statistics of a batch per level and planner: ``summary.json`` and the table printed at the end."""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.experiment.episodes import EpisodeRecord
from guardsim.trace import OUTCOMES

__all__ = ["ALL_OUTCOMES", "GroupSummary", "Statistics", "describe", "format_table", "summarise", "summary_json"]

#: Outcomes counted per group: the simulation's, and ``error`` for an episode that raised.
ALL_OUTCOMES = (*OUTCOMES, "error")


class Statistics(NamedTuple):
    """Five-number summary and mean of a sample. Quartiles interpolate linearly (numpy's default)."""

    count: int
    mean: float
    median: float
    q1: float
    """First quartile (25th percentile)."""
    q3: float
    """Third quartile (75th percentile)."""
    min: int
    max: int


def describe(values: Sequence[int]) -> Statistics | None:
    """:class:`Statistics` of ``values``, rounded to 3 decimals; ``None`` for no values.

    Examples
    --------
    >>> describe([4, 1, 3, 2])
    Statistics(count=4, mean=2.5, median=2.5, q1=1.75, q3=3.25, min=1, max=4)
    """
    if not values:
        return None
    array = np.asarray(values, dtype=np.float64)
    q1, median, q3 = (round(float(value), 3) for value in np.percentile(array, [25, 50, 75]))
    return Statistics(len(values), round(float(array.mean()), 3), median, q1, q3, int(min(values)), int(max(values)))


class GroupSummary(NamedTuple):
    """The episodes of one level with one planner."""

    level: str
    """Level name."""
    level_file: str
    planner: str
    episodes: int
    """Rows in the group, errors included."""
    outcomes: dict[str, int]
    """Count per outcome, every one of :data:`ALL_OUTCOMES` present."""
    steps: Statistics | None
    """Steps of the episodes that did not raise (those stopped by the step limit count with the limit)."""
    t90: Statistics | None
    """T90 of the episodes that reached 90 % coverage."""

    def to_data(self) -> dict[str, Any]:
        """The JSON-ready dictionary."""
        data = self._asdict()
        for name in ("steps", "t90"):
            data[name] = data[name]._asdict() if data[name] is not None else None
        return data


def summarise(records: Iterable[EpisodeRecord]) -> list[GroupSummary]:
    """One :class:`GroupSummary` per ``(level_file, planner)``, in that order."""
    groups: dict[tuple[str, str], list[EpisodeRecord]] = {}
    for record in records:
        groups.setdefault((record.level_file, record.planner), []).append(record)
    summaries = []
    for (level_file, planner), members in sorted(groups.items()):
        outcomes = dict.fromkeys(ALL_OUTCOMES, 0)
        for record in members:
            outcomes[record.outcome] = outcomes.get(record.outcome, 0) + 1
        summaries.append(
            GroupSummary(
                level=members[0].level,
                level_file=level_file,
                planner=planner,
                episodes=len(members),
                outcomes=outcomes,
                steps=describe([record.steps for record in members if record.steps is not None]),
                t90=describe([record.t90 for record in members if record.t90 is not None]),
            )
        )
    return summaries


def summary_json(groups: Sequence[GroupSummary], run: dict[str, Any]) -> str:
    """The text of ``summary.json``: the run's options and one entry per group."""
    return json.dumps({"run": run, "groups": [group.to_data() for group in groups]}, indent=2) + "\n"


def format_table(groups: Sequence[GroupSummary]) -> str:
    """The summary as an aligned text table, one line per level and planner."""
    header = ("level", "planner", "episodes", "covered", "other", "median", "q1", "q3", "min", "max", "mean", "T90 med")
    lines = [header]
    for group in groups:
        steps, t90 = group.steps, group.t90
        other = ", ".join(f"{count} {name}" for name, count in group.outcomes.items() if count and name != "covered")
        lines.append((
            group.level, group.planner, str(group.episodes), str(group.outcomes["covered"]), other or "-",
            *(_number(getattr(steps, name, None)) for name in ("median", "q1", "q3", "min", "max", "mean")),
            _number(t90.median if t90 else None),
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
