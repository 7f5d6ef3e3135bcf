"""String and axis functions of the Sinumerik language (Programming Manual, Job planning,
"String operations" and "Axis functions").

Strings index from 0. ``INDEX(s, c)`` / ``RINDEX(s, c)``: first / last position of the character
``c`` (-1: none); ``MINDEX(s, chars)``: first position of any of ``chars``; ``MATCH(s, t)``: first
position of the string ``t``; ``SUBSTR(s, i[, n])``: ``n`` characters from ``i`` (all to the end
without ``n``); ``STRLEN``, ``TOUPPER``, ``TOLOWER``; ``NUMBER(s)`` reads a number (a string that
is no number is an error, as the control's alarm), ``ISNUMBER(s)`` tells whether it is one;
``SPRINT(format, values…)`` formats as the control does with ``%D %I %F %E %G %S %C %X %B %%``
(width and ``.precision`` allowed; ``%F`` has 6 decimals by default).

Axis values are axis names (``DEF AXIS``): ``AXNAME("X")`` is the axis X, ``AXSTRING(X)`` the
string "X". Functions that need the machine (``AXTOSPI``, ``SPI``, ``ISAXIS``) and the program's
names (``ISVAR``) are compiled against the run's state (:func:`compile_call`).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

from interpreters.sinumerik import sysvars
from interpreters.sinumerik.errors import EvalError

_NUMBER = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)(EX[+-]?\d+)?\s*$", re.IGNORECASE)
_FORMAT = re.compile(r"%(-?\d*)(?:\.(\d+))?([A-Za-z%])")


def _str(v: Any, fn: str) -> str:
    if v.__class__ is not str:
        raise EvalError("type_error", f"{fn} needs a string, got {v!r}")
    return v


def _int(v: Any, fn: str) -> int:
    if v.__class__ is str:
        raise EvalError("type_error", f"{fn} needs a number, got the string {v!r}")
    return int(v)


def _char(v: Any, fn: str) -> str:
    if v.__class__ is str:
        return v[:1]
    return chr(_int(v, fn) & 0xFF)


def _index(s, c):
    return _str(s, "INDEX").find(_char(c, "INDEX")) if _char(c, "INDEX") else -1


def _rindex(s, c):
    return _str(s, "RINDEX").rfind(_char(c, "RINDEX")) if _char(c, "RINDEX") else -1


def _mindex(s, chars):
    s, chars = _str(s, "MINDEX"), _str(chars, "MINDEX")
    return next((i for i, ch in enumerate(s) if ch in chars), -1)


def _match(s, t):
    return _str(s, "MATCH").find(_str(t, "MATCH"))


def _substr(s, i, n=None):
    s, i = _str(s, "SUBSTR"), _int(i, "SUBSTR")
    if i < 0:
        raise EvalError("index_range", f"SUBSTR from position {i}")
    return s[i:] if n is None else s[i:i + max(_int(n, "SUBSTR"), 0)]


def _number(s):
    s = _str(s, "NUMBER")
    if not _NUMBER.match(s):
        raise EvalError("type_error", f"NUMBER: {s!r} is not a number")
    return float(s.upper().replace("EX", "E"))


def _isnumber(s):
    return bool(_NUMBER.match(_str(s, "ISNUMBER")))


def _sprint(fmt, *values):
    fmt = _str(fmt, "SPRINT")
    out: list[str] = []
    rest = list(values)
    last = 0
    for m in _FORMAT.finditer(fmt):
        out.append(fmt[last:m.start()])
        last = m.end()
        width, prec, conv = m.group(1), m.group(2), m.group(3).upper()
        if conv == "%":
            out.append("%")
            continue
        if not rest:
            raise EvalError("syntax", f"SPRINT: format {fmt!r} needs more values")
        v = rest.pop(0)
        out.append(_convert(conv, width, prec, v, m.group(0)))
    out.append(fmt[last:])
    return "".join(out)


def _convert(conv: str, width: str, prec: str | None, v: Any, spec: str) -> str:
    if conv == "S":
        text = v if v.__class__ is str else _plain(v)
        return f"{text:{width}}" if width else text
    if conv == "C":
        return _char(v, "SPRINT")
    if conv == "B":
        return "TRUE" if (v != "" if v.__class__ is str else bool(v)) else "FALSE"
    if v.__class__ is str:
        raise EvalError("type_error", f"SPRINT: {spec} needs a number, got the string {v!r}")
    if conv in ("D", "I"):
        return f"{round(v):{width}d}"
    if conv == "X":
        return f"{round(v):{width}X}"
    if conv in ("F", "E", "G"):
        p = 6 if prec is None else int(prec)
        return f"{float(v):{width}.{p}{conv}}"
    raise EvalError("unsupported", f"SPRINT: the format {spec} is not simulated")


def _plain(v: Any) -> str:
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


#: name -> (min args, max args, implementation) of the functions that need only their values
PURE: dict[str, tuple[int, int, Callable[..., Any]]] = {
    "STRLEN": (1, 1, lambda s: len(_str(s, "STRLEN"))),
    "INDEX": (2, 2, _index),
    "RINDEX": (2, 2, _rindex),
    "MINDEX": (2, 2, _mindex),
    "MATCH": (2, 2, _match),
    "SUBSTR": (2, 3, _substr),
    "TOUPPER": (1, 1, lambda s: _str(s, "TOUPPER").upper()),
    "TOLOWER": (1, 1, lambda s: _str(s, "TOLOWER").lower()),
    "NUMBER": (1, 1, _number),
    "ISNUMBER": (1, 1, _isnumber),
    "SPRINT": (1, 20, _sprint),
    "AXNAME": (1, 1, lambda s: _str(s, "AXNAME").strip().upper()),
    "AXSTRING": (1, 1, lambda a: _str(a, "AXSTRING")),
}

#: functions whose argument may be an axis written bare (``AXSTRING(X)``, ``AXTOSPI(C1)``)
AXIS_ARGUMENT = frozenset({"AXSTRING", "AXTOSPI"})

#: name -> (min args, max args) of the functions compiled against the run's state
STATEFUL: dict[str, tuple[int, int]] = {"AXTOSPI": (1, 1), "SPI": (1, 1), "ISAXIS": (1, 1),
                                        "ISVAR": (1, 1)}


def compile_call(name: str, fs: list[Callable[[], Any]], env: Any) -> Callable[[], Any]:
    """A closure for a STATEFUL function: ``env`` is the expression environment (``expr.Env``,
    its ``sys`` the NCK state with the machine's ``control``)."""
    f = fs[0]
    if name == "ISVAR":
        def isvar():
            n = _str(f(), "ISVAR").strip().upper()
            return n in env.vars or n in env.globals or _is_r(n) or sysvars.lookup(n) is not None
        return isvar

    def control():
        if env.sys is None:
            raise EvalError("unsupported", f"{name} needs the machine's axes")
        return env.sys.control

    if name == "ISAXIS":
        def isaxis():
            c, n = control(), _int(f(), "ISAXIS")
            names = {a.name for a in c.axes}
            return 1 <= n <= 3 and (not c.strict_axes or c.geometry[n - 1] in names)
        return isaxis
    if name == "SPI":
        return lambda: spindle_axis(control(), _int(f(), "SPI"))
    return lambda: axis_spindle(control(), _str(f(), "AXTOSPI").upper())


def _is_r(n: str) -> bool:
    return n[:1] == "R" and n[1:].isdigit() and int(n[1:]) < 1000


def axis_spindle(control: Any, axis: str) -> int:
    """AXTOSPI: the spindle number of a spindle axis (``SP2``, ``C1`` of spindle 1, ``C`` of the
    master spindle on a machine with one C axis)."""
    names = {a.name for a in control.axes}
    m = re.fullmatch(r"(?:SP|C)(\d+)", axis)
    if m and int(m.group(1)) in control.spindles and (axis in names or axis.startswith("SP")):
        return int(m.group(1))
    if axis == "C" and "C" in names:
        return control.master_spindle
    raise EvalError("unknown_axis", f"AXTOSPI: {axis} is not a spindle axis of this machine")


def spindle_axis(control: Any, n: int) -> str:
    """SPI: the axis name of spindle ``n`` (``C1`` when the machine names it so, else ``SPn``)."""
    names = {a.name for a in control.axes}
    if n not in control.spindles:
        raise EvalError("index_range", f"SPI: the machine has no spindle {n}")
    if f"C{n}" in names:
        return f"C{n}"
    if n == control.master_spindle and "C" in names:
        return "C"
    return f"SP{n}"
