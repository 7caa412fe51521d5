"""CI gates: rules a level must keep (cover steps, idleness, reachability, safe spots, sneaks), checked in one go.

A studio's CI runs ``guardsim check`` on each level; it fails only when an edit breaks a rule the team
chose, not on every change as a snapshot would. Rules come from the command line or a small checks file
(JSON or TOML) with the same names::

    max_cover_steps = 400        # the planner sees every reachable cell within this many steps
    max_idleness = 600           # the patrol's worst idleness (ticks a cell goes unwatched) at most this
    no_unreachable = true        # every cell a guard can stand in is reachable from the start
    guards = 1                   # team size of the loop patrol made when no patrol file is given
    planner = "ripplefront"      # the planner of max_cover_steps
    patrol = "patrol.json"       # the patrol for max_idleness, safe and the sneaks (else the loop is made)
    safe = [[30.5, 2.5]]         # cells no guard sees during the lap
    undetected = true            # ... or rather: where a player standing still is never detected
    unheard = true               # the sneaks' paths must also go unheard (a gait chosen for each step)
    min_slack = 20               # each sneak's path exists from at least this many of the lap's ticks
    max_slack = 300              # and from at most this many
    [[sneak]]
    from = [2.5, 2.5]
    to = [57.5, 57.5]
    expect = "caught"            # or "sneaks"; "detected" or "undetected" under the detection model
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from guardsim.detection import NEVER_DETECTED, GuardDetection
from guardsim.detection.watch import MAX_JOINT_LAP, LevelWatch, lap_sight_of, level_watch
from guardsim.errors import CheckError
from guardsim.files.reading import DEFAULT_MAX_DEPTH, data_depth, display_path, parse_json, read_text_file
from guardsim.files.schema import check
from guardsim.patrol import Patrol, patrol_setup, plan_loop, read_patrol, score_patrol
from guardsim.scene import Scene
from guardsim.simulation import Simulation
from guardsim.sneak import sneak_check
from guardsim.vision.table import ViewTable

__all__ = [
    "EXPECTATIONS",
    "CheckError",
    "CheckResult",
    "CheckRules",
    "SafeRule",
    "SneakRule",
    "read_checks",
    "run_checks",
]

#: Largest checks file read.
MAX_CHECKS_BYTES = 1024 * 1024


#: What a sneak rule may expect: ``caught`` (no unseen path may exist), ``sneaks`` (one must), ``detected``
#: (no undetected path may exist, under the detection model) or ``undetected`` (one must).
EXPECTATIONS = ("caught", "sneaks", "detected", "undetected")


class SneakRule(NamedTuple):
    """Whether a player can get from one point to another unseen (or undetected), and what the answer must be."""

    source: tuple[float, float]
    target: tuple[float, float]
    expect: str
    """One of :data:`EXPECTATIONS`: ``"caught"`` or ``"sneaks"`` ask for an unseen path, ``"detected"`` or
    ``"undetected"`` for an undetected one (seen briefly is allowed)."""
    where: str = "--sneak"
    """Where the rule was given, for error lines: ``--sneak`` or ``checks.toml: sneak[0]``."""

    @property
    def undetected(self) -> bool:
        """Whether the rule asks about undetected paths (else unseen ones)."""
        return self.expect in ("detected", "undetected")


class SafeRule(NamedTuple):
    """A point whose cell must stay out of every guard's view during the lap (or never lead to detection)."""

    point: tuple[float, float]
    where: str = "--safe"
    """Where the rule was given, for error lines: ``--safe`` or ``checks.toml: safe[0]``."""


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
    safe: tuple[SafeRule, ...] = field(default=())
    undetected: bool = False
    """The safe rules ask that a player standing there is never detected, not that the cell is never seen."""
    min_slack: int | None = None
    """Each sneak's path must exist from at least this many of the lap's ticks (its undetected path for
    ``detected``/``undetected`` expectations, else its unseen path)."""
    max_slack: int | None = None
    """... and from at most this many."""
    max_lap: int = MAX_JOINT_LAP
    """Longest joint lap of the patrol and the level's camera swings the safe and sneak rules run over."""
    unheard: bool = False
    """The sneak rules ask about paths no guard hears either, choosing to walk or sneak each step by the
    level's intruder noise keys (``sneak --unheard``)."""

    def validate(self) -> None:
        """Raise :class:`CheckError` when an option modifies rules that are not there (slack limits without
        a sneak rule, ``undetected`` without a safe rule), or the slack limits exclude each other.

        >>> CheckRules(min_slack=3).validate()
        Traceback (most recent call last):
        ...
        guardsim.errors.CheckError: slack limits apply to the sneak rules' slack, and there is no sneak rule
        """
        if (self.min_slack is not None or self.max_slack is not None) and not self.sneaks:
            raise CheckError("slack limits apply to the sneak rules' slack, and there is no sneak rule")
        if self.min_slack is not None and self.max_slack is not None and self.min_slack > self.max_slack:
            raise CheckError(f"min slack {self.min_slack} is over max slack {self.max_slack}: no slack meets both")
        if self.undetected and not self.safe:
            raise CheckError("undetected applies to the safe rules, and there is no safe rule")
        if self.unheard and not self.sneaks:
            raise CheckError("unheard applies to the sneak rules, and there is no sneak rule")

    def with_options(
        self, *, sneaks: Sequence[SneakRule] = (), safe: Sequence[SafeRule] = (), **given: object
    ) -> CheckRules:
        """These rules with more on top, checked (:meth:`validate`): ``sneaks`` and ``safe`` rules are added,
        and each other field ``given`` a value (not ``None``; a flag only when set) replaces this one's, as
        ``guardsim check``'s options do a checks file's.

        >>> CheckRules(max_idleness=40).with_options(max_idleness=None, no_unreachable=True, max_cover_steps=90).count
        3
        """
        changes = {name: value for name, value in given.items() if value is not None and value is not False}
        if sneaks:
            changes["sneaks"] = self.sneaks + tuple(sneaks)
        if safe:
            changes["safe"] = self.safe + tuple(safe)
        rules = dataclasses.replace(self, **changes)  # type: ignore[arg-type]
        rules.validate()
        return rules

    @property
    def count(self) -> int:
        """How many rules are checked (a slack limit counts once per sneak)."""
        return (
            (self.max_cover_steps is not None)
            + (self.max_idleness is not None)
            + self.no_unreachable
            + len(self.safe)
            + len(self.sneaks) * (1 + (self.min_slack is not None) + (self.max_slack is not None))
        )


