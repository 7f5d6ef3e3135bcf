"""Sinumerik arithmetic: a Pratt parser and a compiler to closures. Never ``eval``.

Operator priority, highest first (Programming Manual, Job planning, "Priority of the
operations"): NOT B_NOT (and unary signs) · ``* / DIV MOD`` · ``+ -`` · B_AND · B_XOR · B_OR ·
AND · XOR · OR · ``<<`` · comparisons ``== <> > < >= <=``. Equal priority evaluates left to right.
So ``IF R1>0 AND R2>0`` compares ``R1 > (0 AND R2) > 0``, as the control does; write
parentheses.

Semantics kept from the control:
- comparisons test *relative* equality, |a − b| ≤ 1e-12·max(|a|, |b|), also for ``<`` and ``>``;
- ``/`` always divides as REAL (3/4 = 0.75); ``DIV`` truncates toward zero to an INT;
  ``MOD`` is the remainder with the sign of the dividend (REAL operands allowed);
- angles of SIN, COS, TAN, ASIN, ACOS, ATAN2 are degrees; ``POT(x)`` is x²; ROUND rounds half
  away from zero; ROUNDUP rounds away from zero; TRUNC toward zero.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from interpreters.sinumerik import strfuncs, sysvars
from interpreters.sinumerik.errors import EvalError
from interpreters.sinumerik.language import UNSUPPORTED_FUNCTIONS
from interpreters.sinumerik.lexer import END, IDENT, NUM, OP, STR, Token
from vmach.tol import tol

Value = float | int | str | bool


class ParseError(Exception):
    def __init__(self, kind: str, message: str, col: int):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.col = col


# ------------------------------------------------------------------------------------------
# AST
# ------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Node:
    op: str  # "num" "str" "r" "var" "call" "neg" "pos" "not" "bnot" or a binary operator
    col: int
    value: Any = None  # literal value, R index (int or Node), variable / function name
    args: tuple[Node, ...] = ()


CONSTANTS: dict[str, Value] = {"TRUE": True, "FALSE": False, "$PI": math.pi}

BINARY_PRIORITY: dict[str, int] = {
    "==": 1,
    "<>": 1,
    "<": 1,
    ">": 1,
    "<=": 1,
    ">=": 1,
    "<<": 2,
    "OR": 3,
    "XOR": 4,
    "AND": 5,
    "B_OR": 6,
    "B_XOR": 7,
    "B_AND": 8,
    "+": 9,
    "-": 9,
    "*": 10,
    "/": 10,
    "DIV": 10,
    "MOD": 10,
    ":": 9,     # frame chaining (CTRANS(...):CROT(...)); frames only
}
PREFIX_PRIORITY = 11

#: vmach's limits on one expression (not the control's: they keep the parser's and the
#: evaluator's recursion far from Python's limit): brackets, signs and calls nested this deep,
#: and operations chained this long (``1+1+...`` nests to the left as it is evaluated).
MAX_NESTING = 100
MAX_DEPTH = 200
#: vmach's limits on data (``resource_limit``): characters of a string (``<<`` doubling a string
#: in a loop would otherwise fill the memory) and elements of one array (``DEF REAL A[1000,1000,1000]``)
MAX_STRING = 10_000
MAX_ARRAY_ELEMENTS = 1_000_000

#: function name -> (min args, max args)
FUNCTIONS: dict[str, tuple[int, int]] = {
    "SIN": (1, 1),
    "COS": (1, 1),
    "TAN": (1, 1),
    "ASIN": (1, 1),
    "ACOS": (1, 1),
    "ATAN2": (2, 2),
    "SQRT": (1, 1),
    "ABS": (1, 1),
    "POT": (1, 1),
    "TRUNC": (1, 1),
    "ROUND": (1, 1),
    "ROUNDUP": (1, 1),
    "MIN": (2, 2),
    "MAX": (2, 2),
    "LN": (1, 1),
    "EXP": (1, 1),
    "MINVAL": (2, 2),
    "MAXVAL": (2, 2),
    "BOUND": (3, 3),
    "ISFILE": (1, 1),
    "QU": (1, 1),
}
FUNCTIONS.update({name: (lo, hi) for name, (lo, hi, _) in strfuncs.PURE.items()})
FUNCTIONS.update(strfuncs.STATEFUL)
#: frame functions (their arguments are axis names and values; see sysframes.py)
FRAME_FUNCTIONS = frozenset({"CTRANS", "CROT", "CSCALE", "CMIRROR", "CFINE", "CRPL"})


def depth(node: Node) -> int:
    """Levels of ``node``'s tree (a leaf: 1), without recursion."""
    deepest, todo = 0, [(node, 1)]
    while todo:
        n, d = todo.pop()
        deepest = max(deepest, d)
        todo.extend((a, d + 1) for a in n.args if isinstance(a, Node))
        if isinstance(n.value, Node):
            todo.append((n.value, d + 1))
    return deepest


