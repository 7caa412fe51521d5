"""Generated inputs for every kind of file and option guardsim reads, and the rule every run must keep.

Shared by ``tests/test_fuzz.py`` (a few thousand derandomised cases in CI) and ``benchmarks/fuzz.py``
(any number, each in a watched worker process, counted per kind and command).

A :class:`Case` is a folder of files, a command line, and the file whose name an error must carry.
Generators are mutation-based: a valid seed (a tiny level, the references ``regress --update`` writes
for it, a bench run folder, a Moving AI map, a PNG, a Tiled map) is damaged in one of the ways a
fuzzing campaign found guardsim failing on (non-finite and absurd numbers, deep nesting, repeated
holes, wrong types, truncation, special files, newlines in names). :func:`verdict` applies the rule:

- exit 0 with a correct result (the output parses; an accepted level is one the schema accepts, with
  finite numbers; an accepted option value is finite and in range), or exit 1 where the command
  documents it (``regress``: differs), or
- exit 2 with exactly one line on stderr that names the file (or, for a bad option value, the option:
  click's usage error, whose last line names it);
- never a traceback, never a hidden ``.part`` file left behind.

Time (20 s) and memory (2 GB) are watched by ``benchmarks/fuzz.py``, which runs each case in a child.
"""

from __future__ import annotations

import copy
import io
import json
import math
import os
import re
import shutil
import stat
import sys
import traceback
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tests.common import EMPTY_SQUARE, L_ROOM, SQUARE_WITH_HOLE

#: Every input kind and the commands that read it.
KINDS: dict[str, tuple[str, ...]] = {
    "level": ("validate", "validate-fix", "play", "render", "bounds"),
    "manifest": ("regress",),
    "reference": ("regress",),
    "trace": ("regress", "view"),
    "bench-folder": ("bench",),
    "option": (
        "play",
        "bench",
        "validate",
        "render",
        "bounds",
        "regress",
        "patrol",
        "sneak",
        "check",
        "optimum",
        "alert",
    ),
    "patrol": ("evaluate", "sneak", "check", "alert"),
    "checks": ("check",),
    "intruder-route": ("alert",),
    "movingai": ("import",),
    "png": ("import",),
    "ldtk": ("import", "play"),
    "tmx": ("import",),
    "tiled-json": ("import",),
    "checks-toml": ("check",),
    "round4-option": ("patrol", "check", "alert", "import"),
    "tiled-cases": ("import",),
}
#: The newer inputs (``tests/fuzz_newer.py``): cameras, light and noise keys, route files with gaits and
#: throws, and the design commands' levels, patrols and options (``watch`` analyses one save in process).
NEWER_KINDS: dict[str, tuple[str, ...]] = {
    "cameras": ("validate", "sneak", "check", "render", "alert"),
    "lights": ("validate", "sneak", "render", "alert"),
    "noise": ("validate", "alert"),
    "noise-route": ("alert",),
    "design-level": ("report", "diff", "check-baseline", "watch", "fortify"),
    "design-patrol": ("report", "diff", "check-baseline", "watch"),
    "design-option": ("report", "diff", "check-baseline"),
    "fortify-option": ("fortify",),
    "fortify-patrol": ("fortify",),
}
KINDS.update(NEWER_KINDS)
#: Kinds of the fourth round of robustness work (issue 44's findings): run in the slow tier.
ROUND4_KINDS = frozenset({"checks-toml", "round4-option", "tiled-cases"})
#: Kinds read by the importers (counted, not fixed here: guardsim/importers/ has its own owner).
IMPORTER_KINDS = frozenset({"movingai", "png", "tmx", "tiled-json", "ldtk"})

FIFO = b"\0FIFO\0"
"""File content standing for a named pipe."""
DEVICE = b"\0DEVICE\0"
"""File content standing for a symbolic link to ``/dev/zero``."""

_SEED_LEVELS = ({**EMPTY_SQUARE}, {**SQUARE_WITH_HOLE}, {**L_ROOM})


@dataclass
class Case:
    """One generated input and the command that reads it."""

    kind: str
    command: str
    files: dict[str, bytes]
    """Relative path -> content (:data:`FIFO` or :data:`DEVICE` for special files); ``{dir}`` in the
    content stands for the case's folder."""
    args: list[str]
    """The command line after ``guardsim``; ``{dir}`` stands for the case's folder."""
    named: str
    """The relative path an error line must name (the file at fault, or the option's name)."""
    outputs: list[str] = field(default_factory=list)
    """Relative paths of the files the command writes, checked when it succeeds."""
    bad: bool = False
    """Whether the input is known to be wrong: exit 0 would be an accepted bad input."""
    clean: bool = False
    """Whether a failed command must leave none of ``outputs`` behind."""
    note: str = ""
    """What the generator did, for the report."""
    place: str = ""
    """Where in the file the fault is (a key), when known: an error line must name it too."""

    def write(self, folder: Path) -> None:
        """Create the files under ``folder``."""
        for name, content in self.files.items():
            path = folder / name
            path.parent.mkdir(parents=True, exist_ok=True)
            if content == FIFO:
                os.mkfifo(path)
            elif content == DEVICE:
                os.symlink("/dev/zero", path)
            else:
                path.write_bytes(content.replace(b"{dir}", os.fsencode(folder)))

    def argv(self, folder: Path) -> list[str]:
        """The command line with the folder filled in."""
        return [arg.replace("{dir}", str(folder)) for arg in self.args]


# ---------------------------------------------------------------- value mutations


#: An integer JSON allows and no float holds (``float(HUGE_INT)`` is an OverflowError).
HUGE_INT = 10**400


def _nasty_number(rng: np.random.Generator) -> Any:
    return [math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-320, 0, -1, 10**40, 1e15, 2**63, 0.5, HUGE_INT][
        int(rng.integers(13))
    ]


def _nasty_value(rng: np.random.Generator) -> Any:
    choice = int(rng.integers(10))
    if choice < 3:
        return _nasty_number(rng)
    return [
        None,
        True,
        "1",
        "x\ny",
        [],
        {},
        [[[1, 2]] * 300] * 300,  # a 90,000-pair list of lists, echoed whole by old error messages
    ][choice - 3]