class CheckResult(NamedTuple):
    """One rule's verdict."""

    rule: str
    """The rule, as named on the command line (``max-cover-steps``, ``sneak 2.5,2.5 -> 9.5,3.5``)."""
    holds: bool
    message: str
    """What was measured against the limit."""


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
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as error:
            raise CheckError(f"{source}: not valid TOML: {error}") from None
        except RecursionError:  # tomllib parses nested arrays and inline tables recursively, with no limit
            raise CheckError(f"{source}: not valid TOML for guardsim: nested past Python's stack") from None
        except ValueError as error:  # an integer past Python's 4 300 digits
            raise CheckError(f"{source}: not valid TOML for guardsim: {str(error)[:80]}") from None
        depth = data_depth(data)
        if depth > DEFAULT_MAX_DEPTH:
            raise CheckError(
                f"{source}: not valid TOML for guardsim: nested {depth} deep, over the limit of {DEFAULT_MAX_DEPTH}"
            )
        _refuse_non_finite(data, source)
        return data
    raise CheckError(f"{source}: TOML checks files need Python 3.11 or later; write the rules as JSON")


def _refuse_non_finite(data: Any, source: str) -> None:
    """TOML writes ``inf`` and ``nan`` as numbers; JSON checks files cannot hold them, nor may TOML ones."""
    stack: list[tuple[Any, str]] = [(data, "")]
    while stack:
        value, where = stack.pop()
        if isinstance(value, float) and not math.isfinite(value):
            raise CheckError(f"{source}: {where or 'the file'}: {value} is not a finite number")
        if isinstance(value, dict):
            stack.extend((item, f"{where}.{key}" if where else str(key)) for key, item in value.items())
        elif isinstance(value, list):
            stack.extend((item, f"{where}[{index}]") for index, item in enumerate(value))


