"""Re-playing a level's reference episodes and comparing them with what was stored.

``docs/regression.md`` describes the command built on this, ``guardsim regress``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import NamedTuple

import numpy as np

from guardsim.errors import RegressionError
from guardsim.files.reading import display_path, excerpt, parse_json
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, Level, level_to_data, parse_level
from guardsim.motion import GuardMotion, run_episode
from guardsim.regress.frames import DiffRow, Tolerance, compare_frames, diff_image
from guardsim.regress.references import (
    DEFAULT_MAX_FRAME_SIZE,
    KEY_PERCENTS,
    LEVEL_SNAPSHOT,
    MANIFEST,
    REFERENCE_FRAME_SIZE,
    Manifest,
    MotionOverride,
    ReplaySpec,
    default_specs,
    key_frame_path,
    key_tick,
    read_json,
    read_manifest,
    read_png,
    read_text,
    trace_path,
    write_png,
    write_references,
)
from guardsim.regress.stored_trace import trace_from_stored
from guardsim.render import render_frame
from guardsim.scene import Scene
from guardsim.simulation import Simulation
from guardsim.trace import Trace

__all__ = ["EpisodeResult", "FrameDifference", "LevelResult", "regress_level", "replay_trace"]

_FIELD_WORDS = {
    "goal": "reachable cells",
    "traversable": "traversable cells",
    "shape": "grid shape",
    "measures": "motion measures",
}


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


def replay_trace(scene: Scene, spec: ReplaySpec) -> Trace:
    """Run the episode ``spec`` names, exactly as ``guardsim play LEVEL`` with its play options does."""
    if spec.motion == "continuous":
        motion = GuardMotion.of_guard(scene.level.guard, **spec.speeds)
        # play passes RippleFront's sweeps per tick (default 1) on, and the trace records it.
        return run_episode(
            scene, "ripplefront", seed=spec.seed, episode=spec.episode, motion=motion or "continuous", sweeps_per_tick=1
        )
    simulation = Simulation(scene, "ripplefront")
    simulation.reset(seed=spec.seed, episode=spec.episode)
    return simulation.run()


def regress_level(
    level: Level,
    renders: Path,
    *,
    update: bool = False,
    diff_dir: Path | None = None,
    max_frame_size: int = DEFAULT_MAX_FRAME_SIZE,
    max_cells: int = DEFAULT_MAX_CELLS,
    max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    override: MotionOverride | None = None,
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
    max_frame_size, max_cells, max_file_bytes
        Limits on what the stored references may ask for: the manifest's frame size, a stored trace's
        grid, and the size of each stored file. Each is checked before the work it would cost.
    override
        A motion (and speeds) to re-play every episode in instead of the manifest's; with ``update`` the
        references are rewritten in it, so that later runs without it re-play the same.

    Raises
    ------
    RegressionError
        If a stored reference cannot be read.
    """
    stem = Path(level.source).stem
    folder = renders / stem
    limits = Limits(max_frame_size, max_cells, max_file_bytes)
    manifest = read_manifest(folder / MANIFEST, max_frame_size=max_frame_size, max_file_bytes=max_file_bytes)
    if manifest is None and not update:
        return LevelResult(level.source, folder, "missing")
    if manifest is None:
        manifest = Manifest(REFERENCE_FRAME_SIZE, Tolerance(), default_specs(level))
    if override is not None:
        manifest = replace(manifest, specs=tuple(override.applied(spec) for spec in manifest.specs))
    scene = Scene.from_level(level)
    traces = [replay_trace(scene, spec) for spec in manifest.specs]
    default_diff = folder / "diff.png"
    if update:
        write_references(folder, level, manifest, traces)
        default_diff.unlink(missing_ok=True)
        steps = tuple(EpisodeResult(spec, t.steps, t.steps) for spec, t in zip(manifest.specs, traces, strict=True))
        return LevelResult(level.source, folder, "written", steps)
    snapshot_path = folder / LEVEL_SNAPSHOT
    snapshot = parse_level(read_json(snapshot_path, max_file_bytes=max_file_bytes), source=display_path(snapshot_path))
    results: list[EpisodeResult] = []
    rows: list[DiffRow] = []
    for spec, trace in zip(manifest.specs, traces, strict=True):
        result, episode_rows = _compare_episode(folder, level, snapshot, spec, trace, manifest, limits)
        results.append(result)
        rows += episode_rows
    edited = level_to_data(level) != level_to_data(snapshot)
    if not any(result.differs for result in results):
        default_diff.unlink(missing_ok=True)
        return LevelResult(level.source, folder, "ok", tuple(results), edited)
    diff_path = default_diff if diff_dir is None else diff_dir / f"{stem}.diff.png"
    write_png(diff_path, diff_image(rows, manifest.tolerance))
    return LevelResult(level.source, folder, "differs", tuple(results), edited, diff_path)


