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
    phase : str
        The part of a standard cycle called on this line that made the command ("roughing
        depth 2 ring 3", "finishing"); empty outside cycles.
    """

    path: str
    line: int
    column: int = 1
    text: str = ""
    phase: str = ""

    def at(self, column: int) -> SourceRef:
        """The same line, pointing at another 1-based column."""
        return SourceRef(self.path, self.line, column, self.text, self.phase)

    def in_phase(self, phase: str) -> SourceRef:
        """The same place, made by the named part of the cycle called there."""
        return SourceRef(self.path, self.line, self.column, self.text, phase)

    def location(self) -> str:
        """``path:line:col``."""
        return f"{self.path}:{self.line}:{self.column}"


def render(severity: str, kind: str, message: str, source: SourceRef | None) -> str:
    """Render one diagnostic the way compilers do.

    ``file:line:col: severity[kind]: message`` followed by the offending line and a caret
    under the column. Without a source only the first line is produced.
    """
    if source is None:
        return f"vmach: {severity}[{kind}]: {message}"
    head = f"{source.location()}: {severity}[{kind}]: {message}"
    if source.phase:
        head += f" (in the cycle's {source.phase})"
    if not source.text:
        return head
    text = source.text.expandtabs(1).rstrip("\r\n")
    caret = " " * (max(source.column, 1) - 1) + "^"
    return f"{head}\n    {text}\n    {caret}"
