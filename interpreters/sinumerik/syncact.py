"""Motion-synchronous actions (Job planning, "Motion-synchronous actions"):

    [ID=n | IDS=n] [WHEN | WHENEVER | FROM | EVERY condition] DO action action …

The control evaluates the condition in the interpolation cycle, beside the program's motion,
and runs the actions when it holds. vmach does not evaluate them. What a synchronised action
of a builder's or shop program most often does leaves the simulated geometry alone: it writes
a variable (``$R10=1``, ``$AC_MARKER[1]=…``, ``$A_OUT[2]=1``, ``$A_DBB[4]=…``) or outputs an
auxiliary function to the PLC (``M7``, ``H5=2``). Such an action is accepted: an ``info``
finding ``synchronized_action`` says it is not evaluated, and every variable it writes that the
program can read back (an R parameter, ``$AC_MARKER``, ``$AC_PARAM``, ``$AC_TIMER``) becomes
*unknown* from that block on: reading it stops the run as ``unsupported`` naming the action,
since its value depends on when the condition held (a new value the program writes makes it
known again). An action that moves, stops or couples an axis or the spindle, changes the
program's flow or calls a technology cycle (``POS[X]=``, ``SPOS``, ``M3``/``M5``, ``DELDTG``,
``RDISABLE``, ``PRESETON`` …) is ``unsupported`` naming it.

The block is read here as tokens: the condition and the values are not parsed as expressions
(they may read main-run variables vmach does not keep); the actions are split where a new name
follows a complete value.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.expr import EvalError, Node
from interpreters.sinumerik.lexer import END, IDENT, NUM, OP, STR
from vmach.findings import info
from vmach.source import SourceRef

if TYPE_CHECKING:
    from interpreters.sinumerik.running import Reading, Running

#: words that start a synchronised action
STARTS = frozenset({"ID", "IDS", "WHEN", "WHENEVER", "FROM", "EVERY", "DO"})
#: variables the main run can read back: written by an action they become unknown
READABLE = frozenset({"$AC_MARKER", "$AC_PARAM", "$AC_TIMER"})
#: M functions that act on the spindle, the tool or the program's flow (not mere PLC outputs)
_ACTING_M = frozenset({0, 1, 2, 3, 4, 5, 6, 17, 19, 30, 40, 41, 42, 43, 44, 45, 70})
_M = re.compile(r"^M(\d+)$")
_R = re.compile(r"^\$R(\d+)$")


def read(p: Reading, t) -> b.Command:
    """The synchronised action starting at ``t`` (consumed), up to the end of the block: a
    ``Command`` of kind ``synchronised`` whose args name the variables it writes (string
    nodes: ``R10``, ``$AC_MARKER``); an action vmach does not accept is ``unsupported``."""
    toks = p.toks
    i = p.pos
    while toks[i].kind != END and not (toks[i].kind == IDENT and toks[i].text == "DO"):
        i += 1
    if toks[i].kind == END:
        p.fail("syntax", f"{t.text}: a synchronised action needs DO and its actions", t.col)
    if t.text != "DO" and i == p.pos and t.text != "ID" and t.text != "IDS":
        p.fail("syntax", f"{t.text} needs a condition before DO", t.col)
    actions = _split(toks, i + 1)
    if not actions:
        p.fail("syntax", "DO needs at least one action", toks[i].col)
    written: list[Node] = []
    for first, rest in actions:
        name = _written(first, rest)
        if name is not None:
            written.append(Node("str", first.col, name))
            continue
        if _output(first, rest):
            continue
        p.fail("unsupported", f"{first.text} in a synchronised action: vmach does not evaluate synchronised "
               "actions, and this one acts on the motion, the spindle or the program", first.col)
    p.pos = len(toks) - 1        # the rest of the block belongs to the action
    return b.Command(t.col, t.text, "synchronised", tuple(written))


def _split(toks: list, start: int) -> list[tuple[Any, list]]:
    """The actions from ``start``: (first token, the tokens after it); a new action starts at a
    name at bracket depth 0 that follows a complete value."""
    out: list[tuple[Any, list]] = []
    depth = 0
    prev = None
    for tok in toks[start:]:
        if tok.kind == END:
            break
        starts = (depth == 0 and tok.kind == IDENT and
                  (prev is None or prev.kind in (NUM, IDENT, STR) or (prev.kind == OP and prev.text in ")]")))
        if starts:
            out.append((tok, []))
        elif out:
            out[-1][1].append(tok)
        if tok.kind == OP and tok.text in "([":
            depth += 1
        elif tok.kind == OP and tok.text in ")]":
            depth -= 1
        prev = tok
    return out


def _written(first, rest: list) -> str | None:
    """The variable an assignment action writes (``R10`` for ``$R10``/``$R[10]``, the system
    variable's name otherwise), or None when the action is no assignment to a ``$`` variable."""
    if not first.text.startswith("$"):
        return None
    k = 0
    if rest and rest[0].kind == OP and rest[0].text == "[":
        depth = 0
        while k < len(rest):
            tok = rest[k]
            k += 1
            if tok.kind == OP and tok.text == "[":
                depth += 1
            elif tok.kind == OP and tok.text == "]":
                depth -= 1
                if depth == 0:
                    break
    if k >= len(rest) or rest[k].kind != OP or rest[k].text != "=":
        return None
    if (m := _R.match(first.text)) is not None:
        return f"R{int(m.group(1))}"
    if first.text == "$R" and k == 3 and rest[1].kind == NUM:
        return f"R{int(float(rest[1].text))}"
    return first.text


def _output(first, rest: list) -> bool:
    """True for an auxiliary function output to the PLC: ``M7``, ``M=7``, ``M2=10``, ``H5=2``,
    ``H=…`` (an M that acts on the spindle, tool or flow, ``M1=3``, or a computed M, is not)."""
    text = first.text
    if text.startswith("H") and (text[1:].isdigit() or text == "H"):
        return True
    if text != "M" and _M.match(text) is None:
        return False
    if not rest:                        # M7
        return text != "M" and int(text[1:]) not in _ACTING_M
    # M=7, M5=10 (the function for spindle 5): a constant the spindle does not act on
    if len(rest) == 2 and rest[0].kind == OP and rest[0].text == "=" and rest[1].kind == NUM:
        return float(rest[1].text) not in _ACTING_M
    return False


class Unknown:
    """The value of a variable a synchronised action may have written: any use of it is
    ``unsupported``, naming the action (so no value vmach cannot know ever reaches the path)."""

    __slots__ = ("what",)

    def __init__(self, what: str) -> None:
        self.what = what

    def _fail(self, *_a: Any) -> Any:
        raise EvalError("unsupported", self.what)

    __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = _fail
    __truediv__ = __rtruediv__ = __floordiv__ = __rfloordiv__ = __mod__ = __rmod__ = _fail
    __pow__ = __rpow__ = __neg__ = __pos__ = __abs__ = __float__ = __int__ = __index__ = _fail
    __bool__ = __round__ = __lt__ = __le__ = __gt__ = __ge__ = __str__ = __format__ = _fail
    __hash__ = None  # type: ignore[assignment]

    def __eq__(self, other: object) -> bool:
        return self._fail()

    def __ne__(self, other: object) -> bool:
        return self._fail()

    def __repr__(self) -> str:
        return "Unknown()"


def step(it: Running, item: b.Command, src: SourceRef) -> Callable:
    """The step of a synchronised action: an ``info`` finding once per block, and the variables
    it writes made unknown (R parameters in the run's R list, the others in the NCK)."""
    where = src.at(item.col)
    names = [a.value for a in item.args if a is not None]
    what = (f"the value of {{}} depends on the synchronised action at line {src.line}, which vmach does not "
            "evaluate")
    noted = []

    def run(v):
        if not noted:
            noted.append(True)
            said = f"; {', '.join(names)} unknown from here" if names else ""
            it.findings.append(info("synchronized_action", "synchronised action not evaluated (vmach "
                                    f"simulates no interpolation-cycle actions){said}", where,
                                    writes=names))
        for name in names:
            if name.startswith("R"):
                it.env.r[int(name[1:])] = Unknown(what.format(name))
            elif name in READABLE:
                it.nck.unknown(name, Unknown(what.format(name)))

    return run