class ExprParser:
    """Parses expressions out of a block's token list.

    is_variable(name) tells whether a name was declared with DEF (or is a PROC parameter).
    """

    def __init__(self, tokens: list[Token], pos: int, is_variable: Callable[[str], bool]):
        self.toks = tokens
        self.pos = pos
        self.is_variable = is_variable
        self.nesting = 0

    @property
    def tok(self) -> Token:
        return self.toks[self.pos]

    def expect_op(self, text: str) -> Token:
        t = self.tok
        if t.kind != OP or t.text != text:
            found = "end of block" if t.kind == END else repr(t.text)
            raise ParseError("syntax", f"expected {text!r}, found {found}", t.col)
        self.pos += 1
        return t

    def parse(self, min_priority: int = 0) -> Node:
        """The expression from the current token on; at the top level (``min_priority`` 0
        and not nested) also checked against ``MAX_DEPTH``."""
        start = self.tok.col
        self.nesting += 1
        try:
            if self.nesting > MAX_NESTING:
                raise ParseError("syntax", f"expression nested more than {MAX_NESTING} levels deep",
                                 self.tok.col)
            node = self._parse(min_priority)
        finally:
            self.nesting -= 1
        if self.nesting == 0 and depth(node) > MAX_DEPTH:
            raise ParseError("syntax", f"expression longer than {MAX_DEPTH} chained operations", start)
        return node

    def _parse(self, min_priority: int) -> Node:
        left = self._prefix()
        while True:
            t = self.tok
            if t.kind not in (OP, IDENT):
                break
            prio = BINARY_PRIORITY.get(t.text)
            if prio is None or prio <= min_priority:
                break
            self.pos += 1
            right = self.parse(prio)
            left = Node(t.text, t.col, None, (left, right))
        return left

    def _prefix(self) -> Node:
        t = self.tok
        self.pos += 1
        if t.kind == NUM:
            return Node("num", t.col, t.value)
        if t.kind == STR:
            return Node("str", t.col, t.value)
        if t.kind == OP:
            if t.text == "(":
                inner = self.parse()
                self.expect_op(")")
                return inner
            if t.text == "-":
                return Node("neg", t.col, None, (self.parse(PREFIX_PRIORITY - 1),))
            if t.text == "+":
                return self.parse(PREFIX_PRIORITY - 1)
        if t.kind == IDENT:
            name = t.text
            if name == "NOT":
                return Node("not", t.col, None, (self.parse(PREFIX_PRIORITY - 1),))
            if name == "B_NOT":
                return Node("bnot", t.col, None, (self.parse(PREFIX_PRIORITY - 1),))
            return self._name(t)
        self.pos -= 1
        found = "end of block" if t.kind == END else repr(t.text)
        raise ParseError("syntax", f"expected a value, found {found}", t.col)

    def _name(self, t: Token) -> Node:
        name = t.text
        nxt = self.tok
        if name in CONSTANTS:
            return Node("num", t.col, CONSTANTS[name])
        if name == "R" and nxt.kind == OP and nxt.text == "[":
            self.pos += 1
            idx = self.parse()
            self.expect_op("]")
            return Node("r", t.col, idx)
        if len(name) > 1 and name[0] == "R" and name[1:].isdigit():
            if int(name[1:]) >= 1000:
                raise ParseError("index_range", f"{name} is outside R0..R999", t.col)
            return Node("r", t.col, int(name[1:]))
        if nxt.kind == OP and nxt.text == "(" and name in FUNCTIONS:
            self.pos += 1
            args: list[Node] = []
            if not (self.tok.kind == OP and self.tok.text == ")"):
                args.append(self._argument(name))
                while self.tok.kind == OP and self.tok.text == ",":
                    self.pos += 1
                    args.append(self._argument(name))
            self.expect_op(")")
            lo, hi = FUNCTIONS[name]
            if not lo <= len(args) <= hi:
                raise ParseError(
                    "syntax",
                    f"{name} takes {lo if lo == hi else f'{lo}..{hi}'} argument(s), got {len(args)}",
                    t.col,
                )
            return Node("call", t.col, name, tuple(args))
        if self.is_variable(name):
            if nxt.kind == OP and nxt.text == "[":
                self.pos += 1
                idx = [self.parse()]
                while self.tok.kind == OP and self.tok.text == ",":
                    self.pos += 1
                    idx.append(self.parse())
                self.expect_op("]")
                return Node("var", t.col, name, tuple(idx))
            return Node("var", t.col, name)
        if name.startswith("$"):
            return self.system(t)
        if nxt.kind == OP and nxt.text == "(" and name in FRAME_FUNCTIONS:
            return self.frame_function(t)
        if nxt.kind == OP and nxt.text == "(" and name in UNSUPPORTED_FUNCTIONS:
            raise ParseError("unsupported", f"the function {name} is not simulated by vmach", t.col)
        if nxt.kind == OP and nxt.text == "(":
            raise ParseError("unknown_word", f"unknown function {name}", t.col)
        raise ParseError("undefined_variable", f"{name} is not defined (DEF) before use", t.col)


    def _argument(self, function: str) -> Node:
        """One argument of a function call; an axis written bare (``AXSTRING(X)``) is its name."""
        it = self.tok
        if (function in strfuncs.AXIS_ARGUMENT and it.kind == IDENT and not self.is_variable(it.text)
                and it.text not in CONSTANTS and self.pos + 1 < len(self.toks)
                and self.toks[self.pos + 1].text == ")"):
            self.pos += 1
            return Node("str", it.col, it.text)
        return self.parse()

    def system(self, t: Token) -> Node:
        """A system variable (``$P_EP[X]``, ``$P_UIFR[1, X, TR]``): Node("sys", name, indices).
        An index that is a bare name (an axis, ``AX1``, a frame component) is that name as a
        string; a name vmach has no such variable for is ``unsupported``."""
        var = sysvars.lookup(t.text)
        if var is None:
            raise ParseError("unsupported", f"system variable {t.text} is not simulated", t.col)
        idx: list[Node] = []
        if self.tok.kind == OP and self.tok.text == "[":
            self.pos += 1
            while True:
                it = self.tok
                after = self.toks[self.pos + 1] if self.pos + 1 < len(self.toks) else it
                if (it.kind == IDENT and after.kind == OP and after.text in ("]", ",")
                        and not self.is_variable(it.text) and it.text not in CONSTANTS
                        and not (it.text[0] == "R" and it.text[1:].isdigit())
                        and it.text[0] != "$"):     # a system variable is read: $TC_DP6[$P_TOOLNO, 1]
                    self.pos += 1
                    idx.append(Node("str", it.col, it.text))
                else:
                    idx.append(self.parse())
                if self.tok.kind == OP and self.tok.text == ",":
                    self.pos += 1
                    continue
                break
            self.expect_op("]")
        if var.shape(len(idx)) is None:
            raise ParseError("syntax", f"{var.name} takes {var.describe_shapes()}", t.col)
        return Node("sys", t.col, var.name, tuple(idx))

    def frame_function(self, t: Token) -> Node:
        """CTRANS(X, 10, Y, 5), CROT(Z, 45), CMIRROR(X) ...: axis names become strings."""
        self.pos += 1
        args: list[Node] = []
        while not (self.tok.kind == OP and self.tok.text == ")"):
            it = self.tok
            if it.kind == IDENT and not self.is_variable(it.text) and it.text not in CONSTANTS:
                self.pos += 1
                args.append(Node("str", it.col, it.text))
            else:
                args.append(self.parse())
            if not (self.tok.kind == OP and self.tok.text == ","):
                break
            self.pos += 1
        self.expect_op(")")
        return Node("frame", t.col, t.text, tuple(args))


