"""Static checks of an RS274/NGC program (``vmach check``), without running it.

Reported: syntax errors of every line (comments, numbers, expressions, unknown letters and
operators), word errors decidable from constant values (duplicate words, unknown or
conflicting G/M codes, negative F/S/T ...), codes vmach does not interpret, unbalanced
O-word structures (sub/endsub, if/endif, while/endwhile, do/while, repeat/endrepeat),
calls of subroutines defined nowhere, and a missing program end.
"""

from __future__ import annotations

from pathlib import Path

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.flow import _SAFE_NAME
from interpreters.rs274ngc.program import Program, load_program
from vmach.canon import ControlSpec
from vmach.errors import ProgramError
from vmach.files import leads_outside
from vmach.findings import Finding, error, sort_key

_OPENERS = {"if": ("endif",), "while": ("endwhile",), "repeat": ("endrepeat",),
            "do": ("while",), "sub": ("endsub",)}


def check_program(path: str, control: ControlSpec) -> list[Finding]:
    try:
        prog = load_program(path)
    except NgcError as exc:
        return [error(exc.kind, exc.message, None)]
    except ProgramError as exc:                # beyond vmach's size limits
        return [exc.finding]
    findings: list[Finding] = []
    known_axes = {a.name for a in control.axes}

    def report(i: int, exc: NgcError) -> None:
        findings.append(error(exc.kind, exc.message, prog.ref(i, exc.column or 1)))

    contour_lines = _g7x_contour_lines(prog)
    percent = False
    ended = False
    first = next((i for i, r in enumerate(prog.raw) if r.strip()), None)
    if first is not None and prog.raw[first].strip() == "%":
        percent = True
    for i in range(len(prog.raw)):
        line = prog.line(i)
        if line.skip_error is not None:
            report(i, line.skip_error)
            continue
        if line.error is not None:
            report(i, line.error)
        if line.o is not None or line.blank or line.percent:
            continue
        b = blk.Block(line)
        for k, item in enumerate(line.items):
            if item[0] != "w":
                continue
            letter, v = item[1], item[2]
            try:
                if type(v) is float:
                    blk._word(b, letter, v)
                elif letter in b.words:
                    raise NgcError("duplicate_word", letter=letter)
                else:
                    b.words[letter] = 0.0
                if (control.strict_axes and letter in "xyzabc" and letter.upper() not in known_axes
                        and not (letter in "ac" and i in contour_lines)):
                    raise NgcError("unknown_axis", axis=letter.upper())
            except NgcError as exc:
                if not exc.column:
                    exc.column = item[3] or _item_col(line, k)
                report(i, exc)
                break
        else:
            for code in b.g.values():
                if code in blk.UNSUPPORTED_G:
                    report(i, NgcError("unsupported", what=blk.UNSUPPORTED_G[code]))
            for code in b.m.values():
                if code in blk.UNSUPPORTED_M:
                    report(i, NgcError("unsupported", what=blk.UNSUPPORTED_M[code]))
            if b.m.get(4) in (2, 30):
                ended = True
            if b.m_count > 4:
                report(i, NgcError("too_many_m_codes"))
    findings.extend(_check_structure(prog, Path(path).resolve().parent))
    if not percent and not ended and prog.raw and not any(f.is_error for f in findings):
        findings.append(error("file_ended", NgcError("file_ended").message,
                              prog.ref(len(prog.raw) - 1)))
    findings.sort(key=sort_key)
    return findings


def _g7x_contour_lines(prog: Program) -> set[int]:
    """The lines of subroutines a G70..G72 cycle names by a constant Q: there A and C are
    a corner's fillet and chamfer, not axes (LinuxCNC reads them so in any machine)."""
    names: set[str] = set()
    for i in range(len(prog.raw)):
        line = prog.line(i)
        if line.o is not None or line.blank or line.percent or line.error is not None:
            continue
        g = q = None
        for item in line.items:
            if item[0] == "w" and type(item[2]) is float:
                if item[1] == "g" and 70 <= item[2] < 73:
                    g = item[2]
                elif item[1] == "q":
                    q = item[2]
        if g is not None and q is not None and q == int(q):
            names.add(str(int(q)))
    lines: set[int] = set()
    inside = False
    for i in range(len(prog.raw)):
        o = prog.line(i).o
        if o is not None and o.kind == "sub":
            inside = o.name in names
        elif o is not None and o.kind == "endsub":
            inside = False
        elif inside:
            lines.add(i)
    return lines


def _item_col(line, k: int) -> int:
    from interpreters.rs274ngc.lexer import item_column

    return item_column(line, k)


def _check_structure(prog: Program, directory: Path) -> list[Finding]:
    findings: list[Finding] = []
    stack: list[tuple[str, str, int]] = []  # (kind, name, line index)
    defined: set[str] = set()
    calls: list[tuple[str, int, int]] = []
    for i in range(len(prog.raw)):
        o = prog.line(i).o
        if o is None:
            continue
        kind, name = o.kind, o.name
        if kind == "sub":
            defined.add(name)
        if kind in ("program", "m98", "m99"):
            continue  # Fanuc-style: found when run (M98 P may be computed)
        if kind == "call":
            if name:  # else a number computed from parameters (o#1 call)
                calls.append((name, i, o.col))
            continue
        if kind in ("return", "break", "continue", "else", "elseif"):
            opener = next((k for k, n, _ in reversed(stack) if n == name), None)
            if opener is None and kind != "return":
                findings.append(_unmatched(prog, i, o))
            elif kind in ("break", "continue") and opener not in ("while", "do"):
                findings.append(error(
                    "no_matching_loop_label",
                    f"o{_label(name)} {kind} must be inside a while or do loop of that label "
                    f"(not {opener})", prog.ref(i, o.col)))
            elif kind in ("else", "elseif") and opener != "if":
                findings.append(_unmatched(prog, i, o))
            continue
        if kind == "while" and stack and stack[-1][0] == "do" and stack[-1][1] == name:
            stack.pop()
            continue
        if kind in _OPENERS:
            stack.append((kind, name, i))
            continue
        # a closer
        if stack and stack[-1][1] == name and kind in _OPENERS[stack[-1][0]]:
            stack.pop()
            continue
        findings.append(_unmatched(prog, i, o))
    for kind, name, i in stack:
        findings.append(error("unclosed_o_block", f"o{_label(name)} {kind} is never closed",
                              prog.ref(i, prog.line(i).o.col)))
    for name, i, col in calls:
        if name in defined:
            continue
        safe = _SAFE_NAME.fullmatch(name) and ".." not in name
        if not safe or leads_outside(directory / f"{name}.ngc", directory):
            findings.append(error("subprogram_outside", NgcError("subprogram_outside", name=name).message,
                                  prog.ref(i, col)))
            continue
        if (directory / f"{name}.ngc").is_file():
            continue
        findings.append(error(
            "undefined_sub",
            f"subroutine o{_label(name)} is defined neither in this file nor in {name}.ngc "
            "beside it", prog.ref(i, col)))
    return findings


def _label(name: str) -> str:
    return name if name.isdigit() else f"<{name}>"


def _unmatched(prog: Program, i: int, o) -> Finding:
    return error("unmatched_o_word", f"o{_label(o.name)} {o.kind} has no matching opening O-word",
                 prog.ref(i, o.col))
