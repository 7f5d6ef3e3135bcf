"""Source provenance: where a block, a canonical command, a move or a finding came from.

A :class:`SourceRef` travels unchanged from the token that produced it to the canonical
command, the move-table row and the finding, so every message can name file, line and column.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class SourceRef:
    """A place in a program text.

    path : str
        The file as the user named it (or as found beside the calling program).
    line : int
        1-based line number.
    column : int
        1-based column of the offending token (1 when the whole line is meant).
    text : str
        The whole source line without its newline, for the caret display.
    """

    path: str
    line: int
    column: int = 1
    text: str = ""

    def at(self, column: int) -> SourceRef:
        """The same line, pointing at another 1-based column."""
        return SourceRef(self.path, self.line, column, self.text)

    def location(self) -> str:
        """``path:line:col``."""
        return f"{self.path}:{self.line}:{self.column}"


@dataclass(frozen=True, slots=True)
class PhasedRef(SourceRef):
    """A place in a program (a standard cycle's call) and the part of the cycle that made the
    command: ``phase`` ("roughing depth 2/3 ring 4/6", "finishing", "approach"). Findings
    show and report it; :class:`SourceRef` itself keeps its four fields (the RS274/NGC fast
    path builds those by their slots)."""

    phase: str = ""

    def at(self, column: int) -> PhasedRef:
        return PhasedRef(self.path, self.line, column, self.text, self.phase)


def render(severity: str, kind: str, message: str, source: SourceRef | None) -> str:
    """Render one diagnostic the way compilers do.

    ``file:line:col: severity[kind]: message`` followed by the offending line and a caret
    under the column. Without a source only the first line is produced.
    """
    if source is None:
        return f"vmach: {severity}[{kind}]: {message}"
    head = f"{source.location()}: {severity}[{kind}]: {message}"
    if getattr(source, "phase", ""):
        head += f" (in the cycle's {source.phase})"
    if not source.text:
        return head
    text = source.text.expandtabs(1).rstrip("\r\n")
    caret = " " * (max(source.column, 1) - 1) + "^"
    return f"{head}\n    {text}\n    {caret}"
