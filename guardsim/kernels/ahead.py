"""Compiling ahead, on two cores: the first run of a command compiles its kernels in two processes.

numba compiles a function the first time it is called, one after another, on one core. A command's
kernels are known in advance, though: ``plan.json`` beside this file lists, per command, every compiled
function the command compiles (those it calls from Python and, where their argument types can be
written down, the kernels those call), with the argument types, in the order compiling them ended
(recorded by ``python benchmarks/compile_plan.py``). On a cache folder that has not yet seen the
command, :func:`compile_ahead` forks a helper process and both work down that list together, each
taking the next entry it can (:func:`take`: one whose callees are compiled, the longest chain of
callers above it first) into the same cache; then the command runs on cached code. Later runs find the folder's mark and skip it.

:func:`compile_kernels` (``guardsim compile``, the install step) does the same for every command's plan at
once, so that no command's first run compiles.

A plan that no longer matches the code (a function renamed, its argument types changed) costs only
time: what compiling ahead missed is compiled when first called, as without it, and ``tests/
test_kernels.py`` checks that the plan is current.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import multiprocessing
import os
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numba
import numpy as np
from numba.core import types

from guardsim.errors import ArgumentError, GuardsimError
from guardsim.kernels.compiler import cache_folder, silence_notice

__all__ = [
    "PLAN_FILE",
    "SHARED_PLANS",
    "CompiledKernels",
    "compile_ahead",
    "compile_kernels",
    "decode_type",
    "encode_type",
    "plan",
    "plans_of",
    "take",
    "urgency",
]

#: The recorded plan: ``{command: [[module, function, [argument type, ...], seconds, caller], ...]}``, ``seconds``
#: the function's own compile time (its planned callees excluded), ``caller`` the index of the entry it was
#: compiled under (-1: called from Python).
PLAN_FILE = Path(__file__).with_name("plan.json")

_DONE: set[str] = set()


def encode_type(value: Any) -> Any:
    """A numba argument type as plain JSON data (arrays, scalars and named tuples of them)."""
    if isinstance(value, types.Array):
        return {"array": str(np.dtype(str(value.dtype))), "ndim": value.ndim, "layout": value.layout,
                "readonly": not value.mutable}  # fmt: skip
    if isinstance(value, types.BaseNamedTuple):
        cls = value.instance_class
        return {"tuple": f"{cls.__module__}:{cls.__qualname__}", "fields": [encode_type(t) for t in value.types]}
    if isinstance(value, (types.Integer, types.Float, types.Boolean)):
        return str(np.dtype(str(value)))
    raise TypeError(f"no plan encoding for the numba type {value}")


def decode_type(data: Any) -> Any:
    """The numba type of :func:`encode_type`'s data."""
    if isinstance(data, str):
        return numba.from_dtype(np.dtype(data))
    if "array" in data:
        dtype = numba.from_dtype(np.dtype(data["array"]))
        return types.Array(dtype, data["ndim"], data["layout"], readonly=data["readonly"])
    module, _, name = data["tuple"].partition(":")
    cls = getattr(importlib.import_module(module), name)
    return types.BaseTuple.from_types([decode_type(field) for field in data["fields"]], cls)


