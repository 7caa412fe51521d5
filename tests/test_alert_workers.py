"""``guardsim alert --episodes N`` on worker processes and on Dask (issue 26, item 4): the same alert.json
and the same trace files byte for byte whatever runs them, and a stopped run resumes from its traces."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from guardsim.alert import SEARCHES
from guardsim.cli import main
from tests.common import write_level
from tests.test_alert import ROOM, setup, write_patrol

#: Six spotted evader episodes per strategy: 24 episodes, a couple of seconds in one process.
EPISODES = ("--episodes", "6", "--search", "all", "--spotted", "--seed", "4")


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    folder = tmp_path_factory.mktemp("alert-workers")
    level = write_level(folder, ROOM)
    scene, _ = setup()
    return level, write_patrol(folder, scene.grid)


def run(files: tuple[Path, Path], *args: str | Path) -> Result:
    level, patrol = files
    return CliRunner().invoke(main, ["alert", str(level), "--patrol", str(patrol), *map(str, args)])


def contents(folder: Path) -> dict[str, bytes]:
    """Every file of an output folder, by name."""
    return {path.name: path.read_bytes() for path in sorted(folder.iterdir())}


def table(result: Result) -> str:
    """The printed table (the lines naming the output folder left out)."""
    return "\n".join(line for line in result.stdout.splitlines() if not line.startswith("wrote "))


@pytest.fixture(scope="module")
def one_worker(files: tuple[Path, Path], tmp_path_factory: pytest.TempPathFactory) -> tuple[Result, Path]:
    """The reference: every episode in this process."""
    out = tmp_path_factory.mktemp("one") / "out"
    result = run(files, *EPISODES, "--workers", "1", "--out", out)
    assert result.exit_code == 0, result.output
    assert "on 1 worker (this process)" in result.stderr
    return result, out


def test_one_worker_writes_every_trace_and_the_summary(one_worker: tuple[Result, Path]) -> None:
    _, out = one_worker
    names = set(contents(out))
    assert names == {"alert.json", "run.json"} | {f"{s}-{k:04d}.json" for s in SEARCHES for k in range(6)}
    summary = json.loads((out / "alert.json").read_text())
    assert [row["search"] for row in summary["summary"]] == list(SEARCHES)
    for search in SEARCHES:
        traces = [json.loads((out / f"{search}-{k:04d}.json").read_text()) for k in range(6)]
        assert [trace["outcome"] for trace in traces] == summary["outcomes"][search]


def test_two_workers_give_the_same_bytes(files, one_worker, tmp_path: Path) -> None:
    """Two local processes: the same alert.json, the same traces and the same table."""
    reference, reference_out = one_worker
    result = run(files, *EPISODES, "--workers", "2", "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert "on 2 local processes" in result.stderr
    assert contents(tmp_path / "out") == contents(reference_out)
    assert table(result) == table(reference)


def test_resume_runs_only_the_missing_episodes(files, one_worker, tmp_path: Path) -> None:
    """Traces deleted (a run stopped part-way): the same command runs just those, and the folder ends
    byte for byte as the uninterrupted run's; once complete, nothing runs again."""
    reference, reference_out = one_worker
    out = tmp_path / "out"
    out.mkdir()
    for name, data in contents(reference_out).items():
        if name not in ("alert.json", "ripple-0002.json", "team-0005.json", "last-known-0000.json"):
            (out / name).write_bytes(data)
    result = run(files, *EPISODES, "--workers", "2", "--out", out)
    assert result.exit_code == 0, result.output
    assert "running 3 of 24 episodes on 2 local processes (21 already done)" in result.stderr
    assert contents(out) == contents(reference_out)
    assert table(result) == table(reference)
    again = run(files, *EPISODES, "--workers", "2", "--out", out)
    assert again.exit_code == 0, again.output
    assert "all 24 episodes already done" in again.stderr
    assert contents(out) == contents(reference_out)


