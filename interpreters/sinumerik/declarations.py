"""The declarations of a Sinumerik program: ``DEF`` variable definitions (types, array sizes,
initial values) and the ``PROC`` header (parameters by value or reference, attributes). Both
functions are methods of :class:`BlockParser` (``BlockParser.definition``/``proc_header``)."""

from __future__ import annotations

import math

from interpreters.sinumerik import arrays
from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.expr import MAX_ARRAY_ELEMENTS, Node
from interpreters.sinumerik.language import PROC_ATTRIBUTES, STATEMENTS, TYPES
from interpreters.sinumerik.lexer import END, IDENT, NUM, Token


def definition(self, block: b.Block) -> None:
    """``DEF type name[dims] = value, …``: the block's variable definitions, recorded in the
    parser's variables (so later blocks know the names) and in ``block.defs``."""
    t = self.tok
    if t.kind != IDENT or t.text not in TYPES:
        if t.kind == IDENT and t.text == "FRAME":
            self.fail("unsupported", "FRAME variables are not simulated")
        self.fail("syntax", f"DEF needs a type ({', '.join(sorted(TYPES))})")
    typ = t.text
    self.pos += 1
    if typ == "STRING" and self.is_op("["):
        self.pos += 1
        self.expr()
        self.expect_op("]")
    while True:
        nt = self.tok
        if nt.kind != IDENT:
            self.fail("syntax", "DEF needs a variable name")
        if nt.text in STATEMENTS or (nt.text[0] == "R" and nt.text[1:].isdigit()):
            self.fail("syntax", f"{nt.text} cannot be a variable name", nt.col)
        self.pos += 1
        dims: list[int] = []
        if self.is_op("["):
            self.pos += 1
            while True:
                d = self.tok
                if d.kind != NUM or not isinstance(d.value, int) or d.value < 1:
                    self.fail("syntax", "array sizes must be positive whole numbers")
                dims.append(d.value)
                self.pos += 1
                if not self.is_op(","):
                    break
                self.pos += 1
            self.expect_op("]")
            if math.prod(dims) > MAX_ARRAY_ELEMENTS:
                self.fail("resource_limit", f"{nt.text} has {math.prod(dims)} elements (vmach simulates "
                          f"arrays of up to {MAX_ARRAY_ELEMENTS})", nt.col)
        init = None
        init_list: tuple[Node | None, ...] = ()
        if self.is_op("="):
            self.pos += 1
            if dims:
                init_list = arrays.value_list(self, math.prod(dims), nt.text)
            elif typ == "AXIS" and self.tok.kind == IDENT and self.g.is_axis(self.tok.text):
                init = Node("str", self.tok.col, self.tok.text)
                self.pos += 1
            else:
                init = self.expr()
        vd = b.VarDef(nt.col, typ, nt.text, tuple(dims), init, init_list)
        if nt.text in self.variables:
            self.fail("duplicate_definition", f"{nt.text} is defined twice", nt.col)
        self.variables[nt.text] = vd
        block.defs.append(vd)
        if not self.is_op(","):
            break
        self.pos += 1
    self.expect_end("the definition")

def proc_header(self, t: Token) -> b.ProcHeader:
    """``PROC name(type p, VAR type a[…], …) attributes``: the subprogram's signature."""
    nt = self.tok
    if nt.kind != IDENT:
        self.fail("syntax", "PROC needs a program name")
    self.pos += 1
    params: list[b.Param] = []
    if self.is_op("("):
        self.pos += 1
        while not self.is_op(")"):
            by_ref = False
            if self.tok.kind == IDENT and self.tok.text == "VAR":
                by_ref = True
                self.pos += 1
            tt = self.tok
            if tt.kind != IDENT or tt.text not in TYPES:
                self.fail("syntax", "a PROC parameter needs a type")
            self.pos += 1
            if tt.text == "STRING" and self.is_op("["):  # STRING[length] NAME
                self.pos += 1
                self.expr()
                self.expect_op("]")
            pn = self.tok
            if pn.kind != IDENT:
                self.fail("syntax", "a PROC parameter needs a name")
            self.pos += 1
            dims: list[int] = []
            if self.is_op("["):  # array parameter: VAR REAL A[3] (A[] or A[,] of any size)
                while not self.is_op("]"):
                    if self.tok.kind == END:
                        self.fail("syntax", "unclosed '['")
                    if self.tok.kind == NUM:
                        dims.append(int(self.tok.value))
                    self.pos += 1
                self.pos += 1
                dims = dims or [0]
            p = b.Param(tt.text, pn.text, by_ref, tuple(dims))
            params.append(p)
            self.variables[pn.text] = p
            if self.is_op(","):
                self.pos += 1
            elif not self.is_op(")"):
                self.fail("syntax", f"expected ',' or ')', found {self.describe(self.tok)}")
        self.pos += 1
    attrs: list[str] = []
    while self.tok.kind == IDENT:
        if self.tok.text not in PROC_ATTRIBUTES:
            self.fail("syntax", f"{self.tok.text} is not a PROC attribute")
        attrs.append(self.tok.text)
        self.pos += 1
    self.expect_end("the PROC header")
    return b.ProcHeader(t.col, nt.text, tuple(params), tuple(attrs))
