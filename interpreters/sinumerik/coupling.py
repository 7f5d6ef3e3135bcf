"""Synchronous spindle coupling: ``COUPDEF``, ``COUPON``/``COUPONC``, ``COUPOF``/``COUPOFS``,
``COUPDEL``, ``COUPRES`` (SINUMERIK function manual "S3: Synchronous spindle"; its
polygonal turning — multi-edge machining — is a synchronous spindle coupling at an integer
ratio: the tool spindle as following spindle FS, the main spindle as leading spindle LS).

    COUPDEF(FS, LS, ÜFS, ÜLS, block change, coupling type)   ; define (or change) the pair
    COUPON(FS, LS, POSFS)      ; couple; FS at POSFS degrees when LS is at 0 (optional)
    COUPONC(FS, LS)            ; couple, taking over FS's programmed speed
    COUPOF(FS, LS, POSFS, POSLS) / COUPOFS(FS, LS, POSFS)   ; uncouple (COUPOFS stops FS)
    COUPDEL(FS, LS)            ; delete the pair (uncoupled first)
    COUPRES(FS, LS)            ; reset to the configured values

FS and LS are spindle names ``S1``, ``S2``…; the transformation ratio is ÜFS/ÜLS (FS turns
per LS turn, negative: the other way round); block change behaviour ``"NOC"``, ``"FINE"``,
``"COARSE"`` or ``"IPOSTOP"``; coupling type ``"DV"`` (setpoint), ``"AV"`` (actual value) or
``"VV"`` (velocity). Omitted places keep the pair's values (first definition: ratio 1:1,
``"FINE"``, ``"DV"``). vmach's machines configure no couplings in machine data, so a pair
exists once ``COUPDEF`` made it and ``COUPRES`` forgets it.

Each coupling or uncoupling is a :class:`vmach.canon.SpindleCoupling` in the stream; while
coupled, FS turns at the ratio times LS's speed (a :class:`vmach.canon.Spindle` at ``COUPON``;
under G96 FS follows LS's speed as it changes on the control, vmach's stream keeps the speed
at the coupling). Errors (each at its place in the program): a spindle the machine lacks
(``unknown_spindle``), a ratio of 0 or a zero denominator, an unknown behaviour or type
(``invalid_value``), ``COUPDEF`` of an active pair (``coupling_active``: the control's alarm
16797), ``COUPON`` of an undefined pair (``coupling_undefined``).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from interpreters.sinumerik.expr import compile_expr
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef

if TYPE_CHECKING:
    from interpreters.sinumerik import blocks as b
    from interpreters.sinumerik.running import Running

NAMES = ("COUPDEF", "COUPON", "COUPONC", "COUPOF", "COUPOFS", "COUPDEL", "COUPRES")
BLOCK_CHANGE = ("NOC", "FINE", "COARSE", "IPOSTOP")
TYPES = ("DV", "AV", "VV")
_SPINDLE = re.compile(r"^S(\d+)$", re.IGNORECASE)


@dataclass
class Pair:
    """One defined coupling: FS turns ``numerator / denominator`` times per LS turn."""

    numerator: float = 1.0
    denominator: float = 1.0
    block_change: str = "FINE"
    mode: str = "DV"
    active: bool = False

    @property
    def ratio(self) -> float:
        return self.numerator / self.denominator


def pairs(m) -> dict[tuple[int, int], Pair]:
    """The machine's defined couplings, (FS, LS) -> Pair (kept on the machine state)."""
    if not hasattr(m, "couplings"):
        m.couplings = {}
    return m.couplings


def step(it: Running, item: b.Command, src: SourceRef) -> Callable:
    """The run step of one coupling command."""
    fs = [compile_expr(a, it.env) if a is not None else None for a in item.args]
    where = src.at(item.col)
    name = item.name

    def run(v):
        vals = [f() if f is not None else None for f in fs]
        _run(it.machine, name, vals, where)

    return run


