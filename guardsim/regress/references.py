"""A level's stored regression references: the manifest, the level snapshot, traces and key frames.

A level's references live in one folder, ``RENDERS/<level file stem>/``:

- ``manifest.json``: format version, frame size, tolerance, and the episodes re-played (name, seed and,
  for a batch episode, its number);
- ``level.json``: the level as it was when the references were written (to draw the reference side of a
  diff at any tick, and to say "level edited");
- ``<episode>.trace.json``: each episode's trace (:meth:`guardsim.trace.Trace.to_json`), compared as text;
- ``<episode>-<percent>.png``: key frames at 0, 25, 50, 75 and 100 % of the episode's steps, compared as
  decoded images within a :class:`~guardsim.regress.frames.Tolerance`.
"""

from __future__ import annotations

import io
import json
import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from guardsim.errors import OutputError, RegressionError
from guardsim.files.output import atomic_path, write_text_atomic
from guardsim.files.reading import (
    captured_warnings,
    display_path,
    parse_json,
    read_limited_bytes,
    read_text_file,
)
from guardsim.files.schema import check
from guardsim.level import DEFAULT_MAX_FILE_BYTES, Level, level_json_text
from guardsim.regress.frames import Tolerance
from guardsim.render import render_frame
from guardsim.trace import Trace

__all__ = [
    "DEFAULT_MAX_FRAME_SIZE",
    "KEY_PERCENTS",
    "LEVEL_SNAPSHOT",
    "MANIFEST",
    "REFERENCE_FRAME_SIZE",
    "Manifest",
    "MotionOverride",
    "ReplaySpec",
    "default_specs",
    "key_frame_path",
    "key_tick",
    "read_json",
    "read_manifest",
    "read_png",
    "read_text",
    "trace_path",
    "write_png",
    "write_references",
]

#: Version of the manifest layout.
FORMAT = 1
#: Longest side of a stored key frame in pixels (4 pixels per cell on the shipped 60 x 60 grids).
REFERENCE_FRAME_SIZE = 240
#: Largest frame_size a manifest may ask for unless the caller raises it: a 1024-pixel frame draws in
#: about a second; 4096 took a minute and 5 GB.
DEFAULT_MAX_FRAME_SIZE = 1024
#: How much larger than frame_size a stored frame may be (the renderer adds captions and margins).
FRAME_SLACK = 4
#: The continuous-motion parameters an episode may set, as in a level's ``guard`` object.
SPEED_KEYS = ("move_speed", "turn_speed", "tick_hz")
#: Key frames, as percentages of an episode's steps.
KEY_PERCENTS = (0, 25, 50, 75, 100)
MANIFEST = "manifest.json"
LEVEL_SNAPSHOT = "level.json"


@dataclass(frozen=True)
class ReplaySpec:
    """One reference episode: how to re-play it."""

    name: str
    """Names its files, e.g. ``level-start`` or ``seed0-episode0``."""
    seed: int = 0
    episode: int | None = None
    """Batch episode number (start and heading drawn as ``guardsim bench`` does), or ``None`` for the
    level's own start and heading, as ``guardsim play LEVEL --seed SEED`` runs it."""
    motion: str = "grid"
    """``"grid"`` (a step per tick) or ``"continuous"`` (the physics body at game speeds, docs/motion.md)."""
    move_speed: float | None = None
    """Continuous motion: walking speed; ``None`` for the level guard's, else the default."""
    turn_speed: float | None = None
    """Continuous motion: turning speed; ``None`` for the level guard's, else the default."""
    tick_hz: float | None = None
    """Continuous motion: physics rate; ``None`` for the level guard's, else the default."""

    @property
    def speeds(self) -> dict[str, float]:
        """The continuous-motion parameters this episode sets (the others come from the level)."""
        return {name: value for name in SPEED_KEYS if (value := getattr(self, name)) is not None}

    @property
    def play_options(self) -> str:
        """The ``guardsim play`` options that re-run this episode alone."""
        options = f"--seed {self.seed}" + ("" if self.episode is None else f" --episode {self.episode}")
        if self.motion != "grid":
            options += f" --motion {self.motion}"
            options += "".join(f" --{name.replace('_', '-')} {value:g}" for name, value in self.speeds.items())
        return options

    def manifest_entry(self) -> dict[str, Any]:
        """What the manifest stores of this episode (grid episodes keep the format-1 keys only)."""
        entry: dict[str, Any] = {"name": self.name, "seed": self.seed, "episode": self.episode}
        if self.motion != "grid":
            entry.update(motion=self.motion, **self.speeds)
        return entry


