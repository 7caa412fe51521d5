"""A batch of alert episodes from a level's scene and patrol, as ``guardsim alert`` runs it.

:func:`plan_alert_batch` checks the options and draws every episode's start (:class:`AlertBatch`);
:func:`run_alert_batch` runs them (the first here when its episode itself is wanted, the rest on local
worker processes or a Dask scheduler, :mod:`guardsim.experiment.executors`), writing each trace into an
output folder as it comes back and resuming from the traces already there (the folder's ``run.json``,
:func:`alert_run_options`, says which options they were run with); :func:`write_alert_json` writes the
folder's summary. The same options give the same outcomes and bytes wherever the episodes run.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import logging
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import NamedTuple

from guardsim.alert.batch import (
    AlertTask,
    done_outcome,
    episode_trace,
    remember_setup,
    run_alert_task,
    run_task_here,
    tasks_of,
    trace_name,
)
from guardsim.alert.episode import AlertEpisode
from guardsim.alert.intruders import read_route_cells
from guardsim.alert.model import AlertOutcome, AlertRules
from guardsim.alert.run import DEFAULT_MAX_SECONDS, AlertSummary, plan_starts, summarise
from guardsim.alert.search import SEARCHES
from guardsim.detection import GuardDetection
from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic
from guardsim.motion.parameters import GuardMotion
from guardsim.patrol.model import Patrol
from guardsim.scene import Scene
from guardsim.vision.table import ViewTable, view_table

__all__ = [
    "AlertBatch",
    "AlertBatchRun",
    "alert_run_options",
    "local_cluster",
    "plan_alert_batch",
    "run_alert_batch",
    "write_alert_json",
]


class AlertBatch(NamedTuple):
    """Every episode of a batch, planned (:func:`plan_alert_batch`)."""

    scene: Scene
    table: ViewTable
    """The scene's view table."""
    tasks: list[AlertTask]
    """Strategy by strategy, in episode order."""
    searches: list[str]
    episodes: int
    """Episodes per search strategy."""
    first: int
    """The first episode's index (``episode`` of :func:`plan_alert_batch`, else 0)."""
    rules: AlertRules
    detection: GuardDetection


class AlertBatchRun(NamedTuple):
    """What :func:`run_alert_batch` ran: the outcomes by ``(search, episode)``, the first episode itself
    when it ran here, how many were found done in the folder, how many were lost and why."""

    outcomes: dict[tuple[str, int], AlertOutcome]
    first: AlertEpisode | None
    done_before: int
    lost: int
    failure: str
    interrupted: bool

    def runs(self, batch: AlertBatch) -> dict[str, list[AlertOutcome]]:
        """Each strategy's outcomes in episode order (every episode must have run)."""
        return {
            name: [self.outcomes[(name, batch.first + index)] for index in range(batch.episodes)]
            for name in batch.searches
        }

    def summaries(self, batch: AlertBatch) -> list[AlertSummary]:
        """One summary row per strategy."""
        return [summarise(name, found) for name, found in self.runs(batch).items()]


