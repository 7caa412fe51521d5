"""Design questions about a level: how hard it is (:func:`report`), what an edit changed (:func:`diff`),
and the analysis both read (:func:`analyse`), which ``guardsim watch`` recomputes on each save.

- :mod:`~guardsim.design.analysis`: the level, its patrol, exposure and the sneak check of each pair.
- :mod:`~guardsim.design.measures`: path-distance risk, the straight walk's entry ticks, distinct ways
  through, patrol readability.
- :mod:`~guardsim.design.report`: the difficulty report and its 0-100 score.
- :mod:`~guardsim.design.reuse`: the view table of an edited level, rebuilt only near the edit.
- :mod:`~guardsim.design.diff`: two versions compared, and the margins of ``check --baseline``.

See ``docs/design.md``.
"""

from __future__ import annotations

from guardsim.design.analysis import Analysis, PairResult, analyse, default_pairs
from guardsim.design.diff import MARGINS, LevelDiff, PairChange, baseline_verdicts, diff, diff_data, parse_margins
from guardsim.design.measures import GuardReadability, direct_entries, distinct_ways, path_distance_risk, readability
from guardsim.design.report import (
    SOURCES,
    WEIGHTS,
    LevelReport,
    PairReport,
    formula,
    report,
    report_data,
    report_of,
    score_of,
)

__all__ = [
    "MARGINS",
    "SOURCES",
    "WEIGHTS",
    "Analysis",
    "GuardReadability",
    "LevelDiff",
    "LevelReport",
    "PairChange",
    "PairReport",
    "PairResult",
    "analyse",
    "baseline_verdicts",
    "default_pairs",
    "diff",
    "diff_data",
    "direct_entries",
    "distinct_ways",
    "formula",
    "parse_margins",
    "path_distance_risk",
    "readability",
    "report",
    "report_data",
    "report_of",
    "score_of",
]
