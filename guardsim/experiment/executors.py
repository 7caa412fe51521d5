"""Where a batch's episodes run: in this process, in a pool of local processes, or on a Dask cluster.

The three share one small interface, :class:`EpisodeExecutor`: a context manager whose
:meth:`~EpisodeExecutor.run_unordered` applies a function to items and yields a :class:`Completion` per
item as it finishes. The function must be importable (a module-level function) and its items picklable.
A failure of the machinery (a worker process killed, a Dask worker lost for good) comes back as the
completion's ``failure``; errors inside the function are the function's business. Leaving the ``with``
block early (Ctrl-C included) cancels what has not started.
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from types import TracebackType
from typing import Any, NamedTuple, Protocol

from guardsim.errors import GuardsimError

__all__ = [
    "Completion",
    "DaskCluster",
    "EpisodeExecutor",
    "InProcess",
    "LocalPool",
    "default_start_method",
    "make_executor",
]


class Completion(NamedTuple):
    """One item done, or lost."""

    item: Any
    """The item as submitted."""
    result: Any
    """What the function returned; ``None`` if :attr:`failure` is set."""
    failure: BaseException | None
    """Why the item did not run to the end (a dead worker, a cancelled task); ``None`` when it did."""


class EpisodeExecutor(Protocol):
    """Runs a function over items somewhere and hands back each result as it finishes."""

    description: str
    """Where the work runs, for messages: ``2 local processes``."""

    @property
    def forked_workers(self) -> int:
        """How many workers start as copies of this process (``fork``), so that what it computed before
        the first :meth:`run_unordered` (scenes, view tables, compiled code) is theirs for free; 0 for none."""
        ...

    def __enter__(self) -> EpisodeExecutor: ...

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, traceback: TracebackType | None
    ) -> None: ...

    def run_unordered(self, function: Callable[[Any], Any], items: Sequence[Any]) -> Iterator[Completion]:
        """Yield one :class:`Completion` per item, in the order they finish."""
        ...


class InProcess:
    """Runs every item here, one after the other: the reference, and the simplest to debug."""

    description = "1 worker (this process)"
    forked_workers = 0

    def __enter__(self) -> InProcess:
        return self

    def __exit__(self, *_exc: object) -> None:
        return None

    def run_unordered(self, function: Callable[[Any], Any], items: Sequence[Any]) -> Iterator[Completion]:
        """Call ``function`` on each item in turn."""
        for item in items:
            yield Completion(item, function(item), None)


def default_start_method() -> str:
    """``fork`` on Linux while this process runs a single thread, else ``forkserver`` where the platform
    has it, else ``spawn``.

    A forked worker starts as a copy of this process: guardsim imported, compiled code loaded, and every
    scene, vision cache and view table built so far, where a ``forkserver`` worker builds its own
    (``guardsim bench`` with bounds: 0.7 s of CPU per worker; see ``docs/performance.md``). Not with a
    second thread running: it could be mid-way through pymunk's Chipmunk state or hold a lock (a
    progress display, Dask's event loop), and the copy would keep that state with no thread to finish it.
    Nor on macOS, whose system libraries do not survive ``fork``.
    """
    if sys.platform.startswith("linux") and threading.active_count() == 1:
        return "fork"
    return "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"


#: Seconds between a worker's checks that the process that started the pool is still alive.
PARENT_CHECK_SECONDS = 0.5


def _start_worker(parent: int) -> None:
    """Set up a pool worker: ignore Ctrl-C, and exit as soon as ``parent`` (the process that made the
    pool) is gone.

    Ctrl-C reaches every process of the terminal's foreground group; only the parent should react, by
    cancelling what has not started, so that workers do not print tracebacks on the way out. A parent
    killed with SIGKILL cannot shut its pool down, and its workers would run on (each holding a core);
    the kernel's parent-death signal covers the worker's direct parent (ours when forked, else the fork
    server, which exits with ours), and a watchdog thread covers the rest, on any platform.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _exit_with_parent()
    threading.Thread(target=_watch_parent, args=(parent,), name="guardsim-parent-watch", daemon=True).start()


