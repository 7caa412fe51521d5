"""Regression references: re-play a level from fixed seeds and compare it with what was stored.

A level's references live in one folder, ``RENDERS/<level file stem>/``:

- ``manifest.json``: format version, frame size, tolerance, and the episodes re-played (name, seed and,
  for a batch episode, its number);
- ``level.json``: the level as it was when the references were written (to draw the reference side of a
  diff at any tick, and to say "level edited");
- ``<episode>.trace.json``: each episode's trace (:meth:`guardsim.trace.Trace.to_json`), compared as text;
- ``<episode>-<percent>.png``: key frames at 0, 25, 50, 75 and 100 % of the episode's steps, compared as
  decoded images within a :class:`Tolerance`.

``docs/regression.md`` describes the command built on this, ``guardsim regress``.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from guardsim.errors import OutputError, RegressionError
from guardsim.level import Level, level_to_data, parse_level
from guardsim.output import atomic_path, write_text_atomic
from guardsim.planners import make_planner
from guardsim.render import render_frame
from guardsim.simulation import Scene, choose_start, run_batch_episode, run_episode
from guardsim.trace import Trace

__all__ = [
    "KEY_PERCENTS",
    "REFERENCE_FRAME_SIZE",
    "EpisodeResult",
    "FrameDifference",
    "LevelResult",
    "ReplaySpec",
    "Tolerance",
    "compare_frames",
    "default_specs",
    "regress_level",
    "replay_trace",
]

#: Version of the manifest layout.
FORMAT = 1
#: Longest side of a stored key frame in pixels (4 pixels per cell on the shipped 60 x 60 grids).
REFERENCE_FRAME_SIZE = 240
#: Key frames, as percentages of an episode's steps.
KEY_PERCENTS = (0, 25, 50, 75, 100)
MANIFEST = "manifest.json"
LEVEL_SNAPSHOT = "level.json"
_EPISODE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}\Z")
_HIGHLIGHT = (255, 0, 255)
_FIELD_WORDS = {"goal": "reachable cells", "traversable": "traversable cells", "shape": "grid shape"}


@dataclass(frozen=True)
class Tolerance:
    """How far a decoded key frame may drift from its reference and still match.

    The defaults absorb anti-aliasing changes in the percentage text between Pillow or FreeType
    versions (the text's edge pixels are about 0.5 % of a 240-pixel frame). What the guard did is
    compared exactly through the trace, so the frames need not catch a one-cell change (16 pixels).
    """

    channel: int = 32
    """A pixel differs when one of its channels differs by more than this (0-255)."""
    fraction: float = 0.005
    """A frame differs when more than this fraction of its pixels differ."""


@dataclass(frozen=True)
class ReplaySpec:
    """One reference episode: how to re-play it."""

    name: str
    """Names its files, e.g. ``level-start`` or ``seed0-episode0``."""
    seed: int = 0
    episode: int | None = None
    """Batch episode number (start and heading drawn as ``guardsim bench`` does), or ``None`` for the
    level's own start and heading, as ``guardsim play LEVEL --seed SEED`` runs it."""

    @property
    def play_options(self) -> str:
        """The ``guardsim play`` options that re-run this episode alone."""
        return f"--seed {self.seed}" + ("" if self.episode is None else f" --episode {self.episode}")


class FrameDifference(NamedTuple):
    """A key frame outside the tolerance."""

    percent: int
    """Which key frame: a percentage of the episode's steps."""
    reference_tick: int
    current_tick: int
    differing: float
    """Fraction of pixels differing by more than the channel tolerance (1.0 when the sizes differ)."""
    max_channel: int
    """Largest difference of one channel over the frame (0-255)."""


@dataclass(frozen=True)
class EpisodeResult:
    """One re-played episode against its reference."""

    spec: ReplaySpec
    reference_steps: int
    current_steps: int
    trace_changes: tuple[str, ...] = ()
    """What differs in the trace, e.g. ``path from tick 131``; empty when its text is identical."""
    frames: tuple[FrameDifference, ...] = ()
    """Key frames outside the tolerance."""

    @property
    def differs(self) -> bool:
        """Whether the trace or a key frame differs."""
        return bool(self.trace_changes or self.frames)

    def describe(self) -> str:
        """One clause for the level's summary line."""
        if not self.differs:
            return f"{self.spec.name} {self.current_steps} steps"
        parts = list(self.trace_changes)
        if self.frames:
            parts.append("frames " + " ".join(f"{frame.percent}%" for frame in self.frames))
        return f"{self.spec.name}: {', '.join(parts)}, steps {self.reference_steps} -> {self.current_steps}"


@dataclass(frozen=True)
class LevelResult:
    """The outcome of ``guardsim regress`` for one level."""

    source: str
    """The level file."""
    folder: Path
    """Its reference folder."""
    status: str
    """``ok``, ``differs``, ``missing`` (no references yet) or ``written`` (``--update``)."""
    episodes: tuple[EpisodeResult, ...] = ()
    level_edited: bool = False
    """Whether the level differs from the snapshot stored with the references."""
    diff_image: Path | None = None

    def line(self) -> str:
        """The one-line summary printed for the level."""
        episodes = "; ".join(episode.describe() for episode in self.episodes)
        if self.status == "missing":
            return f"{self.source}: no references in {self.folder} (write them with --update)"
        if self.status == "written":
            steps = ", ".join(f"{e.spec.name} {e.current_steps} steps" for e in self.episodes)
            return f"{self.source}: references written to {self.folder} ({steps})"
        if self.status == "ok":
            edited = "; level edited, same results" if self.level_edited else ""
            return f"{self.source}: ok ({episodes}{edited})"
        edited = "level edited; " if self.level_edited else ""
        return f"{self.source}: DIFFERS: {edited}{episodes}; diff {self.diff_image}"


@dataclass(frozen=True)
class _Manifest:
    frame_size: int
    tolerance: Tolerance
    specs: tuple[ReplaySpec, ...]


def default_specs(level: Level) -> tuple[ReplaySpec, ...]:
    """The episodes stored for a new level: its own start (if it has one) and batch episode 0 of seed 0."""
    own_start = (ReplaySpec("level-start", seed=0),) if level.guard.start is not None else ()
    return (*own_start, ReplaySpec("seed0-episode0", seed=0, episode=0))


def replay_trace(scene: Scene, spec: ReplaySpec) -> Trace:
    """Run the episode ``spec`` names, exactly as ``guardsim play LEVEL`` with its play options does."""
    if spec.episode is not None:
        return run_batch_episode(scene, seed=spec.seed, episode=spec.episode)
    guard = scene.level.guard
    cell, heading = choose_start(scene, rng=np.random.default_rng(spec.seed), point=guard.start, heading=guard.heading)
    return run_episode(scene, make_planner("ripplefront"), cell, heading, seed=spec.seed)


def key_tick(steps: int, percent: int) -> int:
    """The tick of a key frame: ``percent`` of the way through ``steps``, rounded half up."""
    return math.floor(steps * percent / 100 + 0.5)


def compare_frames(reference: np.ndarray, current: np.ndarray, tolerance: Tolerance) -> tuple[float, int]:
    """The fraction of pixels differing by more than ``tolerance.channel``, and the largest difference.

    Examples
    --------
    >>> a = np.zeros((10, 10, 3), dtype=np.uint8)
    >>> b = a.copy()
    >>> b[0, :4] = (40, 0, 0)
    >>> b[1, 0] = (10, 0, 0)
    >>> compare_frames(a, b, Tolerance(channel=32))
    (0.04, 40)
    """
    if reference.shape != current.shape:
        return 1.0, 255
    delta = _channel_delta(reference, current)
    return float((delta > tolerance.channel).mean()), int(delta.max(initial=0))


def _channel_delta(reference: np.ndarray, current: np.ndarray) -> np.ndarray:
    difference = np.abs(reference.astype(np.int16) - current.astype(np.int16))
    return difference.max(axis=2) if difference.ndim == 3 else difference


def regress_level(
    level: Level,
    renders: Path,
    *,
    update: bool = False,
    diff_dir: Path | None = None,
) -> LevelResult:
    """Re-play ``level`` and compare it with its references in ``renders/<file stem>/``, or rewrite them.

    Parameters
    ----------
    level
        The level; its ``source`` file stem names the reference folder.
    renders
        The folder holding one reference folder per level.
    update
        Rewrite the references (each file atomically, the manifest last) instead of comparing.
    diff_dir
        Where to write the diff image of a level that differs, as ``<stem>.diff.png``; by default it is
        ``diff.png`` in the level's reference folder.

    Raises
    ------
    RegressionError
        If a stored reference cannot be read.
    """
    stem = Path(level.source).stem
    folder = renders / stem
    manifest = _read_manifest(folder / MANIFEST)
    if manifest is None and not update:
        return LevelResult(level.source, folder, "missing")
    if manifest is None:
        manifest = _Manifest(REFERENCE_FRAME_SIZE, Tolerance(), default_specs(level))
    scene = Scene.from_level(level)
    traces = [replay_trace(scene, spec) for spec in manifest.specs]
    default_diff = folder / "diff.png"
    if update:
        _write_references(folder, level, manifest, traces)
        default_diff.unlink(missing_ok=True)
        steps = tuple(EpisodeResult(spec, t.steps, t.steps) for spec, t in zip(manifest.specs, traces, strict=True))
        return LevelResult(level.source, folder, "written", steps)
    snapshot = parse_level(_read_json(folder / LEVEL_SNAPSHOT), source=str(folder / LEVEL_SNAPSHOT))
    results: list[EpisodeResult] = []
    rows: list[tuple[str, np.ndarray, np.ndarray]] = []
    for spec, trace in zip(manifest.specs, traces, strict=True):
        result, episode_rows = _compare_episode(folder, level, snapshot, spec, trace, manifest)
        results.append(result)
        rows += episode_rows
    edited = level_to_data(level) != level_to_data(snapshot)
    if not any(result.differs for result in results):
        default_diff.unlink(missing_ok=True)
        return LevelResult(level.source, folder, "ok", tuple(results), edited)
    diff_path = default_diff if diff_dir is None else diff_dir / f"{stem}.diff.png"
    _write_png(diff_path, _diff_image(rows, manifest.tolerance))
    return LevelResult(level.source, folder, "differs", tuple(results), edited, diff_path)


def _compare_episode(
    folder: Path, level: Level, snapshot: Level, spec: ReplaySpec, trace: Trace, manifest: _Manifest
) -> tuple[EpisodeResult, list[tuple[str, np.ndarray, np.ndarray]]]:
    trace_path = folder / f"{spec.name}.trace.json"
    reference_text = _read_text(trace_path)
    try:
        reference = Trace.from_data(json.loads(reference_text))
    except (ValueError, KeyError, TypeError, IndexError) as error:
        raise RegressionError(f"{trace_path}: not a trace ({type(error).__name__}: {error})") from None
    size = manifest.frame_size
    rows = []
    changes: tuple[str, ...] = ()
    if trace.to_json() != reference_text:
        changes, divergence = _trace_changes(reference, trace)
        if divergence is not None:
            rows.append(
                (
                    f"{spec.name}, tick {divergence}: first difference",
                    render_frame(snapshot, reference, min(divergence, reference.steps), size=size),
                    render_frame(level, trace, min(divergence, trace.steps), size=size),
                )
            )
    frames = []
    last: tuple[str, np.ndarray, np.ndarray] | None = None
    for percent in KEY_PERCENTS:
        stored = _read_png(folder / f"{spec.name}-{percent:03d}.png")
        before, after = key_tick(reference.steps, percent), key_tick(trace.steps, percent)
        frame = render_frame(level, trace, after, size=size)
        differing, channel = compare_frames(stored, frame, manifest.tolerance)
        last = (
            f"{spec.name}, {percent}%: tick {before} | tick {after} ({differing:.2%} of pixels differ)",
            stored,
            frame,
        )
        if differing > manifest.tolerance.fraction:
            frames.append(FrameDifference(percent, before, after, differing, channel))
            rows.append(last)
    if changes and not rows and last is not None:
        rows.append(last)
    return EpisodeResult(spec, reference.steps, trace.steps, changes, tuple(frames)), rows


def _first_difference(old: Sequence[object], new: Sequence[object]) -> int | None:
    for index, (a, b) in enumerate(zip(old, new)):
        if a != b:
            return index
    return None if len(old) == len(new) else min(len(old), len(new))


def _trace_changes(reference: Trace, current: Trace) -> tuple[tuple[str, ...], int | None]:
    """What differs between two traces, in words, and the first tick where the episodes part."""
    moved = _first_difference(list(zip(reference.path, reference.headings)), list(zip(current.path, current.headings)))
    coverage = _first_difference(reference.unseen_percent, current.unseen_percent)
    changes = []
    if moved is not None:
        changes.append(f"path from tick {moved}")
    elif coverage is not None:
        changes.append(f"coverage from tick {coverage}")
    old, new = reference.to_data(), current.to_data()
    if old["outcome"] != new["outcome"]:
        changes.append(f"outcome {old['outcome']} -> {new['outcome']}")
    # Per-tick fields are summed up by the first difference above; "goal" by "reachable" when it changed.
    said = {"path", "headings", "unseen_percent", "first_seen", "steps", "covered", "start", "outcome"}
    if old["reachable"] != new["reachable"]:
        said.add("goal")
    for key in old:
        if key not in said and old[key] != new[key]:
            plain = isinstance(old[key], (int, float, str))
            changes.append(f"{key} {old[key]} -> {new[key]}" if plain else _FIELD_WORDS.get(key, key))
    return tuple(changes or ["trace text"]), moved if moved is not None else coverage


def _write_references(folder: Path, level: Level, manifest: _Manifest, traces: list[Trace]) -> None:
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"{folder}: cannot create: {error.strerror or error}") from None
    write_text_atomic(folder / LEVEL_SNAPSHOT, json.dumps(level_to_data(level), indent=2) + "\n")
    episodes = []
    for spec, trace in zip(manifest.specs, traces, strict=True):
        write_text_atomic(folder / f"{spec.name}.trace.json", trace.to_json())
        ticks = [key_tick(trace.steps, percent) for percent in KEY_PERCENTS]
        for percent, tick in zip(KEY_PERCENTS, ticks, strict=True):
            frame = render_frame(level, trace, tick, size=manifest.frame_size)
            _write_png(folder / f"{spec.name}-{percent:03d}.png", frame)
        episodes.append(
            {
                "name": spec.name,
                "seed": spec.seed,
                "episode": spec.episode,
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
            for path in [stale, *(folder / f"{name}-{percent:03d}.png" for percent in KEY_PERCENTS)]:
                path.unlink(missing_ok=True)


def _read_manifest(path: Path) -> _Manifest | None:
    """The manifest at ``path``, ``None`` if there is none, or a RegressionError saying what is wrong."""
    if not path.exists():
        return None
    data = _read_json(path)

    def bad(message: str) -> RegressionError:
        return RegressionError(f"{path}: {message}")

    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise bad(f"not a guardsim regress manifest of format {FORMAT}")
    frame_size = data.get("frame_size", REFERENCE_FRAME_SIZE)
    if not _is_count(frame_size) or not 16 <= frame_size <= 4096:
        raise bad(f"frame_size must be a whole number of pixels from 16 to 4096, not {frame_size!r}")
    tolerance = data.get("tolerance", {})
    default = Tolerance()
    channel = tolerance.get("channel", default.channel) if isinstance(tolerance, dict) else None
    fraction = tolerance.get("fraction", default.fraction) if isinstance(tolerance, dict) else None
    if not (_is_count(channel) and channel <= 255 and _is_number(fraction) and 0 <= fraction <= 1):
        raise bad('tolerance must be {"channel": 0 to 255, "fraction": 0 to 1}')
    episodes = data.get("episodes")
    if not isinstance(episodes, list) or not episodes:
        raise bad("episodes must be a non-empty list")
    specs = []
    for index, episode in enumerate(episodes):
        name = episode.get("name") if isinstance(episode, dict) else None
        seed = episode.get("seed", 0) if isinstance(episode, dict) else None
        number = episode.get("episode") if isinstance(episode, dict) else None
        if not isinstance(name, str) or not _EPISODE_NAME.match(name):
            raise bad(f"episodes[{index}]: name must be letters, digits, - and _ (at most 64), not {name!r}")
        if not _is_count(seed) or not (number is None or _is_count(number)):
            raise bad(f"episodes[{index}]: seed and episode must be whole numbers from 0")
        specs.append(ReplaySpec(name, seed, number))
    if len({spec.name for spec in specs}) != len(specs):
        raise bad("two episodes have the same name")
    return _Manifest(frame_size, Tolerance(channel, float(fraction)), tuple(specs))


def _is_count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _read_text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise RegressionError(f"{path}: missing (rewrite the references with --update)") from None
    except (OSError, UnicodeDecodeError) as error:
        raise RegressionError(f"{path}: cannot read: {error}") from None


def _read_json(path: Path) -> Any:
    try:
        return json.loads(_read_text(path))
    except json.JSONDecodeError as error:
        raise RegressionError(f"{path}: not valid JSON: {error.msg} at line {error.lineno}") from None


def _read_png(path: Path) -> np.ndarray:
    from PIL import Image

    try:
        with Image.open(path, formats=["PNG"]) as image:
            return np.asarray(image.convert("RGB"))
    except FileNotFoundError:
        raise RegressionError(f"{path}: missing (rewrite the references with --update)") from None
    except (OSError, ValueError) as error:
        raise RegressionError(f"{path}: not a PNG image ({type(error).__name__})") from None


def _write_png(path: Path, image: np.ndarray) -> None:
    import imageio.v3 as iio

    with atomic_path(path) as temporary:
        iio.imwrite(temporary, image, extension=".png")


def _diff_image(rows: list[tuple[str, np.ndarray, np.ndarray]], tolerance: Tolerance) -> np.ndarray:
    """Rows of reference | current | difference (the reference greyed, differing pixels magenta)."""
    from PIL import Image, ImageDraw, ImageFont

    font = ImageFont.load_default()
    gap, label_height = 4, 14
    strips = [("reference | current | pixels that differ (magenta)", None)]
    for label, reference, current in rows:
        height = max(reference.shape[0], current.shape[0])
        width = max(reference.shape[1], current.shape[1])
        old, new = _padded(reference, height, width), _padded(current, height, width)
        grey = (old.mean(axis=2, keepdims=True) * 0.35 + 160).astype(np.uint8).repeat(3, axis=2)
        grey[_channel_delta(old, new) > tolerance.channel] = _HIGHLIGHT
        spacer = np.full((height, gap, 3), 255, dtype=np.uint8)
        strips.append((label, np.concatenate([old, spacer, new, spacer, grey], axis=1)))
    width = max(strip.shape[1] for _, strip in strips if strip is not None)
    pieces = []
    for label, strip in strips:
        caption = Image.new("RGB", (width, label_height), (255, 255, 255))
        ImageDraw.Draw(caption).text((2, 1), label, fill=(0, 0, 0), font=font)
        pieces.append(np.asarray(caption))
        if strip is not None:
            pieces.append(_padded(strip, strip.shape[0] + gap, width))
    return np.concatenate(pieces, axis=0)


def _padded(image: np.ndarray, height: int, width: int) -> np.ndarray:
    """``image`` as RGB on a white canvas of ``height`` x ``width``."""
    rgb = image[..., :3] if image.ndim == 3 else np.repeat(image[..., None], 3, axis=2)
    canvas = np.full((height, width, 3), 255, dtype=np.uint8)
    canvas[: rgb.shape[0], : rgb.shape[1]] = rgb
    return canvas
