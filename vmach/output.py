"""Writing files so that nothing half-written is ever left behind."""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

from vmach.errors import InputError


@contextmanager
def atomic_writer(path: str | Path, mode: str = "w") -> Iterator[IO]:
    """Write to a temporary file beside ``path`` and rename it into place on success only.

    The file gets the mode of the one it replaces, or a new file's (0666 less the umask) —
    not the temporary file's 0600. Only a regular file (or a new name) is replaced: a link is
    written through (its target is replaced, the link stays), and a device or a pipe
    (``-o /dev/null``, a FIFO) is written to in place — never replaced by a regular file."""
    target = Path(os.path.realpath(writable_file(path)))
    if _special(target):
        with _written_through(path, target, mode) as fh:
            yield fh
        return
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    except OSError as exc:
        raise _unwritable(path, exc) from None
    try:
        os.chmod(fd, _mode_for(target))
        try:
            with os.fdopen(fd, mode, encoding=None if "b" in mode else "utf-8") as fh:
                yield fh
        except OSError as exc:                     # the disk filled up, the quota ran out
            raise _unwritable(path, exc) from None
        try:
            os.replace(tmp, target)
        except OSError as exc:
            raise _unwritable(path, exc) from None
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _special(target: Path) -> bool:
    """True when ``target`` exists and is not a regular file (a device, a FIFO, a socket)."""
    try:
        return not stat.S_ISREG(os.stat(target).st_mode)
    except OSError:                                # a new name (or a link loop: os.replace says)
        return False


@contextmanager
def _written_through(path, target: Path, mode: str) -> Iterator[IO]:
    """``target`` opened for writing as it is (no temporary file, no rename)."""
    try:
        fh = open(target, mode, encoding=None if "b" in mode else "utf-8")  # noqa: SIM115
    except OSError as exc:
        raise _unwritable(path, exc) from None
    try:
        with fh:                                   # closing flushes: a full disk shows there too
            yield fh
    except OSError as exc:
        raise _unwritable(path, exc) from None


def _mode_for(target: Path) -> int:
    """Permission bits for a file written at ``target``: those of the file there, else 0666
    less the process's umask (read by setting it and back: Python has no getter)."""
    try:
        return stat.S_IMODE(target.stat().st_mode)
    except OSError:
        mask = os.umask(0o022)
        os.umask(mask)
        return 0o666 & ~mask


def _unwritable(path, exc: OSError) -> InputError:
    return InputError(f"{path}: cannot write there: {exc.strerror or exc}", kind="unwritable")


def writable_file(path: str | Path) -> Path:
    """``path`` as a file vmach may write: not a directory, in a directory that exists
    (:class:`InputError` otherwise). Checks only; ``Path(path).parent`` is ``.`` for a bare name."""
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{path}: is a directory", kind="unwritable")
    if not target.parent.is_dir():
        raise InputError(f"{path}: the directory {target.parent} does not exist", kind="unwritable")
    return target


def writable_dir(path: str | Path) -> Path:
    """``path`` as a directory vmach may write into — one already, or one that can be made (its
    nearest existing ancestor is a writable directory). Checked before any work is done, so
    that a bad ``--out`` fails at once; creates nothing. Raises :class:`InputError`."""
    target = Path(path)
    probe = target
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        what = "is a file" if probe == target else f"cannot be made: {probe} is a file"
        raise InputError(f"{target}: {what}, not a directory", kind="unwritable")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(f"{target}: {probe} is not writable", kind="unwritable")
    return target


def make_dir(path: str | Path) -> Path:
    """Create the directory ``path`` (and its parents); :class:`InputError` if it cannot be."""
    target = Path(path)
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{target}: cannot create the directory: {exc.strerror or exc}",
                         kind="unwritable") from None
    return target
