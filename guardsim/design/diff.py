"""What an edit changed: two versions of a level analysed alike and compared, and the margins a CI build
holds the new version to (``guardsim check --baseline``).

Both versions are analysed with the same entry-goal pairs (the old version's default pairs when none
are given) and the same kind of patrol (each its own patrol file, or each its own loop patrol of the same
team size). Cell-by-cell figures (safe spots, the exposure difference) need the two grids to line up:
same shape, origin and cell size; otherwise only the totals are compared.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.design.analysis import Analysis, Point, analyse, default_pairs
from guardsim.design.report import LevelReport, PairReport, report_data, report_of
from guardsim.errors import CheckError
from guardsim.level import Level
from guardsim.patrol import Patrol

__all__ = [
    "MARGINS",
    "LevelDiff",
    "PairChange",
    "baseline_verdicts",
    "diff",
    "diff_data",
    "diff_summary",
    "parse_margins",
]


class PairChange(NamedTuple):
    """One entry-goal pair before and after the edit."""

    before: PairReport
    after: PairReport
    hiding_gained: tuple[Point, ...]
    """Hiding spots (cell centres, world units) listed after the edit and not before."""
    hiding_lost: tuple[Point, ...]

    @property
    def outcome_changed(self) -> bool:
        return self.before.outcome != self.after.outcome


class LevelDiff(NamedTuple):
    """Two versions of a level compared."""

    old: Analysis
    new: Analysis
    old_report: LevelReport
    new_report: LevelReport
    aligned: bool
    """Whether the two grids line up cell for cell (same shape, origin and cell size)."""
    cells_added: int
    """Floor cells (a guard-sized body fits) in the new version and not the old."""
    cells_removed: int
    cover_steps: tuple[int | None, int | None]
    """Steps RippleFront takes to see every reachable cell, before and after (``None``: not covered)."""
    pairs: tuple[PairChange, ...]
    safe_gained: tuple[Point, ...]
    """Safe spots (floor no guard sees during the lap) after the edit and not before (cell centres)."""
    safe_lost: tuple[Point, ...]
    exposure_change: np.ndarray | None
    """``float64 (rows, cols)``: exposure after minus before where both are floor, else 0; ``None`` when
    the grids do not line up."""


def _points(analysis: Analysis, cells: np.ndarray) -> tuple[Point, ...]:
    grid = analysis.scene.grid
    return tuple(grid.centre(*grid.unflat(int(cell))) for cell in cells)


def _cover_steps(analysis: Analysis, seed: int) -> int | None:
    from guardsim.simulation import Simulation

    simulation = Simulation(analysis.scene, "ripplefront")
    simulation.reset(seed=seed)
    trace = simulation.run()
    return trace.steps if trace.covered else None


def _hiding(analysis: Analysis, index: int) -> set[Point]:
    pair = analysis.pairs[index]
    if pair.sneak is None:
        return set()
    return set(_points(analysis, np.array([spot.cell for spot in pair.sneak.hiding_spots], dtype=np.int64)))


def diff(
    old: Level,
    new: Level,
    *,
    patrol_old: Patrol | str | None = None,
    patrol_new: Patrol | str | None = None,
    guards: int = 1,
    pairs: Sequence[tuple[Point, Point]] | None = None,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> LevelDiff:
    """Compare two versions of a level: cells added and removed, steps to cover, idleness, each pair's
    sneak outcome, ticks, slack, risk and peak awareness, safe and hiding spots gained and lost, and the
    exposure difference.

    Give both patrols (patrol files or :class:`~guardsim.patrol.Patrol`), or neither: then each version
    gets its loop patrol of ``guards`` guards.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> level = parse_level({"outer": [[0, 0], [16, 0], [16, 10], [0, 10]], "holes": [[[6, 3], [10, 3], [10, 7], [6, 7]]],
    ...                      "guard": {"start": [8.5, 1.5], "view_range": 4}})
    >>> same = diff(level, level, pairs=[((0.5, 5.5), (15.5, 5.5))])
    >>> same.cells_added, same.cells_removed, same.safe_lost, same.pairs[0].outcome_changed
    (0, 0, (), False)
    """
    if (patrol_old is None) != (patrol_new is None):
        raise CheckError("give a patrol for both versions (--patrol-old and --patrol-new), or for neither")
    tell = progress or (lambda line: None)
    tell("analysing the old version")
    before = analyse(old, patrol=patrol_old, guards=guards, pairs=pairs, seed=seed, progress=progress)
    chosen = [(pair.source, pair.target) for pair in before.pairs] if pairs is None else list(pairs)
    if pairs is None and not chosen:
        chosen = list(default_pairs(before.scene, before.goal))
    tell("analysing the new version")
    after = analyse(new, patrol=patrol_new, guards=guards, pairs=chosen, seed=seed, progress=progress)
    tell("counting ways through and the steps to cover, before and after")
    old_report, new_report = report_of(before, seed=seed), report_of(after, seed=seed)
    a, b = before.scene.grid, after.scene.grid
    aligned = a.shape == b.shape and a.origin == b.origin and a.cell_size == b.cell_size
    floor_a, floor_b = a.traversable.ravel(), b.traversable.ravel()
    if aligned:
        added, removed = int((floor_b & ~floor_a).sum()), int((floor_a & ~floor_b).sum())
        safe_a, safe_b = before.safe, after.safe
        safe_gained = _points(after, np.flatnonzero(safe_b & ~safe_a))
        safe_lost = _points(before, np.flatnonzero(safe_a & ~safe_b))
        both = floor_a & floor_b
        change = np.where(both, after.exposure - before.exposure, 0.0).reshape(b.shape)
    else:
        added, removed = max(0, int(floor_b.sum() - floor_a.sum())), max(0, int(floor_a.sum() - floor_b.sum()))
        safe_gained = safe_lost = ()
        change = None
    changes = []
    for index, (first, second) in enumerate(zip(old_report.pairs, new_report.pairs)):
        hiding_a, hiding_b = _hiding(before, index), _hiding(after, index)
        changes.append(
            PairChange(first, second, tuple(sorted(hiding_b - hiding_a)), tuple(sorted(hiding_a - hiding_b)))
        )
    return LevelDiff(
        before,
        after,
        old_report,
        new_report,
        aligned,
        added,
        removed,
        (_cover_steps(before, seed), _cover_steps(after, seed)),
        tuple(changes),
        safe_gained,
        safe_lost,
        change,
    )


def _round(value: float | None, digits: int = 3) -> float | None:
    return None if value is None else round(value, digits)


def diff_data(found: LevelDiff) -> dict[str, Any]:
    """diff.json: every figure before and after, and both reports."""
    old, new = found.old_report, found.new_report
    return {
        "old": old.level,
        "new": new.level,
        "aligned": found.aligned,
        "cells_added": found.cells_added,
        "cells_removed": found.cells_removed,
        "cover_steps": list(found.cover_steps),
        "worst_idleness": [old.worst_idleness, new.worst_idleness],
        "mean_idleness": [_round(old.mean_idleness, 2), _round(new.mean_idleness, 2)],
        "score": [old.score, new.score],
        "safe_spots": [int(found.old.safe.sum()), int(found.new.safe.sum())],
        "safe_gained": [list(point) for point in found.safe_gained],
        "safe_lost": [list(point) for point in found.safe_lost],
        "pairs": [
            {
                "from": list(change.before.source),
                "to": list(change.before.target),
                "outcome": [change.before.outcome, change.after.outcome],
                "ticks": [change.before.ticks, change.after.ticks],
                "slack": [change.before.slack, change.after.slack],
                "risk": [_round(change.before.risk), _round(change.after.risk)],
                "path_distance_risk": [_round(change.before.path_risk), _round(change.after.path_risk)],
                "peak_awareness": [_round(change.before.peak), _round(change.after.peak)],
                "ways": [change.before.ways, change.after.ways],
                "hiding_gained": [list(point) for point in change.hiding_gained],
                "hiding_lost": [list(point) for point in change.hiding_lost],
            }
            for change in found.pairs
        ],
        "old_report": report_data(old),
        "new_report": report_data(new),
    }


#: The margins of ``check --baseline``: how much worse than the baseline the new version may be, and the
#: default of each (``None``: not checked unless given).
MARGINS: dict[str, int | None] = {
    "outcome": 0,
    "safe": 0,
    "hiding": None,
    "score": 10,
    "slack": None,
    "idleness": None,
    "cover": None,
}
_MEANING = {
    "outcome": "entry-goal pairs whose sneak outcome changed",
    "safe": "safe spots lost",
    "hiding": "hiding spots lost on a pair",
    "score": "points the difficulty score moved (either way)",
    "slack": "lap ticks a pair's slack moved (either way)",
    "idleness": "ticks the worst idleness grew",
    "cover": "steps the cover walk grew",
}


def parse_margins(items: Sequence[str]) -> dict[str, int]:
    """The margins to check: :data:`MARGINS`' defaults, changed by ``NAME=N`` items.

    >>> parse_margins(["safe=3", "slack=20"])
    {'outcome': 0, 'safe': 3, 'score': 10, 'slack': 20}
    >>> parse_margins(["safety=3"])
    Traceback (most recent call last):
    ...
    guardsim.errors.CheckError: --max-worse safety=3: unknown margin 'safety' (known: outcome, safe, hiding, score, slack, idleness, cover)
    """
    margins = {name: value for name, value in MARGINS.items() if value is not None}
    for item in items:
        name, _, text = item.partition("=")
        if name not in MARGINS:
            raise CheckError(f"--max-worse {item}: unknown margin {name!r} (known: {', '.join(MARGINS)})")
        try:
            value = int(text)
        except ValueError:
            raise CheckError(f"--max-worse {item}: expected NAME=N with N a whole number") from None
        if value < 0:
            raise CheckError(f"--max-worse {item}: a margin cannot be negative")
        margins[name] = value
    return {name: margins[name] for name in MARGINS if name in margins}


def baseline_verdicts(found: LevelDiff, margins: dict[str, int]) -> list[tuple[str, bool, str]]:
    """``(rule, holds, message)`` for each margin: how much worse than the baseline the new version is."""
    out = []
    old, new = found.old_report, found.new_report

    def verdict(name: str, measured: int, detail: str) -> None:
        limit = margins[name]
        out.append((f"baseline {name}", measured <= limit, f"{measured} {_MEANING[name]} ({detail}), margin {limit}"))

    if "outcome" in margins:
        changed = [change for change in found.pairs if change.outcome_changed]
        detail = "; ".join(
            f"{c.before.source[0]:g},{c.before.source[1]:g} -> {c.before.target[0]:g},{c.before.target[1]:g}: "
            f"{c.before.outcome} -> {c.after.outcome}"
            for c in changed
        )
        verdict("outcome", len(changed), detail or "none")
    if "safe" in margins:
        lost = found.safe_lost
        where = ", ".join(f"({x:g}, {y:g})" for x, y in lost[:3]) + (" ..." if len(lost) > 3 else "")
        verdict("safe", len(lost), f"{where}" if lost else "none")
    if "hiding" in margins:
        worst = max((len(change.hiding_lost) for change in found.pairs), default=0)
        verdict("hiding", worst, "on the worst pair")
    if "score" in margins:
        verdict("score", abs(new.score - old.score), f"{old.score} -> {new.score}")
    if "slack" in margins:
        moved = max((abs(c.after.slack - c.before.slack) for c in found.pairs), default=0)
        verdict("slack", moved, "on the pair that moved most")
    if "idleness" in margins:
        before, after = old.worst_idleness, new.worst_idleness
        grown = (after - before) if before is not None and after is not None else (0 if after == before else 10**9)
        verdict("idleness", max(0, grown), f"{before} -> {after} ticks")
    if "cover" in margins:
        first, second = found.cover_steps
        grown = (second - first) if first is not None and second is not None else (0 if first == second else 10**9)
        verdict("cover", max(0, grown), f"{first} -> {second} steps")
    return out


def _pair(values: list[Any]) -> str:
    return " -> ".join(
        "-" if value is None else f"{value:g}" if isinstance(value, float) else str(value) for value in values
    )


def diff_summary(data: dict[str, Any], name: str) -> list[str]:
    """What ``guardsim diff`` prints of :func:`diff_data`'s document, old -> new, a line each: cells,
    steps to cover, idleness, safe spots, each pair's sneak (with the path-distance risk and the ways
    through, which the score reads), and the difficulty of the level ``name`` (``old -> new`` names when
    the edit renamed it)."""
    lines = [
        f"  cells: {data['cells_added']} added, {data['cells_removed']} removed",
        f"  steps to cover: {_pair(data['cover_steps'])}",
        f"  idleness: worst {_pair(data['worst_idleness'])}, mean {_pair(data['mean_idleness'])}",
        f"  safe spots: {_pair(data['safe_spots'])} ({len(data['safe_gained'])} gained, {len(data['safe_lost'])} lost)",
    ]
    for pair in data["pairs"]:
        where = f"{pair['from'][0]:g},{pair['from'][1]:g} -> {pair['to'][0]:g},{pair['to'][1]:g}"
        lines.append(
            f"  {where}: {_pair(pair['outcome'])}; ticks {_pair(pair['ticks'])}; slack {_pair(pair['slack'])}; "
            f"risk {_pair(pair['risk'])}; peak awareness {_pair(pair['peak_awareness'])}; "
            f"path-distance risk {_pair(pair['path_distance_risk'])}; ways through {_pair(pair['ways'])}; "
            f"hiding spots {len(pair['hiding_gained'])} gained, {len(pair['hiding_lost'])} lost"
        )
    old, new = data.get("old"), data.get("new")
    title = f"{old} -> {new}" if old is not None and new is not None and old != new else name
    lines.append(f"{title}: difficulty {_pair(data['score'])}")
    return lines
