"""The lower bounds of a batch's starts: one task per level, apart from the episodes.

A start's bounds need the level's view table and the start-independent data of its area
(:mod:`guardsim.bounds.area`), 0.3-0.5 CPU s per level, which every worker used to build for every level
it met. So :func:`~guardsim.experiment.runner.run_batch` sends, ahead of the episodes, one
:class:`LevelStarts` task per level: it draws each episode's start as the episode will
(:func:`guardsim.starts.episode_start`) and computes its bounds with
:func:`~guardsim.experiment.episodes.bounds_of`. The episodes run without bounds, and
:func:`with_bounds` gives each row its bounds when both are back: the row :func:`run_spec_logged` would
have written with them, whichever worker ran what.

A row whose start is not the task's (which no episode does today) gets its bounds computed on the spot
rather than borrowed from another start.
"""

from __future__ import annotations

import traceback
from collections.abc import Sequence
from typing import NamedTuple

from guardsim.bounds import Bounds
from guardsim.experiment.episodes import (
    HEADING_NAMES,
    EpisodeRecord,
    EpisodeSpec,
    bounds_of,
    error_record,
    error_text,
    scene_of,
    wants_bounds,
)
from guardsim.level import Level
from guardsim.starts import episode_start

__all__ = ["LevelStarts", "StartBounds", "level_starts_tasks", "run_level_starts", "with_bounds"]


class LevelStarts(NamedTuple):
    """A task: the bounds of some episodes' starts on one level (small: it travels to a worker)."""

    level: Level
    """The validated level, its guard carrying the batch's vision, as in :attr:`EpisodeSpec.level`."""
    level_file: str
    """The level's file, as in :attr:`EpisodeSpec.level_file`."""
    line_of_sight: str
    """As :attr:`EpisodeSpec.line_of_sight`."""
    seed: int
    """Seed of the batch."""
    episodes: tuple[int, ...]
    """Episode indices, ascending; the planners of a batch share their episodes' starts."""

    @property
    def key(self) -> tuple[str, str]:
        """``(level_file, line_of_sight)``: which episodes' rows the task serves."""
        return (self.level_file, self.line_of_sight)


class StartBounds(NamedTuple):
    """What :func:`run_level_starts` found for one episode."""

    start: tuple[int, int] | None
    """``(col, row)`` of the episode's start cell; ``None`` if drawing it raised."""
    heading: int | None
    """The first heading number."""
    bounds: Bounds | None
    """The start's bounds; ``None`` if drawing the start or computing them raised."""
    error: str
    """``Type: message`` of that exception, else empty."""
    traceback: str
    """Its full traceback, else empty."""


def level_starts_tasks(specs: Sequence[EpisodeSpec]) -> list[LevelStarts]:
    """One task per level (and line of sight) of the specs that want bounds, in the specs' order."""
    tasks: dict[tuple[str, str], LevelStarts] = {}
    episodes: dict[tuple[str, str], set[int]] = {}
    for spec in specs:
        if not wants_bounds(spec):
            continue
        key = (spec.level_file, spec.line_of_sight)
        if key not in tasks:
            tasks[key] = LevelStarts(spec.level, spec.level_file, spec.line_of_sight, spec.seed, ())
            episodes[key] = set()
        episodes[key].add(spec.episode)
    return [task._replace(episodes=tuple(sorted(episodes[key]))) for key, task in tasks.items()]


def run_level_starts(task: LevelStarts) -> dict[int, StartBounds]:
    """Each episode's start and its bounds (or why not), by episode index. Runs in a worker."""
    found: dict[int, StartBounds] = {}
    for episode in task.episodes:
        start: tuple[int, int] | None = None
        heading: int | None = None
        try:
            _, start, heading = episode_start(scene_of(task.level, task.line_of_sight), seed=task.seed, episode=episode)
            bounds = bounds_of(task.level, task.line_of_sight, start, heading)
        except Exception as error:
            found[episode] = StartBounds(start, heading, None, error_text(error), traceback.format_exc())
        else:
            found[episode] = StartBounds(start, heading, bounds, "", "")
    return found


def with_bounds(
    spec: EpisodeSpec, record: EpisodeRecord, trace_text: str, found: StartBounds
) -> tuple[EpisodeRecord, str]:
    """The row and traceback of ``spec`` as :func:`run_spec_logged` gives them with the bounds, from the
    row it gave without them and what the level's task ``found`` for the episode.

    An episode that raised keeps its own error. Bounds that raised make the row an error, as they did
    inside the episode.
    """
    if record.outcome == "error" or record.start_col is None or record.start_row is None or not record.start_heading:
        return record, trace_text
    start, heading = (record.start_col, record.start_row), HEADING_NAMES.index(record.start_heading)
    if (found.start, found.heading) != (start, heading):
        try:
            bounds = bounds_of(spec.level, spec.line_of_sight, start, heading)
        except Exception as error:
            return error_record(spec, error_text(error), record.seconds), traceback.format_exc()
    elif found.bounds is None:
        return error_record(spec, found.error, record.seconds), found.traceback
    else:
        bounds = found.bounds
    return record._replace(
        best_bound=bounds.best, eccentricity_bound=bounds.eccentricity, cluster_bound=bounds.cluster
    ), ""
