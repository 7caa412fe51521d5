"""A batch from start to finish: plan the episodes, skip those done, run the rest, write the summary."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

from guardsim.executors import Completion, EpisodeExecutor
from guardsim.experiment.episodes import EpisodeRecord, EpisodeSpec, run_spec_logged
from guardsim.experiment.results import (
    RESULTS_NAME,
    append_record,
    append_traceback,
    appending_results,
    check_run_options,
    prepare_folder,
    read_results,
    write_results_sorted,
)
from guardsim.experiment.summary import GroupSummary, summarise, summary_json
from guardsim.level import Level, load_level
from guardsim.output import write_text_atomic

__all__ = [
    "SUMMARY_NAME",
    "Batch",
    "BatchLevel",
    "Progress",
    "RunReport",
    "finish_batch",
    "run_batch",
    "start_batch",
    "warm_up_specs",
]

SUMMARY_NAME = "summary.json"


class BatchLevel(NamedTuple):
    """A level file of the batch, read and validated once by the command."""

    file: str
    """The path as given, normalised (``./levels/a.json`` and ``levels/a.json`` are one file)."""
    sha256: str
    """Digest of the file's bytes, recorded in ``run.json`` so that a changed level is not resumed."""
    level: Level

    @classmethod
    def load(cls, path: str, level: Level | None = None, **limits: int) -> BatchLevel:
        """Load and validate a level file (or take ``level``, loaded from it); raises :class:`~guardsim.errors.LevelError`."""
        level = level if level is not None else load_level(path, **limits)
        digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
        return cls(os.path.normpath(path), digest, level)


@dataclass(frozen=True)
class Batch:
    """What a ``guardsim bench`` run computes: every (level, planner, episode) with the same options.

    ``fov`` and ``view_range`` are recorded in ``run.json`` as given on the command line; the levels'
    guards must already carry them (``guardsim bench`` applies them as ``guardsim play`` does, with
    :func:`guardsim.cli.common.build_scene`). ``None`` means the level's own.
    """

    levels: tuple[BatchLevel, ...]
    planners: tuple[str, ...]
    episodes: int
    seed: int
    max_steps: int | None = None
    reference: bool = False
    guards: int = 1
    line_of_sight: str = "pymunk"
    fov: float | None = None
    view_range: float | None = None
    bounds: bool = True
    """Compute the lower bounds of each one-guard start (``--no-bounds`` skips them)."""
    motion: str = "grid"
    """``grid`` or ``continuous``, with the guard's speeds (``None``: the level's, else the defaults)."""
    move_speed: float | None = None
    turn_speed: float | None = None
    tick_hz: float | None = None
    max_seconds: float | None = None

    def __post_init__(self) -> None:
        # One order whatever the command line's, so that run.json and the plan do not depend on it.
        unique_levels = {level.file: level for level in self.levels}
        object.__setattr__(self, "levels", tuple(unique_levels[file] for file in sorted(unique_levels)))
        object.__setattr__(self, "planners", tuple(sorted(set(self.planners))))

    def options(self) -> dict[str, Any]:
        """The options that decide the results, as stored in ``run.json``."""
        return {
            "levels": [{"file": level.file, "sha256": level.sha256} for level in self.levels],
            "planners": list(self.planners),
            "episodes": self.episodes,
            "seed": self.seed,
            "max_steps": self.max_steps,
            "reference": self.reference,
            "guards": self.guards,
            "los": self.line_of_sight,
            "fov": self.fov,
            "view_range": self.view_range,
            **({} if self.bounds else {"bounds": False}),
            **({} if self.motion == "grid" else {"motion": self.motion, "move_speed": self.move_speed,
                "turn_speed": self.turn_speed, "tick_hz": self.tick_hz, "max_seconds": self.max_seconds}),
        }  # fmt: skip

    def specs(self) -> list[EpisodeSpec]:
        """Every episode, ordered by level file, planner and episode."""
        return [
            EpisodeSpec(
                level.level,
                level.file,
                planner,
                self.seed,
                episode,
                reference=self.reference,
                max_steps=self.max_steps,
                guards=self.guards,
                line_of_sight=self.line_of_sight,
                bounds=self.bounds,
                motion=self.motion,
                move_speed=self.move_speed,
                turn_speed=self.turn_speed,
                tick_hz=self.tick_hz,
                max_seconds=self.max_seconds,
            )
            for level in self.levels
            for planner in self.planners
            for episode in range(self.episodes)
        ]