def plan_alert_batch(
    scene: Scene,
    patrol: Patrol,
    *,
    patrol_name: str = "patrol",
    intruder: str = "evader",
    source: tuple[float, float] | None = None,
    target: tuple[float, float] | None = None,
    route_path: str | None = None,
    search: str = "ripple",
    episodes: int | None = None,
    episode: int | None = None,
    seed: int = 0,
    max_seconds: float = DEFAULT_MAX_SECONDS,
    intruder_speed: float | None = None,
    run_speed: float | None = None,
    spotted: bool = False,
    motion: GuardMotion | None = None,
    trace: bool = False,
    say: Callable[[str], None] | None = None,
) -> AlertBatch:
    """Check a batch's options and plan its episodes on ``scene`` against ``patrol`` (a repeating grid
    patrol, named ``patrol_name`` in errors).

    Without ``episodes`` and ``episode``, one episode enters at ``source`` (world units; default the
    level's first player start, told to ``say``) at lap tick 0. A batch of ``episodes`` (even of one)
    draws what it is not given, the patrol phase, entry and goal, from ``seed``; ``episode`` K is the
    K-th drawn from the seed, alone, as a batch ran it. ``search`` is one of :data:`SEARCHES` or ``all``;
    ``route_path`` a route intruder's file (:func:`~guardsim.alert.intruders.read_route_cells`);
    ``motion`` continuous motion at those speeds (``None``: grid); ``trace``: the workers send back
    each episode's trace. Every fault is a :class:`~guardsim.errors.GuardsimError` line.
    """
    level, grid = scene.level, scene.grid
    patrol.require_repeating_grid(patrol_name, "alert")
    searches = list(SEARCHES) if search == "all" else [search]
    rules = AlertRules.of_level(level, intruder_speed=intruder_speed, run_speed=run_speed)
    # The scene's level carries the command's view range, and its grid tick is the rules' tick: the same
    # detection as the sneak check and the level checks build.
    detection = GuardDetection.of_level(level)
    start = grid.floor_cell(source, "--from") if source is not None else None
    goal = grid.floor_cell(target, "--to") if target is not None else None
    route = gaits = None
    distractions: list[tuple[int, int, float]] = []
    if route_path is not None:
        if intruder != "route":
            raise GuardsimError("--route is the path of a route intruder: give --intruder route")
        route, gaits, distractions = read_route_cells(
            route_path, grid, sneak_ticks=level.intruder.sneak_ticks, dt=rules.dt
        )
        start, goal = route[0], route[-1]
    alone = episodes is None and episode is None
    if alone and start is None and level.player_starts:
        # One episode enters where the level says the player starts (many draw their entries from the seed).
        point = level.player_starts[0]
        start = grid.floor_cell(point, "the level's player start")
        if say is not None:
            say(f"from the level's player start ({point[0]:g}, {point[1]:g})")
    if alone and start is None:
        raise GuardsimError("one episode needs --from X,Y (and --to X,Y unless the intruder is still)")
    if start is not None and goal is not None and grid.component_labels[start] != grid.component_labels[goal]:
        raise GuardsimError("--to cannot be reached from --from")
    if intruder != "still" and start is not None and goal is None and route is None:
        raise GuardsimError(f"a {intruder} intruder needs --to X,Y (or --route)")
    table = view_table(grid, scene.vision())
    if alone and intruder == "still" and goal is None:
        goal = -1
    count = 1 if episodes is None else episodes
    # Episode K's start is the K-th drawn from the seed's one generator, however many follow it.
    first = 0 if episode is None else episode
    starts = plan_starts(
        scene, patrol, episodes=first + count, seed=seed, source=start, target=goal, spotted=spotted,
        phase=0 if alone else None, table=table,
    )[first:]  # fmt: skip
    tasks = tasks_of(
        level, scene.rule.value, patrol, starts, searches=searches, intruder=intruder, route=route,
        max_seconds=max_seconds, rules=rules, detection=detection, spotted=spotted, trace=trace, motion=motion,
        gaits=gaits, distractions=distractions, seed=None if alone else seed, first=first,
    )  # fmt: skip
    return AlertBatch(scene, table, tasks, searches, count, first, rules, detection)


def _digest(path: str) -> str:
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as error:
        raise GuardsimError(f"{path}: cannot read it: {error.strerror or error}") from None


def _file(path: str | None) -> dict[str, str] | None:
    return None if path is None else {"file": os.path.normpath(path), "sha256": _digest(path)}


def alert_run_options(
    batch: AlertBatch,
    level_path: str,
    patrol_path: str,
    route_path: str | None,
    source: tuple[float, float] | None,
    target: tuple[float, float] | None,
    **given: object,
) -> dict[str, object]:
    """What decides a batch's results, as recorded in its output folder's ``run.json`` (with the files'
    digests and the ``given`` options): a run with other options is not resumed there."""
    scene, detection = batch.scene, batch.detection
    return {
        "command": "guardsim alert",
        "level": _file(level_path),
        "patrol": _file(patrol_path),
        "route": _file(route_path),
        "from": None if source is None else list(source),
        "to": None if target is None else list(target),
        "searches": batch.searches,
        **given,
        "los": scene.rule.value,
        "fov": scene.cone.fov_degrees,
        "view_range": scene.cone.view_range,
        "rules": dataclasses.asdict(batch.rules),
        "detection": {**dataclasses.asdict(detection.model), "view_range": detection.view_range, "dt": detection.dt},
    }


