"""Blocks that name axes without moving them along the path: fixed-point and reference-point
approach (G75, G74) and the working-area / spindle-speed limits (G25, G26).

- ``G75 FP=n X1=0 Z1=0`` (Programming Manual Fundamentals, "Fixed point approach"): the named
  machine axes traverse at rapid, each to its fixed point n (1..4, default 1), machine data
  MD30600 ``$MA_FIX_POINT_POS[n-1, axis]`` from the model, else the control's default 0. The
  values written after the axes are ignored by the control (0 by convention). The move is in
  machine coordinates (frames suppressed, as G53/SUPA), non-modal, and ends where the axes
  stop.
- ``G74 X1=0 Z1=0`` ("Reference point approach"): the same to the reference point,
  MD34100 ``$MA_REFP_SET_POS[0, axis]``.
- ``G25``/``G26`` with axis values (the lower / upper working-area limits) or spindle speeds
  (``G25 S…``, the speed limits): monitoring only; the run records them (``no_effect``) and
  checks the model's own travel limits.

An axis may be written as the machine axis of its channel axis (``Z1`` for ``Z`` when the
machine has no axis ``Z1``): vmach's models name each machine axis as its channel axis.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.execute import Values
from interpreters.sinumerik.expr import EvalError, Node, compile_expr
from interpreters.sinumerik.lexer import END, IDENT, NUM, OP
from vmach.errors import ProgramError
from vmach.source import SourceRef

if TYPE_CHECKING:
    from interpreters.sinumerik.running import Reading, Running

_SPEED = re.compile(r"^S\d*$")
#: G code -> (machine data of the positions, its first index is FP-1)
DATA = {"G75": "$MA_FIX_POINT_POS", "G74": "$MA_REFP_SET_POS"}


def _axis(p: Reading, name: str) -> str | None:
    """The channel axis ``name`` stands for (itself, or ``Z`` for the machine axis ``Z1``)."""
    if p.g.is_axis(name):
        return name
    m = re.fullmatch(r"([A-Z]+)\d+", name)
    if m and p.g.is_axis(m.group(1)):
        return m.group(1)
    return None


def _words(p: Reading, t, speeds: bool) -> list[tuple[str, Node | None]]:
    """``NAME=value`` or ``NAME value`` pairs up to the end of the block: (name, value)."""
    out: list[tuple[str, Node | None]] = []
    while p.tok.kind != END:
        wt = p.tok
        if wt.kind != IDENT:
            p.fail("syntax", f"unexpected {p.describe(wt)} in {t.text} (it takes axis values only)")
        p.pos += 1
        name = wt.text
        if p.is_op("="):
            p.pos += 1
            node = p.expr()
        elif p.tok.kind == NUM or (p.tok.kind == OP and p.tok.text in "+-"):
            node = p.expr()
        else:
            m = re.fullmatch(r"([A-Z])(-?\d+(?:\.\d*)?)", name)   # X10 read as one word
            if m is None:
                p.fail("syntax", f"{name} needs a value in {t.text}", wt.col)
            name, node = m.group(1), Node("num", wt.col, float(m.group(2)))
        if name == "FP" and t.text == "G75":
            out.insert(0, ("FP", node))
            continue
        if speeds and _SPEED.match(name):
            out.append((name, node))
            continue
        axis = _axis(p, name)
        if axis is None:
            p.fail("unknown_axis", f"{t.text}: {name} is not an axis of this machine", wt.col)
        out.append((axis, node))
    return out


def read_limits(p: Reading, t) -> b.Command:
    """``G25``/``G26`` with axis values or spindle speeds (their own block)."""
    words = _words(p, t, speeds=True)
    if not words:
        p.fail("syntax", f"{t.text} needs axis values or a spindle speed S")
    return b.Command(t.col, t.text, "limits", tuple(node for _, node in words))


def read_approach(p: Reading, t) -> b.Command:
    """``G75 FP=n axis=0 …`` / ``G74 axis=0 …``: args are FP (or None) and the axes by name."""
    words = _words(p, t, speeds=False)
    fp = words.pop(0)[1] if words and words[0][0] == "FP" else None
    if not words:
        p.fail("syntax", f"{t.text} needs the axes that approach: {t.text} Z1=0")
    return b.Command(t.col, t.text, "approach", (fp, *(Node("str", t.col, a) for a, _ in words)))


def step(it: Running, item: b.Command, src: SourceRef) -> Callable:
    """The traverse of G75/G74: each named axis to its point, frames suppressed."""
    fp = compile_expr(item.args[0], it.env) if item.args[0] is not None else (lambda: 1)
    axes = [a.value for a in item.args[1:] if a is not None]
    name = item.name
    machine = it.machine
    point = [0]         # FP - 1 of the running block; the readers are made now, for this line
    readers = [(a, it.env.sys.reader(DATA[name], [lambda: point[0], lambda a=a: a], item.col))
               for a in axes]

    def approach(v):
        n = fp()
        if n.__class__ is str or n != int(n) or not 1 <= n <= (4 if name == "G75" else 1):
            raise EvalError("invalid_value", f"{name}: FP={n} is no fixed point (1..4)")
        point[0] = int(n) - 1
        words = []
        for a, read in readers:
            value = float(read())
            words.append((b.Word(item.col, a, "axis", Node("num", item.col, value), None, "AC"), value))
        motion = machine.motion
        machine.motion = "G0"
        try:
            block = Values()
            block.axes = words
            machine.move(block, src, True)
        except EvalError as exc:
            raise ProgramError(exc.kind, exc.message, src.at(item.col)) from None
        finally:
            machine.motion = motion
        machine.refresh_plain()

    return approach