# ------------------------------------------------------------------------------------------
# Evaluation helpers (shared with the interpreter)
# ------------------------------------------------------------------------------------------

_REL = tol.compare_relative


def num(v: Value) -> float | int:
    if v.__class__ is str:
        raise EvalError("type_error", f"a number was expected, got the string {v!r}")
    return v


def eq(a: Value, b: Value) -> bool:
    """Relative equality: |a - b| <= 1e-12 * max(|a|, |b|); strings compare exactly."""
    if a == b:
        return True
    if a.__class__ is str or b.__class__ is str:
        return False
    d = a - b
    aa = a if a >= 0 else -a
    bb = b if b >= 0 else -b
    return (d if d >= 0 else -d) <= _REL * (aa if aa > bb else bb)


def _lt(a, b):
    if a.__class__ is str or b.__class__ is str:
        num(a), num(b)
    return a < b and not eq(a, b)


def _gt(a, b):
    if a.__class__ is str or b.__class__ is str:
        num(a), num(b)
    return a > b and not eq(a, b)


def _le(a, b):
    if a.__class__ is str or b.__class__ is str:
        num(a), num(b)
    return a < b or eq(a, b)


def _ge(a, b):
    if a.__class__ is str or b.__class__ is str:
        num(a), num(b)
    return a > b or eq(a, b)


