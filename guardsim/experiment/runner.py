"""A batch from start to finish: plan the episodes, skip those done, run the rest, write the summary."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

from guardsim.experiment.episodes import LOOK_AHEAD, EpisodeRecord, EpisodeSpec, run_spec_logged, wants_bounds
from guardsim.experiment.executors import Completion, EpisodeExecutor
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
from guardsim.experiment.start_bounds import LevelStarts, StartBounds, level_starts_tasks, run_level_starts, with_bounds
from guardsim.experiment.summary import GroupSummary, summarise, summary_json
from guardsim.files.output import write_text_atomic
from guardsim.importers.loading import load_level
from guardsim.level import DEFAULT_MAX_CELLS, DEFAULT_MAX_FILE_BYTES, DEFAULT_MAX_VERTICES, Level, parse_level

__all__ = [
    "SUMMARY_NAME",
    "Batch",
    "BatchLevel",
    "Progress",
    "RunReport",
    "finish_batch",
    "run_batch",
    "run_task",
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
    def load(
        cls,
        path: str,
        level: Level | None = None,
        *,
        max_cells: int = DEFAULT_MAX_CELLS,
        max_vertices: int = DEFAULT_MAX_VERTICES,
        max_file_bytes: int = DEFAULT_MAX_FILE_BYTES,
    ) -> BatchLevel:
        """Load and validate a level file (or take ``level``, loaded from it); raises :class:`~guardsim.errors.LevelError`."""
        level = (
            level
            if level is not None
            else load_level(path, max_cells=max_cells, max_vertices=max_vertices, max_file_bytes=max_file_bytes)
        )
        digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
        return cls(os.path.normpath(path), digest, level)


@dataclass(frozen=True)
class Batch:
    """What a ``guardsim bench`` run computes: every (level, planner, episode) with the same options.

    ``fov`` and ``view_range`` are recorded in ``run.json`` as given on the command line; the levels'
    guards must already carry them (``Scene.from_level(level, fov_degrees=..., view_range=...).level``, as
    ``guardsim bench`` and ``guardsim play`` do). ``None`` means the level's own.
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
    """Run ``specs`` on ``executor``, appending each record to ``results.csv`` as soon as it is complete.

    The lower bounds of the starts go in one task per level (:mod:`~guardsim.experiment.start_bounds`),
    sent ahead of the episodes, which run without them; a row is written once its episode and its
    level's task are both back (an episode rarely waits: the tasks go first). When the executor forks
    its workers from this process, a few look-ahead episodes run here first (:func:`warm_up_specs`).

    Ctrl-C propagates as ``KeyboardInterrupt`` once the executor has stopped; every row written stays
    (rows still waiting for their level's bounds are not written, and run again on resume).
    """
    records: list[EpisodeRecord] = []
    not_run = errors = 0
    failure = ""
    wanted = {spec.key for spec in specs if wants_bounds(spec)}
    found: dict[tuple[str, str], dict[int, StartBounds]] = {}
    lost: set[tuple[str, str]] = set()
    waiting: dict[tuple[str, str], list[tuple[EpisodeSpec, tuple[EpisodeRecord, str]]]] = {}
    with appending_results(folder / RESULTS_NAME) as stream:

        def write(record: EpisodeRecord, trace_text: str) -> None:
            nonlocal errors
            if record.outcome == "error":
                # The traceback first: a row saying "error" always has its traceback in the log.
                append_traceback(folder, record, trace_text)
                errors += 1
            append_record(stream, record)
            records.append(record)
            if on_record is not None:
                on_record(record)

        def write_with_bounds(spec: EpisodeSpec, result: tuple[EpisodeRecord, str]) -> None:
            write(*with_bounds(spec, *result, found[(spec.level_file, spec.line_of_sight)][spec.episode]))

        for completion in _completions(specs, executor):
            item = completion.item
            if completion.failure is not None:
                failure = failure or " ".join(f"{type(completion.failure).__name__}: {completion.failure}".split())
            if isinstance(item, LevelStarts):
                if completion.failure is not None:
                    lost.add(item.key)
                    not_run += len(waiting.pop(item.key, []))
                else:
                    found[item.key] = completion.result
                    for spec, result in waiting.pop(item.key, []):
                        write_with_bounds(spec, result)
            elif completion.failure is not None:
                not_run += 1
            elif item.key not in wanted:
                write(*completion.result)
            elif (item.level_file, item.line_of_sight) in found:
                write_with_bounds(item, completion.result)
            elif (item.level_file, item.line_of_sight) in lost:
                not_run += 1
            else:
                waiting.setdefault((item.level_file, item.line_of_sight), []).append((item, completion.result))
    return RunReport(records, not_run + sum(map(len, waiting.values())), failure, errors)


