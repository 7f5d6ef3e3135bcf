"""Reading the files a user names: one place that turns an unreadable file into a clear error
(``InputError``, exit 2) and decodes NC text the way controls accept it."""

from __future__ import annotations

import os
from pathlib import Path

from vmach.errors import InputError


def read_bytes(path: str | Path, display: str | None = None) -> bytes:
    """The file's bytes; a missing or unreadable file is an ``unreadable`` InputError naming it."""
    try:
        return Path(path).read_bytes()
    except OSError as exc:
        raise InputError(
            f"{display or path}: cannot read: {exc.strerror or exc}", kind="unreadable"
        ) from None


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