def _div(a, b):
    b = num(b)
    if b == 0:
        raise EvalError("division_by_zero", "division by zero")
    return num(a) / b


def _idiv(a, b):
    a, b = num(a), num(b)
    if b == 0:
        raise EvalError("division_by_zero", "DIV by zero")
    q = a / b
    return int(q) if abs(q) < 9e18 else q


def _mod(a, b):
    a, b = num(a), num(b)
    if b == 0:
        raise EvalError("division_by_zero", "MOD by zero")
    return math.fmod(a, b) if isinstance(a, float) or isinstance(b, float) else int(math.fmod(a, b))


def _int(v, what):
    v = num(v)
    if v != int(v):
        raise EvalError("type_error", f"{what} needs whole numbers, got {v}")
    return int(v)


def _concat(a, b):
    out = _text(a) + _text(b)
    if len(out) > MAX_STRING:
        raise EvalError("resource_limit", f"a string of {len(out)} characters (vmach simulates up to "
                        f"{MAX_STRING})")
    return out


def _text(v: Value) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return repr(v) if isinstance(v, float) else str(v)


BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "+": lambda a, b: num(a) + num(b),
    "-": lambda a, b: num(a) - num(b),
    "*": lambda a, b: num(a) * num(b),
    "/": _div,
    "DIV": _idiv,
    "MOD": _mod,
    "==": eq,
    "<>": lambda a, b: not eq(a, b),
    "<": _lt,
    ">": _gt,
    "<=": _le,
    ">=": _ge,
    "AND": lambda a, b: bool(num(a)) and bool(num(b)),
    "OR": lambda a, b: bool(num(a)) or bool(num(b)),
    "XOR": lambda a, b: bool(num(a)) != bool(num(b)),
    "B_AND": lambda a, b: _int(a, "B_AND") & _int(b, "B_AND"),
    "B_OR": lambda a, b: _int(a, "B_OR") | _int(b, "B_OR"),
    "B_XOR": lambda a, b: _int(a, "B_XOR") ^ _int(b, "B_XOR"),
    "<<": _concat,
    ":": lambda a, b: _no_frames(),
}


def _no_frames():
    raise EvalError("unsupported", "frame expressions need the control's state")


def _sqrt(x):
    x = num(x)
    if x < 0:
        raise EvalError("domain_error", f"SQRT of a negative number ({x})")
    return math.sqrt(x)


def _asin(x):
    x = num(x)
    if abs(x) > 1:
        raise EvalError("domain_error", f"ASIN of {x} (outside -1..1)")
    return math.degrees(math.asin(x))


def _acos(x):
    x = num(x)
    if abs(x) > 1:
        raise EvalError("domain_error", f"ACOS of {x} (outside -1..1)")
    return math.degrees(math.acos(x))


