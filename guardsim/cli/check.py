"""``guardsim check``: CI gates. Exit 0 when every rule holds, 1 with one line per broken rule, 2 on bad input."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

import click

from guardsim.cli.common import (
    DetectionOverrides,
    EarsOverrides,
    build_scene,
    ears_options,
    level_options,
    load,
    parse_point,
)
from guardsim.cli.map_options import MapImport
from guardsim.cli.progress import StageLine
from guardsim.errors import GuardsimError
from guardsim.planners import PLANNERS

if TYPE_CHECKING:
    from guardsim.validate.checks import CheckRules

__all__ = ["check"]


def _points(
    _ctx: click.Context, param: click.Parameter, values: tuple[tuple[str, str], ...]
) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    pairs = []
    for source, target in values:
        first = parse_point(_ctx, param, source)
        second = parse_point(_ctx, param, target)
        assert first is not None and second is not None
        pairs.append((first, second))
    return pairs


def _each_point(_ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> list[tuple[float, float]]:
    points = [parse_point(_ctx, param, value) for value in values]
    return [point for point in points if point is not None]


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option(
    "--max-cover-steps", type=click.IntRange(min=0), help="The planner must see every reachable cell within N steps."
)
@click.option("--max-idleness", type=click.IntRange(min=0), help="The patrol's worst idleness must be at most T ticks.")
@click.option(
    "--no-unreachable",
    is_flag=True,
    default=None,
    help="Every cell a guard can stand in must be reachable from the start.",
)
@click.option(
    "--patrol",
    "patrol_path",
    type=str,
    help="patrol.json for --max-idleness, --safe and --sneak [default: make the loop patrol].",
)
@click.option(
    "--guards",
    type=click.IntRange(min=1, max=64),
    help="Team size of the loop patrol made without --patrol [default: 1].",
)
@click.option(
    "--planner", type=click.Choice(list(PLANNERS)), help="Planner of --max-cover-steps [default: ripplefront]."
)
@click.option(
    "--safe",
    "safe",
    multiple=True,
    callback=_each_point,
    metavar="X,Y",
    help="A safe spot: no guard sees its cell during the lap; repeatable.",
)
@click.option(
    "--undetected",
    is_flag=True,
    default=None,
    help="--safe asks only that a player standing there is never detected (seen briefly is allowed).",
)
@click.option(
    "--sneak",
    "sneaks",
    type=(str, str),
    multiple=True,
    callback=_points,
    metavar="FROM TO",
    help="X,Y X,Y: a sneak to check; repeatable, one --expect each.",
)
@click.option(
    "--expect",
    "expects",
    type=click.Choice(["caught", "sneaks", "detected", "undetected"]),
    multiple=True,
    help="What each --sneak must give: caught/sneaks (an unseen path), detected/undetected (an undetected one).",
)
@click.option(
    "--unheard",
    is_flag=True,
    default=None,
    help="Each --sneak asks about paths no guard hears either: a walk or a sneak chosen for each step, by the "
    "level's intruder noise keys (--walk-noise, --sneak-noise, --sneak-ticks override them).",
)
@ears_options
@click.option(
    "--min-slack",
    type=click.IntRange(min=0),
    help="Each --sneak's path must exist from at least N of the lap's ticks (too tight breaks the build).",
)
@click.option(
    "--max-slack",
    type=click.IntRange(min=0),
    help="... and from at most N of them (too loose breaks the build).",
)
@click.option(
    "--checks", "checks_path", type=str, help="Read the rules from a checks file (TOML or JSON); options add to it."
)
@click.option(
    "--max-lap",
    type=click.IntRange(min=1),
    help="Longest joint lap of the patrol and the level's camera swings, in ticks [default: 10000].",
)
@click.option(
    "--baseline",
    "baseline_path",
    type=str,
    help="An earlier version of LEVEL: fail when LEVEL is worse than it by more than the --max-worse margins.",
)
@click.option(
    "--max-worse",
    "max_worse",
    multiple=True,
    metavar="NAME=N",
    help="A --baseline margin (outcome, safe, hiding, score, slack, idleness, cover); repeatable "
    "[default: outcome=0 safe=0 score=10].",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@level_options(detection=True)
def check(
    level_path: str,
    map_import: MapImport,
    max_cover_steps: int | None,
    max_idleness: int | None,
    no_unreachable: bool | None,
    patrol_path: str | None,
    guards: int | None,
    planner: str | None,
    safe: list[tuple[float, float]],
    undetected: bool | None,
    sneaks: list[tuple[tuple[float, float], tuple[float, float]]],
    expects: tuple[str, ...],
    unheard: bool | None,
    ears_overrides: EarsOverrides,
    min_slack: int | None,
    max_slack: int | None,
    checks_path: str | None,
    max_lap: int | None,
    baseline_path: str | None,
    max_worse: tuple[str, ...],
    seed: int,
    detection_overrides: DetectionOverrides,
    los: str,
    fov: float | None,
    view_range: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Check LEVEL against the rules given; print one line per broken rule and exit 1 if any is broken.

    Exit status: 0 every rule holds, 1 some rule is broken, 2 bad input (a level, patrol or checks file
    that cannot be read, a safe or sneak point outside the level, no rule at all).
    """
    from guardsim.validate.checks import EXPECTATIONS, CheckRules, SafeRule, SneakRule, read_checks, run_checks

    if len(expects) != len(sneaks):
        raise GuardsimError(
            f"each --sneak needs its --expect {'|'.join(EXPECTATIONS)}: {len(sneaks)} --sneak, {len(expects)} --expect"
        )
    rules = (read_checks(checks_path) if checks_path else CheckRules()).with_options(
        sneaks=[SneakRule(a, b, e) for (a, b), e in zip(sneaks, expects)], safe=[SafeRule(point) for point in safe],
        max_cover_steps=max_cover_steps, max_idleness=max_idleness, no_unreachable=no_unreachable, patrol=patrol_path,
        guards=guards, planner=planner, undetected=undetected, min_slack=min_slack, max_slack=max_slack,
        max_lap=max_lap, unheard=unheard,
    )  # fmt: skip
    _check_something(rules, level_path, checks_path, baseline_path, max_worse)
    progress = StageLine(sys.stderr, "check").start()
    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
    level = ears_overrides.apply(detection_overrides.apply(level))
    scene = build_scene(level, los, fov, view_range)
    from guardsim.detection.hearing import walks_audibly
    from guardsim.kernels.ahead import compile_ahead

    progress("compiling", 0, 0)
    compile_ahead("check")
    if rules.unheard and walks_audibly(level.intruder):
        compile_ahead("sneak:unheard")  # audible steps: the sneak rules choose gaits
    if baseline_path is not None:
        compile_ahead("report")  # the baseline's analysis is report's
    progress(f"checking {rules.count} rule{'' if rules.count == 1 else 's'}", 0, 0)
    results = run_checks(scene, rules, seed=seed) if rules.count else []
    if baseline_path is not None:
        from guardsim.cli.baseline import baseline_results

        progress("comparing with the baseline", 0, 0)
        old = load(baseline_path, max_cells, max_vertices, max_file_bytes, map_import)
        old = ears_overrides.apply(detection_overrides.apply(old))
        results += baseline_results(old, level, rules, max_worse, seed=seed)
    progress.close()
    broken = [result for result in results if not result.holds]
    for result in broken:
        click.echo(f"{level_path}: broken: {result.rule}: {result.message}")
    if broken:
        sys.exit(1)
    click.echo(
        f"{level_path}: all {len(results)} rules hold" if len(results) != 1 else f"{level_path}: its one rule holds"
    )


def _check_something(
    rules: CheckRules, level_path: str, checks_path: str | None, baseline_path: str | None, max_worse: tuple[str, ...]
) -> None:
    """Refuse a run with no rule to check and no baseline to compare with."""
    if max_worse and baseline_path is None:
        raise GuardsimError("--max-worse sets the margins of --baseline: give --baseline OLD")
    if rules.count == 0 and baseline_path is None:
        if checks_path:
            raise GuardsimError(
                f"{checks_path}: no rule to check in the checks file (max_cover_steps, max_idleness, "
                "no_unreachable, safe or sneak), nor on the command line"
            )
        raise GuardsimError(
            f"{level_path}: no rule to check: give --max-cover-steps, --max-idleness, --no-unreachable, --safe, "
            "--sneak, --checks or --baseline"
        )
