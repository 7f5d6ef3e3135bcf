"""Reading the files a user names: one place that turns an unreadable file into a clear error
(``InputError``, exit 2) and decodes NC text the way controls accept it."""

from __future__ import annotations

import errno
import os
import re
import stat
from pathlib import Path

from vmach.errors import InputError, ProgramError
from vmach.source import SourceRef
from vmach.tol import tol


def read_bytes(path: str | Path, display: str | None = None, limit: int | None = None) -> bytes:
    """The file's bytes; a missing or unreadable file is an ``unreadable`` InputError naming it,
    a directory is named as one. At most ``limit`` bytes are read (default
    ``tol.max_config_bytes``): a larger file is an ``input_limit`` InputError, found without
    reading it whole (``/dev/zero`` included)."""
    limit = tol.max_config_bytes if limit is None else limit
    shown = display or str(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(limit + 1)
    except IsADirectoryError:
        raise InputError(f"{shown}: is a directory, not a file", kind="unreadable") from None
    except (OSError, ValueError) as exc:          # ValueError: a NUL in the name
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise InputError(f"{shown}: cannot read: {reason}", kind="unreadable") from None
    if len(data) > limit:
        raise InputError(f"larger than {limit:,} bytes (vmach's limit for this file)",
                         kind="input_limit", source=SourceRef(shown, 1))
    return data


def read_program_bytes(path: str | Path, display: str | None = None) -> bytes:
    """An NC program's bytes, held to ``tol.max_program_bytes`` and lines of at most
    ``tol.max_line_length`` characters before anything parses them: a larger file is a
    ``resource_limit`` ProgramError at its first line, a longer line one at that line."""
    shown = display or str(path)
    try:
        data = read_bytes(path, shown, tol.max_program_bytes)
    except InputError as exc:
        if exc.kind != "input_limit":
            raise
        raise ProgramError("resource_limit", f"the program is larger than {tol.max_program_bytes:,} "
                           "bytes (vmach's limit)", SourceRef(shown, 1)) from None
    n = tol.max_line_length
    if len(data) > n and (m := re.search(rb"^[^\r\n]{%d}" % (n + 1), data, re.M)) is not None:
        line = data.count(b"\n", 0, m.start()) + 1
        raise ProgramError("resource_limit", f"line {line} is longer than {n:,} characters "
                           "(vmach's limit)", SourceRef(shown, line, 1))
    return data


def file_problem(path: str | Path) -> str | None:
    """Why ``path`` cannot be read as a regular file (no such file, a directory, a device or a
    pipe, a link loop, a name with a NUL), or None when it can. Nothing is opened."""
    try:
        mode = os.stat(path).st_mode
    except ValueError:
        return "has a NUL character in its name"
    except OSError as exc:
        if exc.errno == errno.ENOENT:
            return "no such file"
        if exc.errno == errno.ELOOP:
            return "is a loop of links"
        return exc.strerror or str(exc)
    if stat.S_ISDIR(mode):
        return "is a directory, not a file"
    if not stat.S_ISREG(mode):
        return "is not a regular file (a device, a pipe or a socket)"
    return None


def input_file(path: str | Path, display: str | None = None) -> Path:
    """``path`` when it names a regular file, else an ``unreadable`` InputError saying why."""
    problem = file_problem(path)
    if problem is not None:
        raise InputError(f"{display or path}: {problem}", kind="unreadable")
    return Path(path)


def decode_text(data: bytes) -> str:
    """NC text: UTF-8 (with or without BOM) first, Latin-1 otherwise (which never fails)."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def contained(path: str | Path, root: str | Path) -> bool:
    """True when ``path``, with every symbolic link along it followed (chains too), lies in
    ``root`` or below it (``root`` resolved the same way). A link loop or an unresolvable name
    is not contained. Only names are resolved: no file is opened."""
    try:
        real = Path(path).resolve()
        base = Path(root).resolve()
    except (OSError, RuntimeError):                # a link loop (RuntimeError before 3.13)
        return False
    return real == base or real.is_relative_to(base)


def leads_outside(path: str | Path, root: str | Path) -> bool:
    """True when the name ``path`` exists (a link counts even when it dangles) and, links
    followed, leads out of ``root``: a file vmach must refuse to read, without opening it."""
    return os.path.lexists(path) and not contained(path, root)