def _ln(x):
    x = num(x)
    if x <= 0:
        raise EvalError("domain_error", f"LN of {x} (must be > 0)")
    return math.log(x)


def _exp(x):
    try:
        return math.exp(num(x))
    except OverflowError:
        raise EvalError("domain_error", f"EXP({x}) overflows") from None


def _round(x):
    x = num(x)
    return math.floor(x + 0.5) if x >= 0 else -math.floor(-x + 0.5)


def _roundup(x):
    x = num(x)
    return math.ceil(x) if x >= 0 else -math.ceil(-x)


def _tan(x):
    x = num(x)
    if math.isclose(math.fmod(abs(x), 180.0), 90.0, abs_tol=1e-12):
        raise EvalError("domain_error", f"TAN({x}) is infinite")
    return math.tan(math.radians(x))


def _bound(lo, hi, x):
    lo, hi, x = num(lo), num(hi), num(x)
    return lo if x < lo else hi if x > hi else x


FUNC_IMPL: dict[str, Callable[..., Any]] = {
    "SIN": lambda x: math.sin(math.radians(num(x))),
    "COS": lambda x: math.cos(math.radians(num(x))),
    "TAN": _tan,
    "ASIN": _asin,
    "ACOS": _acos,
    "ATAN2": lambda y, x: math.degrees(math.atan2(num(y), num(x))),
    "SQRT": _sqrt,
    "ABS": lambda x: abs(num(x)),
    "POT": lambda x: num(x) * num(x),
    "TRUNC": lambda x: int(num(x)),
    "ROUND": _round,
    "ROUNDUP": _roundup,
    "MIN": lambda a, b: min(num(a), num(b)),
    "MAX": lambda a, b: max(num(a), num(b)),
    "MINVAL": lambda a, b: min(num(a), num(b)),
    "MAXVAL": lambda a, b: max(num(a), num(b)),
    "BOUND": _bound,
    "LN": _ln,
    "EXP": _exp,
    "QU": lambda x: x,      # M=QU(8): a quick auxiliary-function output, the value itself
}
FUNC_IMPL.update({name: impl for name, (_, _, impl) in strfuncs.PURE.items()})


_HUGE = 1.7e308


def _check_number(v):
    if isinstance(v, float) and not math.isfinite(v):
        raise EvalError("domain_error", "result is not a finite number")
    return v


# ------------------------------------------------------------------------------------------
# Compiler
# ------------------------------------------------------------------------------------------


class Env:
    """What compiled expressions read: R parameters and the current call frame's variables.

    r : list of float, length 1000 — R0..R999 (global).
    vars : dict name -> value or list — local variables of the running program level.
    globals : dict name -> value or list — global user data (GUD) of the definition files.
    sys : the NCK state (``nck.Nck``) system variables read and write, or None.
    """

    __slots__ = ("r", "vars", "globals", "sys", "files")

    def __init__(self) -> None:
        self.r: list[Any] = [0.0] * 1000
        self.vars: dict[str, Any] = {}
        self.globals: dict[str, Any] = {}
        self.sys: Any = None
        self.files: Any = None  # the run's file sandbox (sandbox.Sandbox), for ISFILE


def r_index(i: Any) -> int:
    i = num(i)
    if i != int(i) or not 0 <= i < 1000:
        raise EvalError("index_range", f"R parameter index {i} is outside R0..R999")
    return int(i)


def element(value: Any, idx: list[Any], name: str) -> tuple[list, int]:
    """The list holding element ``name[idx]`` and the position in it."""
    cur = value
    for k, i in enumerate(idx):
        if not isinstance(cur, list):
            raise EvalError("index_range", f"{name} has fewer than {k + 1} dimensions")
        i = num(i)
        if i != int(i) or not 0 <= i < len(cur):
            raise EvalError("index_range", f"{name}[{i}] is outside 0..{len(cur) - 1}")
        if k == len(idx) - 1:
            return cur, int(i)
        cur = cur[int(i)]
    raise EvalError("index_range", f"{name} needs an index")


