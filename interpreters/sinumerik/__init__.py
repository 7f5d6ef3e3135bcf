"""Sinumerik 840D dialect: ``check`` (static) and ``run`` (canonical commands).

Phases: read (``parser``), check (``structure`` plus name resolution here), execute
(``interpreter``, ``compile``, ``execute``). Deliberate deviations from the real control are
listed in ``DEVIATIONS.md``.
"""

from __future__ import annotations

import difflib
import os
from pathlib import Path

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik import definitions
from interpreters.sinumerik.interpreter import Interpreter, find_subprogram, linked_outside, read_program
from vmach.canon import DEFAULT_CONTROL, ControlSpec, RunOptions, RunResult
from vmach.findings import Finding, error, sort_key
from vmach.source import SourceRef

EXTENSIONS = (".mpf", ".spf", ".arc")
FORMATS: dict = {}


def check(path: str | Path, control: ControlSpec = DEFAULT_CONTROL) -> list[Finding]:
    """Static findings for the program at ``path`` (and nothing else): syntax, unknown words and
    names, jumps, structure, block numbers, unreachable blocks, PROC position."""
    p = Path(path)
    loaded = read_program(p, str(path), control)
    findings = list(loaded.findings) + list(definitions.load(p, str(path), control).findings)
    findings += _names(loaded.program, p.resolve().parent, control)
    return sorted(findings, key=sort_key)


def _names(program: b.Program, directory: Path, control: ControlSpec) -> list[Finding]:
    """Calls by name must reach a machine cycle or a subprogram file beside the program."""
    out: list[Finding] = []
    try:
        files = sorted(os.listdir(directory))
    except OSError:
        files = []
    stems = sorted(
        {os.path.splitext(f)[0].upper() for f in files if os.path.splitext(f)[1].upper() in (".SPF", ".MPF")}
    )
    for blk in program.blocks:
        for item in blk.items:
            if not isinstance(item, b.Call) or item.cycle:
                continue
            if find_subprogram(directory, item.name) is not None:
                continue
            link = linked_outside(directory, item.name)
            if link is not None:
                out.append(error("subprogram_outside", f"{item.name}: {link.name} leads outside the "
                                 "program's directory; vmach reads subprograms only beside the program",
                                 SourceRef(program.path, blk.line, item.col, blk.text), name=item.name))
                continue
            pool = sorted(control.cycles) + stems
            close = difflib.get_close_matches(item.name, pool, n=1, cutoff=0.75)
            hint = f"; did you mean {close[0]}?" if close else ""
            kind = "unknown_cycle" if not item.args else "subprogram_not_found"
            out.append(
                error(
                    kind,
                    f"{item.name} is neither a cycle the machine declares nor a subprogram "
                    f"({item.name}.SPF/.MPF) beside the program{hint}",
                    SourceRef(program.path, blk.line, item.col, blk.text),
                    name=item.name,
                )
            )
    return out


def run(
    path: str | Path, control: ControlSpec = DEFAULT_CONTROL, options: RunOptions | None = None
) -> RunResult:
    """Interpret the program; the result holds the canonical commands and what went wrong."""
    return Interpreter(path, control, options or RunOptions()).run()
