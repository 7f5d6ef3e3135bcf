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

from interpreters.sinumerik import sysvars
from vmach.findings import Finding, info
from vmach.source import SourceRef

_HEADER = re.compile(r"^%(?:(?:_N_)?(?P<name>[A-Z0-9_]+?)(?:_(?P<kind>[A-Z]{3}))?)?\s*$", re.IGNORECASE)
PROGRAM_KINDS = ("MPF", "SPF")
#: the GUD modules in the order the control activates them, and the macro modules: their
#: ``_DEF`` sections in an archive are read as definition files (definitions.py)
GUD_MODULES = ("SGUD", "MGUD", "UGUD", "GUD4", "GUD5", "GUD6", "GUD7", "GUD8", "GUD9")
MACRO_MODULES = ("SMAC", "MMAC", "UMAC")


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
    section is the program; a section that is no program, no initialisation data (``_INI``,
    :func:`data_sections`) and no GUD or macro definitions (read by definitions.py) is said in
    an ``info`` finding ``archive_section`` (vmach does not read it). A SUB character
    (``\x1a``, the end of file of DOS-era transfer programs) at the end of the text, only white
    space after it, ends the file."""
    end = text.rfind("\x1a")
    if end >= 0 and not text[end + 1:].strip():
        text = text[:end]
    secs = sections(text)
    programs = [s for s in secs if s.is_program]
    main = programs[0].text if programs else _only(text.splitlines(), 0, 0)
    others = {s.name: s.text for s in programs[1:] if s.name}
    notes = [info("archive_section", f"{s.name}_{s.kind}: a section that is no program; vmach does "
                  "not read it", SourceRef(display, s.line, 1, ""), section=f"{s.name}_{s.kind}")
             for s in secs if not s.is_program and s.kind != "INI"
             and not (s.kind == "DEF" and s.name in GUD_MODULES + MACRO_MODULES)]
    return main, others, notes


#: a block of an initialisation file that the NCK reads but a program run need not: the end
#: of the file, the channel it is for
_INI_FRAME = re.compile(r"^\s*(?:N\d+\s+)?(?:M17|M30|M0?2|RET|CHANDATA\s*\(\s*1\s*\))\s*(?:;.*)?$",
                        re.IGNORECASE)
_INI_OTHER_CHANNEL = re.compile(r"^\s*(?:N\d+\s+)?CHANDATA\s*\(\s*(\d+)\s*\)", re.IGNORECASE)
#: an assignment to machine data (``$MN_…``, ``$MC_…``, ``$MA_…``, ``$MM_…``)
_INI_MACHINE_DATA = re.compile(r"^\s*(?:N\d+\s+)?\$M[NCAM]_", re.IGNORECASE)
#: the system variables a block of an initialisation file names
_INI_SYSVAR = re.compile(r"\$[A-Z_][A-Z0-9_]*", re.IGNORECASE)


@dataclass(frozen=True, slots=True)
class DataSection:
    """An initialisation section (``%_N_RPA_INI``, ``_N_TOA_INI``, ``_N_UFR_INI`` …) as a program
    vmach runs before the archive's program: name and type as in :class:`Section`, text the
    section's assignments (every other line empty), skipped (first line, what, blocks) the
    blocks it leaves out, by what they hold."""

    name: str
    line: int
    text: str
    skipped: tuple[tuple[int, str, int], ...]


#: a workpiece's data files loaded when its main program is selected (Operating Manual,
#: "Workpiece directory": the files of the program's name with these types), in this order
SELECTION_TYPES = ("TOA", "UFR", "RPA", "SEA", "INI")


def selection_names(program: str) -> list[tuple[str, tuple[str, ...]]]:
    """(type, file names it may have beside the program) for the data files of ``program``
    (its name without type): ``PART.TOA`` or, as the control names it, ``_N_PART_TOA``."""
    return [(t, (f"{program}.{t}", f"_N_{program}_{t}")) for t in SELECTION_TYPES]


def data_file(name: str, text: str) -> DataSection:
    """A data file beside the program (``PART.RPA``) as a :class:`DataSection` of its whole
    text, its header line (if any) left out."""
    lines = text.splitlines()
    if lines and header(lines[0]) is not None:
        lines[0] = ""
    return _data("\n".join(lines) + "\n", name, 1)


def data_sections(text: str) -> list[DataSection]:
    """The ``_INI`` sections of an archive: the data the control loads when the archive is read
    in (R parameters, tool offsets, zero offsets, setting and user data), in file order. The
    file's end (``M17``/``M30``) and ``CHANDATA(1)`` are left out (vmach simulates channel 1);
    the data of another channel, machine data (which a program cannot write, and vmach takes
    from the machine model) and system data vmach does not keep (magazines …) are left out and
    counted."""
    return [_data(sec.text, f"{sec.name}_{sec.kind}", sec.line) for sec in sections(text)
            if sec.kind == "INI"]


def _data(text: str, name: str, line: int) -> DataSection:
    """The data of one initialisation text (see :func:`data_sections`)."""
    lines = text.splitlines()
    skipped: dict[str, list[int]] = {}
    other = ""
    for i, ln in enumerate(lines):
        if not ln:
            continue
        m = _INI_OTHER_CHANNEL.match(ln)
        what = None
        if m is not None:
            other = m.group(1) if int(m.group(1)) != 1 else ""
        elif _INI_FRAME.match(ln):
            pass
        elif other:
            what = f"the data of channel {other}"
        elif _INI_MACHINE_DATA.match(ln):
            what = "machine data"
        elif any(sysvars.lookup(v.upper()) is None for v in _INI_SYSVAR.findall(ln.split(";")[0])):
            what = "system data vmach does not keep"
        else:
            continue
        lines[i] = ""
        if what is not None:
            skipped.setdefault(what, [i + 1, 0])[1] += 1
    return DataSection(name, line, "\n".join(lines) + "\n",
                       tuple((first, what, n) for what, (first, n) in skipped.items()))