def _leaves(value: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Paths to every value in a JSON tree (containers included)."""
    found = [path]
    if isinstance(value, dict):
        for key, item in value.items():
            found += _leaves(item, (*path, key))
    elif isinstance(value, list):
        for index, item in enumerate(value[:20]):
            found += _leaves(item, (*path, index))
    return found


def _set(value: Any, path: tuple[Any, ...], new: Any) -> Any:
    if not path:
        return new
    value[path[0]] = new if len(path) == 1 else _set(value[path[0]], path[1:], new)  # a new key may be set
    return value


def mutate_json(data: Any, rng: np.random.Generator) -> tuple[Any, str]:
    """One structural mutation of decoded JSON, and its description."""
    data = copy.deepcopy(data)
    paths = _leaves(data)
    path = paths[int(rng.integers(len(paths)))]
    what = int(rng.integers(6))
    if what <= 2 and path:
        return _set(data, path, _nasty_value(rng)), f"{'.'.join(map(str, path))} = nasty value"
    if what == 3 and path:
        parent = data
        for step in path[:-1]:
            parent = parent[step]
        if isinstance(parent, dict):
            del parent[path[-1]]
            return data, f"deleted {'.'.join(map(str, path))}"
        if isinstance(parent, list):
            parent.pop(path[-1])
            return data, f"dropped {'.'.join(map(str, path))}"
    if what == 4 and isinstance(data, dict):
        data[["colour", "guard\n", "x" * 1000][int(rng.integers(3))]] = 1
        return data, "unknown key"
    scale = [1e300, 1e-300, -1.0, 1e15][int(rng.integers(4))]
    return _scaled(data, scale), f"numbers scaled by {scale:g}"


def _scaled(value: Any, scale: float) -> Any:
    if isinstance(value, bool):
        return value
    if isinstance(value, (int, float)):
        return value * scale if abs(value) < 2**1023 else value
    if isinstance(value, list):
        return [_scaled(item, scale) for item in value]
    if isinstance(value, dict):
        return {key: _scaled(item, scale) for key, item in value.items()}
    return value


def mutate_text(text: bytes, rng: np.random.Generator) -> tuple[bytes, str]:
    """One textual mutation of a file's bytes, and its description."""
    what = int(rng.integers(8))
    if what == 0 and text:
        cut = int(rng.integers(len(text)))
        return text[:cut], f"truncated at {cut}"
    if what == 1 and text:
        at = int(rng.integers(len(text)))
        return text[:at] + bytes([int(rng.integers(256))]) + text[at + 1 :], f"byte {at} replaced"
    if what == 2:
        depth = int(rng.choice([70, 3000, 100_000]))
        return b"[" * depth + text + b"]" * depth, f"wrapped in {depth} brackets"
    if what == 3:
        return b"\xef\xbb\xbf" + text, "byte-order mark"
    if what == 4:
        return text.replace(b"1", b"1" + b"0" * 5000, 1), "a 5,001-digit number"
    if what == 5:
        return text.replace(b"0", b"NaN", 1), "NaN token"
    if what == 6:
        return b"", "empty file"
    return text + b"\n\x00garbage", "trailing garbage"


def special_file(rng: np.random.Generator) -> tuple[bytes, str]:
    """A FIFO or ``/dev/zero`` in place of the file."""
    return (FIFO, "a FIFO") if rng.random() < 0.5 else (DEVICE, "a link to /dev/zero")


# ---------------------------------------------------------------- the kinds


def _level_bytes(rng: np.random.Generator) -> tuple[bytes, str, bool]:
    """A damaged level file, its description, and whether it is known to be bad."""
    data = copy.deepcopy(_SEED_LEVELS[int(rng.integers(len(_SEED_LEVELS)))])
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
        return content, note, True
    if roll < 0.12:
        count = int(rng.choice([2, 50, 2000]))
        data["holes"] = [[[2, 2], [3, 2], [3, 3]]] * count
        data.setdefault("outer", [[0, 0], [6, 0], [6, 6], [0, 6]])
        data["outer"] = [[0, 0], [6, 0], [6, 6], [0, 6]]
        data.pop("guard", None)
        return json.dumps(data).encode(), f"{count} identical holes", True
    if roll < 0.16:
        points = int(rng.choice([100, 20_000]))
        angles = np.linspace(0, 2 * np.pi, points, endpoint=False)
        data = {"outer": np.stack([5 + 4 * np.cos(angles), 5 + 4 * np.sin(angles)], axis=1).round(6).tolist()}
        return json.dumps(data).encode(), f"a {points}-point ring", False
    if roll < 0.2:
        data = {"outer": [[0, 0], [10, 0], [10, 10], [0, 10]], "cell_size": float(rng.choice([0.02, 0.05, 1e-9]))}
        return json.dumps(data).encode(), f"cell_size {data['cell_size']}", data["cell_size"] < 1e-6
    if roll < 0.26:
        name, bad = LEVEL_NAMES[int(rng.integers(len(LEVEL_NAMES)))]
        data["name"] = name
        return json.dumps(data, ensure_ascii=bool(rng.integers(2))).encode(), f"name {name[:20]!r}", bad
    if roll < 0.32:
        path = _NUMERIC_FIELDS[int(rng.integers(len(_NUMERIC_FIELDS)))]
        data.setdefault("guard", {})
        data.setdefault("holes", [[[2, 2], [3, 2], [3, 3]]])
        return json.dumps(_set(data, path, HUGE_INT)).encode(), f"{'.'.join(map(str, path))} = 10**400", True
    if roll < 0.55:
        mutated, note = mutate_json(data, rng)
        return json.dumps(mutated, allow_nan=True).encode(), note, False
    text, note = mutate_text(json.dumps(data).encode(), rng)
    return text, note, False


#: Level names and whether the loader must refuse them: a name starts every summary line.
LEVEL_NAMES: tuple[tuple[str, bool], ...] = (
    ("x" * 1_000_000, True),
    ("x" * 201, True),
    ("two\nlines", True),
    ("tab\there", True),
    ("escape \x1b[31mred", True),
    ("\x7f", True),
    ("Crypte \u2620 \u2014 niveau 2", False),
    ("\u202eright to left", False),
    ("\ufeffbyte-order mark inside", False),
    ("", False),
)
#: Every numeric field of a level (the seed levels hold each), given an integer no float holds.
_NUMERIC_FIELDS: tuple[tuple[Any, ...], ...] = (
    ("cell_size",),
    ("outer", 0, 0),
    ("outer", 2, 1),
    ("holes", 0, 1, 0),
    ("guard", "view_range"),
    ("guard", "fov_degrees"),
    ("guard", "radius"),
    ("guard", "move_speed"),
    ("guard", "turn_speed"),
    ("guard", "tick_hz"),
    ("guard", "detect_near"),
    ("guard", "detect_far"),
    ("guard", "forget"),
    ("guard", "suspicious"),
    ("guard", "capture_radius"),
    ("guard", "search_seconds"),
    ("guard", "radio_delay"),
    ("guard", "start"),
    ("starts",),
)


def level_case(rng: np.random.Generator, command: str) -> Case:
    content, note, bad = _level_bytes(rng)
    name = "level.json" if rng.random() < 0.9 else "bad\nname.json"
    args = {
        "validate": ["validate", f"{{dir}}/{name}"],
        "validate-fix": ["validate", f"{{dir}}/{name}", "--fix", "{dir}/fixed.json"],
        "play": ["play", f"{{dir}}/{name}", "--trace", "{dir}/out.json", "--max-steps", "30"],
        "render": ["render", f"{{dir}}/{name}", "--png", "{dir}/out.png", "--size", "64"],
        "bounds": ["bounds", f"{{dir}}/{name}"],
    }[command]
    outputs = {"validate-fix": ["fixed.json"], "play": ["out.json"], "render": ["out.png"]}.get(command, [])
    if command == "validate-fix" and note.endswith("identical holes"):
        bad = False  # --fix merges them, and says so
    return Case("level", command, {name: content}, args, name, outputs, bad, note)


_TINY_LEVEL = json.dumps({**SQUARE_WITH_HOLE, "name": "tiny"}).encode()


@dataclass
class Templates:
    """Valid files made once by the real commands, to be damaged by the generators."""

    references: dict[str, bytes]
    """The files of ``renders/tiny/`` after ``guardsim regress tiny.json --update``."""
    bench: dict[str, bytes]
    """The files of a bench run folder after a 3-episode run of ``tiny.json``."""
    patrol: bytes
    """The patrol.json of ``guardsim patrol tiny.json``."""


def make_templates(run: Callable[[list[str]], Any], folder: Path) -> Templates:
    """Write the templates by running guardsim (``run`` takes the command line after ``guardsim``)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "tiny.json").write_bytes(_TINY_LEVEL)
    run(["regress", str(folder / "tiny.json"), "--renders", str(folder / "renders"), "--update"])
    references = {p.name: p.read_bytes() for p in sorted((folder / "renders" / "tiny").iterdir())}
    run(["bench", str(folder / "tiny.json"), *BENCH_OPTIONS, "--out", str(folder / "bench")])
    # The run folder names its level by path: "{dir}" in the templates stands for the case's folder.
    bench = {
        p.name: p.read_bytes().replace(os.fsencode(folder), b"{dir}") for p in sorted((folder / "bench").iterdir())
    }
    run(["patrol", str(folder / "tiny.json"), "--out", str(folder / "patrol")])
    patrol = (folder / "patrol" / "patrol.json").read_bytes()
    shutil.rmtree(folder / "renders")
    shutil.rmtree(folder / "bench")
    shutil.rmtree(folder / "patrol")
    return Templates(references, bench, patrol)


#: The bench options of the template run; a case reruns the same command on a damaged folder.
BENCH_OPTIONS = ["--episodes", "3", "--workers", "1", "--no-bounds"]


def regress_case(rng: np.random.Generator, kind: str, templates: Templates) -> Case:
    files = {f"renders/tiny/{name}": content for name, content in templates.references.items()}
    trace_name = next(name for name in templates.references if name.endswith(".trace.json"))
    if kind == "manifest":
        target = "manifest.json"
    elif kind == "trace":
        target = trace_name
    else:
        names = [name for name in templates.references if name.endswith(".png")] + ["level.json"]
        target = names[int(rng.integers(len(names)))]
    original = templates.references[target]
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif target.endswith(".png"):
        content, note = mutate_png(original, rng)
    elif kind == "trace" and roll < 0.5:
        content, note = _trace_mutation(json.loads(original), rng)
    elif roll < 0.6:
        data, note = mutate_json(json.loads(original), rng)
        content = json.dumps(data, allow_nan=True).encode()
    else:
        content, note = mutate_text(original, rng)
    files[f"renders/tiny/{target}"] = content
    files["tiny.json"] = _TINY_LEVEL
    return Case(
        kind,
        "regress",
        files,
        ["regress", "{dir}/tiny.json", "--renders", "{dir}/renders"],
        f"renders/tiny/{target}",
        note=f"{target}: {note}",
    )


def view_case(rng: np.random.Generator, templates: Templates) -> Case:
    """A damaged trace file given to ``guardsim view``."""
    original = next(content for name, content in templates.references.items() if name.endswith(".trace.json"))
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.5:
        content, note = _trace_mutation(json.loads(original), rng)
    elif roll < 0.75:
        data, note = mutate_json(json.loads(original), rng)
        content = json.dumps(data, allow_nan=True).encode()
    else:
        content, note = mutate_text(original, rng)
    return Case("trace", "view", {"t.trace.json": content}, ["view", "{dir}/t.trace.json", "--html", "{dir}/out.html"],
                "t.trace.json", ["out.html"], note=note)  # fmt: skip


def _trace_mutation(data: dict[str, Any], rng: np.random.Generator) -> tuple[bytes, str]:
    """The damage to stored traces that once raised inside regress."""
    what = int(rng.integers(6))
    if what == 0:
        data["path"] = []
        note = "empty path"
    elif what == 5:
        key = ["cell_size", "origin", "unseen_percent", "shape", "steps", "seed", "reachable"][int(rng.integers(7))]
        value = data.get(key)
        data[key] = [HUGE_INT, *value[1:]] if isinstance(value, list) and value else HUGE_INT
        note = f"{key} holds 10**400"
    elif what == 1:
        data["cell_size"] = "1"
        note = "string cell size"
    elif what == 2:
        data["guard_paths"] = [data["path"], data["path"]]
        data["guard_headings"] = [data["headings"], data["headings"]]
        note = "guard_paths without guards"
    elif what == 3:
        data["shape"] = [100_000, 100_000]
        note = "a 10^10-cell shape"
    else:
        data["first_seen"] = [[1]]
        note = "first_seen of the wrong shape"
    text = "{\n" + ",\n".join(f"  {json.dumps(k)}: {json.dumps(v, separators=(',', ':'))}" for k, v in data.items())
    return (text + "\n}\n").encode(), note


def mutate_png(original: bytes, rng: np.random.Generator) -> tuple[bytes, str]:
    """A damaged or oversized PNG."""
    what = int(rng.integers(4))
    if what == 0:
        return _png_declaring(20_000, 20_000), "declares 20,000 x 20,000"
    if what == 1:
        cut = int(rng.integers(8, max(9, len(original))))
        return original[:cut], f"truncated at {cut}"
    if what == 2:
        data = bytearray(original)
        for _ in range(4):
            data[int(rng.integers(8, len(data)))] = int(rng.integers(256))
        return bytes(data), "4 bytes flipped"
    return b"\x89PNG\r\n\x1a\n" + bytes(rng.integers(0, 256, 64, dtype=np.uint8)), "a PNG signature and noise"


def _png_declaring(width: int, height: int) -> bytes:
    """A small valid PNG that declares ``width`` x ``height`` pixels (one zlib stream of zeros)."""
    import struct
    import zlib

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    data = zlib.compress(b"\0" * (width + 1) * 16, 9)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", data) + chunk(b"IEND", b"")


def bench_case(rng: np.random.Generator, templates: Templates) -> Case:
    files = {f"out/{name}": content for name, content in templates.bench.items()}
    files["tiny.json"] = _TINY_LEVEL
    target = "run.json" if rng.random() < 0.5 else "results.csv"
    original = templates.bench[target]
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif target == "results.csv" and roll < 0.5:
        content, note = _results_mutation(original, rng)
    elif target == "run.json" and roll < 0.6:
        data, note = mutate_json(json.loads(original), rng)
        content = json.dumps(data, allow_nan=True).encode()
    else:
        content, note = mutate_text(original, rng)
    files[f"out/{target}"] = content
    return Case(
        "bench-folder",
        "bench",
        files,
        ["bench", "{dir}/tiny.json", *BENCH_OPTIONS, "--out", "{dir}/out"],
        f"out/{target}",
        ["out/results.csv", "out/summary.json"],
        note=f"{target}: {note}",
    )


def _results_mutation(original: bytes, rng: np.random.Generator) -> tuple[bytes, str]:
    lines = original.decode().splitlines(keepends=True)
    what = int(rng.integers(4))
    if what == 0:
        return "".join([*lines, lines[1]]).encode(), "a finished row twice"
    if what == 1:
        row = lines[1].split(",")
        row[5] = "99"
        return "".join([*lines, ",".join(row)]).encode(), "a row for episode 99 of 3"
    if what == 2:
        return "".join(lines[:-1]).encode() + lines[-1][:7].encode(), "half-written last line"
    row = lines[1].split(",")
    row[int(rng.integers(len(row)))] = "x" * 300_000
    return "".join([lines[0], ",".join(row), *lines[2:]]).encode(), "a 300,000-character field"


#: Option values tried, as typed on a command line.
NASTY_OPTION_VALUES = ("nan", "inf", "-inf", "-1", "0", "1e308", "1" + "0" * 400, "x", "", "0.5", "3", "1,2", "nan,1")
_OPTIONS = {
    "play": ("--fov", "--view-range", "--seed", "--max-steps", "--start", "--stride", "--guards", "--max-cells",
             "--move-speed", "--turn-speed", "--tick-hz", "--max-seconds", "--episode"),
    "bench": ("--fov", "--view-range", "--episodes", "--seed", "--guards", "--max-steps"),
    "validate": ("--max-rays", "--max-cells", "--max-vertices", "--max-file-bytes"),
    "render": ("--size", "--start", "--cone", "--max-cells"),
    "bounds": ("--fov", "--view-range", "--seed", "--start"),
    "regress": ("--max-frame-size", "--max-cells"),
    "patrol": ("--guards", "--fov", "--view-range", "--speed", "--laps", "--warmup-laps", "--max-cells"),
    "sneak": ("--from", "--to", "--fov", "--max-cells"),
    "check": ("--max-cover-steps", "--max-idleness", "--guards", "--fov"),
    "optimum": ("--start", "--heading", "--fov", "--view-range", "--time-limit", "--max-expansions", "--memory-mb"),
    "alert": ("--from", "--to", "--episodes", "--seed", "--max-seconds", "--intruder-speed", "--detect-near",
              "--detect-far"),
}  # fmt: skip
#: Options whose value must be a finite number in a range: exit 0 with nan, inf or out of range is a bug.
_FINITE = {"--fov": (0, 360), "--view-range": (0, math.inf), "--move-speed": (0, math.inf),
           "--turn-speed": (0, math.inf), "--tick-hz": (0, 1000), "--max-seconds": (0, math.inf),
           "--speed": (0, 1e6), "--time-limit": (0, math.inf), "--intruder-speed": (-1e-300, 1e6),
           "--detect-near": (-1e-300, math.inf), "--detect-far": (-1e-300, math.inf)}  # fmt: skip


def option_case(rng: np.random.Generator, command: str, templates: Templates | None = None) -> Case:
    option = _OPTIONS[command][int(rng.integers(len(_OPTIONS[command])))]
    value = NASTY_OPTION_VALUES[int(rng.integers(len(NASTY_OPTION_VALUES)))]
    tail = {
        "play": ["--trace", "{dir}/out.json", "--max-steps", "20"] if option != "--max-steps" else [],
        "bench": [
            "--workers",
            "1",
            "--no-bounds",
            "--out",
            "{dir}/out",
            *(["--episodes", "1"] if option != "--episodes" else []),
        ],
        "render": ["--png", "{dir}/out.png", "--size", "64"] if option != "--size" else ["--png", "{dir}/out.png"],
        "regress": ["--renders", "{dir}/renders", "--update"],
        "patrol": ["--out", "{dir}/out"],
        "sneak": [
            "--patrol",
            "{dir}/in.patrol.json",
            "--out",
            "{dir}/out",
            *([] if option == "--from" else ["--from", _TINY_FROM]),
            *([] if option == "--to" else ["--to", _TINY_TO]),
        ],
        "check": ["--patrol", "{dir}/in.patrol.json", *_CHECK_RULES] if option != "--guards" else _CHECK_RULES,
        "optimum": ["--max-expansions", "20000", "--out", "{dir}/out.json"]
        if option != "--max-expansions"
        else ["--out", "{dir}/out.json"],
        "alert": [
            "--patrol",
            "{dir}/in.patrol.json",
            "--trace",
            "{dir}/out.json",
            *([] if option == "--from" else ["--from", _TINY_FROM]),
            *([] if option == "--to" else ["--to", _TINY_TO]),
            *([] if option == "--max-seconds" else ["--max-seconds", "20"]),
        ],
    }.get(command, [])
    bad = False
    if option in _FINITE:
        low, high = _FINITE[option]
        try:
            number = float(value)
            bad = not (math.isfinite(number) and low < number <= high)
        except ValueError:
            bad = True
    files = {"tiny.json": _TINY_LEVEL}
    if command in ("sneak", "check", "alert"):
        assert templates is not None
        files["in.patrol.json"] = templates.patrol
    return Case(
        "option",
        command,
        files,
        [command, "{dir}/tiny.json", *tail, option, value],
        option,
        bad=bad,
        note=f"{option} {value[:20]!r}",
    )


_MOVINGAI = b"type octile\nheight 4\nwidth 6\nmap\n......\n.@@...\n......\n...T..\n"


def movingai_case(rng: np.random.Generator) -> Case:
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.5:
        field_name = [b"height 4", b"width 6"][int(rng.integers(2))]
        value = [b"\xc2\xb3", b"9999999999999", b"-1", b"1e5", b"0", b"1000000000000", b"4.5"][int(rng.integers(7))]
        content = _MOVINGAI.replace(field_name, field_name.split()[0] + b" " + value)
        note = f"{field_name.split()[0].decode()} {value!r}"
    else:
        content, note = mutate_text(_MOVINGAI, rng)
    return Case("movingai", "import", {"map.map": content}, ["import", "{dir}/map.map", "--out", "{dir}/out.json"],
                "map.map", ["out.json"], note=note)  # fmt: skip


def _png_of(pixels: np.ndarray) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(pixels).save(buffer, format="PNG")
    return buffer.getvalue()


def png_case(rng: np.random.Generator) -> Case:
    pixels = np.full((12, 16), 255, dtype=np.uint8)
    pixels[3:6, 4:9] = 0
    base = _png_of(pixels)
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.15:
        size = int(
            rng.choice([100, 1000])
        )  # 300^2 noise imports in 12-15 s (noted in docs/robustness.md); 100^2 keeps the meaning
        content, note = _png_of((rng.random((size, size)) < 0.5).astype(np.uint8) * 255), f"{size}^2 noise"
    else:
        content, note = mutate_png(base, rng)
    return Case("png", "import", {"map.png": content}, ["import", "{dir}/map.png", "--out", "{dir}/out.json"],
                "map.png", ["out.json"], note=note)  # fmt: skip


_TMX = b"""<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" renderorder="right-down" width="6" height="4" tilewidth="16" tileheight="16" infinite="0">
 <tileset firstgid="1" name="t" tilewidth="16" tileheight="16" tilecount="2" columns="2">
  <tile id="1" type="wall"/>
 </tileset>
 <layer id="1" name="floor" width="6" height="4">
  <data encoding="csv">
1,1,1,1,1,1,
1,2,2,1,1,1,
1,1,1,1,1,1,
1,1,1,1,1,1
</data>
 </layer>
 <objectgroup id="2" name="walls">
  <object id="1" x="64" y="16" width="16" height="16"/>
 </objectgroup>
</map>
"""


_TMX_WALL = b'<object id="1" x="64" y="16" width="16" height="16"/>'
#: ``points`` lists Tiled would never write: each must be refused naming the object, not guessed into a shape.
_BAD_POINTS = (b"0,0 16,0,5 3,3", b"0,0 8,x 8,8", b"0,0 nan,1 3,3", b"0,0 inf,0 3,3", b"0,0 1e999,0 3,3", b"",
               b"0;0 8;0 8;8", b"0,0 16 3,3", b"0,0,0,0")  # fmt: skip


def tmx_case(rng: np.random.Generator) -> Case:
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.15:
        content, note = _TMX.replace(b'encoding="csv">', b'encoding="hex">111111111111', 1), "encoding hex"
    elif roll < 0.25:
        depth = 3000
        groups = b"<group>" * depth + b"</group>" * depth
        content, note = _TMX.replace(b"</map>", groups + b"</map>"), f"{depth} nested groups"
    elif roll < 0.4:
        value = [b"1e308", b"nan", b"-1e308", b"99999999999"][int(rng.integers(4))]
        content, note = (
            _TMX.replace(b'width="16" height="16"/>', b'width="' + value + b'" height="16"/>'),
            f"width {value!r}",
        )
    elif roll < 0.5:
        content, note = (
            _TMX.replace(b'width="6" height="4" tilewidth', b'width="2048" height="2048" tilewidth'),
            "2048^2",
        )
    elif roll < 0.6:
        points = _BAD_POINTS[int(rng.integers(len(_BAD_POINTS)))]
        tag = b"polygon" if rng.random() < 0.7 else b"polyline"
        shape = b'<object id="1" name="blob" x="64" y="16"><' + tag + b' points="' + points + b'"/></object>'
        content, note = _TMX.replace(_TMX_WALL, shape), f"{tag.decode()} points {points!r}"
        return Case("tmx", "import", {"map.tmx": content}, ["import", "{dir}/map.tmx", "--out", "{dir}/out.json"],
                    "map.tmx", ["out.json"], bad=True, note=note)  # fmt: skip
    elif roll < 0.68:
        count = int(rng.choice([300, 3000]))
        long_name = b"n" * int(rng.choice([10, 200]))
        layers = b"".join(
            b'<objectgroup id="%d" name="walls %s %d"><object id="%d" x="%d" y="16" width="16" height="16"/>'
            b"</objectgroup>" % (index + 10, long_name, index, index + 10, 16 * (index % 6))
            for index in range(count)
        )
        content, note = _TMX.replace(b"</map>", layers + b"</map>"), f"{count} layers"
    elif roll < 0.74:
        name = [b"wa&#10;lls", b"w&#9;alls", b"walls \xe2\x98\x83 \xe2\x80\xae", b"w" * 100_000][int(rng.integers(4))]
        content, note = _TMX.replace(b'name="walls"', b'name="' + name + b'"'), f"layer name {name[:20]!r}"
    else:
        content, note = mutate_text(_TMX, rng)
    return Case("tmx", "import", {"map.tmx": content}, ["import", "{dir}/map.tmx", "--out", "{dir}/out.json"],
                "map.tmx", ["out.json"], note=note)  # fmt: skip


def _tiled_json() -> dict[str, Any]:
    return {
        "type": "map", "version": "1.10", "orientation": "orthogonal", "renderorder": "right-down",
        "width": 6, "height": 4, "tilewidth": 16, "tileheight": 16, "infinite": False,
        "tilesets": [{"firstgid": 1, "name": "t", "tilewidth": 16, "tileheight": 16, "tilecount": 2, "columns": 2,
                      "tiles": [{"id": 1, "type": "wall"}]}],
        "layers": [
            {"type": "tilelayer", "id": 1, "name": "floor", "width": 6, "height": 4, "x": 0, "y": 0,
             "data": [1, 1, 1, 1, 1, 1, 1, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1]},
            {"type": "objectgroup", "id": 2, "name": "walls",
             "objects": [{"id": 1, "x": 64, "y": 16, "width": 16, "height": 16}]},
        ],
    }  # fmt: skip


def tiled_json_case(rng: np.random.Generator) -> Case:
    roll = rng.random()
    data = _tiled_json()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.15:
        data["layers"][0]["encoding"] = "base64"
        content, note = json.dumps(data).encode(), "base64 data given as a list"
    elif roll < 0.55:
        mutated, note = mutate_json(data, rng)
        content = json.dumps(mutated, allow_nan=True).encode()
    else:
        content, note = mutate_text(json.dumps(data).encode(), rng)
    return Case("tiled-json", "import", {"map.json": content}, ["import", "{dir}/map.json", "--out", "{dir}/out.json"],
                "map.json", ["out.json"], note=note)  # fmt: skip


def _ldtk() -> dict[str, Any]:
    """A one-level LDtk project: an IntGrid 'Terrain' (value 1 'walls') round a 6 x 4 room, a guard and a hero."""
    csv = [1] * 6 + [1, 0, 0, 0, 0, 1] * 2 + [1] * 6
    return {
        "__header__": {"fileType": "LDtk Project JSON", "app": "LDtk"}, "jsonVersion": "1.5.3",
        "defaultGridSize": 16,
        "defs": {"layers": [
            {"__type": "Entities", "identifier": "Things", "uid": 2, "gridSize": 16},
            {"__type": "IntGrid", "identifier": "Terrain", "uid": 1, "gridSize": 16,
             "intGridValues": [{"value": 1, "identifier": "walls"}]},
        ]},
        "levels": [{"identifier": "Level_0", "pxWid": 96, "pxHei": 64, "layerInstances": [
            {"__identifier": "Things", "__type": "Entities", "__gridSize": 16, "layerDefUid": 2,
             "entityInstances": [
                 {"__identifier": "Guard", "px": [24, 24], "__pivot": [0.5, 0.5], "width": 16, "height": 16},
                 {"__identifier": "Hero", "px": [72, 40], "__pivot": [0.5, 0.5], "width": 16, "height": 16}]},
            {"__identifier": "Terrain", "__type": "IntGrid", "__cWid": 6, "__cHei": 4, "__gridSize": 16,
             "layerDefUid": 1, "intGridCsv": csv},
        ]}],
    }  # fmt: skip


def ldtk_case(rng: np.random.Generator, command: str) -> Case:
    """A damaged LDtk project, imported or played."""
    roll = rng.random()
    if roll < 0.05:
        content, note = special_file(rng)
    elif roll < 0.6:
        mutated, note = mutate_json(_ldtk(), rng)
        content = json.dumps(mutated, allow_nan=True).encode()
    else:
        content, note = mutate_text(json.dumps(_ldtk()).encode(), rng)
    if command == "play":
        return Case("ldtk", "play", {"map.ldtk": content}, ["play", "{dir}/map.ldtk", "--gif", "{dir}/out.gif"],
                    "map.ldtk", ["out.gif"], note=note)  # fmt: skip
    return Case("ldtk", "import", {"map.ldtk": content}, ["import", "{dir}/map.ldtk", "--out", "{dir}/out.json"],
                "map.ldtk", ["out.json"], note=note)  # fmt: skip


#: Two points of ``tiny.json`` (world units) and the rules of the check cases: all hold on the template
#: patrol, so exit 1 comes only from a damaged patrol that breaks them.
_TINY_FROM, _TINY_TO = "0.5,0.5", "5.5,5.5"
_CHECK_RULES = ["--max-idleness", "1000", "--sneak", _TINY_FROM, _TINY_TO, "--expect", "sneaks"]


def _damaged_json(original: bytes, rng: np.random.Generator) -> tuple[bytes, str]:
    roll = rng.random()
    if roll < 0.05:
        return special_file(rng)
    if roll < 0.65:
        data, note = mutate_json(json.loads(original), rng)
        return json.dumps(data, allow_nan=True).encode(), note
    return mutate_text(original, rng)


def patrol_case(rng: np.random.Generator, command: str, templates: Templates) -> Case:
    """A damaged patrol.json read by ``patrol --evaluate``, ``sneak --patrol`` or ``check --patrol``."""
    content, note = _damaged_json(templates.patrol, rng)
    args, outputs = {
        "evaluate": (["patrol", "{dir}/tiny.json", "--evaluate", "{dir}/in.patrol.json", "--out", "{dir}/out"],
                     ["out/patrol.json", "out/idleness.png"]),
        "sneak": (["sneak", "{dir}/tiny.json", "--patrol", "{dir}/in.patrol.json", "--from", _TINY_FROM,
                   "--to", _TINY_TO, "--out", "{dir}/out"], ["out/sneak.json", "out/hiding.png"]),
        "check": (["check", "{dir}/tiny.json", "--patrol", "{dir}/in.patrol.json", *_CHECK_RULES], []),
        "alert": (["alert", "{dir}/tiny.json", "--patrol", "{dir}/in.patrol.json", "--from", _TINY_FROM,
                   "--to", _TINY_TO, "--max-seconds", "20", "--trace", "{dir}/out.json"], ["out.json"]),
    }[command]  # fmt: skip
    files = {"tiny.json": _TINY_LEVEL, "in.patrol.json": content}
    return Case("patrol", command, files, args, "in.patrol.json", outputs, note=note)


def intruder_route_case(rng: np.random.Generator, templates: Templates) -> Case:
    """A damaged intruder route (JSON ``[[x, y], ...]``) read by ``alert --intruder route --route``."""
    route = [[0.5, 0.5], [0.5, 5.5], [5.5, 5.5]]
    content, note = _damaged_json(json.dumps(route).encode(), rng)
    args = ["alert", "{dir}/tiny.json", "--patrol", "{dir}/in.patrol.json", "--intruder", "route", "--route",
            "{dir}/route.json", "--max-seconds", "20", "--trace", "{dir}/out.json"]  # fmt: skip
    files = {"tiny.json": _TINY_LEVEL, "in.patrol.json": templates.patrol, "route.json": content}
    return Case("intruder-route", "alert", files, args, "route.json", ["out.json"], note=note)


def checks_case(rng: np.random.Generator, templates: Templates) -> Case:
    """A damaged checks file (JSON) read by ``check --checks``."""
    checks = {
        "max_idleness": 1000,
        "no_unreachable": True,
        "patrol": "in.patrol.json",
        "sneak": [{"from": [0.5, 0.5], "to": [5.5, 5.5], "expect": "sneaks"}],
    }
    content, note = _damaged_json(json.dumps(checks).encode(), rng)
    files = {"tiny.json": _TINY_LEVEL, "in.patrol.json": templates.patrol, "checks.json": content}
    return Case("checks", "check", files, ["check", "{dir}/tiny.json", "--checks", "{dir}/checks.json"],
                "checks.json", note=note)  # fmt: skip


_CHECKS_TOML = b"""max_idleness = 1000
patrol = "in.patrol.json"
[[sneak]]
from = [0.5, 0.5]
to = [5.5, 5.5]
expect = "sneaks"
"""


def checks_toml_case(rng: np.random.Generator, templates: Templates) -> Case:
    """A TOML checks file: nested past any limit, asking for more guards than the option allows, an empty
    patrol name, no rule at all, or damaged text."""
    roll = int(rng.integers(6))
    bad = True
    if roll == 0:
        depth = int(rng.choice([65, 200, 1000, 5000]))
        shape = int(rng.integers(3))
        if shape == 0:
            content = ("safe = " + "[" * depth + "]" * depth + "\n").encode()
        elif shape == 1:
            content = ("x = " + "{a = " * depth + "1" + "}" * depth + "\n").encode()
        else:
            content = ("[" + ".".join(["a"] * depth) + "]\nx = 1\n").encode()
        note = f"nested {depth} deep ({['arrays', 'inline tables', 'dotted tables'][shape]})"
    elif roll == 1:
        guards = int(rng.choice([0, 65, 1_000_000, 1, 2]))
        bad = guards not in (1, 2)
        content, note = f"guards = {guards}\nmax_idleness = 1000\n".encode(), f"guards = {guards}"
    elif roll == 2:
        content, note = b'patrol = ""\nmax_idleness = 5\n', "patrol = ''"
    elif roll == 3:
        content, note = b"guards = 2\n", "no rule"
    else:
        content, note = mutate_text(_CHECKS_TOML, rng)
        bad = False
    files = {"tiny.json": _TINY_LEVEL, "in.patrol.json": templates.patrol, "checks.toml": content}
    return Case("checks-toml", "check", files, ["check", "{dir}/tiny.json", "--checks", "{dir}/checks.toml"],
                "checks.toml", bad=bad, note=note)  # fmt: skip


def round4_option_case(rng: np.random.Generator, command: str, templates: Templates) -> Case:
    """The option values the fourth round's outside campaign broke: teams up to the allowed 64, empty or
    unwritable output places, physics rates past a game's, LDtk options on a Tiled map, long texts."""
    files: dict[str, bytes] = {"tiny.json": _TINY_LEVEL}
    roll = int(rng.integers(3))
    if command == "patrol":
        if roll == 0:
            guards = str(rng.choice(["32", "64"]))
            return Case("round4-option", "patrol", files, ["patrol", "{dir}/tiny.json", "--out", "{dir}/out",
                        "--guards", guards], "--guards", ["out/patrol.json"], note=f"--guards {guards}")  # fmt: skip
        if roll == 1:
            return Case("round4-option", "patrol", files, ["patrol", "{dir}/tiny.json", "--out", ""], "--out",
                        bad=True, note="--out ''")  # fmt: skip
        option = str(rng.choice(["--godot", "--export", "--tiled-out"]))
        target = "/proc/guardsim-fuzz" + {"--godot": ".tscn", "--export": ".json", "--tiled-out": ".tmj"}[option]
        return Case("round4-option", "patrol", files, ["patrol", "{dir}/tiny.json", "--out", "{dir}/out", option,
                    target], target, ["out/patrol.json", "out/idleness.png"], bad=True, clean=True,
                    note=f"{option} {target}")  # fmt: skip
    if command == "check":
        guards = str(rng.choice(["32", "64", "65", "0"]))
        return Case("round4-option", "check", files, ["check", "{dir}/tiny.json", "--guards", guards,
                    "--max-idleness", "1000"], "--guards", bad=guards in ("65", "0"),
                    note=f"--guards {guards}")  # fmt: skip
    if command == "alert":
        rate = str(rng.choice(["100000", "1001", "1e308", "30", "60"]))
        files["in.patrol.json"] = templates.patrol
        return Case("round4-option", "alert", files, ["alert", "{dir}/tiny.json", "--patrol",
                    "{dir}/in.patrol.json", "--motion", "continuous", "--tick-hz", rate, "--max-seconds", "5", "--from", _TINY_FROM, "--to", _TINY_TO,
                    "--trace", "{dir}/out.json"], "--tick-hz", ["out.json"], bad=rate not in ("30", "60"),
                    clean=True, note=f"--tick-hz {rate}")  # fmt: skip
    files = {"map.tmx": _TMX}
    if roll == 0:
        option, value = str(rng.choice(["--level", "--wall-value"])), "Level_1"
        bad = True
    elif roll == 1:
        option, value, bad = "--wall-property", "p" * int(rng.choice([100, 5000])), False
    else:
        option, value, bad = "--wall-class", "c" * int(rng.choice([100, 5000])), False
    return Case("round4-option", "import", files, ["import", "{dir}/map.tmx", "--out", "{dir}/out.json", option,
                value], "map.tmx", ["out.json"], bad=bad, clean=True, note=f"{option} {value[:20]!r}")  # fmt: skip


def tiled_cases_case(rng: np.random.Generator) -> Case:
    """One of the hand-made maps of ``tests/data/maps/cases`` (per-tile collision, ``z`` heights, bridges,
    shapes in hidden layers, players' starts) with its heights, marks or structure damaged."""
    folder = Path(__file__).resolve().parent / "data" / "maps" / "cases"
    names = sorted(path.name for path in folder.glob("*.tmj"))
    name = names[int(rng.integers(len(names)))]
    data = json.loads((folder / name).read_text(encoding="utf-8"))
    roll = rng.random()
    if roll < 0.4:
        layer = data["layers"][int(rng.integers(len(data["layers"])))]
        value = [-1, 0, 1, 2.5, "high", 1e308, True, None, [1], 10**30][int(rng.integers(10))]
        layer["properties"] = [*layer.get("properties", []), {"name": "z", "type": "string", "value": value}]
        content, note = json.dumps(data).encode(), f"{name}: layer {layer['name']!r} z = {value!r}"
    elif roll < 0.6:
        tiles = data["tilesets"][0]["tiles"]
        item = tiles[int(rng.integers(len(tiles)))]
        item["properties"] = [{"name": "collision", "type": "bool", "value": bool(rng.integers(2))},
                              {"name": "z", "type": "int", "value": int(rng.integers(-2, 3))}]  # fmt: skip
        content, note = json.dumps(data).encode(), f"{name}: tile {item['id']} marks changed"
    elif roll < 0.85:
        mutated, note = mutate_json(data, rng)
        content, note = json.dumps(mutated, allow_nan=True).encode(), f"{name}: {note}"
    else:
        content, note = mutate_text(json.dumps(data).encode(), rng)
        note = f"{name}: {note}"
    return Case("tiled-cases", "import", {"map.tmj": content}, ["import", "{dir}/map.tmj", "--out", "{dir}/out.json"],
                "map.tmj", ["out.json"], clean=True, note=note)  # fmt: skip


def generate(kind: str, command: str, rng: np.random.Generator, templates: Templates | None) -> Case:
    """One case of ``kind`` read by ``command``."""
    if kind in NEWER_KINDS:
        from tests.fuzz_newer import generate_newer

        assert templates is not None
        return generate_newer(kind, command, rng, templates)
    if kind == "checks-toml":
        assert templates is not None
        return checks_toml_case(rng, templates)
    if kind == "round4-option":
        assert templates is not None
        return round4_option_case(rng, command, templates)
    if kind == "tiled-cases":
        return tiled_cases_case(rng)
    if kind == "level":
        return level_case(rng, command)
    if kind == "trace" and command == "view":
        assert templates is not None
        return view_case(rng, templates)
    if kind in ("manifest", "reference", "trace"):
        assert templates is not None
        return regress_case(rng, kind, templates)
    if kind == "bench-folder":
        assert templates is not None
        return bench_case(rng, templates)
    if kind == "option":
        return option_case(rng, command, templates)
    if kind in ("patrol", "checks"):
        assert templates is not None
        return patrol_case(rng, command, templates) if kind == "patrol" else checks_case(rng, templates)
    if kind == "intruder-route":
        assert templates is not None
        return intruder_route_case(rng, templates)
    if kind == "ldtk":
        return ldtk_case(rng, command)
    return {"movingai": movingai_case, "png": png_case, "tmx": tmx_case, "tiled-json": tiled_json_case}[kind](rng)


def cases(count: int, seed: int, kinds: tuple[str, ...] = tuple(KINDS)) -> list[tuple[str, str, int]]:
    """``count`` (kind, command, case seed) triples spread evenly over ``kinds`` and their commands."""
    pairs = [(kind, command) for kind in kinds for command in KINDS[kind]]
    return [(*pairs[index % len(pairs)], seed * 1_000_003 + index) for index in range(count)]


# ---------------------------------------------------------------- the rule


def _level_is_acceptable(content: bytes) -> bool:
    """Whether a level file that validate accepted is one it should accept: schema and finite numbers.

    (Geometry is the loader's own business; this catches accepted non-finite numbers and wrong types.)
    """
    try:
        data = json.loads(content.decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError, RecursionError):
        return False
    import jsonschema

    from guardsim.files.schema import level_schema

    def finite(value: Any, bound: float = math.inf) -> bool:
        if isinstance(value, int) and not isinstance(value, bool):
            return abs(value) <= min(bound, sys.float_info.max)  # math.isfinite(10**400) would raise
        if isinstance(value, float):
            return math.isfinite(value) and abs(value) <= bound
        if isinstance(value, list):
            return all(finite(item, bound) for item in value)
        if isinstance(value, dict):
            return all(finite(item, bound) for item in value.values())
        return True

    try:
        jsonschema.validate(data, level_schema())
    except jsonschema.ValidationError:
        return False
    guard = data.get("guard") or {}
    points = [data.get("outer"), data.get("holes"), data.get("starts"), guard.get("start")]
    return finite(data) and all(finite(item, 1e15) for item in points if item is not None)


#: Longest line any command may print: a name or a list echoed whole once made lines of 190,000.
MAX_LINE_CHARS = 2000


def verdict(case: Case, folder: Path, exit_code: int, stdout: str, stderr: str, exception: str = "") -> str:
    """``ok`` or the class of failure: ``traceback``, ``huge-line``, ``multi-line``, ``unnamed``, ``unplaced``,
    ``accepted-bad``, ``wrong-result``, ``half-written`` or ``bad-status``."""
    if exception or "Traceback (most recent call last)" in stderr + stdout:
        return "traceback"
    if any(len(line) > MAX_LINE_CHARS for line in (stdout + "\n" + stderr).splitlines()):
        return "huge-line"
    leftovers = [p for p in folder.rglob(".*") if ".part" in p.name]
    if leftovers:
        return "half-written"
    if exit_code == 0:
        return _check_success(case, folder, stdout)
    if exit_code == 1 and case.command == "fortify":
        # Not sealed within the budget: its one line, and its outputs (the placement reached) written.
        lines = stdout.splitlines()
        return "ok" if len(lines) == 1 and ": not sealed: " in lines[0] and not case.bad else "bad-status"
    if case.clean and any((folder / output).exists() for output in case.outputs):
        return "half-written"
    if exit_code == 1 and case.command == "regress":
        return "ok" if "DIFFERS" in stdout or "no references" in stdout else "bad-status"
    if exit_code == 1 and case.command in ("check", "check-baseline"):
        # A damaged patrol may break a rule: one "broken:" line per rule, nothing else.
        lines = stdout.splitlines()
        return "ok" if lines and all(": broken: " in line for line in lines) else "bad-status"
    if exit_code != 2:
        return "bad-status"
    lines = stderr.splitlines()
    if case.command in ("regress", "bench"):
        # Progress lines (the run folder's, the episode count) are not part of the error.
        lines = [line for line in lines if not (line.startswith(str(folder)) or _PROGRESS.match(line))]
    # A long stage's progress line ("guardsim: bounds: view table (2s)") may come first on a busy machine.
    lines = [line for line in lines if not _STAGE.match(line)]
    if case.kind in NEWER_KINDS:
        # Progress and warning lines (the design commands' steps, a camera's rounded swing) come first.
        lines = [line for line in lines if line.startswith("guardsim: error:") or not line.startswith("guardsim: ")]
    if len(lines) != 1:
        return "multi-line"
    named = case.named.replace("\n", "\\n")
    if not (named in lines[0] or case.kind == "option"):
        return "unnamed"
    # validate lists each problem, with its place, on stdout; the error line counts them.
    said = lines[0] + (stdout if case.command.startswith("validate") else "")
    return "unplaced" if case.place and case.place not in said else "ok"


_PROGRESS = re.compile(r"\d+ of \d+ episodes|guardsim regress: ")
_STAGE = re.compile(r"guardsim: (?!error:|warning:)[a-z-]+: .* \(\d+(m\d+)?s\)$")


def run_in_process(case: Case, folder: Path) -> str:
    """Write the case's files into ``folder``, run its command through click's test runner, and return
    the :func:`verdict`."""
    from click.testing import CliRunner
    from numba.core.errors import NumbaIRAssumptionWarning

    from guardsim.cli import main

    if case.command == "watch":
        from tests.fuzz_newer import run_watch

        return run_watch(case, folder)
    case.write(folder)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            # As every guardsim process does (guardsim.kernels.compiler): numba's own pedantic IR check,
            # raised only while a kernel compiles (a cold cache, a race with compiling ahead), is not the
            # command's to print.
            warnings.filterwarnings("ignore", category=NumbaIRAssumptionWarning)
            result = CliRunner().invoke(main, case.argv(folder), catch_exceptions=True)
    except Exception:  # the runner itself failing is a finding too
        return "traceback"
    if caught:
        return "warning"  # a real process prints it on stderr, around the one line
    exception = ""
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        exception = "".join(traceback.format_exception(result.exception))
    return verdict(case, folder, result.exit_code, result.stdout, result.stderr, exception)


def _check_success(case: Case, folder: Path, stdout: str) -> str:
    if case.bad:
        return "accepted-bad"
    if case.kind == "level" and case.command.startswith("validate"):
        content = case.files[case.named]
        if content in (FIFO, DEVICE) or not _level_is_acceptable(content):
            return "accepted-bad"
    for output in case.outputs:
        path = folder / output
        if not path.exists():
            continue
        if not stat.S_ISREG(path.stat().st_mode):
            return "wrong-result"
        data = path.read_bytes()
        if output.endswith(".json"):
            try:
                parsed = json.loads(data)
            except ValueError:
                return "wrong-result"
            if output == "out.json" and case.command == "play" and len(parsed["path"]) != parsed["steps"] + 1:
                return "wrong-result"
        elif output.endswith(".csv"):
            rows = data.decode().splitlines()[1:]
            keys = [tuple(row.split(",")[1:6]) for row in rows]
            if len(rows) != 3 or len(set(keys)) != 3:
                return "wrong-result"
        elif output.endswith(".png") and not data.startswith(b"\x89PNG"):
            return "wrong-result"
    return "ok"
