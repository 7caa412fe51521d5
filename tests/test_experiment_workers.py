"""How a batch's episodes reach local workers: forked after a warm-up, in chunks, each item's outcome its own."""

from __future__ import annotations

import subprocess
import sys
import threading
from pathlib import Path

import pytest

from guardsim.experiment import Batch, BatchLevel, read_results, run_batch, start_batch
from guardsim.experiment.executors import InProcess, LocalPool, default_start_method
from guardsim.experiment.runner import warm_up_specs
from tests.common import L_ROOM, REPO, SQUARE_WITH_HOLE, write_level

#: Filled by a test before its pool starts: forked workers see it, fork-server ones do not.
PARENT_STATE: list[int] = []

linux_only = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="workers are forked on Linux only")


def tenfold_unless_seven(item: int) -> int:
    """Fast work that raises on item 7 (module-level, so workers can import it)."""
    if item == 7:
        raise ValueError("seven")
    return item * 10


def parent_state_size(_item: int) -> int:
    return len(PARENT_STATE)


@pytest.mark.parametrize("method", ["fork", "forkserver"])
def test_every_item_comes_back_once_with_its_own_error(method: str) -> None:
    """400 fast items go out in chunks; each comes back once, and the item that raised alone has a failure."""
    with LocalPool(2, start_method=method) as pool:
        completions = list(pool.run_unordered(tenfold_unless_seven, range(400)))
    assert sorted(completion.item for completion in completions) == list(range(400))
    failed = {completion.item: completion.failure for completion in completions if completion.failure is not None}
    assert list(failed) == [7]
    assert isinstance(failed[7], ValueError) and str(failed[7]) == "seven"
    assert all(c.result == c.item * 10 for c in completions if c.item != 7)


#: Run in a fresh interpreter: this one may have threads left by other tests (Dask's), and then no fork.
FORK_CHECK = """
import tests.test_experiment_workers as here
from guardsim.experiment.executors import LocalPool

with LocalPool(2) as forked, LocalPool(2, start_method="forkserver") as served:
    print(forked.forked_workers, served.forked_workers)
    here.PARENT_STATE.extend([1, 2, 3])
    print(sorted({c.result for c in forked.run_unordered(here.parent_state_size, range(8))}))
    print(sorted({c.result for c in served.run_unordered(here.parent_state_size, range(8))}))
"""


@linux_only
def test_forked_workers_start_with_what_this_process_computed() -> None:
    """The pool forks its workers at the first run_unordered, not on entering the block, so they see what
    this process did in between; fork-server workers start from a fresh import."""
    done = subprocess.run([sys.executable, "-c", FORK_CHECK], cwd=REPO, capture_output=True, text=True, check=True)
    assert done.stdout.split("\n")[:3] == ["2 0", "[3]", "[0]"]


@linux_only
def test_no_fork_while_another_thread_runs() -> None:
    """A second thread could be mid-way through something a copy would keep half done: no fork then."""
    alone = default_start_method()  # "fork" unless the test runner has threads of its own
    release = threading.Event()
    thread = threading.Thread(target=release.wait)
    thread.start()
    try:
        assert default_start_method() != "fork"
        assert LocalPool(2).forked_workers == 0
    finally:
        release.set()
        thread.join()
    assert default_start_method() == alone
    assert InProcess().forked_workers == 0


def tiny_batch(tmp_path: Path, episodes: int, planners: tuple[str, ...] = ("ripplefront", "random-walk")) -> Batch:
    levels = tuple(
        BatchLevel.load(str(write_level(tmp_path, data, name)))
        for data, name in ((SQUARE_WITH_HOLE, "hole.json"), (L_ROOM, "l.json"))
    )
    return Batch(levels, planners, episodes, seed=5)


def test_warm_up_is_the_first_episode_of_each_level_and_look_ahead_planner(tmp_path: Path) -> None:
    """Only planners that read the view table in every worker warm up here, and only with more
    episodes than workers."""
    specs = tiny_batch(tmp_path, 3, ("frontier", "ripplefront", "tour")).specs()
    warm = warm_up_specs(specs, 2)
    assert [(specs[i].level_file, specs[i].planner, specs[i].episode) for i in warm] == [
        (level, planner, 0) for level in sorted({s.level_file for s in specs}) for planner in ("frontier", "tour")
    ]
    assert warm_up_specs(specs, 3) == []
    assert warm_up_specs(specs[1:], 2) == [index - 1 for index in warm[1:]]  # the first group has 2 left


def test_forked_batch_writes_the_rows_of_one_process(tmp_path: Path) -> None:
    """Warm-up here, then chunks on two forked workers: the same rows, bounds included, as all in this process."""
    batch = tiny_batch(tmp_path, 12)
    tables = []
    for name, executor in (("one", InProcess()), ("two", LocalPool(2))):
        folder = tmp_path / name
        _, pending = start_batch(batch, folder)
        with executor:
            report = run_batch(pending, folder, executor)
        assert (report.not_run, report.errors, len(report.records)) == (0, 0, 48)
        tables.append(
            sorted(
                record._replace(seconds=0.0, plan_us_per_step=None) for record in read_results(folder / "results.csv")
            )
        )
    assert tables[0] == tables[1]
    assert all(record.best_bound is not None for record in tables[0])
