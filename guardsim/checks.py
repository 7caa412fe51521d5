"""CI gates: rules a level must keep (cover steps, idleness, reachability, sneaks), checked in one go.

A studio's CI runs ``guardsim check`` on each level; it fails only when an edit breaks a rule the team
chose, not on every change as a snapshot would. Rules come from the command line or a small checks file
(JSON or TOML) with the same names::

    max_cover_steps = 400        # the planner sees every reachable cell within this many steps
    max_idleness = 600           # the patrol's worst idleness (ticks a cell goes unwatched) at most this
    no_unreachable = true        # every cell a guard can stand in is reachable from the start
    guards = 1                   # team size of the loop patrol made when no patrol file is given
    planner = "ripplefront"      # the planner of max_cover_steps
    patrol = "patrol.json"       # the patrol for max_idleness and the sneaks (else the loop is made)
    [[sneak]]
    from = [2.5, 2.5]
    to = [57.5, 57.5]
    expect = "caught"            # or "sneaks"
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

from guardsim.detection import GuardDetection
from guardsim.errors import GuardsimError
from guardsim.patrol import Patrol, patrol_setup, plan_loop, read_patrol, score_patrol
from guardsim.planners import PLANNERS
from guardsim.reading import display_path, json_type, parse_json, read_text_file
from guardsim.scene import Scene
from guardsim.simulation import Simulation
from guardsim.sneak import sneak_check

__all__ = ["CheckError", "CheckResult", "CheckRules", "SneakRule", "read_checks", "run_checks"]

#: Largest checks file read.
MAX_CHECKS_BYTES = 1024 * 1024


class CheckError(GuardsimError):
    """A checks file or a rule cannot be used (bad input, not a broken rule)."""


class SneakRule(NamedTuple):
    """Whether a player can get from one point to another unseen, and what the answer must be."""

    source: tuple[float, float]
    target: tuple[float, float]
    expect: str
    """``"caught"`` (no unseen path may exist) or ``"sneaks"`` (one must)."""
    where: str = "--sneak"
    """Where the rule was given, for error lines: ``--sneak`` or ``checks.toml: sneak[0]``."""


@dataclass(frozen=True)
class CheckRules:
    """The rules of one level; ``None`` (or false) means the rule is not checked."""

    max_cover_steps: int | None = None
    max_idleness: int | None = None
    no_unreachable: bool = False
    guards: int = 1
    planner: str = "ripplefront"
    patrol: str | None = None
    sneaks: tuple[SneakRule, ...] = field(default=())

    @property
    def count(self) -> int:
        """How many rules are checked."""
        return (
            (self.max_cover_steps is not None)
            + (self.max_idleness is not None)
            + self.no_unreachable
            + len(self.sneaks)
        )


class CheckResult(NamedTuple):
    """One rule's verdict."""

    rule: str
    """The rule, as named on the command line (``max-cover-steps``, ``sneak 2.5,2.5 -> 9.5,3.5``)."""
    holds: bool
    message: str
    """What was measured against the limit."""


_KEYS = {"max_cover_steps", "max_idleness", "no_unreachable", "guards", "planner", "patrol", "sneak"}


def read_checks(path: str | os.PathLike[str]) -> CheckRules:
    """The rules in a checks file (``.toml``, else JSON), every fault one :class:`CheckError` line."""
    source = display_path(path)
    text = read_text_file(path, max_file_bytes=MAX_CHECKS_BYTES, kind="checks file", error=CheckError)
    if Path(path).suffix.lower() == ".toml":
        data: Any = _toml(text, source)
    else:
        data = parse_json(text, source=source, error=CheckError)
    return parse_checks(data, source=source, base=Path(path).parent)


def _toml(text: str, source: str) -> Any:
    if sys.version_info >= (3, 11):
        import tomllib

        try:
            return tomllib.loads(text)
        except tomllib.TOMLDecodeError as error:
            raise CheckError(f"{source}: not valid TOML: {error}") from None
    raise CheckError(f"{source}: TOML checks files need Python 3.11 or later; write the rules as JSON")


def parse_checks(data: Any, *, source: str = "<checks>", base: Path | None = None) -> CheckRules:
    """:class:`CheckRules` from checks-file data; a relative ``patrol`` path is taken from ``base``.

    >>> parse_checks({"max_idleness": 600, "sneak": [{"from": [1, 2], "to": [3, 4], "expect": "caught"}]}).count
    2
    >>> parse_checks({"max_idle": 600})
    Traceback (most recent call last):
    ...
    guardsim.checks.CheckError: <checks>: unknown rule 'max_idle' (known: guards, max_cover_steps, max_idleness, no_unreachable, patrol, planner, sneak)
    """
    if not isinstance(data, dict):
        raise CheckError(f"{source}: expected a table of rules, got {json_type(data)}")
    for key in data:
        if key not in _KEYS:
            raise CheckError(f"{source}: unknown rule {key!r} (known: {', '.join(sorted(_KEYS))})")

    def count(key: str, minimum: int) -> int | None:
        value = data.get(key)
        if value is None:
            return None
        if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
            raise CheckError(f"{source}: {key}: expected a whole number of at least {minimum}, got {value!r}"[:160])
        return value

    unreachable = data.get("no_unreachable", False)
    if not isinstance(unreachable, bool):
        raise CheckError(f"{source}: no_unreachable: expected true or false, got {unreachable!r}"[:160])
    planner = data.get("planner", "ripplefront")
    if planner not in PLANNERS:
        raise CheckError(f"{source}: planner: {planner!r} is not one of {', '.join(PLANNERS)}"[:200])
    patrol = data.get("patrol")
    if patrol is not None and not isinstance(patrol, str):
        raise CheckError(f"{source}: patrol: expected a file name, got {json_type(patrol)}")
    if patrol is not None and base is not None and not Path(patrol).is_absolute():
        patrol = str(base / patrol)
    if patrol is not None and not os.path.lexists(patrol):
        # Named here, or the line would name only a file the user never typed (the path joined to the folder).
        raise CheckError(f"{source}: patrol: {display_path(patrol)}: no such file")
    sneaks_data = data.get("sneak", [])
    if not isinstance(sneaks_data, list):
        raise CheckError(
            f"{source}: sneak: expected a list of {{from, to, expect}} tables, got {json_type(sneaks_data)}"
        )
    sneaks = tuple(_sneak_rule(item, f"{source}: sneak[{index}]") for index, item in enumerate(sneaks_data))
    return CheckRules(
        max_cover_steps=count("max_cover_steps", 0),
        max_idleness=count("max_idleness", 0),
        no_unreachable=unreachable,
        guards=count("guards", 1) or 1,
        planner=planner,
        patrol=patrol,
        sneaks=sneaks,
    )


