"""Array values: ``SET(a, , b)`` and ``REP(v[, n])`` in a DEF or written from an element on
(Job planning, "Array definition and initialization"): row order, the last index fastest; an
empty place leaves its element as it is."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.expr import Node
from interpreters.sinumerik.lexer import IDENT, NUM, OP

if TYPE_CHECKING:
    from interpreters.sinumerik.running import Reading


def _num(value, col: int) -> Node:
    return Node("num", col, value)


def value_list(p: Reading, room: int, name: str) -> tuple[Node | None, ...]:
    """``SET(a, , b)``, ``(a, b)`` or ``REP(v[, n])``: values for consecutive elements in
    row order (the last index fastest); None keeps an element as it is. ``room``: elements
    from the first one written to the array's end."""
    col = p.tok.col
    if p.tok.kind == IDENT and p.tok.text == "REP":
        p.pos += 1
        p.expect_op("(")
        value = p.expr()
        count: int = room
        if p.is_op(","):
            p.pos += 1
            n = p.tok
            if n.kind != NUM or not isinstance(n.value, int) or n.value < 1:
                p.fail("syntax", "REP(value, n) needs a whole number of elements n >= 1")
            count = n.value
            p.pos += 1
        p.expect_op(")")
        values: list[Node | None] = [value] * count
    else:
        if p.tok.kind == IDENT and p.tok.text == "SET":
            p.pos += 1
        p.expect_op("(")
        values = []
        while True:
            values.append(None if p.is_op(",") or p.is_op(")") else p.expr())
            if not p.is_op(","):
                break
            p.pos += 1
        p.expect_op(")")
    if len(values) > room:
        p.fail("index_range", f"{len(values)} values for {room} element(s) of {name}", col)
    return tuple(values)

def _rep_counted(p: Reading) -> bool:
    """Whether the REP(...) ahead gives its count (a ',' at its top level)."""
    depth = 0
    for tok in p.toks[p.pos + 1:]:
        if tok.kind == OP and tok.text in "([":
            depth += 1
        elif tok.kind == OP and tok.text in ")]":
            depth -= 1
            if depth == 0:
                return False
        elif tok.kind == OP and tok.text == "," and depth == 1:
            return True
    return False

def fill(p: Reading, t, target: b.Target) -> list[b.Item]:
    """``A[i, j]=SET(...)`` / ``A[i]=REP(...)``: one assignment per value, from element
    ``[i, j]`` on in row order (constant or computed indices; REP without its count needs
    constant ones)."""
    d = p.variables[target.name]
    dims = getattr(d, "dims", ())
    if not dims:
        p.fail("type_error", f"{target.name} is not an array; SET/REP fill arrays", t.col)
    idx = target.index or tuple(_num(0, t.col) for _ in dims)
    if len(idx) != len(dims):
        p.fail("index_range", f"{target.name} has {len(dims)} dimension(s)", t.col)
    if all(x.op == "num" for x in idx):
        start = 0
        for x, n in zip(idx, dims, strict=True):
            if not (isinstance(x.value, int) and 0 <= x.value < n):
                p.fail("index_range", f"{target.name}[...]: index {x.value} is outside "
                          f"0..{n - 1}", t.col)
            start = start * n + x.value
        values = value_list(p, math.prod(dims) - start, target.name)
        return [b.Assign(t.col, b.Target(name=target.name, index=tuple(
            _num(i, t.col) for i in unravel(start + k, dims))), v)
            for k, v in enumerate(values) if v is not None]
    if p.is_op("(", 1) and p.tok.text == "REP" and not _rep_counted(p):
        p.fail("unsupported", f"{target.name}[...]=REP(value) with a computed index (REP without "
                  "its count fills to the array's end, which vmach knows only at run time)", t.col)
    values = value_list(p, math.prod(dims), target.name)
    return [b.Assign(t.col, b.Target(name=target.name, index=idx if k == 0 else _following(
        idx, dims, k, t.col)), v) for k, v in enumerate(values) if v is not None]


def _following(idx: tuple[Node, ...], dims: tuple[int, ...], k: int, col: int) -> tuple[Node, ...]:
    """Index expressions of the ``k``-th element after ``[idx]`` in row order: the flat
    position ``p = Σ idx[j]·stride[j] + k`` split again (``p DIV stride[j] MOD dims[j]``; the
    first index not wrapped, so running past the array's end is ``index_range``)."""
    flat: Node = _num(k, col)
    stride = 1
    strides = []
    for n in reversed(dims):
        strides.append(stride)
        stride *= n
    strides.reverse()
    for x, st in zip(idx, strides, strict=True):
        flat = Node("+", col, None, (flat, x if st == 1 else Node("*", col, None, (x, _num(st, col)))))
    out = []
    for j, (n, st) in enumerate(zip(dims, strides, strict=True)):
        e = flat if st == 1 else Node("DIV", col, None, (flat, _num(st, col)))
        out.append(e if j == 0 else Node("MOD", col, None, (e, _num(n, col))))
    return tuple(out)


def unravel(k: int, dims: tuple[int, ...]) -> tuple[int, ...]:
    """Indices of the ``k``-th element of an array of ``dims`` in row order."""
    out = []
    for n in reversed(dims):
        k, i = divmod(k, n)
        out.append(i)
    return tuple(reversed(out))
