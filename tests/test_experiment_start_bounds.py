"""A batch's lower bounds come from one task per level, apart from the episodes, and land in the same rows."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from guardsim.experiment import Batch, BatchLevel, EpisodeRecord, read_results, run_batch, run_spec, start_batch
from guardsim.experiment.episodes import bounds_of
from guardsim.experiment.executors import Completion, InProcess
from guardsim.experiment.start_bounds import LevelStarts, level_starts_tasks, run_level_starts, with_bounds
from tests.common import EMPTY_SQUARE, L_ROOM, SQUARE_WITH_HOLE, write_level

#: A valid level in which the guard fits nowhere: every episode raises when it draws its start.
NO_ROOM = {**EMPTY_SQUARE, "name": "no room", "guard": {"radius": 2.5}}


def tiny_batch(tmp_path: Path, episodes: int = 5, **options: Any) -> Batch:
    levels = tuple(
        BatchLevel.load(str(write_level(tmp_path, data, name)))
        for data, name in ((SQUARE_WITH_HOLE, "hole.json"), (L_ROOM, "l.json"))
    )
    return Batch(levels, ("ripplefront", "random-walk"), episodes, seed=2, **options)


def timeless(records: list[EpisodeRecord]) -> list[EpisodeRecord]:
    return sorted(record._replace(seconds=0.0, plan_us_per_step=None) for record in records)


class Backwards(InProcess):
    """Runs the items here in reverse order: every episode comes back before its level's bounds."""

    def run_unordered(self, function: Callable[[Any], Any], items: Sequence[Any]) -> Iterator[Completion]:
        return super().run_unordered(function, list(items)[::-1])


class LosesLevelTasks(InProcess):
    """Runs the episodes here and loses every level task, as a worker killed mid-task would."""

    def run_unordered(self, function: Callable[[Any], Any], items: Sequence[Any]) -> Iterator[Completion]:
        for item in items:
            if isinstance(item, LevelStarts):
                yield Completion(item, None, RuntimeError("worker lost"))
            else:
                yield Completion(item, function(item), None)


def test_one_task_per_level_with_every_episode_once(tmp_path: Path) -> None:
    """Two planners share each level's starts: one task per level, each episode index once."""
    specs = tiny_batch(tmp_path).specs()
    tasks = level_starts_tasks(specs)
    assert [task.level_file for task in tasks] == sorted({spec.level_file for spec in specs})
    assert all(task.episodes == (0, 1, 2, 3, 4) for task in tasks)
    assert level_starts_tasks([spec._replace(bounds=False) for spec in specs]) == []
    assert level_starts_tasks(tiny_batch(tmp_path, guards=2).specs()) == []  # a team's makespan has no bound here


def test_rows_equal_those_of_episodes_computing_their_own_bounds(tmp_path: Path) -> None:
    """run_batch's rows (level tasks first, or every episode before its level's task) are the rows of
    run_spec with the bounds computed inside the episode."""
    batch = tiny_batch(tmp_path)
    expected = timeless([run_spec(spec) for spec in batch.specs()])
    assert all(record.best_bound is not None for record in expected)
    for name, executor in (("forwards", InProcess()), ("backwards", Backwards())):
        folder = tmp_path / name
        _, pending = start_batch(batch, folder)
        report = run_batch(pending, folder, executor)
        assert (report.not_run, report.errors) == (0, 0)
        assert timeless(read_results(folder / "results.csv")) == expected


def test_lost_level_task_leaves_its_rows_to_the_resume(tmp_path: Path) -> None:
    """Without their level's bounds the episodes' rows are not written: they count as not run."""
    batch = tiny_batch(tmp_path)
    _, pending = start_batch(batch, tmp_path / "out")
    report = run_batch(pending, tmp_path / "out", LosesLevelTasks())
    assert report.not_run == len(pending) and report.records == []
    assert report.failure == "RuntimeError: worker lost"
    assert read_results(tmp_path / "out" / "results.csv") == []


def test_a_start_other_than_the_tasks_gets_its_own_bounds(tmp_path: Path) -> None:
    """A row whose start the task did not draw is given the bounds of its own start, not the task's."""
    spec = tiny_batch(tmp_path).specs()[0]
    found = run_level_starts(level_starts_tasks([spec])[0])[spec.episode]
    record = run_spec(spec._replace(bounds=False))
    assert record.start_col is not None and record.start_row is not None
    assert timeless([with_bounds(spec, record, "", found)[0]]) == timeless([run_spec(spec)])
    other = found._replace(start=(0, 0) if found.start != (0, 0) else (1, 0))
    own, _ = with_bounds(spec, record, "", other)
    bounds = bounds_of(spec.level, spec.line_of_sight, (record.start_col, record.start_row), found.heading or 0)
    assert (own.best_bound, own.eccentricity_bound, own.cluster_bound) == (
        bounds.best,
        bounds.eccentricity,
        bounds.cluster,
    )


def test_an_episode_that_raised_keeps_its_own_error(tmp_path: Path) -> None:
    """On a level where no start can be drawn the task records the error too; the row is the episode's."""
    level = BatchLevel.load(str(write_level(tmp_path, NO_ROOM, "no_room.json")))
    spec = Batch((level,), ("ripplefront",), 1, seed=0).specs()[0]
    found = run_level_starts(level_starts_tasks([spec])[0])[0]
    assert found.bounds is None and found.start is None and found.error.startswith("LevelError: ")
    record = run_spec(spec._replace(bounds=False))
    assert record.outcome == "error"
    assert with_bounds(spec, record, "the episode's traceback", found) == (record, "the episode's traceback")
