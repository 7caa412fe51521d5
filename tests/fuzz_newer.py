"""Generated inputs for the newer keys and commands: cameras, light, the intruder's noise, route files
with gaits and throws, and the design commands (``report``, ``diff``, ``check --baseline``, ``watch``).

Used by :mod:`tests.fuzz_cases` (its :func:`~tests.fuzz_cases.generate` hands these kinds here), so
``tests/test_fuzz.py`` and ``benchmarks/fuzz.py`` run them like every other kind. Each generator starts
from a valid input on the tiny square with a pillar (a camera on the pillar's edge sweeping, a lamp in a
dark room, a noisy intruder, a route that sneaks and throws) and damages it: a key given a nasty value
(non-finite, past float range, of the wrong type, out of its schema's range), a key path the schema does
not know, the file's structure or its bytes. A level the schema refuses is a bad input for every command
that reads it: exit 0 on it is an accepted bad input.

``watch`` serves a page until Ctrl-C, so its cases parse the command line as ``guardsim watch`` does and
run one analysis of the saved file (:meth:`guardsim.viewer.serve.LiveAnalyser.analyse_now`): a save that
cannot be used must be one :class:`~guardsim.errors.GuardsimError` line naming the file, which the page
shows.
"""

from __future__ import annotations

import copy
import json
import math
import traceback
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from tests.common import SQUARE_WITH_HOLE
from tests.fuzz_cases import (
    HUGE_INT,
    Case,
    Templates,
    _level_is_acceptable,
    _set,
    mutate_json,
    mutate_text,
    special_file,
    verdict,
)

_FROM, _TO = "0.5,0.5", "5.5,5.5"

#: The tiny square with a pillar, watched by a sweeping camera on the pillar's right edge and lit by one
#: lamp in a dim room, and an intruder whose steps are heard.
BASE: dict[str, Any] = {
    **copy.deepcopy(SQUARE_WITH_HOLE),
    "name": "tiny watched",
    "cameras": [
        {"position": [4, 3], "heading": 0, "fov_degrees": 60, "view_range": 3, "sweep": 90, "turn_speed": 45,
         "pause": 0.5, "detect_near": 0.5, "detect_far": 1.0},
    ],
    "ambient_light": 0.3,
    "lights": [{"position": [1, 5], "radius": 3, "intensity": 0.8}],
    "intruder": {"walk_noise": 2, "sneak_ticks": 2, "sneak_noise": 0.5},
}  # fmt: skip
BASE["guard"] = {**BASE["guard"], "dark_sight": 1.0}

#: A route that walks, sneaks a step and throws a bottle into the far corner.
ROUTE: list[Any] = [
    [0.5, 0.5], [1.5, 0.5], {"to": [1.5, 1.5], "gait": "sneak"}, [1.5, 2.5],
    {"throw": [5.5, 5.5], "at": 1.0, "noise": 4},
]  # fmt: skip

#: A sneak.json as ``guardsim sneak`` writes it (its path in cells of its grid), walked as a route.
SNEAK_ROUTE: dict[str, Any] = {"cell_size": 1.0, "origin": [0, 0], "path": [[0, 0], [0, 1], [1, 1], [1, 2]]}

#: Values tried at a key: the ones that broke number parsers before, and the wrong types.
NASTY: tuple[Any, ...] = (math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-300, 5e-324, 0, -1, 361, 1e15, HUGE_INT, 2**63, 0.5,
         "1", None, True, [], {}, [1, 2], "x" * 5000)  # fmt: skip

#: The key paths of each level kind's targeted cases.
_PATHS: dict[str, tuple[tuple[Any, ...], ...]] = {
    "cameras": (
        ("cameras",), ("cameras", 0), ("cameras", 0, "position"), ("cameras", 0, "position", 0),
        ("cameras", 0, "heading"), ("cameras", 0, "fov_degrees"), ("cameras", 0, "view_range"),
        ("cameras", 0, "sweep"), ("cameras", 0, "turn_speed"), ("cameras", 0, "pause"),
        ("cameras", 0, "detect_near"), ("cameras", 0, "detect_far"), ("cameras", 0, "x" * 60),
    ),
    "lights": (
        ("ambient_light",), ("lights",), ("lights", 0), ("lights", 0, "position"), ("lights", 0, "position", 1),
        ("lights", 0, "radius"), ("lights", 0, "intensity"), ("guard", "dark_sight"), ("lights", 0, "colour"),
    ),
    "noise": (
        ("intruder",), ("intruder", "walk_noise"), ("intruder", "sneak_ticks"), ("intruder", "sneak_noise"),
        ("intruder", "gait\n"), ("guard", "tick_hz"),
    ),
}  # fmt: skip