def run_alert_batch(
    batch: AlertBatch,
    *,
    folder: Path | None = None,
    options: dict[str, object] | None = None,
    here: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    starting: Callable[[int, int, int, str], None] | None = None,
    advance: Callable[[], None] | None = None,
) -> AlertBatchRun:
    """Run ``batch``: the first episode in this process when ``here`` (kept, for its trace, GIF or page;
    it runs even when ``folder`` holds its trace), the others on ``workers`` local processes (default:
    the cores; 1 runs here) or a Dask ``scheduler`` (an address, or ``local`` for a local cluster).

    With a ``folder``, ``options`` (:func:`alert_run_options`) are recorded in its ``run.json`` or checked
    against it, each trace is written there as it comes back, and episodes whose trace is there already
    are not run again. ``starting(to_run, total, done_before, where)`` is told before the workers start
    (``where`` names the executor), ``advance()`` after each episode back. Ctrl-C and lost episodes end
    the run early: the result says so (the traces written stay, for a resume).
    """
    from guardsim.experiment.executors import make_executor
    from guardsim.experiment.results import RUN_NAME, check_run_options

    tasks = batch.tasks
    outcomes: dict[tuple[str, int], AlertOutcome] = {}
    if folder is not None:
        resuming = (folder / RUN_NAME).exists()
        check_run_options(folder, options or {})
        if resuming:
            for task in tasks:
                kept = done_outcome(folder, task)
                if kept is not None:
                    outcomes[task.key] = kept
    first = None
    if here:
        first = run_task_here(batch.scene, batch.table, tasks[0])
        if folder is not None:
            write_text_atomic(folder / trace_name(*tasks[0].key), episode_trace(first, batch.scene, tasks[0]))
        outcomes.pop(tasks[0].key, None)
    done_before = len(outcomes)
    if first is not None:
        outcomes[tasks[0].key] = first.result()
    pending = [task for task in tasks if task.key not in outcomes]
    lost, failure, interrupted = 0, "", False
    if pending:
        remember_setup(batch.scene, batch.table)
        with contextlib.ExitStack() as stack:
            if scheduler == "local":
                scheduler = stack.enter_context(local_cluster(workers))
                workers = None
            if scheduler is None:
                # More processes than episodes would only cost start-up time.
                workers = min(workers or os.cpu_count() or 1, len(pending))
            executor = make_executor(workers, scheduler, preload=[run_alert_task.__module__])
            if starting is not None:
                starting(
                    len(pending), done_before + (1 if here else 0) + len(pending), done_before, executor.description
                )
            try:
                with executor:
                    for done in executor.run_unordered(run_alert_task, pending):
                        if done.failure is not None:
                            lost += 1
                            text = f"{type(done.failure).__name__}: {done.failure}"
                            failure = failure or (text.splitlines() or [""])[0]
                            continue
                        task, result = done.item, done.result
                        if folder is not None and result.trace is not None:
                            write_text_atomic(folder / trace_name(*task.key), result.trace)
                        outcomes[task.key] = result.outcome
                        if advance is not None:
                            advance()
            except KeyboardInterrupt:
                interrupted = True
    return AlertBatchRun(outcomes, first, done_before, lost, failure, interrupted)


def write_alert_json(
    folder: Path, batch: AlertBatch, done: AlertBatchRun, *, patrol: str, intruder: str, seed: int
) -> Path:
    """Write the batch's summary per strategy and every outcome into ``folder/alert.json``; its path."""
    summary = {
        "level": batch.scene.level.name,
        "patrol": patrol,
        "intruder": intruder,
        "episodes": batch.episodes,
        "seed": seed,
        "summary": [row._asdict() for row in done.summaries(batch)],
        "outcomes": {name: [o._asdict() for o in found] for name, found in done.runs(batch).items()},
    }
    path = folder / "alert.json"
    write_text_atomic(path, json.dumps(summary, indent=1) + "\n")
    return path


@contextlib.contextmanager
def local_cluster(workers: int | None) -> Iterator[str]:
    """A ``distributed.LocalCluster`` of ``workers`` processes (default: the cores), one thread each;
    yields its address."""
    try:
        from distributed import LocalCluster
    except ImportError:
        raise GuardsimError(
            "--scheduler local needs dask.distributed, which is not installed: pip install 'guardsim[cluster]'"
        ) from None
    count = workers or os.cpu_count() or 1
    with LocalCluster(
        n_workers=count, processes=True, threads_per_worker=1, dashboard_address=None, silence_logs=logging.ERROR
    ) as cluster:
        yield cluster.scheduler_address