@cache
def plan() -> dict[str, list[list[Any]]]:
    """The recorded plan (empty if the file is missing)."""
    try:
        loaded: dict[str, list[list[Any]]] = json.loads(PLAN_FILE.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return loaded


def _dispatcher(entry: list[Any]) -> Any:
    return getattr(importlib.import_module(entry[0]), entry[1])


def _entry_name(entry: list[Any]) -> str:
    return f"{entry[0]}:{entry[1]}"


def _compiled_with(entry: list[Any]) -> set[str]:
    """The compiled functions that compiling ``entry``'s function compiles: itself and, recursively,
    every compiled function its code names (``module:name``; empty when the entry is stale)."""
    try:
        waiting = [_dispatcher(entry)]
    except (ImportError, AttributeError):
        return set()
    found: set[str] = set()
    while waiting:
        function = waiting.pop()
        python = getattr(function, "py_func", None)
        if python is None:
            continue
        name = f"{python.__module__}:{python.__name__}"
        if name in found:
            continue
        found.add(name)
        for word in python.__code__.co_names:
            named = python.__globals__.get(word)
            if hasattr(named, "py_func"):
                waiting.append(named)
    return found


def _compile(entry: list[Any]) -> None:
    _dispatcher(entry).compile(tuple(decode_type(argument) for argument in entry[2]))


#: An entry's state in the table both processes share: free, being compiled, compiled.
FREE, TAKEN, COMPILED = 0, 1, 2
#: Seconds a process waits before looking again when every free entry waits on a callee being compiled.
_POLL = 0.005


def _callees(entries: list[list[Any]]) -> list[list[int]]:
    """For each entry, the earlier entries whose functions compiling it compiles too (its code reaches
    them: a callee compiled first for another caller is recorded under that one, not under this)."""
    names = [_entry_name(entry) for entry in entries]
    below: list[list[int]] = []
    for index, entry in enumerate(entries):
        reached = _compiled_with(entry) - {names[index]}
        below.append([earlier for earlier in range(index) if names[earlier] in reached])
    return below


def urgency(entries: list[list[Any]], below: list[list[int]]) -> list[float]:
    """For each entry, the recorded seconds of compiling from its start to the end of the longest chain
    of callers above it (itself included): what must still be compiled, one after another, once it is."""
    chain = [float(entry[3]) for entry in entries]
    for index in range(len(entries) - 1, -1, -1):
        for callee in below[index]:
            chain[callee] = max(chain[callee], float(entries[callee][3]) + chain[index])
    return chain


def take(state: Any, below: list[list[int]], chain: list[float]) -> int | None:
    """The entry a process compiles next, marked taken in ``state``: among the free entries whose
    callees are all compiled, the one with the longest ``chain`` of callers still to compile above it
    (the first in the plan's order on a tie); -1 when none is free; None when the free ones wait on
    callees the other process is compiling.

    Both processes take entries from the one table, each when it is done with one, so neither sits idle
    while the other has a long list left (a split made in advance from recorded compile times, which
    vary by half from run to run, left one process up to 1.6 s behind on ``bounds``), and the longest
    chain goes first, so that its last caller does not end up compiling alone (``optimum``'s search
    started 5.8 s in, taking the plan in order, and the other process was idle for its last 1.5 s).
    """
    best = -1
    waiting = False
    for index, callees in enumerate(below):
        if state[index] != FREE:
            continue
        if any(state[callee] != COMPILED for callee in callees):
            waiting = True
            continue
        if best < 0 or chain[index] > chain[best]:
            best = index
    if best >= 0:
        state[best] = TAKEN
        return best
    return None if waiting else -1


def _work(entries: list[list[Any]], below: list[list[int]], chain: list[float], state: Any) -> None:
    """Compile entries taken from the shared ``state`` until none is left."""
    while True:
        with state.get_lock():
            index = take(state, below, chain)
        if index is None:
            time.sleep(_POLL)
            continue
        if index < 0:
            return
        _compile_quietly([entries[index]])
        with state.get_lock():
            state[index] = COMPILED


def compile_ahead(command: str) -> None:
    """Compile (or load) every kernel ``command`` will call, on two processes if it was never compiled.

    Quick when done before: once per process, and once per cache folder (a mark file). Never raises:
    an entry that fails to compile is left to be compiled, and its error reported, when it is called.
    """
    if command in _DONE or os.environ.get("GUARDSIM_COMPILE_AHEAD") == "0":
        return
    _DONE.add(command)
    if plan().get(command) and not _mark(command).exists():
        _compile_plans([command], None)


@dataclass(frozen=True)
class CompiledKernels:
    """What :func:`compile_kernels` made ready: the commands asked for (empty: every command), the plans
    they use, the compiled functions those list (each once, however many plans share it), whether all
    were compiled before, and where they are kept."""

    commands: tuple[str, ...]
    plans: tuple[str, ...]
    functions: int
    already: bool
    folder: Path
    writable: bool
    """Whether ``folder`` could be written (if not, numba kept the kernels in its own places, if any)."""


#: ``progress(what, done, total)``: the library's progress callback (functions compiled of the total).
Progress = Callable[[str, int, int], None]

#: Commands that run another command's work, and so compile its plan too (``check --baseline`` analyses
#: the level as ``report`` does, ``check --unheard`` searches as ``sneak --unheard``).
SHARED_PLANS = {"diff": ("report",), "watch": ("report",), "check": ("report", "sneak:unheard")}


def plans_of(command: str) -> tuple[str, ...]:
    """The plans a ``guardsim`` command (``patrol``) or a plan's own name (``patrol:team``) compiles: the
    command's own (``patrol``, ``patrol:team``) and those of the analysis it shares; empty when none."""
    known = plan()
    if command in known and ":" in command:
        return (command,)
    own = [name for name in known if name == command or name.startswith(f"{command}:")]
    return tuple(dict.fromkeys([*own, *SHARED_PLANS.get(command, ())]))


def compile_kernels(
    commands: str | Sequence[str] | None = None, *, progress: Progress | None = None
) -> CompiledKernels:
    """Compile every kernel the ``commands`` call (``guardsim`` command names such as ``"sneak"`` or
    ``"diff"``, or plan names such as ``"play:tour"``; all of them by default), on two processes, into
    :func:`~guardsim.kernels.compiler.cache_folder`, so that their first runs load them instead.

    The install step (``guardsim compile``): commands share most of their kernels, so compiling every plan
    at once takes far less than compiling each on its command's first run. A plan already compiled in the
    folder (its mark there) is not compiled again. Raises :class:`~guardsim.ArgumentError` naming a name that is
    neither a command that compiles nor a plan.
    """
    known = plan()
    if not known:
        raise GuardsimError(f"{PLAN_FILE}: no compile plans (the file is missing or unreadable): reinstall guardsim")
    asked = (commands,) if isinstance(commands, str) else tuple(dict.fromkeys(commands or ()))
    unknown = [name for name in asked if not plans_of(name)]
    if unknown:
        commands_that_compile = sorted({name.partition(":")[0] for name in known} | set(SHARED_PLANS))
        raise ArgumentError(
            f"no compiled kernels for {', '.join(unknown)}: the commands that compile are "
            f"{', '.join(commands_that_compile)} (the others need none), the plans {', '.join(known)}"
        )
    chosen = tuple(dict.fromkeys(name for command in asked for name in plans_of(command))) if asked else tuple(known)
    entries = _union(chosen)
    already = all(_mark(name).exists() for name in chosen)
    if not already:
        silence_notice()  # compiling is what was asked for: no notice that it compiles
        _compile_plans(list(chosen), progress)
    folder = cache_folder()
    writable = folder.is_dir() and os.access(folder, os.W_OK)
    return CompiledKernels(asked, chosen, len(entries), already, folder, writable)


def _mark(command: str) -> Path:
    """The file that says ``command``'s plan has been compiled into this cache folder."""
    return cache_folder() / f"ahead-{command.replace(':', '-')}"


def _key(entry: list[Any]) -> str:
    return f"{entry[0]}:{entry[1]}:{json.dumps(entry[2], sort_keys=True)}"


def _union(commands: Sequence[str]) -> list[list[Any]]:
    """The plans' entries, each function and argument types once, callees still before their callers
    (in every plan a callee is compiled before its caller, so its first appearance comes first too)."""
    entries: dict[str, list[Any]] = {}
    for command in commands:
        for entry in plan().get(command, []):
            key = _key(entry)
            # The longest recorded time of the function: what scheduling it by its chain should assume.
            first = entries.get(key, entry)
            entries[key] = [*first[:3], max(float(entry[3]), float(first[3])), -1]
    return list(entries.values())


def _compile_plans(commands: list[str], progress: Progress | None) -> None:
    """Compile the plans of ``commands`` on two processes (one where the system cannot fork), then mark them."""
    entries = _union(commands)
    # Set numba's compiler up once, here (a first compile sets up most of it), so that the forked
    # helper starts with it ready.
    numba.njit(_warm_up)(np.zeros(1, dtype=np.int64))
    if "fork" in multiprocessing.get_all_start_methods() and len(entries) > 1:
        context = multiprocessing.get_context("fork")
        below = _callees(entries)
        chain = urgency(entries, below)
        state = context.Array("b", len(entries))
        watcher = _Watcher(state, progress) if progress is not None else None
        helper = context.Process(target=_helper, args=(entries, below, chain, state), daemon=True)
        helper.start()
        try:
            _work(entries, below, chain, state)
            helper.join()
        finally:
            if watcher is not None:
                watcher.stop()
    else:
        for done, entry in enumerate(entries):
            if progress is not None:
                progress("compiling kernels", done, len(entries))
            _compile_quietly([entry])
    if progress is not None:
        progress("compiling kernels", len(entries), len(entries))
    for command in commands:
        with contextlib.suppress(OSError):  # an unwritable cache: the next run compiles ahead again, no harm
            _mark(command).touch()


class _Watcher:
    """Tells ``progress`` how many entries both processes have compiled, five times a second."""

    def __init__(self, state: Any, progress: Progress) -> None:
        self.state = state
        self.progress = progress
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="guardsim-compile-progress", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(0.2):
            done = sum(1 for value in self.state[:] if value == COMPILED)
            self.progress("compiling kernels", done, len(self.state))

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()


def _warm_up(values: np.ndarray) -> int:
    # Indexing only: a reduction (``values.sum()``) doubled the time, 0.2 -> 0.4 s, before the fork, and
    # the kernels no longer use one (guardsim.kernels.arrays).
    return int(values[0]) + values.shape[0]


def _helper(entries: list[list[Any]], below: list[list[int]], chain: list[float], state: Any) -> None:
    silence_notice()  # this process has said it already, or will
    _work(entries, below, chain, state)


def _compile_quietly(entries: list[list[Any]]) -> None:
    # A stale entry only costs time; the call it stood for compiles, and reports, on its own.
    for entry in entries:
        try:
            _compile(entry)
        except Exception:
            continue
