"""Predefined commands that are not G-group codes (``commands.toml``): how each kind is read and
what it does in a run. One reader and one handler per kind:

================  ==============================  ============================================
kind              written                         run
================  ==============================  ============================================
keyword           ``STOPRE``                      no effect on geometry (``no_effect`` info)
procedure         ``WAITM(1,1,2)``, ``GET(Z)``    no effect on geometry (``no_effect`` info)
value             ``ADIS=0.5``                    evaluated; no effect on geometry
axis_value        ``FA[X]=1000``                  evaluated; no effect on geometry
position          ``POS[C]=ACP(90)``              the axis moves (a traverse after the block's
                                                  path motion)
alarm             ``SETAL(61000)``                error ``program_alarm`` with the number; stops
setting_cycle     ``CYCLE832(0.01,_FINISH,1)``    no effect on geometry (``no_effect`` info)
cycle             ``CYCLE800(...)``               ``unsupported`` naming it (unless a program
                                                  of that name is beside the program)
================  ==============================  ============================================

Accepted G-group codes (``language.toml``: BRISK, COMPCAD, FNORM …) are recorded the same way
as the keywords. The ``no_effect`` info is given once per command and run, with the count.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable
from typing import TYPE_CHECKING

from interpreters.sinumerik import approach, coupling, orientation, sandbox, surface, syncact
from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.cycles import NAMES as MILLING
from interpreters.sinumerik.drilling import CYCLES as DRILLING
from interpreters.sinumerik.drilling import PATTERNS
from interpreters.sinumerik.expr import EvalError, Node, compile_expr
from interpreters.sinumerik.language import CODES, COMMANDS
from interpreters.sinumerik.lexer import IDENT, NUM, OP, STR
from interpreters.sinumerik.turning import NAMES as TURNING
from vmach import canon
from vmach.errors import ProgramError
from vmach.findings import Finding, info
from vmach.source import SourceRef

if TYPE_CHECKING:
    from interpreters.sinumerik.running import Reading, Running


# -- reading -------------------------------------------------------------------------------
def read(p: Reading, t) -> b.Item:
    """The command ``t`` (its name token, already consumed) with what follows it."""
    c = COMMANDS[t.text]
    return _READERS[c.kind](p, t)


def _keyword(p: Reading, t) -> b.Item:
    if p.is_op("(") or p.is_op("="):
        p.fail("syntax", f"{t.text} takes no arguments or value")
    return b.Command(t.col, t.text, "keyword")


def _procedure(p: Reading, t) -> b.Item:
    return b.Command(t.col, t.text, COMMANDS[t.text].kind, p.arguments(loose=True) if p.is_op("(") else ())


def _value(p: Reading, t) -> b.Item:
    p.expect_op("=")
    return b.Command(t.col, t.text, COMMANDS[t.text].kind, (p.expr(),))


def _axis_value(p: Reading, t) -> b.Item:
    p.expect_op("[")
    at = p.tok
    if at.kind != IDENT or not p.g.is_axis(at.text):
        p.fail("unknown_axis", f"{t.text}[...] needs an axis of this machine, found {p.describe(at)}")
    p.pos += 1
    p.expect_op("]")
    p.expect_op("=")
    kind = COMMANDS[t.text].kind
    if kind == "position":
        mode, node = p.moded_value()
        return b.Command(t.col, t.text, kind, (node,), at.text, mode)
    return b.Command(t.col, t.text, kind, (p.expr(),), at.text)


def _axis_mark(p: Reading, t) -> b.Item:
    """``FINEA[X]`` or ``FINEA=X``: an axis named, no value."""
    close = p.is_op("[")
    if not (close or p.is_op("=")):
        p.fail("syntax", f"{t.text} needs an axis: {t.text}[X] or {t.text}=X")
    p.pos += 1
    at = p.tok
    if at.kind != IDENT or not p.g.is_axis(at.text):
        p.fail("unknown_axis", f"{t.text} needs an axis of this machine, found {p.describe(at)}")
    p.pos += 1
    if close:
        p.expect_op("]")
    return b.Command(t.col, t.text, "axis_mark", (), at.text)


def _alarm(p: Reading, t) -> b.Item:
    p.expect_op("(")
    node = p.expr()
    p.expect_op(")")
    return b.Command(t.col, t.text, "alarm", (node,))


def _cycle(p: Reading, t) -> b.Item:
    p.fail("unsupported", f"{t.text} is a Siemens standard cycle that vmach does not simulate", t.col)
    raise AssertionError


def _interrupt(p: Reading, t) -> b.Item:
    """``SETINT(n) [PRIO=m] [NAME] [LIFTFAST] [BLSYNC]``, ``ENABLE(n)``, ``DISABLE(n)``,
    ``CLRINT(n)``: the input's number, and for SETINT the rest of the block (the routine it
    names is started by the input only, never by the program)."""
    p.expect_op("(")
    node = p.expr()
    p.expect_op(")")
    if t.text == "SETINT":
        while p.tok.kind == IDENT:
            name = p.tok.text
            p.pos += 1
            if name == "PRIO":
                p.expect_op("=")
                p.expr()
    return b.Command(t.col, t.text, "interrupt", (node,))


def _unsupported(p: Reading, t) -> b.Item:
    p.fail("unsupported", f"{t.text}: {COMMANDS[t.text].effect}", t.col)
    raise AssertionError


def spindle_position(p: Reading, t) -> b.Word:
    """``SPOS[n]=value`` / ``SPOSA[n]=value`` (the ``[`` is next)."""
    p.pos += 1
    n = p.tok
    if n.kind != NUM or not isinstance(n.value, int):
        p.fail("syntax", f"{t.text}[n] needs a spindle number")
    p.pos += 1
    p.expect_op("]")
    p.expect_op("=")
    mode, node = p.moded_value()
    return b.Word(t.col, f"{t.text}{n.value}", "spos", node, n.value, mode)


def axis_address(p: Reading, t) -> b.Word:
    """``AX[axis]=value``: the axis word written with the axis in brackets; an AXIS variable
    there (an axis chosen at run time) is not simulated."""
    p.pos += 1
    at = p.tok
    if at.kind == IDENT and p.g.is_axis(at.text) and p.is_op("]", 1):
        p.pos += 2
        p.expect_op("=")
        mode, node = p.moded_value()
        return b.Word(t.col, at.text, "axis", node, None, mode)
    if at.kind == IDENT and at.text in p.variables and p.is_op("]", 1):
        p.pos += 2
        p.expect_op("=")
        mode, node = p.moded_value()
        return b.Word(t.col, at.text, "axis_var", node, None, mode)
    p.fail("unknown_axis", f"AX[...] needs an axis of this machine, found {p.describe(at)}", at.col)
    raise AssertionError


def runtime_axis(it: Running, word: b.Word) -> Callable[[], b.Word]:
    """The axis word of ``AX[variable]=value`` (``word.name`` the AXIS variable): a closure
    giving the word of the axis the variable names when the block runs; an axis the machine
    does not have is ``unknown_axis``."""
    get = compile_expr(Node("var", word.col, word.name), it.env)
    control = it.control
    axes = {a.name for a in control.axes} | set(control.geometry)

    def resolve() -> b.Word:
        name = get()
        if name.__class__ is not str or not name:
            raise EvalError("type_error", f"AX[{word.name}]: {word.name} holds no axis ({name!r})")
        name = name.strip().upper()
        if name not in axes and (control.strict_axes or not re.fullmatch(r"[ABCUVWXYZ]\d*", name)):
            raise EvalError("unknown_axis", f"AX[{word.name}]: {name} is not an axis of this machine")
        return b.Word(word.col, name, "axis", word.expr, None, word.mode)

    return resolve


def program_call(p: Reading, t) -> b.Call:
    """``CALL "NAME"``, ``EXTCALL "NAME"``, ``PCALL NAME(args)`` or ``PCALL /_N_…_SPF(args)``
    (the statement's token consumed)."""
    how = t.text
    if how == "CALL" and p.tok.kind == IDENT and p.tok.text in p.variables:   # CALL PNAME (a STRING)
        v = p.tok
        p.pos += 1
        return b.Call(t.col, v.text, (Node("var", v.col, v.text),), how="CALL_VAR")
    if how != "PCALL":
        if p.tok.kind != STR:
            p.fail("syntax", f'{how} needs a program name in quotes: {how} "NAME"')
        p.pos += 1
        return b.Call(t.col, program_name(p.toks[p.pos - 1].value, how), how=how)
    path = ""
    while p.tok.kind == IDENT or p.is_op("/"):
        path += p.tok.text
        p.pos += 1
    if not path:
        p.fail("syntax", "PCALL needs a program name or path")
    args = p.arguments() if p.is_op("(") else ()
    return b.Call(t.col, program_name(path, how), args, how=how)


def bracketed(p: Reading, t) -> b.Word:
    """``AX[axis]=value`` or ``SPOS[n]=value`` / ``SPOSA[n]=value`` (the ``[`` is next)."""
    return axis_address(p, t) if t.text == "AX" else spindle_position(p, t)


_READERS: dict[str, Callable] = {
    "keyword": _keyword,
    "procedure": _procedure,
    "setting_cycle": _procedure,
    "value": _value,
    "axis_value": _axis_value,
    "position": _axis_value,
    "alarm": _alarm,
    "file": _procedure,
    "cycle": _cycle,
    "unsupported": _unsupported,
    "approach": approach.read_approach,
    "limits": approach.read_limits,
    "axis_mark": _axis_mark,
    "zero_value": _value,
    "coupling": _procedure,
    "interrupt": _interrupt,
    "synchronised": syncact.read,
}


def is_command_start(p: Reading, name: str) -> bool:
    """Whether ``name`` here starts a command of the table (a program file of a cycle's name
    beside the program is called instead)."""
    c = COMMANDS.get(name)
    if c is None or name in p.variables:
        return False
    if c.kind == "cycle" and name in p.g.programs:
        return False
    return not (c.kind == "keyword" and p.tok.kind == OP and p.tok.text == "[")


# -- running -------------------------------------------------------------------------------
class Recorder:
    """Commands and codes a run met that have no effect on the simulated geometry: one
    ``no_effect`` info per name, at its first block, with the count."""

    def __init__(self) -> None:
        self.seen: dict[str, list] = {}   # name -> [source, count, what it does]

    def note(self, name: str, effect: str, src: SourceRef, kind: str = "no_effect") -> None:
        entry = self.seen.get(name)
        if entry is None:
            self.seen[name] = [src, 1, effect, kind]
        else:
            entry[1] += 1

    def findings(self) -> list[Finding]:
        tail = {"no_effect": "; no effect on the geometry vmach simulates", "file_sandbox": ""}
        return [info(kind, f"{name}: {effect}{tail[kind]}" + (f" ({count} times)" if count > 1 else ""),
                     src, command=name, count=count)
                for name, (src, count, effect, kind) in self.seen.items()]


def code_step(it: Running, code, col: int, src: SourceRef) -> Callable:
    """The step of an accepted G-group code (BRISK, COMPCAD, FNORM …): recorded."""
    effect = f"{code.group_name.replace('_', ' ')} (G group {code.group})"
    name = code.name
    note = it.recorder.note
    where = src.at(col)
    return lambda v: note(name, effect, where)


def step(it: Running, item: b.Command, src: SourceRef, positions: list) -> Callable:
    """The step of one command: evaluates what it holds, records or acts. ``positions``
    collects the block's positioning moves (POS/POSA), run after its path motion."""
    fs = [compile_expr(a, it.env) if a is not None else None for a in item.args]
    kind = item.kind
    name = item.name
    if kind == "position":
        f = fs[0]
        word = b.Word(item.col, item.axis, "axis", item.args[0], None, item.mode)  # type: ignore[arg-type]
        return lambda v: positions.append((word, _number(f(), name)))  # type: ignore[misc]
    if kind == "file":
        return sandbox.step(it, item, src)
    if kind == "approach":
        return approach.step(it, item, src)
    if kind == "zero_value":
        return _zero_value(it, item, fs[0], src)
    if kind == "coupling":
        return coupling.step(it, item, src)
    if kind == "synchronised":
        return syncact.step(it, item, src)
    if kind == "alarm":
        f = fs[0]

        def alarm(v):
            n = _number(f(), name)
            raise ProgramError("program_alarm", f"SETAL({n:g}): the program raises alarm {n:g}",
                               src.at(item.col), alarm=n)

        return alarm
    if name == "TCARR":                      # the orientable tool carrier (toolcarrier.py)
        f = fs[0]
        return lambda v: orientation.carrier(it.machine, f(), src.at(item.col))
    if name == "LIMS":                       # the speed limit under G96 (interpreters/sinumerik/surface.py)
        f = fs[0]
        return lambda v: surface.lims(it.machine, _number(f(), name), src.at(item.col))
    effect = COMMANDS[name].effect if name in COMMANDS else CODES[name].group_name
    note = it.recorder.note

    def record(v):
        vals = tuple(g() if g is not None else None for g in fs)
        note(name, effect, src.at(item.col))
        if name == "CYCLE832":           # kept in the stream: its tolerance (mm) first
            tol = vals[0] if vals and isinstance(vals[0], (int, float)) else 0.0
            it.machine.out.append(canon.PathTolerance(src.at(item.col), tolerance=float(tol),
                                                      setting=vals[1:]))

    return record


def _zero_value(it: Running, item: b.Command, f: Callable, src: SourceRef) -> Callable:
    note, effect = it.recorder.note, COMMANDS[item.name].effect

    def zero(v):
        value = _number(f(), item.name)
        if value != 0:
            raise EvalError("unsupported", f"{item.name}={value:g}: {effect}; vmach simulates only 0")
        note(item.name, effect, src.at(item.col))

    return zero


def run_positions(it: Running, positions: list, src: SourceRef) -> None:
    """POS/POSA of one block: each axis traverses to its value after the path motion."""
    machine = it.machine
    motion = machine.motion
    machine.motion = "G0"
    try:
        for word, value in positions:
            machine.general_move([(word, value)], src)
    finally:
        machine.motion = motion
        positions.clear()


#: names of the cycles in the control's cycle directories: Siemens and the machine maker's
#: CYCLEnnn, and the ShopMill (E_…) and ShopTurn (F_…) step cycles of a machining step program
CONTROL_CYCLE = re.compile(r"^(CYCLE\d+|[EF]_[A-Z][A-Z0-9_]*)$")


def not_found(name: str, how: str, programs, control) -> tuple[str, str]:
    """Kind and message for a call whose program is not beside the caller: a file the program
    names (CALL/PCALL/EXTCALL) is ``subprogram_not_found``; a name that is no command, cycle
    or program is ``unknown_cycle``, with the nearest known name."""
    if how:
        return "subprogram_not_found", f"{how} {name}: no {name}.SPF or {name}.MPF beside the program"
    if CONTROL_CYCLE.match(name):     # the control's cycle directories hold these
        return "unsupported", (f"{name} is a cycle of the control (Siemens, ShopMill/ShopTurn or the "
                               "machine maker's) that vmach does not simulate and that is not beside the "
                               "program")
    pool = sorted({*programs, *control.cycles, *DRILLING, *PATTERNS, *MILLING, *TURNING, *COMMANDS})
    close = difflib.get_close_matches(name, pool, n=1, cutoff=0.75)
    hint = f"; did you mean {close[0]}?" if close else ""
    return "unknown_cycle", (f"{name} is no Sinumerik command, no cycle the machine declares and no "
                             f"program {name}.SPF/.MPF beside the program{hint}")


def program_name(text: str, how: str) -> str:
    """The program a CALL/PCALL/EXTCALL names, as vmach looks it up beside the caller: the last
    part of an NCK path (``/_N_WKS_DIR/_N_PART_WPD/_N_SUB_SPF``), or of any path for EXTCALL
    (external storage), without ``_N_`` and ``_SPF``/``_MPF`` or ``.SPF``/``.MPF``. Any other
    path is kept whole, so that it is found nowhere (vmach never leaves the directory)."""
    name = text.strip().upper()
    if name.startswith("/_N_") or how == "EXTCALL":
        name = re.split(r"[/\\]", name)[-1]
    if name.startswith("_N_") and name[-4:] in ("_SPF", "_MPF"):
        name = name[3:-4]
    if name[-4:] in (".SPF", ".MPF"):
        name = name[:-4]
    return name


def _number(v, name: str):
    if v.__class__ is str:
        raise EvalError("type_error", f"{name} needs a number, not the string {v!r}")
    return v


__all__ = ["Recorder", "bracketed", "code_step", "is_command_start", "not_found", "program_call", "read",
           "run_positions", "step"]
