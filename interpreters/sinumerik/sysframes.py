"""Frame values of the NCK's frame variables (``$P_UIFR[n]``, ``$P_PFRAME`` ...) and the frame
functions CTRANS, CROT, CSCALE, CMIRROR, CFINE and the chain operator ``:``.

A frame holds, per axis, the components the control stores and a program addresses as
``$P_UIFR[1, X, TR]``: coarse offset TR and fine offset FI (mm or degrees), rotation RT
(degrees, geometry axes: about Z, then the new Y, then the new X as ROT does), scale SC and
mirror MI (0/1). Point map of a frame for geometry axes: ``p' = T + R · S · M · p``; other axes
are only translated (TR + FI). Chaining ``A : B`` applies B inside A: ``T = Ta + Ra·Sa·Ma·Tb``,
rotations multiply, scales multiply and mirrors toggle per axis — the control's result when
scale and mirror are uniform over the axes a rotation mixes (vmach's stated limit).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from interpreters.sinumerik.expr import EvalError
from interpreters.sinumerik.frames import IDENTITY, Matrix, apply, diagonal, matmul, rpy

COMPONENTS = ("TR", "FI", "RT", "SC", "MI")
#: the settable frames' G codes by $P_UIFR index (then G505 .. G599 for 5 .. 99)
SETTABLE = ("G500", "G54", "G55", "G56", "G57")
FUNCTIONS = ("CTRANS", "CROT", "CSCALE", "CMIRROR", "CFINE", "CRPL")


@dataclass(frozen=True, slots=True, eq=True)
class Frame:
    """A frame value. Each mapping holds only the axes whose component is not neutral."""

    tr: Mapping[str, float] = field(default_factory=dict)
    fi: Mapping[str, float] = field(default_factory=dict)
    rt: Mapping[str, float] = field(default_factory=dict)
    sc: Mapping[str, float] = field(default_factory=dict)
    mi: frozenset[str] = frozenset()

    # A frame is no number: arithmetic and truth tests are the control's type error.
    def _no(self, *_):
        raise EvalError("type_error", "a FRAME is not a number (use it with ':' or a frame variable)")

    __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = __truediv__ = _no
    __neg__ = __pos__ = __abs__ = __lt__ = __gt__ = __le__ = __ge__ = __bool__ = _no
    __float__ = __int__ = __index__ = __mod__ = __rmod__ = __rtruediv__ = _no

    def get(self, axis: str, comp: str) -> float:
        if comp == "TR":
            return self.tr.get(axis, 0.0)
        if comp == "FI":
            return self.fi.get(axis, 0.0)
        if comp == "RT":
            return self.rt.get(axis, 0.0)
        if comp == "SC":
            return self.sc.get(axis, 1.0)
        return 1.0 if axis in self.mi else 0.0

    def with_component(self, axis: str, comp: str, value: float) -> Frame:
        if comp == "MI":
            mi = self.mi | {axis} if value else self.mi - {axis}
            return Frame(self.tr, self.fi, self.rt, self.sc, frozenset(mi))
        if comp == "SC" and value == 0:
            raise EvalError("invalid_value", f"a scale factor of 0 for {axis}")
        attr = comp.lower()
        table = dict(getattr(self, attr))
        table[axis] = float(value)
        parts = {"tr": self.tr, "fi": self.fi, "rt": self.rt, "sc": self.sc}
        parts[attr] = table
        return Frame(parts["tr"], parts["fi"], parts["rt"], parts["sc"], self.mi)

    def offsets(self) -> dict[str, float]:
        """Translation per axis (coarse + fine), mm or degrees."""
        return {a: self.tr.get(a, 0.0) + self.fi.get(a, 0.0) for a in {*self.tr, *self.fi}}

    def linear(self, geometry: tuple[str, str, str]) -> Matrix:
        """R · S · M for the geometry axes."""
        g = geometry
        rot = rpy(self.rt.get(g[0], 0.0), self.rt.get(g[1], 0.0), self.rt.get(g[2], 0.0))
        diag = tuple(self.sc.get(a, 1.0) * (-1.0 if a in self.mi else 1.0) for a in g)
        return matmul(rot, diagonal(diag)) if diag != (1.0, 1.0, 1.0) else rot  # type: ignore[arg-type]


NEUTRAL = Frame()


def make(name: str, args: list, geometry: tuple[str, str, str]) -> Frame:
    """CTRANS/CROT/CSCALE/CMIRROR/CFINE of their arguments (axis names as strings, values as
    numbers); no arguments: the neutral frame."""
    if name == "CMIRROR":
        axes = []
        for a in args:
            if not isinstance(a, str):
                raise EvalError("type_error", f"CMIRROR takes axis names, got {a!r}")
            axes.append(a.upper())
        return Frame(mi=frozenset(axes))
    if len(args) % 2:
        raise EvalError("syntax", f"{name} takes pairs of axis name and value")
    values: dict[str, float] = {}
    for k in range(0, len(args), 2):
        axis, value = args[k], args[k + 1]
        if not isinstance(axis, str) or isinstance(value, str) or isinstance(value, Frame):
            raise EvalError("type_error", f"{name} takes pairs of axis name and value")
        values[axis.upper()] = float(value)
    if name == "CTRANS":
        return Frame(tr=values)
    if name == "CFINE":
        return Frame(fi=values)
    if name == "CSCALE":
        if any(v == 0 for v in values.values()):
            raise EvalError("invalid_value", "CSCALE: a scale factor of 0")
        return Frame(sc=values)
    for axis in values:
        if axis not in geometry:
            raise EvalError("invalid_value", f"CROT: {axis} is not a geometry axis")
    return Frame(rt=values)


def crpl(args: list, geometry: tuple[str, str, str], normal: str) -> Frame:
    """CRPL(plane, angle): a rotation in a plane — 0 the working plane (about ``normal``), 1
    about the third geometry axis, 2 about the second, 3 about the first."""
    if len(args) != 2 or any(isinstance(a, str | Frame) for a in args):
        raise EvalError("syntax", "CRPL takes a plane number and an angle")
    plane, angle = args
    if plane not in (0, 1, 2, 3):
        raise EvalError("invalid_value", f"CRPL: plane {plane} is not 0..3")
    axis = normal if plane == 0 else geometry[3 - int(plane)]
    return Frame(rt={axis: float(angle)})


def chain(a: Frame, b: Frame, geometry: tuple[str, str, str]) -> Frame:
    """``a : b`` — b applied inside a."""
    if not isinstance(a, Frame) or not isinstance(b, Frame):
        raise EvalError("type_error", "':' chains frames only")
    g = geometry
    lin = a.linear(g)
    tb = tuple(b.tr.get(n, 0.0) for n in g)
    fb = tuple(b.fi.get(n, 0.0) for n in g)
    tr = dict(a.tr)
    fi = dict(a.fi)
    mt, mf = apply(lin, tb), apply(lin, fb)  # type: ignore[arg-type]
    for i, n in enumerate(g):
        if mt[i] or n in tr:
            tr[n] = tr.get(n, 0.0) + mt[i]
        if mf[i] or n in fi:
            fi[n] = fi.get(n, 0.0) + mf[i]
    for n, v in b.tr.items():
        if n not in g:
            tr[n] = tr.get(n, 0.0) + v
    for n, v in b.fi.items():
        if n not in g:
            fi[n] = fi.get(n, 0.0) + v
    rot = matmul(rpy(*(a.rt.get(n, 0.0) for n in g)), rpy(*(b.rt.get(n, 0.0) for n in g)))
    angles = angles_of(rot)
    rt = {n: v for n, v in zip(g, angles, strict=True) if abs(v) > 1e-12}
    sc = {n: a.sc.get(n, 1.0) * b.sc.get(n, 1.0) for n in {*a.sc, *b.sc}}
    return Frame(tr, fi, rt, {n: v for n, v in sc.items() if v != 1.0}, a.mi ^ b.mi)


def angles_of(m: Matrix) -> tuple[float, float, float]:
    """RPY angles (about X, Y, Z, degrees) of rotation ``m = Rz · Ry · Rx``; Y in −90..90."""
    if m == IDENTITY:
        return (0.0, 0.0, 0.0)
    sy = max(-1.0, min(1.0, -m[2][0]))
    ry = math.degrees(math.asin(sy))
    if abs(sy) < 1.0 - 1e-12:
        rx = math.degrees(math.atan2(m[2][1], m[2][2]))
        rz = math.degrees(math.atan2(m[1][0], m[0][0]))
    else:  # gimbal lock: all of the turn about Z
        rx = 0.0
        rz = math.degrees(math.atan2(-m[0][1], m[1][1]))
    return (rx, ry, rz)


def from_state(trans: Mapping[str, float], rot: Matrix, geometry: tuple[str, str, str]) -> Frame:
    """The frame of a translation and a (rotation) matrix, as the programmable frame holds
    them; a matrix with scale or mirror reads as its nearest rotation's angles."""
    rt = {n: v for n, v in zip(geometry, angles_of(rot), strict=True) if abs(v) > 1e-12}
    return Frame(tr=dict(trans), rt=rt)


def settable_code(n: int) -> str | None:
    """G code of settable frame ``$P_UIFR[n]``."""
    if 0 <= n < len(SETTABLE):
        return SETTABLE[n]
    return f"G5{n:02d}" if 5 <= n <= 99 else None


def settable_index(code: str) -> int:
    return SETTABLE.index(code) if code in SETTABLE else int(code[2:])
