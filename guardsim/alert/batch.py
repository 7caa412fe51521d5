"""Many alert episodes on local worker processes or a Dask cluster, as ``guardsim bench`` runs its own.

The command plans every episode here (:func:`~guardsim.alert.run.plan_starts`: one generator of the
seed draws all the starts in order), so that where an episode runs changes nothing: each
:class:`AlertTask` carries everything its episode depends on, and :func:`run_alert_task` (the function
the workers run, through :mod:`guardsim.experiment.executors`) gives the same outcome and the same trace text
wherever it runs. With an output folder, each episode's trace is written as soon as it is back and an
episode whose trace is already there is not run again (:func:`done_outcome`): a run stopped part-way
resumes.
"""

from __future__ import annotations

import json
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.model import AlertOutcome, AlertRules
from guardsim.alert.run import alert_episode, alert_trace_data
from guardsim.detection import GuardDetection
from guardsim.level import Level
from guardsim.motion.parameters import GuardMotion
from guardsim.patrol.model import Patrol
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable, view_table

__all__ = [
    "AlertTask",
    "TaskResult",
    "done_outcome",
    "episode_trace",
    "remember_setup",
    "run_alert_task",
    "run_task_here",
    "tasks_of",
    "trace_name",
    "trace_text",
]

TRACE_FORMAT = "guardsim alert trace"


class AlertTask(NamedTuple):
    """One episode of a batch: everything a worker needs, and nothing of this process's."""

    level: Level
    """The scene's level (its guard carrying the command's field of view and view range)."""
    line_of_sight: str
    """``pymunk`` or ``bresenham``."""
    patrol: Patrol
    intruder: str
    search: str
    episode: int
    """Index of the episode within its search strategy's (names its trace file)."""
    phase: int
    """Lap tick the guards start at."""
    source: int
    """Flat cell the intruder enters at."""
    target: int
    """Flat cell it heads for (-1: none)."""
    route: tuple[int, ...] | None
    max_seconds: float
    rules: AlertRules
    detection: GuardDetection
    spotted: bool
    trace: bool
    """Send back the episode's trace as JSON text (for ``--out``)."""
    motion: GuardMotion | None = None
    """Continuous motion at these speeds; ``None``: grid motion."""
    gaits: tuple[str, ...] | None = None
    """A route intruder's gait into each cell of ``route``; ``None``: it walks."""
    distractions: tuple[tuple[int, int, float], ...] = ()
    """Noises away from the intruder: ``(tick, cell, radius)``."""
    seed: int | None = None
    """The seed of the batch its start was drawn from (``None``: a start given, not drawn); the trace
    records it with :attr:`episode`."""

    @property
    def key(self) -> tuple[str, int]:
        """``(search, episode)``."""
        return (self.search, self.episode)


class TaskResult(NamedTuple):
    """What a worker sends back."""

    outcome: AlertOutcome
    trace: str | None
    """The trace as the text of its file (:func:`trace_text`), if asked for."""


_SETUPS: dict[tuple[Level, str], tuple[Scene, ViewTable]] = {}
_SETUPS_LOCK = threading.Lock()
# A continuous episode steps its scene's pymunk space, which is not safe from two threads at once.
_SPACE_LOCK = threading.Lock()
#: Scenes a worker keeps.
_MOST_SETUPS = 8


def remember_setup(scene: Scene, table: ViewTable) -> None:
    """Let the tasks of ``scene.level`` use ``scene`` and ``table`` (built by the command already): with
    one worker they run here, and forked workers start with them."""
    with _SETUPS_LOCK:
        _SETUPS[(scene.level, scene.rule.value)] = (scene, table)


def _setup(level: Level, line_of_sight: str) -> tuple[Scene, ViewTable]:
    """The level's scene and view table, built once per worker process. A grid episode only reads them
    (the grid and the table), so a Dask worker's threads share them; a continuous one steps the scene's
    space, so those run one at a time (:data:`_SPACE_LOCK`)."""
    key = (level, line_of_sight)
    with _SETUPS_LOCK:
        found = _SETUPS.get(key)
    if found is not None:
        return found
    scene = Scene.from_level(level, line_of_sight=line_of_sight)
    table = view_table(scene.grid, scene.vision())
    with _SETUPS_LOCK:
        if len(_SETUPS) >= _MOST_SETUPS:
            _SETUPS.pop(next(iter(_SETUPS)))
        _SETUPS[key] = (scene, table)
    return scene, table


