"""Where compiling a command's kernels goes: numba's own stages and LLVM's, in seconds of one core.

Compiles one plan of ``guardsim/kernels/plan.json`` (``report`` by default) in this process, in order,
into an empty cache folder, with compiling ahead off, and prints the compile time split by what did it:
LLVM's per-function optimisation, its optimisation of each function with its linked callees, its code
generation, and numba's own passes (type inference, lowering, the rest) by their recorded times. This is
why a first run on an empty cache cannot be much shorter than half its compiling on two cores.

    python benchmarks/compile_stages.py [PLAN] [--opt 0-3]
"""

from __future__ import annotations

import argparse
import collections
import gc
import os
import sys
import tempfile
import time
from typing import Any


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plan", nargs="?", default="report", help="a plan's name (default: report)")
    parser.add_argument("--opt", choices="0123", help="numba's LLVM optimisation level (NUMBA_OPT; default 3)")
    args = parser.parse_args()
    if args.opt is not None:
        os.environ["NUMBA_OPT"] = args.opt
    with tempfile.TemporaryDirectory() as folder:
        os.environ.update(GUARDSIM_CACHE_DIR=folder, GUARDSIM_COMPILE_AHEAD="0", GUARDSIM_COMPILE_NOTICE="0")
        measure(args.plan)


def measure(name: str) -> None:
    from numba.core import codegen
    from numba.core.registry import CPUDispatcher

    from guardsim.kernels import ahead

    spent: collections.Counter[str] = collections.Counter()

    def timed(cls: Any, method: str, label: str) -> None:
        original = getattr(cls, method)

        def wrapper(*args: Any, **kwargs: Any) -> Any:
            began = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                spent[label] += time.perf_counter() - began

        setattr(cls, method, wrapper)

    library = codegen.CPUCodeLibrary
    timed(library, "_optimize_functions", "LLVM: optimising each function")
    timed(library, "_optimize_final_module", "LLVM: optimising each function with its linked callees")
    timed(library, "_finalize_final_module", "LLVM: generating machine code")
    entries = ahead.plan().get(name)
    if not entries:
        sys.exit(f"no plan named {name!r}; the plans are {', '.join(ahead.plan())}")
    began = time.perf_counter()
    for entry in entries:
        ahead._compile(entry)
    total = time.perf_counter() - began
    passes: collections.Counter[str] = collections.Counter()
    overloads = 0
    for found in gc.get_objects():
        if isinstance(found, CPUDispatcher) and found.py_func.__module__.startswith("guardsim"):
            for result in found.overloads.values():
                overloads += 1
                for times in result.metadata.get("pipeline_times", {}).values():
                    for key, value in times.items():
                        passes[key.split("_", 1)[1]] += value.init + value.run + value.finalize
    llvm = sum(spent.values())
    lowering = passes.pop("native_lowering", 0.0) - llvm  # numba's lowering pass runs LLVM inside it
    typing = passes.pop("nopython_type_inference", 0.0)
    print(f"plan {name}: {len(entries)} entries, {overloads} compiled versions, {total:.1f} s of one core")
    for label, seconds in sorted(spent.items()):
        print(f"  {seconds:5.1f} s  {label}")
    print(f"  {lowering:5.1f} s  numba: lowering to LLVM IR (its Python)")
    print(f"  {typing:5.1f} s  numba: type inference")
    print(f"  {sum(passes.values()):5.1f} s  numba: its other passes (bytecode, rewrites, inlining, SSA)")
    print(f"  {total - llvm - lowering - typing - sum(passes.values()):5.1f} s  the rest (caching, dispatch)")


if __name__ == "__main__":
    main()