#: Whole watchers that are wrong in ways a key's type is not: off the level, inside the pillar, a swing
#: whose period no tick count holds, a lap past any limit.
_PLACED: tuple[tuple[tuple[Any, ...], Any, str], ...] = (
    (("cameras", 0, "position"), [3, 3], "a camera inside the pillar"),
    (("cameras", 0, "position"), [60, 3], "a camera off the level"),
    (("lights", 0, "position"), [3, 3], "a lamp inside the pillar"),
    (("lights", 0, "position"), [-1e15, 3], "a lamp far off the level"),
    (("cameras", 0, "turn_speed"), 1e-300, "a swing of 1e302 seconds"),
    (("cameras", 0, "pause"), 1e308, "a pause of 1e308 seconds"),
    (("cameras", 0, "turn_speed"), 1e308, "a swing in no time"),
    (("cameras", 0, "pause"), 1e-300, "a pause of no time"),
    (("cameras",), [{"position": [4, 3], "sweep": 360, "turn_speed": 0.001, "pause": 0}] * 3, "a week-long swing"),
    (("cameras",), [{"position": [4, 2 + k / 100], "sweep": 10 + k, "pause": 0.1 * k} for k in range(40)],
     "40 cameras of co-prime periods"),
    (("lights",), [{"position": [1, 1], "radius": 1e308}] * 50, "50 lamps of radius 1e308"),
    (("intruder", "sneak_ticks"), 10**9, "a sneaking step of 10^9 ticks"),
    (("intruder", "walk_noise"), 1e308, "a step heard everywhere"),
    (("guard", "tick_hz"), 100_000, "tick_hz 100000"),
)  # fmt: skip


#: The level's top keys each level kind damages.
_TOP_KEYS = {"cameras": ("cameras",), "lights": ("lights", "ambient_light"), "noise": ("intruder", "guard")}


def _level(kind: str, rng: np.random.Generator) -> tuple[bytes, str, str]:
    """A damaged level of ``kind`` (its keys targeted), what was done, and the top key at fault when one
    is (``""`` otherwise): an error must name it."""
    data = copy.deepcopy(BASE)
    roll = rng.random()
    if roll < 0.04:
        return (*special_file(rng), "")
    if roll < 0.5:
        path = _PATHS[kind][int(rng.integers(len(_PATHS[kind])))]
        value = NASTY[int(rng.integers(len(NASTY)))]
        note = f"{'.'.join(map(str, path))[:40]} = {repr(value)[:20]}"
        return json.dumps(_set(data, path, value), allow_nan=True).encode(), note, str(path[0])
    if roll < 0.65:
        fitting = [item for item in _PLACED if item[0][0] in _TOP_KEYS[kind]]
        path, value, note = fitting[int(rng.integers(len(fitting)))]
        return json.dumps(_set(data, path, copy.deepcopy(value))).encode(), note, str(path[0])
    if roll < 0.85:
        key = {"cameras": "cameras", "lights": "lights", "noise": "intruder"}[kind]
        sub, note = mutate_json({key: data[key]}, rng)
        data.update(sub if isinstance(sub, dict) else {key: sub})
        return json.dumps(data, allow_nan=True).encode(), note, ""
    return (*mutate_text(json.dumps(data).encode(), rng), "")


def _known_bad(content: bytes) -> bool:
    """Whether the schema (or a non-finite number) refuses the level: every command must then refuse it."""
    return not content.startswith(b"\0") and not _level_is_acceptable(content)


