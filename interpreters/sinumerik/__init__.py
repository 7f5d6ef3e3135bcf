"""Sinumerik 840D dialect: ``check`` (static) and ``run`` (canonical commands).

Phases: read (``parser``), check (``structure`` plus name resolution here), execute
(``interpreter``, ``compile``, ``execute``). Deliberate deviations from the real control are
listed in ``DEVIATIONS.md``.
"""

from __future__ import annotations

import os
from pathlib import Path

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik import definitions
from interpreters.sinumerik.commands import not_found
from interpreters.sinumerik.interpreter import (
    Interpreter,
    find_subprogram,
    linked_outside,
    names_a_path,
    program_names,
    read_program,
)
from interpreters.sinumerik.selection import selection_data
from vmach.canon import DEFAULT_CONTROL, ControlSpec, RunOptions, RunResult
from vmach.findings import Finding, error, sort_key
from vmach.source import SourceRef

EXTENSIONS = (".mpf", ".spf", ".arc")
FORMATS: dict = {}


def check(path: str | Path, control: ControlSpec = DEFAULT_CONTROL) -> list[Finding]:
    """Static findings for the program at ``path`` (and the other programs of its file, when it
    is an archive): syntax, unknown words and names, jumps, structure, block numbers,
    unreachable blocks, PROC position."""
    p = Path(path)
    loaded = read_program(p, str(path), control)
    archived = frozenset(loaded.archive)
    findings = list(loaded.findings) + list(definitions.load(p, str(path), control).findings)
    findings += _names(loaded.program, p.resolve().parent, control, archived)
    for text in [*loaded.archive.values(), *(d.text for d in loaded.data)]:
        other = read_program(p, str(path), control, text)
        findings += other.findings + _names(other.program, p.resolve().parent, control, archived)
    for shown, d in selection_data(p, str(path)):        # PART.TOA, PART.RPA … beside it
        beside = p.resolve().parent / os.path.basename(shown)
        findings += read_program(beside, shown, control, d.text).findings
    return sorted(findings, key=sort_key)


def _names(
    program: b.Program, directory: Path, control: ControlSpec, archived: frozenset[str]
) -> list[Finding]:
    """Calls by name must reach a machine cycle, a subprogram file beside the program or a
    later program of its own file (an archive)."""
    out: list[Finding] = []
    stems = program_names(directory) | archived
    for blk in program.blocks:
        for item in blk.items:
            if not isinstance(item, b.Call) or item.cycle or item.how == "CALL_VAR":   # named at run time
                continue
            if item.name in archived or find_subprogram(directory, item.name) is not None:
                continue
            if names_a_path(item.name):
                out.append(error("subprogram_outside", f"{item.name}: a path; vmach reads subprograms "
                                 "only beside the program", SourceRef(program.path, blk.line, item.col,
                                                                      blk.text), name=item.name))
                continue
            link = linked_outside(directory, item.name)
            if link is not None:
                out.append(error("subprogram_outside", f"{item.name}: {link.name} leads outside the "
                                 "program's directory; vmach reads subprograms only beside the program",
                                 SourceRef(program.path, blk.line, item.col, blk.text), name=item.name))
                continue
            kind, message = not_found(item.name, item.how, stems, control)
            out.append(error(kind, message, SourceRef(program.path, blk.line, item.col, blk.text),
                             name=item.name))
    return out


def run(
    path: str | Path, control: ControlSpec = DEFAULT_CONTROL, options: RunOptions | None = None
) -> RunResult:
    """Interpret the program; the result holds the canonical commands and what went wrong."""
    return Interpreter(path, control, options or RunOptions()).run()