def trace_text(data: dict[str, object]) -> str:
    """A trace file's text: compact JSON and a newline."""
    return json.dumps(data, separators=(",", ":")) + "\n"


def run_alert_task(task: AlertTask) -> TaskResult:
    """Run one episode (the function workers run); its outcome and, if asked, its trace's text."""
    scene, table = _setup(task.level, task.line_of_sight)
    if task.motion is None:
        return _run(task, scene, table)
    with _SPACE_LOCK:
        return _run(task, scene, table)


def _run(task: AlertTask, scene: Scene, table: ViewTable) -> TaskResult:
    episode = run_task_here(scene, table, task)
    return TaskResult(episode.result(), episode_trace(episode, scene, task) if task.trace else None)


def run_task_here(scene: Scene, table: ViewTable, task: AlertTask) -> AlertEpisode:
    """Run ``task``'s episode in this process on ``scene`` and ``table``, keeping the episode itself (a
    trace, GIF or page needs it)."""
    episode = alert_episode(
        scene, task.patrol, intruder=task.intruder, source=task.source, target=task.target, route=task.route,
        search=task.search, phase=task.phase, max_seconds=task.max_seconds, table=table, rules=task.rules,
        detection=task.detection, spotted=task.spotted, motion=task.motion or "grid", gaits=task.gaits,
        distractions=task.distractions,
    )  # fmt: skip
    episode.run()
    return episode


def episode_trace(episode: AlertEpisode, scene: Scene, task: AlertTask) -> str:
    """The trace file text of ``task``'s episode, as the workers write it."""
    return trace_text(
        alert_trace_data(episode, scene, search=task.search, intruder=task.intruder, index=task.episode, seed=task.seed)
    )


def trace_name(search: str, episode: int) -> str:
    """The file of an episode's trace in the output folder: ``ripple-0007.json``."""
    return f"{search}-{episode:04d}.json"


def done_outcome(folder: Path, task: AlertTask) -> AlertOutcome | None:
    """The outcome recorded in the task's trace file, if a finished one is there (traces are written
    whole, atomically); ``None`` when it must run."""
    path = folder / trace_name(task.search, task.episode)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if data.get("format") != TRACE_FORMAT or data.get("search") != task.search:
            return None
        return AlertOutcome(**data["outcome"])
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return None


def tasks_of(
    level: Level,
    line_of_sight: str,
    patrol: Patrol,
    starts: Sequence[tuple[int, int, int]],
    *,
    searches: Sequence[str],
    intruder: str,
    route: Sequence[int] | None,
    max_seconds: float,
    rules: AlertRules,
    detection: GuardDetection,
    spotted: bool,
    trace: bool,
    motion: GuardMotion | None = None,
    gaits: Sequence[str] | None = None,
    distractions: Sequence[tuple[int, int, float]] = (),
    seed: int | None = None,
    first: int = 0,
) -> list[AlertTask]:
    """Every episode of every strategy, strategy by strategy, in episode order, numbered from ``first``;
    ``motion``: continuous motion at these speeds (``None``: grid); ``seed``: the batch's, when the
    starts were drawn from it."""
    path = None if route is None else tuple(int(cell) for cell in route)
    tasks = []
    for name in searches:
        for index, (lap, entry, goal) in enumerate(starts, start=first):
            tasks.append(
                AlertTask(
                    level=level,
                    line_of_sight=line_of_sight,
                    patrol=patrol,
                    intruder=intruder,
                    search=name,
                    episode=index,
                    phase=lap,
                    source=entry,
                    target=-1 if intruder == "still" else goal,
                    route=path,
                    max_seconds=max_seconds,
                    rules=rules,
                    detection=detection,
                    spotted=spotted,
                    trace=trace,
                    motion=motion,
                    gaits=None if gaits is None else tuple(gaits),
                    distractions=tuple(distractions),
                    seed=seed,
                )
            )
    return tasks