class Limits(NamedTuple):
    """What the stored references may ask for (see :func:`regress_level`)."""

    max_frame_size: int
    max_cells: int
    max_file_bytes: int


def _compare_episode(
    folder: Path, level: Level, snapshot: Level, spec: ReplaySpec, trace: Trace, manifest: Manifest, limits: Limits
) -> tuple[EpisodeResult, list[DiffRow]]:
    stored_trace = trace_path(folder, spec.name)
    source = display_path(stored_trace)
    reference_text = read_text(stored_trace, max_file_bytes=limits.max_file_bytes, listed_in=folder / MANIFEST)
    data = parse_json(reference_text, source=source, error=RegressionError)
    reference = trace_from_stored(data, source=source, max_cells=limits.max_cells)
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
    last: DiffRow | None = None
    for percent in KEY_PERCENTS:
        stored = read_png(
            key_frame_path(folder, spec.name, percent),
            max_size=size,
            max_file_bytes=limits.max_file_bytes,
            listed_in=folder / MANIFEST,
        )
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
    posed = _first_difference(_pose_rows(reference), _pose_rows(current))
    changes = []
    if moved is not None:
        changes.append(f"path from tick {moved}")
    elif posed is not None:
        # Same cells, another walk through them (a speed, a turn): the ticks at which the poses part.
        changes.append(f"poses from tick {posed}")
        moved = posed
    elif coverage is not None:
        changes.append(f"coverage from tick {coverage}")
    old, new = reference.to_data(), current.to_data()
    if old["outcome"] != new["outcome"]:
        changes.append(f"outcome {old['outcome']} -> {new['outcome']}")
    # Per-tick fields are summed up by the first difference above; "goal" by "reachable" when it changed.
    said = {"path", "headings", "unseen_percent", "first_seen", "steps", "covered", "start", "outcome", "poses"}
    if old["reachable"] != new["reachable"]:
        said.add("goal")
    # Grid traces carry no motion fields: a change of motion is one clause, not one per field.
    before_motion, after_motion = old.get("motion", "grid"), new.get("motion", "grid")
    if before_motion != after_motion:
        changes.append(f"motion {before_motion} -> {after_motion}")
        said |= {"motion", "move_speed", "turn_speed", "tick_hz", "seconds", "measures"}
    # A key only the reference has (a stored team trace against a one-guard run) is a change; a key only
    # the current trace has is a field added since the reference was written, and is not.
    for key in old:
        before, after = old[key], new.get(key)
        if key not in said and before != after:
            plain = isinstance(before, (int, float, str)) and isinstance(after, (int, float, str))
            changes.append(
                f"{key} {excerpt(before, 40)} -> {excerpt(after, 40)}" if plain else _FIELD_WORDS.get(key, key)
            )
    return tuple(changes or ["trace text"]), moved if moved is not None else coverage


def _pose_rows(trace: Trace) -> list[tuple[float, ...]]:
    """The poses as the trace's JSON writes them (6 decimals), one tuple per tick; none for grid traces."""
    if trace.poses is None:
        return []
    return [tuple(row) for row in np.round(trace.poses, 6).tolist()]
