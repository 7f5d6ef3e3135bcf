"""Global user data (GUD): the definition files beside a program.

A control keeps its global variables in definition files (``_N_SGUD_DEF`` for the machine
maker, ``_N_MGUD_DEF``, ``_N_UGUD_DEF`` for the user, ``_N_GUD4_DEF`` .. ``_N_GUD9_DEF``)::

    %_N_UGUD_DEF
    ;$PATH=/_N_DEF_DIR
    DEF NCK REAL RTP
    DEF CHAN INT QUANTITY=10
    DEF NCK APR 7 APW 2 REAL SPEED[3]=SET(1, 2, 3)
    M30

vmach reads such files from the program's own directory only (never a link leading out of it),
named as the control names them or as a PC copy does: ``_N_UGUD_DEF``, ``UGUD.DEF``,
``_N_UGUD_DEF.DEF`` (any case), and the files the machine model (``[control] definitions``) or
the setup file (``definitions`` in ``vmach.toml``) name, relative to the program's directory
and inside it, read after those. Their variables exist in every program of the directory with
their types, initial values and arrays; NCK and CHAN variables are both global (vmach simulates
one channel). Macro files (``_N_SMAC_DEF``, ``_N_MMAC_DEF``, ``_N_UMAC_DEF``) give the macros
(``DEFINE … AS``, ``macros.py``) every program of the directory knows. Access attributes
(``APR``/``APW`` ...), limits (``LLI``/``ULI``) and ``PHU`` are read and have no effect. A
definition vmach does not simulate (``DEF NCK FRAME``) is a warning (``unsupported_definition``),
since the file is valid on the control.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from interpreters.sinumerik import archive, macros
from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.archive import GUD_MODULES as MODULES
from interpreters.sinumerik.archive import MACRO_MODULES
from interpreters.sinumerik.language import TYPES
from interpreters.sinumerik.lexer import IDENT, split_comment, tokenize
from interpreters.sinumerik.parser import BlockParser, Grammar
from vmach.canon import ControlSpec
from vmach.errors import ProgramError
from vmach.files import contained, decode_text, read_bytes
from vmach.findings import Finding, error, warning
from vmach.source import SourceRef

#: a GUD file's name: _N_<MODULE>_DEF, <MODULE>.DEF or _N_<MODULE>_DEF.DEF
GUD_FILE = re.compile(r"^(?:_N_)?(SGUD|MGUD|UGUD|GUD[4-9])(?:_DEF(?:\.DEF)?|\.DEF)$", re.IGNORECASE)
#: a macro file's name (``DEFINE … AS`` lines, macros.py), in the order the control reads them
MACRO_FILE = re.compile(r"^(?:_N_)?(SMAC|MMAC|UMAC)(?:_DEF(?:\.DEF)?|\.DEF)$", re.IGNORECASE)
_END = {"M30", "M17", "M02", "M2", "RET"}


@dataclass(frozen=True)
class Definitions:
    """variables : name -> VarDef (the global variables); findings : problems in the files;
    sources : name -> SourceRef of its definition."""

    variables: dict[str, b.VarDef]
    findings: tuple[Finding, ...]
    sources: dict[str, SourceRef]
    macros: dict[str, str] = field(default_factory=dict)   # name -> text (macro files)


EMPTY = Definitions({}, (), {})
_cache: dict[tuple, Definitions] = {}


def files(directory: Path, pattern: re.Pattern = GUD_FILE, order: tuple[str, ...] = MODULES) -> list[Path]:
    """The GUD files (or macro files) of ``directory`` in activation order (links leading out
    are left out)."""
    try:
        entries = sorted(os.listdir(directory))
    except OSError:
        return []
    found = []
    for entry in entries:
        m = pattern.match(entry)
        p = directory / entry
        if m and p.is_file() and p.resolve().parent == directory.resolve():
            found.append((order.index(m.group(1).upper()), entry, p))
    return [p for _, _, p in sorted(found)]


def _macros(paths: list[Path], display_dir: str, extra: tuple = ()) -> tuple[dict[str, str], list[Finding]]:
    """The macros of the macro files (and of ``extra`` (display, text) pairs): every ``DEFINE
    name AS text`` line; other lines are left alone (a macro file holds definitions only)."""
    table: dict[str, str] = {}
    findings: list[Finding] = []
    for _display, text in [*_texts(paths, display_dir, findings), *extra]:
        for raw in text.splitlines():
            if (d := macros.definition(split_comment(raw)[0])) is not None:
                table[d[0]] = d[1]
    return table, findings


def _texts(paths: list[Path], display_dir: str, findings: list[Finding]) -> Iterator[tuple[str, str]]:
    """(name to show, text) of each file; one that cannot be read is an ``unreadable`` finding."""
    for path in paths:
        display = os.path.join(display_dir, path.name)
        try:
            text = decode_text(read_bytes(path, display))
        except Exception as exc:  # an unreadable file is a finding, not a traceback
            findings.append(error("unreadable", f"{display}: {exc}", SourceRef(display, 1)))
            continue
        yield display, text


def named(directory: Path, control: ControlSpec) -> tuple[list[Path], list[str]]:
    """The GUD files ``control.definitions`` names (the model's, the setup file's) that are in
    ``directory`` or below it, and the names that lead outside it (never read). A name that
    is not there is left out: a model names its files for every program of the machine."""
    inside, outside = [], []
    for name in control.definitions:
        p = directory / name
        if not os.path.lexists(p):
            continue
        if not contained(p, directory):
            outside.append(name)
        elif p.is_file():
            inside.append(p)
    return inside, outside


def load(program: Path, display: str, control: ControlSpec) -> Definitions:
    """The global variables defined in the GUD files beside ``program`` (cached per file
    state); findings name the files as ``display`` (the program as the user named it) does."""
    directory = program.resolve().parent
    paths = files(directory)
    macro_paths = files(directory, MACRO_FILE, MACRO_MODULES)
    extra, outside = named(directory, control)
    paths += [p for p in extra if all(p.resolve() != q.resolve() for q in paths)]
    refused = tuple(error("file_outside", f"the GUD file {n} the machine or setup names leads outside the "
                          "program's directory (never read)", SourceRef(display, 1)) for n in outside)
    own, own_macros = _own_sections(program, display)
    if not paths and not macro_paths and not own and not own_macros:
        return Definitions({}, refused, {}) if refused else EMPTY
    key = (str(directory), os.path.dirname(display),
           tuple((str(p), p.stat().st_mtime_ns, p.stat().st_size) for p in paths + macro_paths),
           tuple(sorted(a.name for a in control.axes)), control.definitions, own, own_macros)
    if key not in _cache:
        got = _read(paths, os.path.dirname(display), control, own)
        table, problems = _macros(macro_paths, os.path.dirname(display), own_macros)
        _cache[key] = Definitions(got.variables, got.findings + tuple(problems), got.sources, table)
    found = _cache[key]
    return Definitions(found.variables, refused + found.findings, found.sources, found.macros) if refused \
        else found


def _own_sections(program: Path, display: str) -> tuple[tuple, tuple]:
    """((display, text) of each GUD section, of each macro section) of the program's own file
    when it is an archive (``%_N_UGUD_DEF`` among its sections, archive.py); their lines keep
    the file's numbers. The GUD sections come in activation order, after the files beside."""
    try:
        text = decode_text(read_bytes(program, display))
    except Exception:  # unreadable: reading the program itself says so
        return (), ()
    if "%" not in text:
        return (), ()
    gud, mac = [], []
    for sec in archive.sections(text):
        if sec.kind != "DEF":
            continue
        name = sec.name.upper()
        if name in MODULES:
            gud.append((MODULES.index(name), (display, sec.text)))
        elif name in MACRO_MODULES:
            mac.append((MACRO_MODULES.index(name), (display, sec.text)))
    return tuple(t for _, t in sorted(gud)), tuple(t for _, t in sorted(mac))


