"""``guardsim check --baseline``: the margins by which a level may be worse than an earlier version."""

from __future__ import annotations

from guardsim.cli.design_common import progress_line
from guardsim.level import Level
from guardsim.validate.checks import CheckResult, CheckRules

__all__ = ["baseline_results"]


def baseline_results(
    old: Level, new: Level, rules: CheckRules, max_worse: tuple[str, ...], *, seed: int
) -> list[CheckResult]:
    """One verdict per margin (:func:`guardsim.design.baseline_verdicts`): both versions under the rules'
    patrol file (or each under its loop patrol of the rules' team size), with the rules' sneak pairs
    (else the old version's default pairs)."""
    from guardsim.design import baseline_verdicts, diff, parse_margins

    margins = parse_margins(max_worse)
    pairs = [(rule.source, rule.target) for rule in rules.sneaks] or None
    found = diff(
        old, new, patrol_old=rules.patrol, patrol_new=rules.patrol, guards=rules.guards, pairs=pairs, seed=seed,
        progress=progress_line,
    )  # fmt: skip
    return [CheckResult(rule, holds, message) for rule, holds, message in baseline_verdicts(found, margins)]