def compile_expr(node: Node, env: Env) -> Callable[[], Any]:
    """A zero-argument closure computing ``node`` against ``env``. Constants are folded."""
    op = node.op
    if op in ("num", "str"):
        v = node.value
        return lambda: v
    if op == "r":
        r = env.r
        if isinstance(node.value, int):
            i = node.value
            return lambda: r[i]
        f = compile_expr(node.value, env)
        return lambda: r[r_index(f())]
    if op in ("sys", "frame") or (op == ":" and env.sys is not None):
        return _compile_system(node, env)
    if op == "var":
        name = node.value
        scope = scope_of(name, env)
        if not node.args:

            def get():
                v = scope.vars[name]
                if v.__class__ is list:
                    raise EvalError("type_error", f"{name} is an array; give an index")
                return v

            return get
        fs = [compile_expr(a, env) for a in node.args]

        def get_elem():
            lst, i = element(scope.vars[name], [f() for f in fs], name)
            return lst[i]

        return get_elem
    if op == "call" and node.value == "ISFILE":    # the run's sandbox: never folded
        fa = compile_expr(node.args[0], env)
        return lambda: env.files is not None and env.files.exists(fa())
    if op == "call" and node.value in strfuncs.STATEFUL:    # the run's state: never folded
        return strfuncs.compile_call(node.value, [compile_expr(a, env) for a in node.args], env)
    if op == "call":
        impl = FUNC_IMPL[node.value]
        fs = [compile_expr(a, env) for a in node.args]
        if all(a.op in ("num", "str") for a in node.args):
            try:
                v = _check_number(impl(*[a.value for a in node.args]))
                return lambda: v
            except EvalError:
                pass  # keep the error for run time, at the right moment
        if len(fs) == 1:
            f0 = fs[0]
            return lambda: _check_number(impl(f0()))
        return lambda: _check_number(impl(*[f() for f in fs]))
    if op == "neg":
        f = compile_expr(node.args[0], env)
        if node.args[0].op == "num":
            v = -node.args[0].value
            return lambda: v
        return lambda: -num(f())
    if op == "not":
        f = compile_expr(node.args[0], env)
        return lambda: not num(f())
    if op == "bnot":
        f = compile_expr(node.args[0], env)
        return lambda: ~_int(f(), "B_NOT")
    impl2 = BINARY[op]
    fa = compile_expr(node.args[0], env)
    fb = compile_expr(node.args[1], env)
    a, b = node.args
    if a.op in ("num", "str") and b.op in ("num", "str"):
        try:
            v = _check_number(impl2(a.value, b.value))
            return lambda: v
        except EvalError:
            pass
    # fast paths for the common arithmetic on numbers
    if op in ("+", "-", "*"):
        arith = {"+": operator.add, "-": operator.sub, "*": operator.mul}[op]

        def finite_arith():
            x, y = fa(), fb()
            if x.__class__ is str or y.__class__ is str:
                num(x), num(y)
            v = arith(x, y)
            if -_HUGE < v < _HUGE:  # false for inf and NaN
                return v
            raise EvalError("domain_error", "result is not a finite number")

        return finite_arith
    if op == "/":
        return lambda: _check_number(_div(fa(), fb()))
    return lambda: impl2(fa(), fb())


def _compile_system(node: Node, env: Env) -> Callable[[], Any]:
    """A system variable read, a frame function or a frame chain, through the NCK state."""
    nck = env.sys
    if nck is None:
        raise EvalError("unsupported", f"{node.value}: system variables need the control's state")
    if node.op == ":":
        fa, fb = compile_expr(node.args[0], env), compile_expr(node.args[1], env)
        return lambda: nck.chain(fa(), fb())
    fs = [compile_expr(a, env) for a in node.args]
    if node.op == "frame":
        return nck.frame_function(node.value, fs)
    return nck.reader(node.value, fs, node.col)



class GlobalScope:
    """Where a global user variable (GUD) lives: ``vars`` is ``Env.globals`` (a compiled read
    or write of a level's own variable looks in ``Env.vars`` instead, which changes per level)."""

    __slots__ = ("vars",)

    def __init__(self, variables: dict[str, Any]) -> None:
        self.vars = variables


def scope_of(name: str, env: Env) -> Env | GlobalScope:
    """The object whose ``vars`` hold variable ``name``: a GUD's scope, else ``env``."""
    return GlobalScope(env.globals) if name in env.globals else env