def level_kind_case(kind: str, command: str, rng: np.random.Generator, templates: Templates) -> Case:
    """A level whose cameras, light or noise keys are damaged, read by ``command``."""
    content, note, place = _level(kind, rng)
    files = {"level.json": content, "in.patrol.json": templates.patrol}
    level = "{dir}/level.json"
    args, outputs = {
        "validate": (["validate", level], []),
        "sneak": (["sneak", level, "--patrol", "{dir}/in.patrol.json", "--from", _FROM, "--to", _TO, "--undetected",
                   "--out", "{dir}/out"], ["out/sneak.json"]),
        "check": (["check", level, "--patrol", "{dir}/in.patrol.json", "--safe", "0.5,5.5", "--sneak", _FROM, _TO,
                   "--expect", "sneaks", "--undetected"], []),
        "render": (["render", level, "--png", "{dir}/out.png", "--size", "64"], ["out.png"]),
        "alert": (["alert", level, "--patrol", "{dir}/in.patrol.json", "--from", _FROM, "--to", _TO,
                   "--max-seconds", "20", "--trace", "{dir}/out.json"], ["out.json"]),
    }[command]  # fmt: skip
    return Case(kind, command, files, args, "level.json", outputs, bad=_known_bad(content), clean=True, note=note,
                place=place)  # fmt: skip


def noise_route_case(rng: np.random.Generator, templates: Templates) -> Case:
    """A route file with gaits and throws, damaged, walked by ``alert --intruder route`` on the noisy level."""
    route = copy.deepcopy(ROUTE)
    roll = rng.random()
    bad = False
    if roll < 0.04:
        content, note = special_file(rng)
    elif roll < 0.55:
        index = int(rng.choice([2, 4]))
        key = {2: ("to", "gait"), 4: ("throw", "at", "noise")}[index][int(rng.integers(2 if index == 2 else 3))]
        value: Any = NASTY[int(rng.integers(len(NASTY)))]
        if key == "gait" and rng.random() < 0.5:
            value = ["run", "Sneak", "", "walk\n", "s" * 5000][int(rng.integers(5))]
        route[index][key] = value
        bad = key == "gait" or key == "to" or (key in ("at", "noise") and not _finite_at_least(value, 0))
        if key == "throw":
            bad = not _pair_of_finite(value)
        content, note = json.dumps(route, allow_nan=True).encode(), f"item {index}.{key} = {repr(value)[:20]}"
    elif roll < 0.7:
        choice = int(rng.integers(6))
        throw, note = [
            ({"throw": [3, 3], "at": 1, "noise": 2}, "a throw into the pillar"),
            ({"throw": [60, 60], "at": 1, "noise": 2}, "a throw off the level"),
            ({"throw": [5.5, 5.5], "at": 1e308, "noise": 2}, "a throw after 1e308 seconds"),
            ({"throw": [5.5, 5.5], "at": 1, "noise": 1e308}, "a throw heard everywhere"),
            ({"throw": [5.5, 5.5], "at": 1, "noise": 2, "x" * 3000: 1}, "a throw with a long unknown key"),
            ({"to": [2.5, 2.5], "gait": "sneak"}, "a sneak into the pillar"),
        ][choice]
        route.append(throw)
        bad = choice in (0, 1, 4, 5)
        content = json.dumps(route).encode()
    elif roll < 0.78:
        mutated, note = mutate_json(route, rng)
        content = json.dumps(mutated, allow_nan=True).encode()
    elif roll < 0.9:
        # sneak.json's route: [col, row] cells of its grid (cell size, origin), read as their centres.
        mutated, note = mutate_json(SNEAK_ROUTE, rng)
        content, note = json.dumps(mutated, allow_nan=True).encode(), f"sneak.json: {note}"
    else:
        content, note = mutate_text(json.dumps(route).encode(), rng)
    files = {"level.json": json.dumps(BASE).encode(), "in.patrol.json": templates.patrol, "route.json": content}
    args = ["alert", "{dir}/level.json", "--patrol", "{dir}/in.patrol.json", "--intruder", "route", "--route",
            "{dir}/route.json", "--max-seconds", "20", "--trace", "{dir}/out.json"]  # fmt: skip
    return Case("noise-route", "alert", files, args, "route.json", ["out.json"], bad=bad, clean=True, note=note)


def _finite_at_least(value: Any, low: float) -> bool:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    return abs(value) <= 1.7e308 and math.isfinite(float(value)) and value >= low


def _pair_of_finite(value: Any) -> bool:
    return isinstance(value, list) and len(value) == 2 and all(_finite_at_least(v, -math.inf) for v in value)


_DESIGN_TAIL = ["--from", _FROM, "--to", _TO]


