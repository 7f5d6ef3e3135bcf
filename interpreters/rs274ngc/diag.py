"""Diagnostics of the RS274/NGC dialect: one exception type with a stable ``kind``.

Message texts live in ``messages.toml`` (LinuxCNC's own wording where it has one). Code
raises :class:`NgcError` with a kind and the format fields; the interpreter turns it into a
:class:`vmach.findings.Finding` with the place it happened.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

MESSAGES: dict[str, str] = tomllib.loads(
    (Path(__file__).with_name("messages.toml")).read_text(encoding="utf-8")
)


class NgcError(Exception):
    """An error in an RS274/NGC program.

    kind : stable snake_case identifier (a key of ``messages.toml``).
    column : 1-based column in the source line when known (0: unknown, the whole line).
    fields : values for the message template.
    """

    def __init__(self, kind: str, column: int = 0, **fields):
        super().__init__(kind)
        self.kind = kind
        self.column = column
        self.fields = fields

    @property
    def message(self) -> str:
        template = MESSAGES.get(self.kind, self.kind)
        try:
            return template.format(**self.fields)
        except (KeyError, IndexError, ValueError):
            return template

    def __str__(self) -> str:
        return self.message


def fail(kind: str, column: int = 0, **fields) -> NgcError:
    """Build (not raise) an :class:`NgcError`; ``raise fail(...)`` reads well at call sites."""
    return NgcError(kind, column, **fields)
