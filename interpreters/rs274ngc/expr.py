"""Values and expressions of RS274/NGC, read the way LinuxCNC reads them (interp_read.cc).

A value is a number, a parameter (``#5``, ``##2``, ``#<name>``), a unary function
(``sin[30]``, ``atan[1]/[1]``, ``exists[#<x>]``) or a bracketed expression. Binary operators
and their precedence, from loosest to tightest::

    and or xor          (2)
    eq ne gt ge lt le   (3)
    + -                 (4)
    * / mod             (5)
    **                  (6)

Operators of equal precedence associate to the left. Angles are in degrees.

Parsing happens once per source line; it yields a *value*: a ``float`` when the text is a
constant, else a function ``value(ctx) -> float`` that reads parameters through ``ctx``
(an object with ``par(index)``, ``named(name)``, ``exists(name)``, ``tool_diameter(n)``
and ``params``, the list of stored numbered parameters that ``par`` reads, except
#5420..#5425, the current position).
Arithmetic errors raise :class:`~interpreters.rs274ngc.diag.NgcError` when evaluated.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable

from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.longdouble import cos_deg, sin_deg, tan_deg, to_degrees

Value = float | Callable  # a constant, or a function of the evaluation context

TOLERANCE_EQUAL = 0.0001  # LinuxCNC 2.9 interp_internal.hh
_DEG = math.pi / 180.0

_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)")
_SPAN = re.compile(r"[+-]*[0-9.]*")


def is_const(v: Value) -> bool:
    return type(v) is float


def evaluate(v: Value, ctx) -> float:
    """The value of ``v`` (constant or function) as a float."""
    return v if type(v) is float else v(ctx)


# --------------------------------------------------------------------------------------------
# Operators
# --------------------------------------------------------------------------------------------


def _div(a: float, b: float) -> float:
    if b == 0.0:
        raise NgcError("divide_by_zero")
    return a / b


def _mod(a: float, b: float) -> float:
    if b == 0.0 or a in (math.inf, -math.inf) or a != a or b != b:
        return math.nan  # fmod(x, 0), fmod(inf, y) are NaN in C; reported by the NaN check
    r = math.fmod(a, b)
    if r < 0.0:
        r += abs(b)
    return r


def _pow(a: float, b: float) -> float:
    if a < 0.0 and math.floor(b) != b:
        raise NgcError("negative_power")
    try:
        return math.pow(a, b)
    except (OverflowError, ValueError):
        # C's pow: 0 to a negative power and overflows are infinite (odd powers keep the sign)
        odd = b == math.floor(b) and math.fmod(b, 2.0) != 0.0
        negative = math.copysign(1.0, a) < 0 and odd
        return -math.inf if negative else math.inf


def _eq(a, b):
    return 1.0 if abs(a - b) < TOLERANCE_EQUAL else 0.0


def _ne(a, b):
    return 1.0 if abs(a - b) >= TOLERANCE_EQUAL else 0.0


def _le(a, b):  # LinuxCNC 2.9 compares LE/GE/LT/GT exactly, only EQ/NE with a tolerance
    return 1.0 if a <= b else 0.0


def _ge(a, b):
    return 1.0 if a >= b else 0.0


def _mul(a, b):
    return a * b


def _add(a, b):
    return a + b


def _sub(a, b):
    return a - b


BINARY: dict[str, tuple[int, Callable[[float, float], float]]] = {
    "**": (6, _pow),
    "*": (5, _mul),
    "/": (5, _div),
    "mod": (5, _mod),
    "+": (4, _add),
    "-": (4, _sub),
    "eq": (3, _eq),
    "ne": (3, _ne),
    "gt": (3, lambda a, b: 1.0 if a > b else 0.0),
    "ge": (3, _ge),
    "lt": (3, lambda a, b: 1.0 if a < b else 0.0),
    "le": (3, _le),
    "and": (2, lambda a, b: 0.0 if (a == 0.0 or b == 0.0) else 1.0),
    "or": (2, lambda a, b: 1.0 if (a != 0.0 or b != 0.0) else 0.0),
    "xor": (2, lambda a, b: 1.0 if ((a == 0.0) != (b == 0.0)) else 0.0),
}
#: operations that raise nothing for any floats (inf and NaN included): no error to locate
_INFALLIBLE = frozenset(BINARY[op][1] for op in (
    "*", "mod", "+", "-", "eq", "ne", "gt", "ge", "lt", "le", "and", "or", "xor"))


def _acos(x):
    if x < -1.0 or x > 1.0:
        raise NgcError("acos_range")
    return to_degrees(math.acos(x))


def _asin(x):
    if x < -1.0 or x > 1.0:
        raise NgcError("asin_range")
    return to_degrees(math.asin(x))


def _ln(x):
    if x <= 0.0:
        raise NgcError("ln_range")
    return math.log(x)


def _sqrt(x):
    if x < 0.0:
        raise NgcError("sqrt_range")
    return math.sqrt(x)


def _exp(x):
    try:
        return math.exp(x)
    except OverflowError:
        return math.inf


def _round(x):
    return float(int(x + (-0.5 if x < 0.0 else 0.5)))


def _abs(x):
    return -x if x < 0.0 else x  # as LinuxCNC: ABS[-0] stays -0


def _floor(x):  # C's floor and ceil keep the sign of a zero result: FUP[-0.2] is -0
    r = float(math.floor(x))
    return math.copysign(r, x) if r == 0.0 else r


def _ceil(x):
    r = float(math.ceil(x))
    return math.copysign(r, x) if r == 0.0 else r


UNARY: dict[str, Callable[[float], float]] = {
    "abs": _abs,
    "acos": _acos,
    "asin": _asin,
    "cos": cos_deg,
    "exp": _exp,
    "fix": _floor,
    "fup": _ceil,
    "ln": _ln,
    "round": _round,
    "sin": sin_deg,
    "sqrt": _sqrt,
    "tan": tan_deg,
}

# read_operation_unary: names by first letter, tried in LinuxCNC's order.
_UNARY_NAMES = {
    "a": ("abs", "acos", "asin", "atan"),
    "c": ("cos",),
    "e": ("exp", "exists"),
    "f": ("fix", "fup"),
    "l": ("ln",),
    "r": ("round",),
    "s": ("sin", "sqrt"),
    "t": ("tan", "td"),
}

# read_operation: binary operator names by first letter.
_BINARY_NAMES = {
    "a": ("and",),
    "m": ("mod",),
    "o": ("or",),
    "x": ("xor",),
    "e": ("eq",),
    "n": ("ne",),
    "g": ("ge", "gt"),
    "l": ("le", "lt"),
}


def checked(x: float) -> float:
    """LinuxCNC rejects NaN and infinity after every value it reads."""
    if x != x:
        raise NgcError("not_a_number")
    if x in (math.inf, -math.inf):
        raise NgcError("infinity")
    return x


# --------------------------------------------------------------------------------------------
# Parser
# --------------------------------------------------------------------------------------------


class Reader:
    """Reads values from one reduced line (lower case, blanks removed outside comments).

    cols : 1-based source column of each character of ``text`` (for diagnostics).
    """

    __slots__ = ("text", "cols", "defer", "deferred")

    def __init__(self, text: str, cols: list[int]):
        self.text = text
        self.cols = cols
        self.defer = False
        self.deferred = None

    # With ``defer`` set (O-lines, whose conditions LinuxCNC may read while skipping), an
    # error met while folding constants is kept in the value, raised when it is evaluated;
    # the first one is remembered in ``deferred`` (it precedes later syntax errors).

    def _failed(self, exc: NgcError) -> Value:
        if not self.defer:
            raise exc
        if self.deferred is None:
            self.deferred = exc

        def fail(ctx):
            raise exc

        return fail

    def col(self, pos: int) -> int:
        if pos < len(self.cols):
            return self.cols[pos]
        return (self.cols[-1] + 1) if self.cols else 1

    def error(self, kind: str, pos: int, **fields) -> NgcError:
        return NgcError(kind, self.col(pos), **fields)

    # -- real_value ----------------------------------------------------------------------

    def real_value(self, pos: int) -> tuple[Value, int]:
        s = self.text
        if pos >= len(s):
            raise self.error("missing_value", pos)
        c = s[pos]
        c1 = s[pos + 1] if pos + 1 < len(s) else ""
        if c == "[":
            return self.expression(pos)
        if c == "#":
            return self.parameter(pos)
        if c in "+-" and c1 and not c1.isdigit() and c1 != ".":
            v, pos = self.real_value(pos + 1)
            if c == "+":
                return v, pos
            if type(v) is float:
                return -v, pos
            return (lambda ctx, f=v: -f(ctx)), pos
        if "a" <= c <= "z":
            return self.unary(pos)
        return self.number(pos)

    def number(self, pos: int) -> tuple[float, int]:
        span = _SPAN.match(self.text, pos).group()
        m = _NUMBER.match(span)
        if not m:
            raise self.error("bad_number", pos, text=span)
        if m.end() != len(span):
            raise self.error("bad_number_trailing", pos, text=span)
        return float(m.group()), pos + len(span)

    def integer(self, pos: int) -> tuple[Value, int]:
        """A value that must be within 0.0001 of an integer (read_integer_value)."""
        v, end = self.real_value(pos)
        col = self.col(pos)
        if type(v) is float:
            try:
                return float(to_integer(v, col)), end
            except NgcError as exc:
                return self._failed(exc), end
        return (lambda ctx, f=v: float(to_integer(f(ctx), col))), end

    # -- parameters ----------------------------------------------------------------------

    def name(self, pos: int) -> tuple[str, int]:
        """``<name>`` starting at ``pos`` (which holds ``<``)."""
        end = self.text.find(">", pos + 1)
        if end < 0:
            raise self.error("named_parameter_unterminated", pos)
        return self.text[pos + 1 : end], end + 1

    def parameter(self, pos: int) -> tuple[Value, int]:
        s = self.text
        col = self.col(pos)
        pos += 1
        if pos < len(s) and s[pos] == "<":
            name, pos = self.name(pos)
            return (lambda ctx: _read(ctx.named, name, col)), pos
        index, pos = self.integer(pos)
        if type(index) is float:
            i = int(index)
            if 1 <= i < 5602 and not 5420 <= i <= 5425:  # a stored value: read it directly
                return (lambda ctx: ctx.params[i]), pos
            if 1 <= i < 5602:
                return (lambda ctx: ctx.par(i)), pos
            return (lambda ctx: _read(ctx.par, i, col)), pos
        return (lambda ctx: _read(ctx.par, int(index(ctx)), col)), pos

    # -- unary functions -----------------------------------------------------------------

    def unary(self, pos: int) -> tuple[Value, int]:
        s = self.text
        c = s[pos]
        names = _UNARY_NAMES.get(c)
        if names is None:
            raise self.error("unknown_word", pos)
        op = next((n for n in names if s.startswith(n, pos)), None)
        if op is None:
            raise self.error("unknown_function", pos, char=c)
        start = pos
        pos += len(op)
        if pos >= len(s) or s[pos] != "[":
            raise self.error("missing_bracket_after_function", pos)
        if op == "exists":
            return self.exists(pos)
        arg, pos = self.expression(pos)
        if op == "atan":
            if pos >= len(s) or s[pos] != "/":
                raise self.error("atan_slash_missing", pos)
            pos += 1
            if pos >= len(s) or s[pos] != "[":
                raise self.error("atan_bracket_missing", pos)
            arg2, pos = self.expression(pos)
            if type(arg) is float and type(arg2) is float:
                return to_degrees(math.atan2(arg, arg2)), pos
            return (
                lambda ctx: to_degrees(math.atan2(evaluate(arg, ctx), evaluate(arg2, ctx)))
            ), pos
        if op == "td":
            return (lambda ctx: ctx.tool_diameter(int(evaluate(arg, ctx)))), pos
        fn = UNARY[op]
        col = self.col(start)
        if type(arg) is float:
            try:
                return checked(fn(arg)), pos
            except NgcError as exc:
                exc.column = col
                return self._failed(exc), pos
        return (lambda ctx: _call(fn, arg(ctx), col)), pos

    def exists(self, pos: int) -> tuple[Value, int]:
        s = self.text
        pos += 1  # '['
        if pos >= len(s) or s[pos] != "#":
            raise self.error("exists_hash_missing", pos)
        pos += 1
        if pos < len(s) and s[pos] == "<":
            name, pos = self.name(pos)
            fn = lambda ctx: 1.0 if ctx.exists(name) else 0.0  # noqa: E731
        else:
            index, pos = self.integer(pos)
            fn = lambda ctx: 1.0 if 1 <= int(evaluate(index, ctx)) < 5602 else 0.0  # noqa: E731
        if pos >= len(s) or s[pos] != "]":
            raise self.error("exists_bracket_missing", pos)
        return fn, pos + 1

    # -- bracketed expressions -----------------------------------------------------------

    def operator(self, pos: int) -> tuple[str, int]:
        s = self.text
        if pos >= len(s):
            raise self.error("unclosed_expression", pos)
        c = s[pos]
        if c == "*":
            if s.startswith("**", pos):
                return "**", pos + 2
            return "*", pos + 1
        if c in "+-/]":
            return c, pos + 1
        names = _BINARY_NAMES.get(c)
        if names is None:
            raise self.error("unknown_operation", pos)
        for n in names:
            if s.startswith(n, pos):
                return n, pos + len(n)
        raise self.error("unknown_operation_name", pos, char=c)

    def expression(self, pos: int) -> tuple[Value, int]:
        """``[ ... ]`` starting at ``pos`` (which holds ``[``).

        As LinuxCNC's read_real_expression (a shunting-yard), an operation is applied as
        soon as the operator after it is read and does not bind tighter, so errors come in
        LinuxCNC's order: constants are folded then, non-constant operands give a function
        that evaluates in that same order.
        """
        start_col = self.col(pos)
        v, pos = self.real_value(pos + 1)
        values = [v]
        ops: list[str] = []
        while True:
            op, pos = self.operator(pos)
            prec = 0 if op == "]" else BINARY[op][0]
            while ops and prec <= BINARY[ops[-1]][0]:
                b = values.pop()
                a = values.pop()
                fn = BINARY[ops.pop()][1]
                try:
                    values.append(_combine(fn, a, b, start_col))
                except NgcError as exc:
                    values.append(self._failed(exc))
            if op == "]":
                break
            ops.append(op)
            v, pos = self.real_value(pos)
            values.append(v)
        tree = values[0]
        # LinuxCNC checks for NaN/infinity after each value it reads, a bracketed
        # expression being one value; intermediate results may be NaN ([1 MOD 0 GT 1] is 0)
        if type(tree) is float:
            try:
                return checked(tree), pos
            except NgcError as exc:
                exc.column = start_col
                return self._failed(exc), pos

        def checked_tree(ctx):
            x = tree(ctx)
            if x - x == 0.0:  # not NaN, not infinite: _check_at inlined
                return x
            return _check_at(x, start_col)

        return checked_tree, pos


def _read(fn, key, col):
    try:
        return fn(key)
    except NgcError as exc:
        if not exc.column:
            exc.column = col
        raise


def _call(fn, x, col):
    try:
        return checked(fn(x))
    except NgcError as exc:
        exc.column = col
        raise


def to_integer(x: float, col: int = 0) -> int:
    """read_integer_value: round when within 0.0001 of an integer, else an error."""
    i = math.floor(x)
    frac = x - i
    if frac > 0.9999:
        return int(math.ceil(x))
    if frac > 0.0001:
        raise NgcError("non_integer", col)
    return int(i)


def _combine(fn, a: Value, b: Value, col: int) -> Value:
    if type(a) is float and type(b) is float:
        return _apply(fn, a, b, col)
    if fn in _INFALLIBLE:  # the same values, without _apply's error handling
        if fn is _add:
            if type(a) is float:
                return lambda ctx: a + b(ctx)
            if type(b) is float:
                return lambda ctx: a(ctx) + b
            return lambda ctx: a(ctx) + b(ctx)
        if type(a) is float:
            return lambda ctx: fn(a, b(ctx))
        if type(b) is float:
            return lambda ctx: fn(a(ctx), b)
        return lambda ctx: fn(a(ctx), b(ctx))
    if type(a) is float:
        return lambda ctx: _apply(fn, a, b(ctx), col)
    if type(b) is float:
        return lambda ctx: _apply(fn, a(ctx), b, col)
    return lambda ctx: _apply(fn, a(ctx), b(ctx), col)


def _apply(fn, a: float, b: float, col: int) -> float:
    try:
        return fn(a, b)
    except NgcError as exc:
        if not exc.column:
            exc.column = col
        raise
    except OverflowError:
        return math.inf


def _check_at(x: float, col: int) -> float:
    if x - x != 0.0:  # NaN or infinite (x - x is NaN exactly then)
        raise NgcError("not_a_number" if x != x else "infinity", col)
    return x