def parse_checks(data: Any, *, source: str = "<checks>", base: Path | None = None) -> CheckRules:
    """:class:`CheckRules` from checks-file data, checked against ``checks.schema.json``; a relative
    ``patrol`` path is taken from ``base``.

    The file must hold the rules its ``undetected``, ``unheard`` and slack limits apply to (safe and sneak
    rules).

    >>> parse_checks({"max_idleness": 600, "sneak": [{"from": [1, 2], "to": [3, 4], "expect": "caught"}]}).count
    2
    >>> parse_checks({"safe": [[3.5, 2.5]], "undetected": True}).safe
    (SafeRule(point=(3.5, 2.5), where='<checks>: safe[0]'),)
    >>> parse_checks({"max_idle": 600})
    Traceback (most recent call last):
    ...
    guardsim.errors.CheckError: <checks>: unknown rule 'max_idle' (known: guards, max_cover_steps, max_idleness, max_slack, min_slack, no_unreachable, patrol, planner, safe, sneak, undetected, unheard)
    """
    check(data, "checks", source=source, error=CheckError)
    patrol = data.get("patrol")
    if patrol is not None and not patrol.strip():
        raise CheckError(f"{source}: patrol: expected a patrol file name, got an empty text")
    if patrol is not None and base is not None and not Path(patrol).is_absolute():
        patrol = str(base / patrol)
    if patrol is not None and not os.path.lexists(patrol):
        # Named here, or the line would name only a file the user never typed (the path joined to the folder).
        raise CheckError(f"{source}: patrol: {display_path(patrol)}: no such file")
    sneaks = tuple(
        SneakRule(_point(item["from"]), _point(item["to"]), item["expect"], f"{source}: sneak[{index}]")
        for index, item in enumerate(data.get("sneak", []))
    )
    safe = tuple(SafeRule(_point(item), f"{source}: safe[{index}]") for index, item in enumerate(data.get("safe", [])))
    undetected = data.get("undetected", False)
    if undetected and not safe:
        raise CheckError(f"{source}: undetected: there is no safe rule in the file for it to apply to")
    unheard = data.get("unheard", False)
    if unheard and not sneaks:
        raise CheckError(f"{source}: unheard: there is no sneak rule in the file for it to apply to")
    min_slack, max_slack = data.get("min_slack"), data.get("max_slack")
    for key, limit in (("min_slack", min_slack), ("max_slack", max_slack)):
        if limit is not None and not sneaks:
            raise CheckError(f"{source}: {key}: there is no sneak rule in the file for it to limit")
    if min_slack is not None and max_slack is not None and min_slack > max_slack:
        raise CheckError(f"{source}: min_slack: {min_slack} is over max_slack {max_slack}: no slack meets both")
    return CheckRules(
        max_cover_steps=data.get("max_cover_steps"),
        max_idleness=data.get("max_idleness"),
        no_unreachable=data.get("no_unreachable", False),
        guards=data.get("guards") or 1,
        planner=data.get("planner", "ripplefront"),
        patrol=patrol,
        sneaks=sneaks,
        safe=safe,
        undetected=undetected,
        min_slack=min_slack,
        max_slack=max_slack,
        unheard=unheard,
    )


def _point(value: list[Any]) -> tuple[float, float]:
    """A point the schema has checked: two numbers a float holds."""
    return float(value[0]), float(value[1])


def _cell(scene: Scene, point: tuple[float, float], where: str, what: str) -> int:
    cell = scene.grid.cell_of(point)
    if cell is None or not scene.grid.traversable[cell[1], cell[0]]:
        raise CheckError(f"{where}: {what} {point[0]:g},{point[1]:g} is not a cell a guard-sized player can stand in")
    return scene.grid.flat(*cell)


#: Places named in the unreachable rule's message, largest first.
SHOWN_PLACES = 3