def _point(value: Any, where: str) -> tuple[float, float]:
    if not (
        isinstance(value, list)
        and len(value) == 2
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
    ):
        raise CheckError(f"{where}: expected [x, y], two finite numbers, got {value!r}"[:160])
    return float(value[0]), float(value[1])


def _sneak_rule(item: Any, where: str) -> SneakRule:
    if not isinstance(item, dict) or set(item) - {"from", "to", "expect"} or not {"from", "to", "expect"} <= set(item):
        raise CheckError(f"{where}: expected a table with exactly from, to and expect")
    if item["expect"] not in ("caught", "sneaks"):
        raise CheckError(f"{where}: expect: {item['expect']!r} is not 'caught' or 'sneaks'"[:160])
    return SneakRule(_point(item["from"], f"{where}: from"), _point(item["to"], f"{where}: to"), item["expect"], where)


def _cell(scene: Scene, point: tuple[float, float], where: str, what: str) -> int:
    cell = scene.grid.cell_of(point)
    if cell is None or not scene.grid.traversable[cell[1], cell[0]]:
        raise CheckError(f"{where}: {what} {point[0]:g},{point[1]:g} is not a cell a guard-sized player can stand in")
    return scene.grid.flat(*cell)


def run_checks(scene: Scene, rules: CheckRules, *, seed: int = 0) -> list[CheckResult]:
    """Every rule's verdict, in the order: unreachable, cover steps, idleness, sneaks."""
    results: list[CheckResult] = []
    setup = patrol_setup(scene, rules.guards, seed=seed)
    goal = setup.goal
    if rules.no_unreachable:
        unreachable = int(scene.grid.traversable.sum()) - int(goal.sum())
        results.append(
            CheckResult(
                "no-unreachable",
                unreachable == 0,
                f"{unreachable} cells a guard can stand in cannot be reached from the start",
            )
        )
    if rules.max_cover_steps is not None:
        simulation = Simulation(scene, rules.planner)
        simulation.reset(seed=seed)
        trace = simulation.run()
        steps = trace.steps if trace.covered else None
        holds = steps is not None and steps <= rules.max_cover_steps
        measured = f"{steps} steps" if steps is not None else f"not covered ({trace.outcome.replace('_', ' ')})"
        results.append(
            CheckResult(
                "max-cover-steps",
                holds,
                f"{rules.planner} sees every reachable cell in {measured}, limit {rules.max_cover_steps}",
            )
        )
    patrol: Patrol | None = None
    if rules.max_idleness is not None or rules.sneaks:
        if rules.patrol is not None:
            patrol = read_patrol(rules.patrol, scene.grid, level=scene.level.name)
            if patrol.motion != "grid":
                raise CheckError(
                    f"{rules.patrol}: motion is {patrol.motion!r}: check scores grid-motion patrols (ticks) only"
                )
            what = rules.patrol
        else:
            patrol = plan_loop(setup, rules.guards)[0].patrol
            what = f"the loop patrol of {rules.guards} guard(s)"
    if rules.max_idleness is not None:
        assert patrol is not None
        score = score_patrol(setup.table, patrol, goal)
        worst = score.worst_idleness
        measured = f"{worst} ticks" if worst is not None else f"unbounded ({score.never_seen} cells never seen)"
        results.append(
            CheckResult(
                "max-idleness",
                worst is not None and worst <= rules.max_idleness,
                f"worst idleness of {what} is {measured}, limit {rules.max_idleness}",
            )
        )
    for rule in rules.sneaks:
        assert patrol is not None
        if patrol.period is None:
            raise CheckError(f"{what}: the sneak rules need a repeating patrol (period null)")
        source, target = _cell(scene, rule.source, rule.where, "from"), _cell(scene, rule.target, rule.where, "to")
        if scene.grid.component_labels[source] != scene.grid.component_labels[target]:
            raise CheckError(
                f"{rule.where}: to {rule.target[0]:g},{rule.target[1]:g} cannot be reached from "
                f"{rule.source[0]:g},{rule.source[1]:g}"
            )
        result = sneak_check(
            scene.grid, setup.table, patrol, source, target, detection=GuardDetection.of_level(scene.level)
        )
        path = result.path
        assert path is not None
        answer = "sneaks" if result.found else "caught"
        told = (
            f"an unseen path of {path.ticks} ticks from lap tick {path.start_tick}"
            if result.found
            else f"no unseen path (closest call: {path.ticks_in_view} ticks in view)"
        )
        name = f"sneak {rule.source[0]:g},{rule.source[1]:g} -> {rule.target[0]:g},{rule.target[1]:g}"
        results.append(CheckResult(name, answer == rule.expect, f"expected {rule.expect}, {answer}: {told}"))
    return results
