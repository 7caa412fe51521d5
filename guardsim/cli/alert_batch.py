"""How ``guardsim alert`` runs its episodes: the first one here when its trace, GIF or page is asked
for, the rest on local worker processes or a Dask scheduler, each trace written into the ``--out`` folder
as it comes back, and the record of the options there (``run.json``) that lets the same command resume."""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import io
import logging
import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import click

from guardsim.errors import GuardsimError
from guardsim.files.output import write_text_atomic

if TYPE_CHECKING:
    from guardsim.alert import AlertEpisode, AlertOutcome, AlertRules
    from guardsim.alert.batch import AlertTask
    from guardsim.detection import GuardDetection
    from guardsim.scene import Scene
    from guardsim.vision.table import ViewTable

__all__ = ["episode_trace", "local_cluster", "run_first", "run_options", "run_pending"]


def run_first(scene: Scene, table: ViewTable, task: AlertTask) -> AlertEpisode:
    """Run ``task``'s episode here, keeping the episode itself (its trace, GIF and page need it)."""
    from guardsim.alert import alert_episode

    episode = alert_episode(
        scene, task.patrol, intruder=task.intruder, source=task.source, target=task.target, route=task.route,
        search=task.search, phase=task.phase, max_seconds=task.max_seconds, table=table, rules=task.rules,
        detection=task.detection, spotted=task.spotted, motion=task.motion or "grid", gaits=task.gaits,
        distractions=task.distractions,
    )  # fmt: skip
    episode.run()
    return episode


def episode_trace(episode: AlertEpisode, scene: Scene, task: AlertTask) -> str:
    """The trace JSON of an episode run here, as the workers write it."""
    from guardsim.alert import alert_trace_data
    from guardsim.alert.batch import trace_text

    return trace_text(
        alert_trace_data(episode, scene, search=task.search, intruder=task.intruder, index=task.episode, seed=task.seed)
    )


def _digest(path: str) -> str:
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as error:
        raise GuardsimError(f"{path}: cannot read it: {error.strerror or error}") from None


def run_options(
    level_path: str,
    patrol_path: str,
    route_path: str | None,
    source: tuple[float, float] | None,
    target: tuple[float, float] | None,
    searches: list[str],
    scene: Scene,
    rules: AlertRules,
    detection: GuardDetection,
    **given: object,
) -> dict[str, object]:
    """What decides the episodes' results, as recorded in the output folder's ``run.json``: a run with
    other options is not resumed there."""
    return {
        "command": "guardsim alert",
        "level": {"file": os.path.normpath(level_path), "sha256": _digest(level_path)},
        "patrol": {"file": os.path.normpath(patrol_path), "sha256": _digest(patrol_path)},
        "route": None if route_path is None else {"file": os.path.normpath(route_path), "sha256": _digest(route_path)},
        "from": None if source is None else list(source),
        "to": None if target is None else list(target),
        "searches": searches,
        **given,
        "los": scene.rule.value,
        "fov": scene.cone.fov_degrees,
        "view_range": scene.cone.view_range,
        "rules": dataclasses.asdict(rules),
        "detection": {**dataclasses.asdict(detection.model), "view_range": detection.view_range, "dt": detection.dt},
    }


def run_pending(
    pending: list[AlertTask],
    outcomes: dict[tuple[str, int], AlertOutcome],
    folder: Path | None,
    *,
    done_before: int,
    first_here: str,
    workers: int | None,
    scheduler: str | None,
) -> None:
    """Run ``pending`` on the executor ``--workers``/``--scheduler`` ask for (:func:`guardsim.experiment.executors.make_executor`,
    as ``guardsim bench``), filling ``outcomes`` and writing each trace into ``folder`` as it comes back.
    ``done_before`` episodes were found done in ``folder``; ``first_here`` names the options the first
    episode ran for in this process (empty: it did not). On Ctrl-C or lost episodes, say how to resume
    and exit."""
    from guardsim.alert.batch import run_alert_task, trace_name
    from guardsim.cli.bench import NOT_RUN, ProgressLine
    from guardsim.experiment.executors import make_executor

    ran_here = 1 if first_here else 0
    total = done_before + ran_here + len(pending)
    with contextlib.ExitStack() as stack:
        if scheduler == "local":
            scheduler = stack.enter_context(local_cluster(workers))
            workers = None
        if scheduler is None:
            # More processes than episodes would only cost start-up time.
            workers = min(workers or os.cpu_count() or 1, len(pending))
        executor = make_executor(workers, scheduler, preload=[run_alert_task.__module__])
        chatty = total > 1
        if chatty:
            already = f" ({done_before} already done)" if done_before else ""
            where = f" on {executor.description}"
            if first_here:
                where = f": the first here for {first_here}, {len(pending)}{where}"
            click.echo(f"running {ran_here + len(pending)} of {total} episodes{where}{already}", err=True)
        progress = ProgressLine(len(pending), sys.stderr if chatty else io.StringIO())
        resume = f"; traces in {folder}; run the same command again to resume" if folder is not None else ""
        lost = 0
        failure = ""
        try:
            with executor:
                for done in executor.run_unordered(run_alert_task, pending):
                    if done.failure is not None:
                        lost += 1
                        failure = failure or (f"{type(done.failure).__name__}: {done.failure}".splitlines() or [""])[0]
                        continue
                    task, result = done.item, done.result
                    if folder is not None and result.trace is not None:
                        write_text_atomic(folder / trace_name(*task.key), result.trace)
                    outcomes[task.key] = result.outcome
                    progress.advance(None)  # type: ignore[arg-type]  # it only counts
        except KeyboardInterrupt:
            progress.close()
            click.echo(f"guardsim: interrupted; {len(outcomes)} of {total} episodes done{resume}", err=True)
            sys.exit(130)
        finally:
            progress.close()
    if lost:
        click.echo(f"guardsim: error: {lost} episodes did not run ({failure}){resume}", err=True)
        sys.exit(NOT_RUN)


@contextlib.contextmanager
def local_cluster(workers: int | None) -> Iterator[str]:
    """A ``distributed.LocalCluster`` of ``workers`` processes (default: the cores), one thread each, for
    ``--scheduler local``; yields its address."""
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