def test_the_first_episode_run_for_trace_is_not_counted_as_done(files, one_worker, tmp_path: Path) -> None:
    """--trace runs the first episode in this process: it is counted as run, never as 'already done',
    in a new folder and on resume (where it runs again for its trace); the folder and the trace are the
    uninterrupted run's."""
    _, reference_out = one_worker
    out, trace = tmp_path / "out", tmp_path / "first.json"
    fresh = run(files, *EPISODES, "--workers", "1", "--out", out, "--trace", trace)
    assert fresh.exit_code == 0, fresh.output
    assert "running 24 of 24 episodes: the first here for --trace, 23 on 1 worker (this process)\n" in fresh.stderr
    assert "already done" not in fresh.stderr
    assert contents(out) == contents(reference_out)
    assert trace.read_bytes() == (reference_out / "ripple-0000.json").read_bytes()
    (out / "team-0005.json").unlink()
    resumed = run(files, *EPISODES, "--workers", "1", "--out", out, "--trace", trace, "--gif", tmp_path / "a.gif")
    assert resumed.exit_code == 0, resumed.output
    assert (
        "running 2 of 24 episodes: the first here for --trace, --gif, 1 on 1 worker (this process) (22 already done)"
        in resumed.stderr
    )
    again = run(files, *EPISODES, "--workers", "1", "--out", out, "--trace", trace)
    assert again.exit_code == 0, again.output
    assert f"{out}: 23 of 24 episodes already done, the first run here for --trace\n" in again.stderr
    assert contents(out) == contents(reference_out)


def test_episode_k_runs_one_episode_of_the_batch_again_exactly(files, one_worker, tmp_path: Path) -> None:
    """``--episode K`` with the batch's seed writes the trace the batch wrote for episode K, byte for byte
    (the trace records K and the seed); it runs one episode alone, so --episodes and --out are refused."""
    _, reference_out = one_worker
    trace = tmp_path / "again.json"
    result = run(files, "--search", "team", "--spotted", "--seed", "4", "--episode", "4", "--trace", trace)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("alert room: episode 4 of seed 4: ")
    assert trace.read_bytes() == (reference_out / "team-0004.json").read_bytes()
    data = json.loads(trace.read_text())
    assert (data["episode"], data["seed"]) == (4, 4) and data["phase"] >= 0 and data["goal"] is not None
    # A batch of one draws its start from the seed like any batch: episode 0's.
    one = tmp_path / "one.json"
    result = run(files, "--search", "team", "--spotted", "--seed", "4", "--episodes", "1", "--trace", one)
    assert result.exit_code == 0, result.output
    assert one.read_bytes() == (reference_out / "team-0000.json").read_bytes()
    refused = run(files, *EPISODES, "--episode", "4")
    assert refused.exit_code == 2
    assert refused.stderr == (
        "guardsim: error: --episode 4 runs one episode of a batch again: give it without --episodes and --out "
        "(write it with --trace, --gif or --html)\n"
    )


def test_other_options_are_not_resumed(files, one_worker, tmp_path: Path) -> None:
    """A folder holding a run with another seed is refused in one line; nothing is overwritten."""
    _, reference_out = one_worker
    out = tmp_path / "out"
    out.mkdir()
    for name, data in contents(reference_out).items():
        (out / name).write_bytes(data)
    result = run(files, "--episodes", "6", "--search", "all", "--spotted", "--seed", "5", "--out", out)
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and "holds a run with other options (seed: 4 there, 5 here)" in lines[0], result.stderr
    assert contents(out) == contents(reference_out)


def test_workers_and_a_scheduler_address_exclude_each_other(files) -> None:
    result = run(files, *EPISODES, "--workers", "2", "--scheduler", "tcp://127.0.0.1:1")
    assert result.exit_code == 2
    assert "--workers and --scheduler exclude each other" in result.stderr


# -- Dask -----------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """The address of a two-worker local cluster of separate processes, one thread each (as
    tests/test_bench_cluster.py starts one)."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster:  # fmt: skip
        yield cluster.scheduler_address


def test_dask_cluster_gives_the_same_bytes(files, one_worker, scheduler: str, tmp_path: Path) -> None:
    """On a real dask.distributed cluster (workers in other processes, which build their own scenes):
    the same folder and table as in this process."""
    reference, reference_out = one_worker
    result = run(files, *EPISODES, "--scheduler", scheduler, "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert f"on Dask scheduler {scheduler}" in result.stderr
    assert contents(tmp_path / "out") == contents(reference_out)
    assert table(result) == table(reference)


@pytest.mark.slow
def test_scheduler_local_starts_its_own_cluster(files, one_worker, tmp_path: Path) -> None:
    """``--scheduler local --workers 2``: a local Dask cluster of two processes, the same results."""
    pytest.importorskip("distributed")
    reference, reference_out = one_worker
    result = run(files, *EPISODES, "--scheduler", "local", "--workers", "2", "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert "on Dask scheduler tcp://127.0.0.1:" in result.stderr
    assert contents(tmp_path / "out") == contents(reference_out)
    assert table(result) == table(reference)