def run_task(task: EpisodeSpec | LevelStarts) -> Any:
    """What a worker runs: an episode (:func:`run_spec_logged`) or a level's start bounds
    (:func:`~guardsim.experiment.start_bounds.run_level_starts`)."""
    return run_level_starts(task) if isinstance(task, LevelStarts) else run_spec_logged(task)


def warm_up_specs(specs: Sequence[EpisodeSpec], workers: int) -> list[int]:
    """Indices of the episodes to run in this process before forking ``workers`` workers: the first of
    each level and look-ahead planner (:data:`~guardsim.experiment.episodes.LOOK_AHEAD`) with more
    episodes than workers.

    Such a planner reads the level's view table in every worker; built here once, every forked worker
    has it (and the scene, the vision cache and the planner's own tables), where each would build its
    own. Other planners need nothing per level that a worker does not fill as it goes, and a level
    and planner with no more episodes than workers can have them all run at once, each worker building
    what it needs, which is no later.
    """
    first: dict[tuple[str, str], int] = {}
    count: dict[tuple[str, str], int] = {}
    for index, spec in enumerate(specs):
        if spec.planner not in LOOK_AHEAD:
            continue
        group = (spec.level_file, spec.planner)
        first.setdefault(group, index)
        count[group] = count.get(group, 0) + 1
    return [index for group, index in first.items() if count[group] > workers]


#: A tiny room with a pillar, on which :func:`load_compiled_code` runs the batch's kinds of work.
COMPILED_CODE_ROOM = {
    "name": "compiled-code warm-up",
    "outer": [[0, 0], [5, 0], [5, 3], [0, 3]],
    "holes": [[[2, 1], [3, 1], [3, 2], [2, 2]]],
}


def load_compiled_code(specs: Sequence[EpisodeSpec]) -> None:
    """Run one episode of each planner, line of sight and motion of ``specs``, and the bounds of its
    start, on :data:`COMPILED_CODE_ROOM`, and keep nothing of them.

    numba loads a process's compiled functions on their first call (0.27 CPU s for the paper
    experiment's: vision, view table, bounds, the episode loop); done here, before forking, the
    workers inherit them instead of each loading its own copy. The room is tiny, so the work is not.
    """
    room = parse_level(COMPILED_CODE_ROOM)
    done: set[tuple[str, str, str]] = set()
    for spec in specs:
        kind = (spec.planner, spec.line_of_sight, spec.motion)
        if kind in done:
            continue
        done.add(kind)
        tiny = spec._replace(level=room, level_file="<compiled-code warm-up>", episode=0, guards=1, bounds=False)
        run_spec_logged(tiny)  # an error here is the tiny room's business: the batch's episodes report their own
        if wants_bounds(spec):
            run_level_starts(LevelStarts(room, tiny.level_file, spec.line_of_sight, spec.seed, (0,)))


def _completions(specs: Sequence[EpisodeSpec], executor: EpisodeExecutor) -> Iterator[Completion]:
    """The completions of the level tasks and of every episode (run without bounds): the warm-up
    episodes here (if the workers are forked), then the rest on the executor, the level tasks first."""
    bare = [spec._replace(bounds=False) for spec in specs]
    warm = warm_up_specs(bare, executor.forked_workers) if executor.forked_workers else []
    if executor.forked_workers and specs:
        load_compiled_code(specs)
    for index in warm:
        yield Completion(bare[index], run_spec_logged(bare[index]), None)
    chosen = set(warm)
    tasks: list[EpisodeSpec | LevelStarts] = [*level_starts_tasks(specs)]
    tasks += [spec for index, spec in enumerate(bare) if index not in chosen]
    yield from executor.run_unordered(run_task, tasks)


def finish_batch(batch: Batch, folder: Path) -> tuple[list[EpisodeRecord], list[GroupSummary]]:
    """Rewrite ``results.csv`` in order and write ``summary.json``; returns the rows and their summary."""
    records = read_results(folder / RESULTS_NAME)
    write_results_sorted(folder / RESULTS_NAME, records)
    groups = summarise(records)
    write_text_atomic(folder / SUMMARY_NAME, summary_json(groups, batch.options()))
    return sorted(records, key=lambda record: record.sort_key), groups