def _exit_with_parent() -> None:
    """Ask Linux to send SIGKILL when this process's parent dies (``prctl(PR_SET_PDEATHSIG)``)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # 1 is PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass  # the watchdog thread still stops the worker


def _watch_parent(parent: int) -> None:
    """Exit when ``parent`` is gone, or a zombie nobody has reaped yet, or this process was re-parented."""
    direct = os.getppid()
    while True:
        time.sleep(PARENT_CHECK_SECONDS)
        if os.getppid() != direct or not _alive(parent):
            os._exit(1)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as stat_file:
            # The state follows the command name in parentheses: "Z" is a zombie, dead but not reaped.
            return stat_file.read().rsplit(")", 1)[-1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


class LocalPool:
    """A pool of worker processes on this machine (:class:`concurrent.futures.ProcessPoolExecutor`).

    The processes start at the first :meth:`run_unordered`, not on entering the ``with`` block, so that
    forked ones (:attr:`forked_workers`) start with what this process computed until then.

    Parameters
    ----------
    workers
        Number of processes.
    start_method
        ``multiprocessing`` start method; :func:`default_start_method` (at the first
        :meth:`run_unordered`) by default.
    preload
        Modules the ``forkserver`` imports before forking workers, e.g. the one defining the function.
    """

    def __init__(self, workers: int, start_method: str | None = None, preload: Sequence[str] = ()) -> None:
        self.workers = workers
        self.preload = tuple(preload)
        self.start_method = start_method
        self.description = f"{workers} local processes"
        self._entered = False
        self._pool: concurrent.futures.ProcessPoolExecutor | None = None

    @property
    def forked_workers(self) -> int:
        """:attr:`workers` if they will be forked from this process (so far as can be told before they
        start: a thread started in between makes them ``forkserver`` ones), else 0."""
        return self.workers if (self.start_method or default_start_method()) == "fork" else 0

    def __enter__(self) -> LocalPool:
        self._entered = True
        return self

    def __exit__(self, *_exc: object) -> None:
        self._entered = False
        if self._pool is not None:
            # Running items finish (an episode is short); queued ones are dropped.
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def _started_pool(self) -> concurrent.futures.ProcessPoolExecutor:
        if not self._entered:
            raise RuntimeError("LocalPool.run_unordered called outside its with block")
        if self._pool is None:
            method = self.start_method or default_start_method()
            context = multiprocessing.get_context(method)
            if method == "forkserver":
                # Import guardsim once in the fork server rather than once in each worker.
                context.set_forkserver_preload(list(self.preload))
            # With fork the executor forks every worker at the first submit, before it starts its own
            # thread; the others start theirs when work arrives.
            self._pool = concurrent.futures.ProcessPoolExecutor(
                self.workers, mp_context=context, initializer=_start_worker, initargs=(os.getpid(),)
            )
        return self._pool

    def run_unordered(self, function: Callable[[Any], Any], items: Sequence[Any]) -> Iterator[Completion]:
        """Submit a few chunks of items per worker at a time, so that stopping early leaves little queued.

        A chunk holds about :data:`CHUNK_SECONDS` of work, going by the items done so far (one item until
        the first chunk is back): an episode of a small level takes 3 ms, and sending each alone cost
        as much CPU again in the pool's machinery. Which items share a chunk changes nothing in their
        results, only in how often the workers and this process talk.
        """
        pool = self._started_pool()
        window = 2 * self.workers
        queue = list(items)
        sent = 0
        size = 1
        running: dict[concurrent.futures.Future[Any], list[Any]] = {}
        broken: BaseException | None = None
        while True:
            while broken is None and len(running) < window and sent < len(queue):
                # Never so large that the last chunks leave a worker idle.
                count = max(1, min(size, (len(queue) - sent) // window))
                chunk = queue[sent : sent + count]
                sent += count
                try:
                    running[pool.submit(_run_chunk, function, chunk)] = chunk
                except concurrent.futures.BrokenExecutor as lost:
                    broken = lost
                    yield from (Completion(item, None, lost) for item in chunk)
            if not running:
                break
            done, _ = concurrent.futures.wait(running, return_when=concurrent.futures.FIRST_COMPLETED)
            for future in done:
                chunk = running.pop(future)
                error = future.exception()
                if error is not None:
                    if isinstance(error, concurrent.futures.BrokenExecutor):
                        broken = broken or error
                    yield from (Completion(item, None, error) for item in chunk)
                    continue
                outcomes, seconds = future.result()
                size = max(1, min(MOST_CHUNK, int(CHUNK_SECONDS * len(chunk) / max(seconds, 1e-9))))
                for item, (finished, value) in zip(chunk, outcomes):
                    yield Completion(item, value, None) if finished else Completion(item, None, value)
        if broken is not None:
            for item in queue[sent:]:
                yield Completion(item, None, broken)


#: Seconds of work :meth:`LocalPool.run_unordered` puts in one chunk, going by the items done so far.
CHUNK_SECONDS = 0.05
#: Most items in one chunk.
MOST_CHUNK = 64


def _run_chunk(function: Callable[[Any], Any], items: Sequence[Any]) -> tuple[list[tuple[bool, Any]], float]:
    """``(True, result)`` or ``(False, exception)`` per item, and the seconds the chunk took (a pool worker
    runs this)."""
    began = time.perf_counter()
    outcomes: list[tuple[bool, Any]] = []
    for item in items:
        try:
            outcomes.append((True, function(item)))
        except Exception as error:
            outcomes.append((False, error))
    return outcomes, time.perf_counter() - began


class DaskCluster:
    """The workers of a running ``dask.distributed`` scheduler (``pip install 'guardsim[cluster]'``).

    Parameters
    ----------
    address
        The scheduler, e.g. ``tcp://host:8786``.
    timeout
        Seconds to wait for the connection.
    """

    def __init__(self, address: str, timeout: float = 10.0) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise GuardsimError(
                "running on a Dask scheduler needs dask.distributed, which is not installed: "
                "pip install 'guardsim[cluster]'"
            ) from None
        try:
            self._client = Client(address, timeout=timeout, set_as_default=False)
        except (OSError, ValueError, TypeError) as error:
            message = " ".join(str(error).split()) or type(error).__name__
            raise GuardsimError(f"Dask scheduler {address}: cannot connect to it: {message}") from None
        workers = len(self._client.scheduler_info().get("workers", {}))
        self.description = f"Dask scheduler {address} ({workers} worker{'' if workers == 1 else 's'} now)"
        self.forked_workers = 0
        self._futures: list[Any] = []

    def __enter__(self) -> DaskCluster:
        return self

    def __exit__(self, *_exc: object) -> None:
        pending = [future for future in self._futures if not future.done()]
        if pending:
            self._client.cancel(pending)
        self._futures = []
        self._client.close()

    def run_unordered(self, function: Callable[[Any], Any], items: Sequence[Any]) -> Iterator[Completion]:
        """Send every item to the scheduler at once (it balances them) and yield them as they finish.

        A worker lost mid-task is retried by the scheduler; only a task that keeps killing workers comes
        back as a failure (``KilledWorker``).
        """
        from distributed import as_completed

        items = list(items)
        if not items:
            return
        self._futures = self._client.map(function, items, pure=False)
        item_of = {future.key: item for future, item in zip(self._futures, items)}
        for future in as_completed(self._futures, loop=self._client.loop):
            item = item_of[future.key]
            if future.status == "finished":
                yield Completion(item, future.result(), None)
            else:
                yield Completion(item, None, future.exception())
            future.release()


def make_executor(
    workers: int | None = None, scheduler: str | None = None, preload: Sequence[str] = ()
) -> EpisodeExecutor:
    """The executor for ``--workers`` and ``--scheduler``: Dask if a scheduler is given, else local.

    ``workers`` defaults to the number of cores; 1 runs in this process. ``preload`` is passed to
    :class:`LocalPool`.
    """
    if scheduler is not None:
        return DaskCluster(scheduler)
    count = workers if workers is not None else os.cpu_count() or 1
    return InProcess() if count == 1 else LocalPool(count, preload=preload)
