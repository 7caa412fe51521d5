"""How guardsim compiles: one decorator, one cache folder per version of the compiled sources.

numba caches a compiled function under the text of its own file only, so a caller compiled against a
callee in another file would keep running the old callee after that file changed. Here every compiled
function is cached in a folder named after a digest of *all* of guardsim's compiled sources (and the
numba and Python versions): after any edit to any of them the digest changes, the folder is new and
everything is compiled afresh; nothing is ever deleted by hand.

The folder lies under ``$GUARDSIM_CACHE_DIR`` if set, else ``$NUMBA_CACHE_DIR/guardsim``, else
``$XDG_CACHE_HOME/guardsim`` (``~/.cache/guardsim``). Compiling once takes seconds; when it takes more
than :data:`NOTICE_SECONDS` (or ``$GUARDSIM_COMPILE_NOTICE`` seconds) a process says so on one line of
standard error; ``GUARDSIM_COMPILE_NOTICE=0`` silences it.
"""

from __future__ import annotations

import hashlib
import os
import platform
import re
import shutil
import sys
import threading
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numba
from numba.core import config, event, types
from numba.core.errors import NumbaIRAssumptionWarning

__all__ = ["NOTICE_SECONDS", "cache_folder", "compiled_sources", "jit", "silence_notice", "source_digest"]

F = TypeVar("F", bound=Callable[..., Any])

#: The package whose compiled sources the digest covers.
PACKAGE = Path(__file__).resolve().parents[1]
#: A file outside this folder holds compiled code when a line of it applies the decorator.
_COMPILED = re.compile(rb"^\s*@jit\b|=\s*jit\(", re.MULTILINE)
#: Cache folders of other versions kept beside the current one (other checkouts may share the root).
KEEP_OTHER_VERSIONS = 4
#: Compiling for longer than this in one process is said on standard error.
NOTICE_SECONDS = 2.0


def compiled_sources(package: Path = PACKAGE) -> list[Path]:
    """Every file whose text is compiled: all of ``kernels/`` and each module that applies :func:`jit`."""
    kernels = package / "kernels"
    found = []
    for path in sorted(package.rglob("*.py")):
        if path.parent == kernels or _COMPILED.search(path.read_bytes()):
            found.append(path)
    return found


def source_digest(package: Path = PACKAGE) -> str:
    """A digest of the compiled sources and of the compiler that reads them."""
    digest = hashlib.sha256(f"{numba.__version__} {platform.python_version()}".encode())
    for path in compiled_sources(package):
        digest.update(path.relative_to(package).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def _cache_root() -> Path:
    if os.environ.get("GUARDSIM_CACHE_DIR"):
        return Path(os.environ["GUARDSIM_CACHE_DIR"])
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / "guardsim"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "guardsim"


def _prune(root: Path, current: Path) -> None:
    # Other versions' folders are kept a while (another checkout may still use them), then dropped.
    try:
        others = [p for p in root.glob("kernels-*") if p != current and p.is_dir()]
        others.sort(key=lambda p: p.stat().st_mtime, reverse=True)
    except OSError:
        return
    for old in others[KEEP_OTHER_VERSIONS:]:
        shutil.rmtree(old, ignore_errors=True)


def _prepare_folder() -> Path:
    root = _cache_root()
    folder = root / f"kernels-{source_digest()}"
    try:
        if not folder.is_dir():
            folder.mkdir(parents=True, exist_ok=True)
            _prune(root, folder)
        os.utime(folder)
    except OSError:
        # An unwritable cache root: numba then falls back to its own places, or compiles every run.
        pass
    return folder


_FOLDER: Path | None = None


def cache_folder() -> Path:
    """The folder that holds this version's compiled kernels."""
    global _FOLDER
    if _FOLDER is None:
        _FOLDER = _prepare_folder()
    return _FOLDER


def jit(function: F | None = None, *, inline: str = "never") -> Any:
    """Compile ``function`` with numba (no Python objects, GIL released), cached in :func:`cache_folder`.

    Use as ``@jit`` or ``@jit(inline="always")`` (numba then inlines it into compiled callers; called
    from Python it is compiled and cached as any other).
    """

    def decorate(func: F) -> F:
        # numba picks a cached function's folder when it is decorated: point it at this version's.
        saved = config.CACHE_DIR
        config.CACHE_DIR = str(cache_folder())
        try:
            dispatcher = numba.njit(cache=True, nogil=True, inline=inline)(func)
        finally:
            config.CACHE_DIR = saved
        _one_version_per_type(dispatcher)
        return dispatcher

    return decorate if function is None else decorate(function)


def _notice_seconds() -> float | None:
    """Seconds of compiling after which the notice is said; None: never."""
    value = os.environ.get("GUARDSIM_COMPILE_NOTICE", "")
    try:
        seconds = float(value) if value else NOTICE_SECONDS
    except ValueError:
        return NOTICE_SECONDS
    return seconds if seconds > 0 else None


def _one_version_per_type(dispatcher: Any) -> None:
    """Compile ``dispatcher`` once per argument *type* when compiled code calls it.

    numba types a constant argument of a compiled call as its value (``Literal[int](-1)``,
    ``Literal[bool](True)``) and compiles the callee anew for every value it is called with: one fill
    was compiled five times by the bounds alone. No kernel here depends on a constant's value to type, so
    calls resolve on the plain types, as calls from Python do.
    """
    resolve = dispatcher.get_call_template

    def get_call_template(args: tuple[Any, ...], kws: dict[str, Any]) -> Any:
        return resolve(tuple(types.unliteral(a) for a in args), {k: types.unliteral(v) for k, v in kws.items()})

    dispatcher.get_call_template = get_call_template


class _CompileNotice(event.Listener):
    """Says once per process, on standard error, that guardsim is compiling, if that takes a while."""

    def __init__(self) -> None:
        self.depth = 0
        self.began = 0.0
        self.spent = 0.0
        self.said = False
        self.timer: threading.Timer | None = None

    def on_start(self, event: Any) -> None:
        if self.depth == 0:
            self.began = time.perf_counter()
            seconds = _notice_seconds()
            if self.timer is None and not self.said and seconds is not None:
                self.timer = threading.Timer(seconds, self._still_compiling)
                self.timer.daemon = True
                self.timer.start()
        self.depth += 1

    def on_end(self, event: Any) -> None:
        self.depth -= 1
        if self.depth == 0:
            self.spent += time.perf_counter() - self.began
            seconds = _notice_seconds()
            if seconds is not None and self.spent > seconds:
                self._say()

    def _still_compiling(self) -> None:
        if self.depth > 0:
            self._say()

    def _say(self) -> None:
        if self.said:
            return
        self.said = True
        stream = sys.__stderr__
        if stream is not None:
            print(
                f"guardsim: compiling kernels once for this version (kept in {cache_folder()}; "
                "`guardsim compile` compiles every command's at once)",
                file=stream,
            )
            stream.flush()


# numba asks users to report this internal check of its own IR ("variable ... is not in scope") while it
# compiles some loops correctly; it says nothing about guardsim's results, so a user never sees it.
warnings.filterwarnings("ignore", category=NumbaIRAssumptionWarning)

_NOTICE = _CompileNotice()
event.register("numba:compile", _NOTICE)


def silence_notice() -> None:
    """Say nothing more about compiling in this process (a helper process of one that says it)."""
    _NOTICE.said = True