def _design_args(command: str, level: str, patrol: str | None, old: str = "{dir}/old.json") -> list[str]:
    """The command line of a design command on ``level`` (the new version for ``diff``)."""
    if command == "report":
        return ["report", level, *(["--patrol", patrol] if patrol else []), *_DESIGN_TAIL, "--json", "{dir}/r.json"]
    if command == "diff":
        both = ["--patrol-old", "{dir}/in.patrol.json", "--patrol-new", patrol] if patrol else []
        return ["diff", old, level, *both, *_DESIGN_TAIL, "--json", "{dir}/r.json"]
    if command == "fortify":
        return [*_FORTIFY[:1], level, *_FORTIFY[2:-2], *(["--patrol", patrol] if patrol else [])]
    if command == "check-baseline":
        return ["check", level, "--baseline", old, *(["--patrol", patrol] if patrol else []), "--sneak", _FROM, _TO,
                "--expect", "sneaks", "--max-worse", "score=100"]  # fmt: skip
    return ["watch", level, *(["--patrol", patrol] if patrol else []), *_DESIGN_TAIL]


def design_level_case(command: str, rng: np.random.Generator, templates: Templates) -> Case:
    """A damaged level (any of the newer keys, or the plain level's) given to a design command."""
    kind = ("cameras", "lights", "noise")[int(rng.integers(3))]
    content, note, place = _level(kind, rng)
    files = {"level.json": content, "old.json": json.dumps(BASE).encode(), "in.patrol.json": templates.patrol}
    args = _design_args(command, "{dir}/level.json", None)
    outputs = ["r.json"] if command in ("report", "diff") else []
    return Case("design-level", command, files, args, "level.json", outputs, bad=_known_bad(content), clean=True,
                note=f"{kind}: {note}", place=place)  # fmt: skip


def _damaged_patrol(rng: np.random.Generator, templates: Templates) -> tuple[bytes, str]:
    """The template patrol.json damaged (a special file, a JSON mutation or a byte mutation), and how."""
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.65:
        data, note = mutate_json(json.loads(templates.patrol), rng)
        content = json.dumps(data, allow_nan=True).encode()
    else:
        content, note = mutate_text(templates.patrol, rng)
    return content, note


def design_patrol_case(command: str, rng: np.random.Generator, templates: Templates) -> Case:
    """A damaged patrol.json given to a design command (``diff``'s new version's)."""
    content, note = _damaged_patrol(rng, templates)
    files = {"level.json": json.dumps(BASE).encode(), "old.json": json.dumps(BASE).encode(),
             "in.patrol.json": templates.patrol, "bad.patrol.json": content}  # fmt: skip
    args = _design_args(command, "{dir}/level.json", "{dir}/bad.patrol.json")
    outputs = ["r.json"] if command in ("report", "diff") else []
    return Case("design-patrol", command, files, args, "bad.patrol.json", outputs, clean=True, note=note)


#: Option values tried on the design commands, as typed.
_VALUES = ("nan", "inf", "-1", "0", "1e308", "1" + "0" * 400, "x", "", "0.5,0.5", "3,3", "60,60", "nan,1", "1e308,1")
_DESIGN_OPTIONS = {
    "report": ("--from", "--to", "--guards", "--alert", "--seed", "--json", "--html"),
    "diff": ("--from", "--to", "--guards", "--seed", "--png", "--json", "--patrol-old"),
    "check-baseline": ("--max-worse", "--baseline", "--from-to"),
}