@dataclass(frozen=True)
class MotionOverride:
    """``guardsim regress --motion M [--move-speed ...]``: re-play every episode in motion ``motion``
    (``None``: each episode's own), with the speeds given over the episode's."""

    motion: str | None = None
    move_speed: float | None = None
    turn_speed: float | None = None
    tick_hz: float | None = None

    def applied(self, spec: ReplaySpec) -> ReplaySpec:
        """``spec`` re-played this way; speeds apply to continuous episodes only (a grid step has none)."""
        motion = self.motion or spec.motion
        if motion == "grid":
            return replace(spec, motion="grid", move_speed=None, turn_speed=None, tick_hz=None)
        given = {name: value for name in SPEED_KEYS if (value := getattr(self, name)) is not None}
        return replace(spec, motion=motion, **given)


@dataclass(frozen=True)
class Manifest:
    """What ``manifest.json`` says: how the key frames were drawn and compared, and the episodes."""

    frame_size: int
    """Longest side of a key frame in pixels."""
    tolerance: Tolerance
    specs: tuple[ReplaySpec, ...]
    """The episodes re-played, in the manifest's order."""


def default_specs(level: Level) -> tuple[ReplaySpec, ...]:
    """The episodes stored for a new level: its own start (if it has one) and batch episode 0 of seed 0."""
    own_start = (ReplaySpec("level-start", seed=0),) if level.guard.start is not None else ()
    return (*own_start, ReplaySpec("seed0-episode0", seed=0, episode=0))


def key_tick(steps: int, percent: int) -> int:
    """The tick of a key frame: ``percent`` of the way through ``steps``, rounded half up."""
    return math.floor(steps * percent / 100 + 0.5)


def trace_path(folder: Path, name: str) -> Path:
    """Where the reference trace of episode ``name`` is stored."""
    return folder / f"{name}.trace.json"


def key_frame_path(folder: Path, name: str, percent: int) -> Path:
    """Where the reference key frame at ``percent`` of episode ``name`` is stored."""
    return folder / f"{name}-{percent:03d}.png"


def write_references(folder: Path, level: Level, manifest: Manifest, traces: list[Trace]) -> None:
    """Write the level snapshot, each episode's trace and key frames, then the manifest, into ``folder``.

    Each file is written atomically and the manifest last; files of episodes the manifest no longer
    names are removed.

    Raises
    ------
    OutputError
        If ``folder`` cannot be created.
    """
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"{folder}: cannot create: {error.strerror or error}") from None
    write_text_atomic(folder / LEVEL_SNAPSHOT, level_json_text(level))
    episodes = []
    for spec, trace in zip(manifest.specs, traces, strict=True):
        write_text_atomic(trace_path(folder, spec.name), trace.to_json())
        ticks = [key_tick(trace.steps, percent) for percent in KEY_PERCENTS]
        for percent, tick in zip(KEY_PERCENTS, ticks, strict=True):
            frame = render_frame(level, trace, tick, size=manifest.frame_size)
            write_png(key_frame_path(folder, spec.name, percent), frame)
        episodes.append(
            {
                **spec.manifest_entry(),
                "play_options": spec.play_options,
                "steps": trace.steps,
                "outcome": trace.outcome,
                "key_ticks": ticks,
            }
        )
    data = {
        "format": FORMAT,
        "level": level.name,
        "frame_size": manifest.frame_size,
        "tolerance": {"channel": manifest.tolerance.channel, "fraction": manifest.tolerance.fraction},
        "episodes": episodes,
    }
    # The manifest goes last: a run stopped half-way leaves the old manifest naming the episodes.
    write_text_atomic(folder / MANIFEST, json.dumps(data, indent=2) + "\n")
    names = {spec.name for spec in manifest.specs}
    for stale in folder.glob("*.trace.json"):
        name = stale.name.removesuffix(".trace.json")
        if name not in names:
            for path in [stale, *(key_frame_path(folder, name, percent) for percent in KEY_PERCENTS)]:
                path.unlink(missing_ok=True)


def read_manifest(
    path: Path, *, max_frame_size: int = DEFAULT_MAX_FRAME_SIZE, max_file_bytes: int = DEFAULT_MAX_FILE_BYTES
) -> Manifest | None:
    """The manifest at ``path``, ``None`` if there is none, or a RegressionError saying what is wrong.

    The manifest is checked against ``manifest.schema.json``, then: a ``frame_size`` over
    ``max_frame_size`` is refused here, before any frame is drawn (a frame's cost grows with its area:
    4096 pixels a side took a minute and 5 GB); episode names are unique; speeds belong to continuous
    episodes.
    """
    if not path.exists() and not path.is_symlink():
        return None
    data = read_json(path, max_file_bytes=max_file_bytes)
    source = display_path(path)
    check(data, "manifest", source=source, error=RegressionError)
    frame_size = data.get("frame_size", REFERENCE_FRAME_SIZE)
    if frame_size > max_frame_size:
        raise RegressionError(
            f"{source}: frame_size {frame_size} is over the limit of {max_frame_size} pixels (max_frame_size)"
        )
    specs = tuple(_spec(episode, f"{source}: episodes[{index}]") for index, episode in enumerate(data["episodes"]))
    if len({spec.name for spec in specs}) != len(specs):
        raise RegressionError(f"{source}: two episodes have the same name")
    tolerance = {**vars(Tolerance()), **data.get("tolerance", {})}
    return Manifest(frame_size, Tolerance(tolerance["channel"], float(tolerance["fraction"])), specs)


