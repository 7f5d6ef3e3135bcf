"""One file of an RS274/NGC program: its lines, parsed on first use, and the file read within
vmach's limits. Both the interpreter and its subroutine lookup (``flow``) load programs
through here."""

from __future__ import annotations

from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.lexer import Line, parse_line
from vmach.errors import InputError
from vmach.files import read_program_bytes
from vmach.source import SourceRef

MAX_LINE = 254  # LinuxCNC reads lines with fgets into LINELEN = 255 bytes


class Program:
    """The lines of one file, parsed on first use."""

    __slots__ = ("path", "text", "raw", "lines", "refs", "last_newline", "flat")

    def __init__(self, path: str, text: str):
        self.path = path
        self.text = text
        self.flat: list[tuple] | None = None  # fastpath.flat_tokens(text), on first use
        self.raw = text.split("\n")
        self.last_newline = True
        if self.raw and self.raw[-1] == "":
            self.raw.pop()
        elif self.raw:
            self.last_newline = False
        self.lines: list[Line | None] = [None] * len(self.raw)
        self.refs: list[SourceRef | None] = [None] * len(self.raw)

    def line(self, i: int) -> Line:
        ln = self.lines[i]
        if ln is None:
            raw = self.raw[i]
            # LinuxCNC reads lines with fgets(LINELEN = 255): 254 bytes with the newline fail
            length = len(raw.encode("utf-8", "replace"))
            if i < len(self.raw) - 1 or self.last_newline:
                length += 1
            if raw.endswith("\r"):
                raw = raw[:-1]
            if length >= MAX_LINE:
                ln = Line(i + 1, raw)
                ln.skip_error = NgcError("line_too_long")
            else:
                ln = parse_line(i + 1, raw)
            self.lines[i] = ln
        return ln

    def ref(self, i: int, column: int = 1) -> SourceRef:
        if column != 1:
            return SourceRef(self.path, i + 1, column, self.raw[i].rstrip("\r"))
        r = self.refs[i]
        if r is None:
            r = self.refs[i] = SourceRef(self.path, i + 1, 1, self.raw[i].rstrip("\r"))
        return r


def load_program(path: str) -> Program:
    try:
        data = read_program_bytes(path)        # held to vmach's size limits (ProgramError)
    except InputError as exc:
        raise NgcError("unreadable", path=path, reason=exc.message.removeprefix(f"{path}: ")) from None
    return Program(path, data.decode("utf-8", errors="replace"))
