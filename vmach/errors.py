"""Exceptions. One root, :class:`VmachError`; the CLI turns each into a diagnostic and an exit code.

- :class:`ProgramError` — the NC program is wrong (syntax, runtime): exit 1.
- :class:`InputError` — a file cannot be read or decoded, or an option is malformed: exit 2.
- :class:`ModelError` — a machine model, tool library or setup file is wrong; it carries every
  problem found, not only the first: exit 2.
"""

from __future__ import annotations

from collections.abc import Sequence

from vmach.findings import Finding
from vmach.source import SourceRef


class VmachError(Exception):
    """Root of every error vmach raises on purpose."""

    exit_code = 1

    def findings(self) -> list[Finding]:
        return [Finding("error", "error", str(self))]


class ProgramError(VmachError):
    """An error in an NC program, with a stable ``kind`` and the place it happened."""

    exit_code = 1

    def __init__(self, kind: str, message: str, source: SourceRef | None = None, **data):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.source = source
        self.data = data

    @property
    def finding(self) -> Finding:
        return Finding(self.kind, "error", self.message, self.source, None, self.data)

    def findings(self) -> list[Finding]:
        return [self.finding]

    def __str__(self) -> str:
        return self.finding.render()


class InputError(VmachError):
    """Unreadable input or bad usage (exit code 2)."""

    exit_code = 2

    def __init__(self, message: str, kind: str = "input", source: SourceRef | None = None):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.source = source

    def findings(self) -> list[Finding]:
        return [Finding(self.kind, "error", self.message, self.source)]


class ModelError(VmachError):
    """A machine model, tool library or setup file with one or more problems (exit code 2)."""

    exit_code = 2

    def __init__(self, problems: Sequence[Finding]):
        self.problems = list(problems)
        super().__init__("\n".join(p.render() for p in self.problems))

    def findings(self) -> list[Finding]:
        return list(self.problems)