def _read(paths: list[Path], display_dir: str, control: ControlSpec, extra: tuple = ()) -> Definitions:
    grammar = Grammar(control)
    variables: dict = {}
    sources: dict[str, SourceRef] = {}
    findings: list[Finding] = []
    for display, text in [*_texts(paths, display_dir, findings), *extra]:
        for lineno, raw in enumerate(text.splitlines(), start=1):
            code = split_comment(raw)[0].strip()
            if not code or code.startswith("%") or code.upper() in _END:
                continue
            src = SourceRef(display, lineno, 1, raw)
            try:
                stripped = _without_attributes(code, src)
                block = b.Block(index=0, line=lineno, text=raw)
                BlockParser(grammar, variables, src).parse(block, stripped)
            except ProgramError as exc:
                f = exc.finding
                if f.kind == "unsupported":  # valid on the control: the files are not at fault
                    f = warning("unsupported_definition", f"{f.message}; a program that uses it stops there",
                                f.source)
                findings.append(f)
                continue
            if block.kind != "def":
                findings.append(error("syntax", "a definition file holds DEF statements only", src))
                continue
            for d in block.defs:
                sources[d.name] = src.at(d.col)
    defs = {k: v for k, v in variables.items() if isinstance(v, b.VarDef)}
    return Definitions(defs, tuple(findings), sources)


def _without_attributes(code: str, src: SourceRef) -> str:
    """``DEF NCK APR 7 REAL X`` -> ``DEF REAL X`` (same columns: the rest is blanked)."""
    toks = tokenize(code, src)
    if not toks or toks[0].kind != IDENT or toks[0].text != "DEF":
        return code
    for t in toks[1:]:
        if t.kind == IDENT and (t.text in TYPES or t.text == "FRAME"):
            start = t.col - 1
            return "DEF" + " " * (start - 3) + code[start:]
    raise ProgramError("syntax", f"DEF needs a type ({', '.join(sorted(TYPES))})", src)
