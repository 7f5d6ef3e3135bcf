"""Findings: everything vmach has to say about a program, with a stable ``kind``.

Static diagnostics (``vmach check``), runtime errors of an interpreter, and the verdicts of the
checks downstream (limits, collisions, profile) are all :class:`Finding` objects. Tests assert
``kind``, ``line`` and the numbers in ``data``, never the prose of ``message``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from vmach.source import SourceRef, render

SEVERITIES = ("error", "warning", "info")


@dataclass(frozen=True, slots=True)
class Finding:
    """One finding.

    kind : str
        Stable snake_case identifier (``undefined_label``, ``axis_limit`` ...).
    severity : str
        ``"error"``, ``"warning"`` or ``"info"``.
    message : str
        Human-readable sentence; free to change between versions.
    source : SourceRef or None
        Where in the program the finding points.
    move_index : int or None
        Row of the move table the finding belongs to, when it belongs to a move.
    data : mapping
        Numbers that back the finding (mm, degrees, seconds), JSON-serialisable.
    """

    kind: str
    severity: str
    message: str
    source: SourceRef | None = None
    move_index: int | None = None
    data: Mapping[str, Any] = field(default_factory=dict)

    @property
    def line(self) -> int | None:
        return None if self.source is None else self.source.line

    @property
    def is_error(self) -> bool:
        return self.severity == "error"

    def render(self) -> str:
        """``file:line:col: severity[kind]: message`` plus the line and a caret."""
        return render(self.severity, self.kind, self.message, self.source)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "severity": self.severity,
            "kind": self.kind,
            "file": None if self.source is None else self.source.path,
            "line": None if self.source is None else self.source.line,
            "column": None if self.source is None else self.source.column,
            "message": self.message,
        }
        if getattr(self.source, "phase", ""):
            out["phase"] = self.source.phase           # a standard cycle's part (PhasedRef)
        if self.move_index is not None:
            out["move_index"] = self.move_index
        if self.data:
            out.update({k: v for k, v in self.data.items() if k not in out})
        return out


def error(kind: str, message: str, source: SourceRef | None = None, **data: Any) -> Finding:
    return Finding(kind, "error", message, source, None, data)


def warning(kind: str, message: str, source: SourceRef | None = None, **data: Any) -> Finding:
    return Finding(kind, "warning", message, source, None, data)


def info(kind: str, message: str, source: SourceRef | None = None, **data: Any) -> Finding:
    return Finding(kind, "info", message, source, None, data)


def sort_key(f: Finding) -> tuple:
    """Order findings by file, line, column, then severity (errors first)."""
    if f.source is None:
        return ("", 0, 0, SEVERITIES.index(f.severity))
    return (f.source.path, f.source.line, f.source.column, SEVERITIES.index(f.severity))