def unreachable_places(scene: Scene, goal: np.ndarray) -> str:
    """Where the cells a guard can stand in but not reach from the start are: ``": N around (x, y), ..."``
    for the largest connected areas of them (a cell's centre in world units, inside the area), and how
    many more areas there are; ``""`` when there are none.

    Examples
    --------
    >>> from guardsim.level import parse_level
    >>> level = parse_level({"outer": [[0, 0], [6, 0], [6, 3], [0, 3]],
    ...                      "holes": [[[2.9, 0], [3.1, 0], [3.1, 3], [2.9, 3]]]})
    >>> scene = Scene.from_level(level)
    >>> unreachable_places(scene, scene.grid.component(0, 0).ravel())
    ': 9 around (4.5, 1.5)'
    """
    grid = scene.grid
    pocket = grid.traversable & ~goal.reshape(grid.shape)
    if not pocket.any():
        return ""
    labels = grid.component_labels.reshape(grid.shape)
    areas, sizes = np.unique(labels[pocket], return_counts=True)
    order = sorted(range(len(areas)), key=lambda k: (-int(sizes[k]), int(areas[k])))
    places = []
    for k in order[:SHOWN_PLACES]:
        members = np.argwhere(labels == areas[k])
        mean = members.mean(axis=0)
        row, col = members[int(np.argmin(((members - mean) ** 2).sum(axis=1)))]
        x, y = grid.centre(int(col), int(row))
        places.append(f"{int(sizes[k])} around ({x:g}, {y:g})")
    more = len(areas) - SHOWN_PLACES
    return ": " + ", ".join(places) + (f" and {more} more place{'s' if more != 1 else ''}" if more > 0 else "")


