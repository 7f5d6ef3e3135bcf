"""Reading the files a user names: one place that turns an unreadable file into a clear error
(``InputError``, exit 2) and decodes NC text the way controls accept it."""

from __future__ import annotations

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
