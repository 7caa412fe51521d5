"""``guardsim bench --scheduler``: episodes on a real ``distributed.LocalCluster`` give the local rows."""

from __future__ import annotations

import socket
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from guardsim.errors import GuardsimError
from guardsim.experiment.executors import DaskCluster
from tests.common import SQUARE, SQUARE_WITH_HOLE, assert_one_line_error, bench, rows, without_seconds, write_level

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """The address of a two-worker local cluster of separate processes, one thread each."""
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster:  # fmt: skip
        yield cluster.scheduler_address


def test_cluster_rows_equal_local_rows(tmp_path: Path, scheduler: str) -> None:
    """The same batch on the cluster and in this process: identical rows apart from wall time."""
    hole = write_level(tmp_path, SQUARE_WITH_HOLE, "hole.json")
    options = (SQUARE, hole, "--episodes", "3", "--seed", "5", "--max-steps", "400")
    local = bench(*options, "--workers", "1", "--out", tmp_path / "local")
    cluster = bench(*options, "--scheduler", scheduler, "--out", tmp_path / "cluster")
    assert local.exit_code == 0, local.output
    assert cluster.exit_code == 0, cluster.output
    assert f"on Dask scheduler {scheduler} (2 workers now)" in cluster.stderr
    assert len(rows(tmp_path / "local")) == 6
    assert without_seconds(rows(tmp_path / "cluster")) == without_seconds(rows(tmp_path / "local"))
    assert (tmp_path / "cluster" / "summary.json").read_bytes() == (tmp_path / "local" / "summary.json").read_bytes()
    assert cluster.stdout == local.stdout


def test_missing_dask_is_one_line_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Without dask.distributed installed, --scheduler says what to install."""
    monkeypatch.setitem(sys.modules, "distributed", None)  # makes `import distributed` fail as if absent
    hole = write_level(tmp_path, SQUARE_WITH_HOLE)
    line = assert_one_line_error(
        bench(hole, "--scheduler", "tcp://127.0.0.1:8786", "--out", tmp_path), "Dask scheduler"
    )
    assert "pip install 'guardsim[cluster]'" in line


def test_unreachable_scheduler_is_a_guardsim_error() -> None:
    """No scheduler at the address: a one-line GuardsimError naming it, after the timeout."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{probe.getsockname()[1]}"
    with pytest.raises(GuardsimError) as caught:
        DaskCluster(address, timeout=1)
    message = str(caught.value)
    assert message.startswith(f"Dask scheduler {address}: cannot connect to it")
    assert "\n" not in message
