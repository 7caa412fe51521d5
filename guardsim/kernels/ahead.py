"""Compiling ahead, on two cores: the first run of a command compiles its kernels in two processes.

numba compiles a function the first time it is called, one after another, on one core. A command's
kernels are known in advance, though: ``plan.json`` beside this file lists, per command, every compiled
function the command compiles (those it calls from Python and, where their argument types can be
written down, the kernels those call), with the argument types, in the order compiling them ended
(recorded by ``python benchmarks/compile_plan.py``). On a cache folder that has not yet seen the
command, :func:`compile_ahead` deals that list out to two processes so that both finish about together
(a callee the other process has not compiled yet is counted where it would be compiled twice); a forked
process compiles its share while this one compiles the other, both into the same cache, and then the
command runs on cached code. Later runs find the folder's mark and skip it.

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
from functools import cache
from pathlib import Path
from typing import Any

import numba
import numpy as np
from numba.core import types

from guardsim.kernels.compiler import cache_folder, silence_notice

__all__ = ["PLAN_FILE", "compile_ahead", "decode_type", "encode_type", "plan"]

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


def _halves(entries: list[list[Any]]) -> tuple[list[list[Any]], list[list[Any]]]:
    """The plan split between this process and the helper, each list in the plan's order.

    The plan lists functions in the order their compiling ended, callees before callers, each with its
    own compile time (callees excluded). Entries are dealt out in that order, each to the process that
    would be done with it first: a process that reaches a caller before the other has compiled one of
    its callees (any earlier entry its code reaches) compiles that callee too, and the cost is counted;
    one that finds it compiled loads it from the cache.
    """
    # What compiling an entry compiles too: the earlier entries whose functions its code reaches (a
    # callee compiled first for another caller is recorded under that one, not under this).
    names = [_entry_name(entry) for entry in entries]
    below: list[list[int]] = []
    for index, entry in enumerate(entries):
        reached = _compiled_with(entry) - {names[index]}
        below.append([earlier for earlier in range(index) if names[earlier] in reached])
    clock = [0.0, 0.0]
    side = [0] * len(entries)
    finish = [0.0] * len(entries)
    for index, entry in enumerate(entries):
        best: tuple[float, int] | None = None
        for process in (0, 1):
            start = clock[process]
            extra = sum(
                float(entries[callee][3])
                for callee in below[index]
                if side[callee] != process and finish[callee] > start
            )
            done = start + float(entry[3]) + extra
            if best is None or done < best[0]:
                best = (done, process)
        assert best is not None
        finish[index], side[index] = best
        clock[best[1]] = best[0]
    return (
        [entry for index, entry in enumerate(entries) if side[index] == 0],
        [entry for index, entry in enumerate(entries) if side[index] == 1],
    )


def compile_ahead(command: str) -> None:
    """Compile (or load) every kernel ``command`` will call, on two processes if it was never compiled.

    Quick when done before: once per process, and once per cache folder (a mark file). Never raises:
    an entry that fails to compile is left to be compiled, and its error reported, when it is called.
    """
    if command in _DONE or os.environ.get("GUARDSIM_COMPILE_AHEAD") == "0":
        return
    _DONE.add(command)
    entries = plan().get(command, [])
    mark = cache_folder() / f"ahead-{command}"
    if not entries or mark.exists():
        return
    mine, theirs = _halves(entries)
    # Set numba's compiler up once, here (a first compile sets up most of it), so that the forked
    # helper starts with it ready.
    numba.njit(_warm_up)(np.zeros(1, dtype=np.int64))
    helper = None
    if theirs and "fork" in multiprocessing.get_all_start_methods():
        helper = multiprocessing.get_context("fork").Process(target=_helper, args=(theirs,), daemon=True)
        helper.start()
    else:
        mine = entries
    _compile_quietly(mine)
    if helper is not None:
        helper.join()
    with contextlib.suppress(OSError):  # an unwritable cache: the next run compiles ahead again, no harm
        mark.touch()


def _warm_up(values: np.ndarray) -> int:
    return int(values.sum()) + values.shape[0]


def _helper(entries: list[list[Any]]) -> None:
    silence_notice()  # this process has said it already, or will
    _compile_quietly(entries)


def _compile_quietly(entries: list[list[Any]]) -> None:
    # A stale entry only costs time; the call it stood for compiles, and reports, on its own.
    for entry in entries:
        try:
            _compile(entry)
        except Exception:
            continue