def run_checks(scene: Scene, rules: CheckRules, *, seed: int = 0) -> list[CheckResult]:
    """Every rule's verdict, in the order: unreachable, cover steps, idleness, safe spots, sneaks (each
    followed by its slack limits).

    Raises
    ------
    CheckError
        When a rule cannot be checked: a point outside the level or in a wall, a patrol that does not
        repeat for the safe and sneak rules, slack limits without a sneak rule, ``undetected`` without a
        safe rule.
    """
    rules.validate()
    results: list[CheckResult] = []
    setup = patrol_setup(scene, rules.guards, seed=seed)
    goal = setup.goal
    if rules.no_unreachable:
        unreachable = int(scene.grid.traversable.sum()) - int(goal.sum())
        results.append(
            CheckResult(
                "no-unreachable",
                unreachable == 0,
                f"{unreachable} cells a guard can stand in cannot be reached from the start"
                + unreachable_places(scene, goal),
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
    if rules.max_idleness is None and not rules.sneaks and not rules.safe:
        return results
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
    if (rules.safe or rules.sneaks) and patrol.period is None:
        raise CheckError(f"{what}: the safe and sneak rules need a repeating patrol (period null)")
    if rules.safe:
        results += _safe_results(scene, setup.table, patrol, rules)
    for rule in rules.sneaks:
        results += _sneak_results(scene, setup.table, patrol, rule, rules)
    return results


def _guards(guards: list[int]) -> str:
    """``guard 0``, ``guards 0 and 2``, ``guards 0, 1 and 2``."""
    if len(guards) == 1:
        return f"guard {guards[0]}"
    return f"guards {', '.join(map(str, guards[:-1]))} and {guards[-1]}"


def _watchers(watchers: list[int], guards: int) -> str:
    """The guards among ``watchers`` as :func:`_guards` names them, then the cameras (``camera 1``)."""
    parts = []
    theirs = [watcher for watcher in watchers if watcher < guards]
    if theirs:
        parts.append(_guards(theirs))
    for watcher in watchers:
        if watcher >= guards:
            parts.append(f"camera {watcher - guards}")
    return " and ".join(parts)


def _ticks(ticks: np.ndarray, shown: int = 12) -> str:
    """``3-7, 12, 20-21`` (runs of lap ticks), the first ``shown`` runs and how many more."""
    runs: list[str] = []
    begin = previous = int(ticks[0])
    for tick in [*ticks[1:].tolist(), None]:
        if tick is not None and tick == previous + 1:
            previous = tick
            continue
        runs.append(str(begin) if begin == previous else f"{begin}-{previous}")
        if tick is not None:
            begin = previous = tick
    more = f" and {len(runs) - shown} more runs" if len(runs) > shown else ""
    return ", ".join(runs[:shown]) + more


def _level_watch(scene: Scene, max_lap: int = MAX_JOINT_LAP) -> LevelWatch | None:
    level = scene.level
    if not level.cameras and level.lit:
        return None
    return level_watch(scene, GuardDetection.of_level(level).dt, max_lap=max_lap)


def _safe_results(scene: Scene, table: ViewTable, patrol: Patrol, rules: CheckRules) -> list[CheckResult]:
    """The safe rules' verdicts: each cell out of every watcher's view all lap (``undetected``: a player
    standing there never detected). The lap is the joint lap with the level's cameras."""
    cells = [_cell(scene, rule.point, rule.where, "point") for rule in rules.safe]
    detection = GuardDetection.of_level(scene.level)
    watch = _level_watch(scene, rules.max_lap)
    # The sparse sight (as the sneak rules read it): nothing over every (watcher, lap tick, cell).
    sight, _ = lap_sight_of(scene.grid, table, patrol.states, detection, watch, max_lap=rules.max_lap)
    lasts = sight.time_to_detection(scene.grid.traversable) if rules.undetected else None
    guards = sight.watchers - sight.cameras
    results = []
    for rule, cell in zip(rules.safe, cells):
        col, row = scene.grid.unflat(cell)
        events = slice(sight.start[cell], sight.start[cell + 1])
        when, who = sight.tick[events], sight.watcher[events]
        ticks = np.unique(when)
        watchers = np.unique(who).tolist()
        seen = (
            f"in view of {_watchers(watchers, guards)} for {ticks.size} of {sight.period} lap ticks, first at lap tick {ticks[0]}"
            if ticks.size
            else f"never in view during the {sight.period}-tick lap"
        )
        if ticks.size and sight.cameras:
            cameras = [watcher for watcher in watchers if watcher >= guards]
            for watcher in cameras:
                watched = np.unique(when[who == watcher])
                seen += f"; camera {watcher - guards} watches it at lap ticks {_ticks(watched)}"
        if lasts is None:
            holds, message = ticks.size == 0, f"cell [{col}, {row}] is {seen}"
        elif lasts[cell] == NEVER_DETECTED:
            holds, message = True, f"cell [{col}, {row}]: a player standing there is never detected ({seen})"
        else:
            holds = False
            message = f"cell [{col}, {row}]: a player standing there is detected after {lasts[cell]} ticks ({seen})"
        results.append(CheckResult(f"safe {rule.point[0]:g},{rule.point[1]:g}", holds, message))
    return results


def _sneak_results(
    scene: Scene, table: ViewTable, patrol: Patrol, rule: SneakRule, rules: CheckRules
) -> list[CheckResult]:
    """A sneak rule's verdict, then its slack limits' verdicts."""
    source, target = _cell(scene, rule.source, rule.where, "from"), _cell(scene, rule.target, rule.where, "to")
    if scene.grid.component_labels[source] != scene.grid.component_labels[target]:
        raise CheckError(
            f"{rule.where}: to {rule.target[0]:g},{rule.target[1]:g} cannot be reached from "
            f"{rule.source[0]:g},{rule.source[1]:g}"
        )
    result = sneak_check(
        scene.grid,
        table,
        patrol,
        source,
        target,
        detection=GuardDetection.of_level(scene.level),
        undetected=rule.undetected,
        watch=_level_watch(scene, rules.max_lap),
        max_lap=rules.max_lap,
        unheard=rules.unheard,
        intruder=scene.level.intruder,
    )
    path, grade = result.path, result.grade
    assert path is not None and grade is not None
    kind = ("undetected" if rule.undetected else "unseen") + (", unheard" if rules.unheard else "")
    if rule.undetected:
        answer = "undetected" if result.found else "detected"
    else:
        answer = "sneaks" if result.found else "caught"
    if result.found:
        told = f"an {kind} path of {path.ticks} ticks from lap tick {path.start_tick}"
        if rule.undetected:
            told += f" (peak awareness {grade.peak:.2f})"
    else:
        heard = f", heard {path.steps_heard} times" if rules.unheard else ""
        told = f"no {kind} path (closest call: {path.ticks_in_view} ticks in view{heard})"
    name = f"sneak {rule.source[0]:g},{rule.source[1]:g} -> {rule.target[0]:g},{rule.target[1]:g}"
    results = [CheckResult(name, answer == rule.expect, f"expected {rule.expect}, {answer}: {told}")]
    slack = f"{name}: an {kind} path exists from {result.slack} of {result.period} lap ticks"
    if rules.min_slack is not None:
        results.append(
            CheckResult("min-slack", result.slack >= rules.min_slack, f"{slack}, limit at least {rules.min_slack}")
        )
    if rules.max_slack is not None:
        results.append(
            CheckResult("max-slack", result.slack <= rules.max_slack, f"{slack}, limit at most {rules.max_slack}")
        )
    return results