def start_batch(batch: Batch, folder: Path) -> tuple[list[EpisodeRecord], list[EpisodeSpec]]:
    """Prepare the folder and split the batch into the rows already done and the episodes still to run.

    Episodes that ended in ``error`` are not done: their rows are taken out of ``results.csv`` (which is
    rewritten atomically) and they run again; their tracebacks stay in ``errors.log``.

    Raises
    ------
    OutputError
        If the folder cannot be made, holds a run with other options, or has an unreadable results file
        (a row of an episode outside the batch, or two rows of one episode, included).
    """
    prepare_folder(folder)
    check_run_options(folder, batch.options())
    specs = batch.specs()
    done = read_results(folder / RESULTS_NAME, expected={spec.key for spec in specs})
    kept = [record for record in done if record.outcome != "error"]
    if len(kept) < len(done):
        write_results_sorted(folder / RESULTS_NAME, kept)
    finished = {record.key for record in kept}
    return kept, [spec for spec in specs if spec.key not in finished]


class RunReport(NamedTuple):
    """What :func:`run_batch` did."""

    records: list[EpisodeRecord]
    """Rows appended by this run, in the order they finished."""
    not_run: int
    """Episodes lost to a failed worker or transport (not to an error in the episode); they run on resume."""
    failure: str
    """The first such failure, as ``Type: message``; empty if none."""
    errors: int = 0
    """Episodes that raised (their rows say ``error``, their tracebacks are in ``errors.log``); they run
    again on resume."""


#: Called with each record as it is written (for a progress display).
Progress = Callable[[EpisodeRecord], None]


def run_batch(
    specs: Sequence[EpisodeSpec], folder: Path, executor: EpisodeExecutor, on_record: Progress | None = None
) -> RunReport:
    """Run ``specs`` on ``executor``, appending each record to ``results.csv`` as soon as it arrives.

    When the executor forks its workers from this process, a few episodes run here first
    (:func:`warm_up_specs`), so that the workers start with their levels' scenes, vision, view tables
    and bound data and with the compiled code loaded, instead of each building them again.

    Ctrl-C propagates as ``KeyboardInterrupt`` once the executor has stopped; every row written stays.
    """
    records: list[EpisodeRecord] = []
    not_run = errors = 0
    failure = ""
    with appending_results(folder / RESULTS_NAME) as stream:
        for completion in _completions(specs, executor):
            if completion.failure is not None:
                not_run += 1
                failure = failure or " ".join(f"{type(completion.failure).__name__}: {completion.failure}".split())
                continue
            record, trace_text = completion.result
            if record.outcome == "error":
                # The traceback first: a row saying "error" always has its traceback in the log.
                append_traceback(folder, record, trace_text)
                errors += 1
            append_record(stream, record)
            records.append(record)
            if on_record is not None:
                on_record(record)
    return RunReport(records, not_run, failure, errors)


def warm_up_specs(specs: Sequence[EpisodeSpec], workers: int) -> list[int]:
    """Indices of the episodes to run in this process before forking ``workers`` workers: the first of
    each level and planner with more episodes than workers.

    What an episode builds once per level and planner (the scene, the vision cache, the view table, the
    start-independent bound data, a look-ahead planner's tables) then exists once, and every forked
    worker has it. A level and planner with no more episodes than workers is left to them: its
    episodes can all run at once, each worker building what it needs, which is no later.
    """
    first: dict[tuple[str, str], int] = {}
    count: dict[tuple[str, str], int] = {}
    for index, spec in enumerate(specs):
        group = (spec.level_file, spec.planner)
        first.setdefault(group, index)
        count[group] = count.get(group, 0) + 1
    return [index for group, index in first.items() if count[group] > workers]


def _completions(specs: Sequence[EpisodeSpec], executor: EpisodeExecutor) -> Iterator[Completion]:
    """Every spec's completion: the warm-up episodes here (if the workers are forked), then the rest."""
    warm = warm_up_specs(specs, executor.forked_workers) if executor.forked_workers else []
    for index in warm:
        yield Completion(specs[index], run_spec_logged(specs[index]), None)
    chosen = set(warm)
    yield from executor.run_unordered(
        run_spec_logged, [spec for index, spec in enumerate(specs) if index not in chosen]
    )


def finish_batch(batch: Batch, folder: Path) -> tuple[list[EpisodeRecord], list[GroupSummary]]:
    """Rewrite ``results.csv`` in order and write ``summary.json``; returns the rows and their summary."""
    records = read_results(folder / RESULTS_NAME)
    write_results_sorted(folder / RESULTS_NAME, records)
    groups = summarise(records)
    write_text_atomic(folder / SUMMARY_NAME, summary_json(groups, batch.options()))
    return sorted(records, key=lambda record: record.sort_key), groups