def _spec(episode: dict[str, Any], where: str) -> ReplaySpec:
    """A manifest episode the schema has checked; its speeds need ``"motion": "continuous"`` (an entry
    without ``motion`` is a grid episode, as manifests written before continuous motion say)."""
    motion = episode.get("motion", "grid")
    speeds = [episode.get(key) for key in SPEED_KEYS]
    for key, value in zip(SPEED_KEYS, speeds):
        if value is not None and motion == "grid":
            raise RegressionError(f'{where}: {key} is a continuous-motion parameter; add "motion": "continuous"')
    floats = [None if value is None else float(value) for value in speeds]
    return ReplaySpec(episode["name"], episode.get("seed", 0), episode.get("episode"), motion, *floats)


def read_text(path: Path, *, max_file_bytes: int = DEFAULT_MAX_FILE_BYTES, listed_in: Path | None = None) -> str:
    """The text of a stored reference, or a RegressionError saying it is missing or unreadable.

    ``listed_in`` is the manifest that names the file, for the message when it is missing.
    """
    if not path.exists() and not path.is_symlink():
        raise RegressionError(_missing(path, listed_in))
    return read_text_file(path, max_file_bytes=max_file_bytes, kind="reference file", error=RegressionError)


def read_json(path: Path, *, max_file_bytes: int = DEFAULT_MAX_FILE_BYTES) -> Any:
    """A stored reference parsed as JSON, or a RegressionError saying where it is not valid."""
    text = read_text(path, max_file_bytes=max_file_bytes)
    return parse_json(text, source=display_path(path), error=RegressionError)


def _missing(path: Path, listed_in: Path | None) -> str:
    listed = f" (listed in {display_path(listed_in)})" if listed_in is not None else ""
    return f"{display_path(path)}: missing{listed}: the references need rewriting (update)"


def read_png(
    path: Path,
    *,
    max_size: int = DEFAULT_MAX_FRAME_SIZE,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    listed_in: Path | None = None,
) -> np.ndarray:
    """A stored key frame decoded as RGB ``uint8``, or a RegressionError if it is missing, not a PNG, or
    declares a side longer than :data:`FRAME_SLACK` times ``max_size`` pixels (checked from the header,
    before decoding: a 20,000 x 20,000 PNG of a few kilobytes would decode to 1.2 GB)."""
    import struct
    import zlib

    from PIL import Image

    source = display_path(path)
    if not path.exists() and not path.is_symlink():
        raise RegressionError(_missing(path, listed_in))
    data = read_limited_bytes(path, max_file_bytes=max_file_bytes, kind="reference file", error=RegressionError)
    if data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR" and len(data) >= 24:
        # The size from the header, before Pillow sees the file (it refuses bombs only past 178 million pixels).
        width, height = struct.unpack(">II", data[16:24])
        if max(width, height) > FRAME_SLACK * max_size:
            raise RegressionError(
                f"{source}: a key frame of {width} x {height} pixels, larger than any frame drawn at "
                f"frame_size {max_size}"
            )
    try:
        with captured_warnings(), Image.open(io.BytesIO(data), formats=["PNG"]) as image:
            width, height = image.size
            if max(width, height) > FRAME_SLACK * max_size:
                raise RegressionError(
                    f"{source}: a key frame of {width} x {height} pixels, larger than any frame drawn at "
                    f"frame_size {max_size}"
                )
            return np.asarray(image.convert("RGB"))
    except (
        OSError,
        ValueError,
        SyntaxError,
        EOFError,
        struct.error,
        zlib.error,
        Image.DecompressionBombError,
    ) as error:
        raise RegressionError(f"{source}: not a PNG image ({type(error).__name__})") from None


def write_png(path: Path, image: np.ndarray) -> None:
    """Write ``image`` to ``path`` as a PNG, atomically."""
    import imageio.v3 as iio

    with atomic_path(path) as temporary:
        iio.imwrite(temporary, image, extension=".png")