def design_option_case(command: str, rng: np.random.Generator, templates: Templates) -> Case:
    """One option of a design command given a nasty value (a point in the pillar or off the level, a team
    past 64, an output into a folder that does not exist, a margin that is not NAME=N)."""
    options = _DESIGN_OPTIONS[command]
    option = options[int(rng.integers(len(options)))]
    value = _VALUES[int(rng.integers(len(_VALUES)))]
    files = {"level.json": json.dumps(BASE).encode(), "old.json": json.dumps(BASE).encode(),
             "in.patrol.json": templates.patrol, "adir/keep": b""}  # fmt: skip
    args = _design_args(command, "{dir}/level.json", None)
    named = option
    if option in ("--from", "--to"):
        args[args.index(option) + 1] = value
    elif option in ("--json", "--html", "--png"):
        value = ["{dir}/no/such/folder/out.x", "/proc/guardsim-fuzz.x", "{dir}/adir", ""][int(rng.integers(4))]
        args += [option, value]
        named = value.replace("{dir}/", "") if value else option
    elif option == "--max-worse":
        value = ["score", "score=", "=3", "nope=3", "score=nan", "score=-1", "score=1e400", "slack=x"][
            int(rng.integers(8))
        ]
        args += [option, value]
    elif option == "--baseline":
        value = ["{dir}/missing.json", "{dir}/adir", "{dir}/in.patrol.json"][int(rng.integers(3))]
        args[args.index("--baseline") + 1] = value
        named = value.replace("{dir}/", "")
    elif option == "--from-to":
        args[args.index("--sneak") + 1 : args.index("--sneak") + 3] = [value, value]
        option = named = "--sneak"
    elif option == "--patrol-old":
        args += ["--patrol-old", "{dir}/in.patrol.json"]  # without --patrol-new
        value = "(alone)"
    else:
        args += [option, value]
    bad = option not in ("--seed", "--guards", "--alert") or not _whole_in(value, option)
    if option in ("--from", "--to", "--sneak") and value in ("0.5,0.5",):
        bad = False
    if option in ("--from", "--to") and value in ("3,3", "60,60", "1e308,1"):
        bad = False  # report and diff answer "unreachable" for an end in a wall or off the floor
    outputs = ["r.json"] if command in ("report", "diff") else []
    return Case("design-option", command, files, args, named, outputs, bad=bad, clean=True,
                note=f"{option} {value[:20]!r}")  # fmt: skip


def _whole_in(value: str, option: str) -> bool:
    high = {"--seed": math.inf, "--guards": 64, "--alert": 100_000}[option]  # any seed: numpy takes any integer
    return value.isdigit() and (1 if option == "--guards" else 0) <= int(value) <= high


#: ``guardsim fortify`` on the tiny square, small budgets so that each run takes a moment.
_FORTIFY = ["fortify", "{dir}/level.json", "--from", _FROM, "--to", _TO, "--max-rounds", "3", "--candidates", "8",
            "--out", "{dir}/out"]  # fmt: skip
_FORTIFY_OUTPUTS = ["out/fortify.json", "out/level.json", "out/patrol.json", "out/fortify.png"]
_FORTIFY_BUDGETS = ("--cameras", "--posts", "--candidates", "--max-rounds", "--max-lap")
_FORTIFY_NUMBERS = ("0", "-1", "1" + "0" * 400, "2", "x", "nan", "1e3", "")
_FORTIFY_PICTURES = ("{dir}/no/such/folder/p.png", "/proc/guardsim-fuzz.png", "{dir}/adir", "")


def fortify_option_case(rng: np.random.Generator) -> Case:
    """One option of ``guardsim fortify`` given a nasty value: an entry or goal in the pillar or off the
    level, a budget of 0, negative or past any integer, a keep-open pair that is also a pair to seal or
    lies in a wall, a min-slack without its pair, a picture or folder that cannot be written."""
    files = {"level.json": json.dumps(SQUARE_WITH_HOLE).encode(), "adir/keep": b""}
    args = list(_FORTIFY)
    roll = int(rng.integers(6))
    value = _VALUES[int(rng.integers(len(_VALUES)))]
    named = option = ("--from", "--to", "budget", "--keep-open", "--min-slack", "output")[roll]
    bad = True
    if option in ("--from", "--to"):
        args[args.index(option) + 1] = value
        bad = value != "0.5,0.5"
    elif option == "budget":
        named = option = _FORTIFY_BUDGETS[int(rng.integers(len(_FORTIFY_BUDGETS)))]
        value = _FORTIFY_NUMBERS[int(rng.integers(len(_FORTIFY_NUMBERS)))]
        if option in args:
            args[args.index(option) + 1] = value
        else:
            args += [option, value]
        # Budgets are whole numbers of at least 1 (0 watchers, rounds or candidates cannot fortify, a lap
        # under 4 ticks holds no turning candidate); a huge one is only a budget not reached.
        bad = not value.isdigit() or int(value) < (4 if option == "--max-lap" else 1)
        if option in ("--cameras", "--posts") and value == "0":
            bad = False  # the other kind is still there
    elif option == "--keep-open":
        pair = [("0.5,5.5", "5.5,0.5"), ("0.5,0.5", "5.5,5.5"), ("3,3", "5.5,5.5"), ("0.5,5.5", "60,60"),
                ("nan,1", "0.5,5.5"), ("0.5,5.5", "")][int(rng.integers(6))]  # fmt: skip
        args += ["--keep-open", *pair]
        value = " ".join(pair)
        named = "keep-open"
        bad = pair != ("0.5,5.5", "5.5,0.5")
    elif option == "--min-slack":
        with_pair = rng.random() < 0.5
        value = _FORTIFY_NUMBERS[int(rng.integers(len(_FORTIFY_NUMBERS)))]
        args += [*(["--keep-open", "0.5,5.5", "5.5,0.5"] if with_pair else []), "--min-slack", value]
        bad = not with_pair or not value.isdigit()
    else:
        option = ("--picture", "--out")[int(rng.integers(2))]
        value = _FORTIFY_PICTURES[int(rng.integers(len(_FORTIFY_PICTURES)))]
        if option == "--out":
            value = {"{dir}/adir": "{dir}/adir/keep"}.get(value, value)  # a file where the folder goes
            args[args.index("--out") + 1] = value
        else:
            # Alone: with --out, a picture that cannot be written still leaves the folder's files behind
            # and an empty name is "." (test_fuzz_findings.py's xfail
            # test_fortify_picture_that_cannot_be_written_is_refused_before_any_work).
            del args[args.index("--out") : args.index("--out") + 2]
            value = value or "{dir}/adir"  # an empty name: the same xfail test
            args += ["--picture", value]
        named = value.replace("{dir}/", "") if value else option
        # The output folder is made when missing; a picture's folder is not.
        bad = not (option == "--out" and value.startswith("{dir}/no/"))
    return Case("fortify-option", "fortify", files, args, named, _FORTIFY_OUTPUTS, bad=bad,
                clean=True, note=f"{option} {value[:20]!r}")  # fmt: skip


