"""Files in punched-tape format, as the control reads and writes them (archives, ``.ARC``, and
programs saved from it): each file of the archive starts with a header line ``%_N_NAME_MPF``
(or ``%NAME_SPF``, ``%_N_NAME_DEF`` …), often followed by ``;$PATH=/_N_MPF_DIR``.

:func:`sections` splits a text at its header lines. Each section keeps the line numbers of
the whole file (the other lines are left empty), so findings point into the file as written.
The first program section is the program itself; the later program sections (``_MPF``,
``_SPF``) are programs a call may reach by name; other sections (``_DEF``, ``_INI`` …) are
not programs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from vmach.findings import Finding, info
from vmach.source import SourceRef

_HEADER = re.compile(r"^%(?:(?:_N_)?(?P<name>[A-Z0-9_]+?)(?:_(?P<kind>[A-Z]{3}))?)?\s*$", re.IGNORECASE)
PROGRAM_KINDS = ("MPF", "SPF")


@dataclass(frozen=True, slots=True)
class Section:
    """One file of a punched-tape text.

    name : the file's name without prefix and type (``PART1``); kind : its type (``MPF``,
    ``SPF``, ``DEF`` …; "" when the header gives none); line : the header's line (1-based);
    text : the whole text with every line outside this section empty.
    """

    name: str
    kind: str
    line: int
    text: str

    @property
    def is_program(self) -> bool:
        return self.kind in PROGRAM_KINDS or self.kind == ""


def header(line: str) -> tuple[str, str] | None:
    """(name, type) of a header line ``%_N_NAME_MPF``, else None."""
    m = _HEADER.match(line.strip())
    if m is None:
        return None
    return (m.group("name") or "").upper(), (m.group("kind") or "").upper()


def sections(text: str) -> list[Section]:
    """The files of ``text``; one section named "" for a text without header lines."""
    lines = text.splitlines()
    starts = [(i, h) for i, ln in enumerate(lines) if ln.startswith("%") and (h := header(ln)) is not None]
    if not starts:
        return [Section("", "", 1, text)]
    out = []
    if any(ln.split(";")[0].strip() for ln in lines[: starts[0][0]]):
        out.append(Section("", "", 1, _only(lines, 0, starts[0][0])))   # code before the first header
    for k, (i, (name, kind)) in enumerate(starts):
        end = starts[k + 1][0] if k + 1 < len(starts) else len(lines)
        out.append(Section(name, kind, i + 1, _only(lines, i + 1, end)))
    return out


def _only(lines: list[str], start: int, stop: int) -> str:
    """The text with the lines outside ``start..stop-1`` left empty (the header's line too)."""
    return "\n".join(ln if start <= i < stop else "" for i, ln in enumerate(lines)) + "\n"


def split(text: str, display: str) -> tuple[str, dict[str, str], list[Finding]]:
    """(the program's text, the other programs by name, notes) of a file: its first program
    section is the program; a section that is no program is said in an ``info`` finding
    ``archive_section`` (vmach does not read it). A SUB character (``\x1a``, the end of file of
    DOS-era transfer programs) at the end of the text, only white space after it, ends the file."""
    end = text.rfind("\x1a")
    if end >= 0 and not text[end + 1:].strip():
        text = text[:end]
    secs = sections(text)
    programs = [s for s in secs if s.is_program]
    main = programs[0].text if programs else _only(text.splitlines(), 0, 0)
    others = {s.name: s.text for s in programs[1:] if s.name}
    notes = [info("archive_section", f"{s.name}_{s.kind}: a section that is no program; vmach does "
                  "not read it", SourceRef(display, s.line, 1, ""), section=f"{s.name}_{s.kind}")
             for s in secs if not s.is_program]
    return main, others, notes
