"""Batches of episodes: the paper's evaluation, run by ``guardsim bench``.

A :class:`Batch` is every (level, planner, episode) of one set of options. :func:`start_batch` prepares
the output folder and leaves out what an earlier run of the same batch already wrote; :func:`run_batch`
runs the rest on an executor (see :mod:`guardsim.experiment.executors`), appending rows to ``results.csv`` as they
finish; :func:`finish_batch` sorts the rows and writes ``summary.json``.

Modules, in the order the data flows: :mod:`~guardsim.experiment.episodes` (one episode),
:mod:`~guardsim.experiment.results` (the folder's files), :mod:`~guardsim.experiment.summary`
(statistics), :mod:`~guardsim.experiment.runner` (the batch).
"""

from __future__ import annotations

from guardsim.experiment.episodes import CSV_COLUMNS, TIMED_COLUMNS, EpisodeRecord, EpisodeSpec, run_spec
from guardsim.experiment.results import ERRORS_NAME, RESULTS_NAME, RUN_NAME, read_results
from guardsim.experiment.runner import (
    SUMMARY_NAME,
    Batch,
    BatchLevel,
    RunReport,
    finish_batch,
    run_batch,
    start_batch,
)
from guardsim.experiment.summary import GroupSummary, Statistics, format_table, summarise

__all__ = [
    "CSV_COLUMNS",
    "ERRORS_NAME",
    "RESULTS_NAME",
    "RUN_NAME",
    "SUMMARY_NAME",
    "TIMED_COLUMNS",
    "Batch",
    "BatchLevel",
    "EpisodeRecord",
    "EpisodeSpec",
    "GroupSummary",
    "RunReport",
    "Statistics",
    "finish_batch",
    "format_table",
    "read_results",
    "run_batch",
    "run_spec",
    "start_batch",
    "summarise",
]