def fortify_patrol_case(rng: np.random.Generator, templates: Templates) -> Case:
    """A damaged patrol.json of the guards already there, given to ``guardsim fortify --patrol``."""
    content, note = _damaged_patrol(rng, templates)
    files = {"level.json": json.dumps(SQUARE_WITH_HOLE).encode(), "bad.patrol.json": content}
    args = [*_FORTIFY, "--patrol", "{dir}/bad.patrol.json", "--max-lap", "200"]
    return Case("fortify-patrol", "fortify", files, args, "bad.patrol.json", _FORTIFY_OUTPUTS, clean=True, note=note)


def generate_newer(kind: str, command: str, rng: np.random.Generator, templates: Templates) -> Case:
    """One case of a newer ``kind`` read by ``command``."""
    if kind == "fortify-option":
        return fortify_option_case(rng)
    if kind == "fortify-patrol":
        return fortify_patrol_case(rng, templates)
    if kind in ("cameras", "lights", "noise"):
        return level_kind_case(kind, command, rng, templates)
    if kind == "noise-route":
        return noise_route_case(rng, templates)
    if kind == "design-level":
        return design_level_case(command, rng, templates)
    if kind == "design-patrol":
        return design_patrol_case(command, rng, templates)
    return design_option_case(command, rng, templates)


def run_watch(case: Case, folder: Path) -> str:
    """Parse ``case``'s ``guardsim watch`` line as the command does and analyse the saved file once, as the
    server does on a save; the :func:`~tests.fuzz_cases.verdict` of what the page would show."""
    import click
    from numba.core.errors import NumbaIRAssumptionWarning

    from guardsim.cli.design_common import pairs_of
    from guardsim.cli.watch import watch
    from guardsim.errors import GuardsimError
    from guardsim.viewer.serve.app import LiveAnalyser

    case.write(folder)
    argv = case.argv(folder)[1:]
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            warnings.filterwarnings("ignore", category=NumbaIRAssumptionWarning)  # as in run_in_process
            try:
                context = watch.make_context("watch", argv)
                params = context.params
                analyser = LiveAnalyser(
                    params["level_path"],
                    patrol=params["patrol_path"],
                    guards=params["guards"],
                    pairs=pairs_of(params["sources"], params["targets"]),
                    echo=lambda _line: None,
                )
                analyser.analyse_now(0, lambda _payload: None)
            except click.ClickException as error:
                return verdict(case, folder, 2, "", f"Error: {error.format_message()}")
            except GuardsimError as error:
                return verdict(case, folder, 2, "", f"guardsim: error: {' '.join(str(error).split())}")
    except Exception:
        return verdict(case, folder, 1, "", "", traceback.format_exc())
    if caught:
        return "warning"
    return verdict(case, folder, 0, "", "")