def _run(m, name: str, vals: list, src: SourceRef) -> None:
    if len(vals) < 2 or vals[0] is None or vals[1] is None:
        raise ProgramError("syntax", f"{name} needs the following and the leading spindle: "
                                     f"{name}(S2, S1, ...)", src)
    most = {"COUPDEF": 6, "COUPON": 3, "COUPONC": 2, "COUPOF": 4, "COUPOFS": 3, "COUPDEL": 2,
            "COUPRES": 2}[name]
    if len(vals) > most:
        raise ProgramError("syntax", f"{name} takes at most {most} arguments", src)
    fs, ls = _spindle(m, vals[0], name, src), _spindle(m, vals[1], name, src)
    if fs == ls:
        raise ProgramError("invalid_value", f"{name}: a spindle cannot follow itself (S{fs})", src)
    known = pairs(m)
    key = (fs, ls)
    pair = known.get(key)
    if name == "COUPDEF":
        if pair is not None and pair.active:
            raise ProgramError("coupling_active", f"COUPDEF(S{fs}, S{ls}): the coupling is active "
                                                  "(COUPOF first; the control's alarm 16797)", src)
        pair = pair or Pair()
        _define(pair, vals[2:], src)
        known[key] = pair
        return
    if name in ("COUPON", "COUPONC"):
        if pair is None:
            raise ProgramError("coupling_undefined", f"{name}(S{fs}, S{ls}): no such coupling "
                                                     "(define it with COUPDEF first)", src)
        offset = _number(vals[2], name, "POSFS", src) if len(vals) > 2 and vals[2] is not None else None
        pair.active = True
        m.out.append(canon.SpindleCoupling(src, following=fs, leading=ls, ratio=pair.ratio, active=True,
                                           offset=offset, mode=pair.mode))
        lead = m.spindles.get(ls, [0.0, "stop"])
        turn = lead[1] if pair.ratio > 0 or lead[1] == "stop" else {"cw": "ccw", "ccw": "cw"}[lead[1]]
        m.spindles[fs] = [abs(pair.ratio) * float(lead[0]), turn]
        m.out.append(canon.Spindle(src, spindle=fs, speed=m.spindles[fs][0], direction=turn))
        return
    for k, v in enumerate(vals[2:]):
        if v is not None:
            _number(v, name, ("POSFS", "POSLS")[k], src)
    if pair is not None and pair.active:
        pair.active = False
        m.out.append(canon.SpindleCoupling(src, following=fs, leading=ls, ratio=pair.ratio, active=False,
                                           mode=pair.mode))
        if name == "COUPOFS":
            m.spindles[fs] = [0.0, "stop"]
            m.out.append(canon.Spindle(src, spindle=fs, speed=0.0, direction="stop"))
    if name in ("COUPDEL", "COUPRES"):
        known.pop(key, None)


def _define(pair: Pair, rest: list, src: SourceRef) -> None:
    """COUPDEF's places after FS and LS: ÜFS, ÜLS, block change, coupling type."""
    rest = rest + [None] * (4 - len(rest))
    num, den, block, mode = rest[:4]
    numerator = pair.numerator if num is None else _number(num, "COUPDEF", "ÜFS", src)
    denominator = pair.denominator if den is None else _number(den, "COUPDEF", "ÜLS", src)
    if denominator == 0 or numerator == 0:
        raise ProgramError("invalid_value", "COUPDEF: the transformation ratio ÜFS/ÜLS needs both "
                                            "non-zero", src)
    if block is not None:
        if not isinstance(block, str) or block.upper() not in BLOCK_CHANGE:
            raise ProgramError("invalid_value", f"COUPDEF: block change behaviour must be one of "
                                                f"{', '.join(BLOCK_CHANGE)}; got {block!r}", src)
        pair.block_change = block.upper()
    if mode is not None:
        if not isinstance(mode, str) or mode.upper() not in TYPES:
            raise ProgramError("invalid_value", f"COUPDEF: coupling type must be one of {', '.join(TYPES)}; "
                                                f"got {mode!r}", src)
        pair.mode = mode.upper()
    pair.numerator, pair.denominator = numerator, denominator


def _spindle(m, v, name: str, src: SourceRef) -> int:
    """The spindle number of ``S<n>`` (an unknown one: ``unknown_spindle``)."""
    hit = _SPINDLE.match(v.strip()) if isinstance(v, str) else None
    if hit is None:
        raise ProgramError("invalid_value", f"{name}: a spindle is named S1, S2, ...; got {v!r}", src)
    s = int(hit.group(1))
    if s not in m.spindles:
        if m.control.strict_axes:
            raise ProgramError("unknown_spindle", f"{name}: the machine has no spindle {s}", src)
        m.spindles[s] = [0.0, "stop"]
    return s


def _number(v, name: str, what: str, src: SourceRef) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ProgramError("invalid_value", f"{name}: {what} must be a number; got {v!r}", src)
    v = float(v)
    if v != v or abs(v) == float("inf"):
        raise ProgramError("invalid_value", f"{name}: {what} must be finite", src)
    return v


__all__ = ["NAMES", "Pair", "pairs", "step"]
