"""Writing files so that an interruption never leaves a half-written one behind.

A target that exists and is not a regular file is never renamed over: a character device (``/dev/null``,
a terminal) is written in place, which is what a user naming it means, and anything else (a FIFO, a
socket, a block device) is refused, since writing to it could block or destroy data.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

from guardsim.errors import OutputError

__all__ = ["atomic_path", "check_writable", "write_text_atomic"]


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path beside ``target``; rename it onto ``target`` only if the block succeeds.

    The temporary file keeps ``target``'s suffix so that writers choosing a format by extension work.
    A reader of ``target`` sees the old file or the new one, never a partial one.
    """
    target = Path(target)
    special = _special_kind(target)
    if special == "a character device":
        # Written in place: renaming over /dev/null would replace the device with a regular file.
        try:
            yield target
        except OSError as error:
            raise OutputError(f"{target}: cannot write: {error.strerror or error}") from None
        return
    if special:
        raise OutputError(f"{target}: is {special}, not a regular file; guardsim writes outputs to files only")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise OutputError(f"{target}: folder {folder} does not exist")
    try:
        handle, name = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=f".part{target.suffix}")
    except OSError as error:
        raise OutputError(f"{target}: cannot write: {error.strerror or error}") from None
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        # mkstemp makes the file private (0600); give it the mode a plain open() would have.
        os.chmod(temporary, target.stat().st_mode & 0o777 if target.exists() else 0o666 & ~_umask())
        os.replace(temporary, target)
    except OSError as error:
        raise OutputError(f"{target}: cannot write: {error.strerror or error}") from None
    finally:
        with contextlib.suppress(FileNotFoundError):
            temporary.unlink()


def check_writable(target: str | os.PathLike[str]) -> None:
    """Raise the :class:`OutputError` writing ``target`` would raise for a reason known now (it is a
    folder or a special file, or its folder does not exist), so a command can refuse before its work."""
    target = Path(target)
    special = _special_kind(target)
    if special and special != "a character device":
        raise OutputError(f"{target}: is {special}, not a regular file; guardsim writes outputs to files only")
    if target.is_dir():
        raise OutputError(f"{target}: cannot write: Is a directory")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise OutputError(f"{target}: folder {folder} does not exist")
    # A folder may exist and still take no files (/proc, a read-only mount, no permission): trying is
    # the only sure test, and the output is written the same way (a temporary file in that folder).
    try:
        handle, probe = tempfile.mkstemp(dir=folder, prefix=".guardsim-check-")
    except OSError as error:
        raise OutputError(f"{target}: cannot write in folder {folder}: {error.strerror or error}") from None
    os.close(handle)
    with contextlib.suppress(OSError):
        os.unlink(probe)


def _special_kind(target: Path) -> str:
    """What ``target`` is when it exists and is neither a regular file nor a folder; ``""`` otherwise.

    A folder is left to the rename, which fails with a clear "is a directory".
    """
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return ""
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return ""
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a block device" if stat.S_ISBLK(mode) else "a special file"


def _umask() -> int:
    """The process's umask (reading it means setting it, so set it straight back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_text_atomic(target: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``target`` through :func:`atomic_path`."""
    with atomic_path(target) as temporary:
        temporary.write_text(text, encoding="utf-8")
