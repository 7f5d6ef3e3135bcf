"""Read a Sinumerik program text into :class:`Program` blocks (phase 1: read).

Errors do not stop the reading: every line that does not parse becomes a ``bad`` block and a
finding, so ``vmach check`` reports all of them at once.
"""

from __future__ import annotations

import difflib
import re

from interpreters.sinumerik import arrays, commands, declarations, macros, sysvars
from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.cycles import MODAL as MODAL_CYCLES
from interpreters.sinumerik.cycles import NAMES as MILLING
from interpreters.sinumerik.drilling import CYCLES as DRILLING
from interpreters.sinumerik.drilling import PATTERNS
from interpreters.sinumerik.expr import FUNCTIONS, ExprParser, Node, ParseError
from interpreters.sinumerik.language import (
    ACCEPTED_WORDS,
    CODES,
    COMMANDS,
    STATEMENTS,
    UNSUPPORTED_WORDS,
    Code,
)
from interpreters.sinumerik.lexer import END, IDENT, NUM, OP, STR, Token, number, split_comment, tokenize
from interpreters.sinumerik.polar import POLES
from interpreters.sinumerik.turning import NAMES as TURNING
from vmach.canon import ControlSpec
from vmach.errors import ProgramError
from vmach.findings import Finding, error
from vmach.source import SourceRef

_GCODE = re.compile(r"^G(\d+)$")
_ADDR_NUM = re.compile(r"^([A-Z])(\d+(?:\.\d*)?|\.\d+)$")
_LOOSE_AXIS = re.compile(r"^[ABCUVWXYZ]\d*$")
_LABEL = re.compile(r"^[A-Z_][A-Z_][A-Z0-9_]{0,30}$")
_BLOCKNO = re.compile(r"^N(\d+)$")
_SPINDLE_ADDR = re.compile(r"^([SM])(\d+)$")
_H_ADDR = re.compile(r"^H(\d+)$")
_JUMPS = ("GOTOF", "GOTOB", "GOTO", "GOTOC", "GOTOS")
#: statements that open or close a control structure (blocks.Block.shape)
_SHAPES = frozenset({"IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "REPEAT", "UNTIL",
                     "LOOP", "ENDLOOP"})
_MODES = ("AC", "IC", "ACP", "ACN", "DC")
_INTERP = {"I": "interp", "J": "interp", "K": "interp", "CR": "cr", "TURN": "turn",
           "RND": "corner", "RNDM": "corner", "CHF": "corner", "CHR": "corner", "FRC": "corner",
           "FRCM": "corner", "AP": "polar", "RP": "polar", "I1": "interp", "J1": "interp", "K1": "interp",
           "AR": "interp", "SF": "interp"}
_INTERP_UNSUPPORTED = {"ANG"}
_BUILTINS = {"SETMS", "MSG", "WORKPIECE", "TRACYL", "TRAORI", "CYCLE800", "TRANSMIT"}
# orientation words under TRAORI (orientation.py): angles, vector, cone axis, intermediate vector
_ORIENT = {"A2", "B2", "C2", "A3", "B3", "C3", "A6", "B6", "C6", "A7", "B7", "C7",
           "A4", "B4", "C4", "A5", "B5", "C5", "LEAD", "TILT"}
_SINGLE = {"F": "feed", "S": "speed", "M": "m", "T": "tool", "D": "edge", "H": "aux", "P": "repeat"}


class Grammar:
    """What a word may be on this machine: axes, cycles, machine G codes."""

    def __init__(self, control: ControlSpec, programs: frozenset[str] = frozenset()):
        self.control = control
        self.axes = {a.name for a in control.axes} | set(control.geometry)
        #: AX1, AX2 …: the machine axes by number (Fundamentals, "Axis identifiers")
        self.numbered = {f"AX{k}": a.name for k, a in enumerate(control.axes, start=1)}
        self.strict = control.strict_axes
        self.cycles = control.cycles
        self.gcodes = control.gcodes
        self.programs = programs
        #: names read whole in words without separators (lexer.split_words): the language's
        #: words, the machine's axes, cycles and G codes, the programs beside this one
        self.names = frozenset().union(CODES, STATEMENTS, COMMANDS, UNSUPPORTED_WORDS, FUNCTIONS,
                                       _BUILTINS, DRILLING, PATTERNS, MILLING, self.axes, self.cycles,
                                       self.gcodes, programs)

    def is_axis(self, name: str) -> bool:
        if name in self.axes:
            return True
        return not self.strict and bool(_LOOSE_AXIS.match(name))


def _num_node(value, col: int) -> Node:
    return Node("num", col, value)


class BlockParser:
    """Parses the tokens of one line into a Block."""

    def __init__(self, grammar: Grammar, variables: dict, source: SourceRef):
        self.g = grammar
        self.variables = variables
        self.src = source
        self.toks: list[Token] = []
        self.pos = 0

    # -- token helpers -------------------------------------------------------------------
    @property
    def tok(self) -> Token:
        return self.toks[self.pos]

    def peek(self, k: int = 1) -> Token:
        return self.toks[min(self.pos + k, len(self.toks) - 1)]

    def is_op(self, text: str, k: int = 0) -> bool:
        t = self.peek(k) if k else self.tok
        return t.kind == OP and t.text == text

    def fail(self, kind: str, message: str, col: int | None = None):
        raise ProgramError(kind, message, self.src.at(col or self.tok.col))

    def literal(self, text: str, col: int) -> float | int:
        """The number written after an address letter (``X12.5``), as the lexer reads one."""
        try:
            return number(text)
        except OverflowError:
            self.fail("syntax", f"number {text} is out of range", col)

    def expect_op(self, text: str) -> Token:
        if not self.is_op(text):
            self.fail("syntax", f"expected {text!r}, found {self.describe(self.tok)}")
        t = self.tok
        self.pos += 1
        return t

    def expect_end(self, what: str) -> None:
        if self.tok.kind != END:
            self.fail("syntax", f"unexpected {self.describe(self.tok)} after {what}")

    @staticmethod
    def describe(t: Token) -> str:
        return "end of block" if t.kind == END else repr(t.text)

    def expr(self) -> Node:
        p = ExprParser(self.toks, self.pos, self.variables.__contains__)
        try:
            node = p.parse()
        except ParseError as exc:
            raise ProgramError(exc.kind, exc.message, self.src.at(exc.col)) from None
        self.pos = p.pos
        return node

    # -- block -----------------------------------------------------------------------------
    def is_name(self, ident: str) -> bool:
        """Whether the control knows ``ident`` as one name (never split into address words)."""
        return ident in self.g.names or ident in self.variables

    def parse(self, block: b.Block, code: str) -> None:
        self.toks = tokenize(code, self.src, self.is_name)
        if "AX" in code.upper():    # AX2=10, POS[AX3]: the machine axis of that number
            numbered = self.g.numbered
            self.toks = [Token(IDENT, numbered[t.text], t.col) if t.kind == IDENT and t.text in numbered
                         and t.text not in self.variables else t for t in self.toks]
        self.pos = 0
        if self.is_op("/"):
            block.skip = True
            self.pos += 1
            if self.tok.kind == NUM and isinstance(self.tok.value, int) and self.tok.col == 2:
                self.pos += 1
        t = self.tok
        if t.kind == IDENT and (m := _BLOCKNO.match(t.text)):
            block.number, block.number_col = int(m.group(1)), t.col
            self.pos += 1
        elif self.is_op(":") and self.peek().kind == NUM:
            block.number, block.number_col = int(self.peek().value), t.col
            self.pos += 2
        t = self.tok
        if t.kind == IDENT and self.is_op(":", 1) and t.text not in STATEMENTS:
            if not _LABEL.match(t.text):
                self.fail("syntax", f"{t.text!r} is not a valid label (two letters or '_' first)", t.col)
            block.label, block.label_col = t.text, t.col
            self.pos += 2
        if self.tok.kind == END:
            block.kind = "label" if block.label else "empty"
            return
        t = self.tok
        if t.kind == IDENT and t.text in STATEMENTS:
            self.statement(block, t)
            return
        self.nc_items(block)

    def statement(self, block: b.Block, t: Token) -> None:
        name = t.text
        if name in _SHAPES:  # kept when the rest of the block does not parse
            jumps = name == "IF" and any(x.kind == IDENT and x.text in _JUMPS for x in self.toks)
            section = name == "REPEAT" and self.peek().kind != END      # REPEAT label: no structure
            block.shape = "" if jumps or section else name.lower()
        self.pos += 1
        if name == "IF":
            block.cond = self.expr()
            if self.tok.kind == IDENT and self.tok.text in _JUMPS:
                block.kind = "nc"
                block.jump = self.jump()
                self.expect_end("the jump")
            else:
                block.kind = "if"
                self.expect_end("the IF condition")
        elif name in ("REPEAT", "REPEATB") and (self.tok.kind != END or name == "REPEATB"):
            self.section(block, name)
        elif name in ("ELSE", "ENDIF", "ENDWHILE", "ENDFOR", "REPEAT", "LOOP", "ENDLOOP"):
            block.kind = name.lower()
            self.expect_end(name)
        elif name in ("WHILE", "UNTIL"):
            block.kind = name.lower()
            block.cond = self.expr()
            self.expect_end(f"the {name} condition")
        elif name == "FOR":
            block.kind = "for"
            tt = self.tok
            if tt.kind != IDENT:
                self.fail("syntax", "FOR needs a variable")
            self.pos += 1
            block.for_target = self.target(tt)
            self.expect_op("=")
            block.for_start = self.expr()
            if not (self.tok.kind == IDENT and self.tok.text == "TO"):
                self.fail("syntax", f"expected TO, found {self.describe(self.tok)}")
            self.pos += 1
            block.for_end = self.expr()
            self.expect_end("FOR")
        elif name == "CASE":
            block.kind = "case"
            block.cond = self.expr()
            if not (self.tok.kind == IDENT and self.tok.text == "OF"):
                self.fail("syntax", f"expected OF, found {self.describe(self.tok)}")
            self.pos += 1
            while self.tok.kind != END:
                if self.tok.kind == IDENT and self.tok.text == "DEFAULT":
                    self.pos += 1
                    block.default = self.jump()
                    continue
                value = self.expr()
                block.cases.append((value, self.jump()))
        elif name in _JUMPS:
            self.pos -= 1
            block.kind = "nc"
            block.jump = self.jump()
            self.expect_end("the jump")
        elif name == "DEF":
            block.kind = "def"
            self.definition(block)
        elif name == "PROC":
            block.kind = "proc"
            block.proc = self.proc_header(t)
        elif name == "RET":
            block.kind = "nc"
            block.items.append(b.Keyword(t.col, "RET"))
            if self.is_op("("):     # RET(target, after, levels, to start): where the caller goes on
                args = self.arguments()
                if not args or args[0] is None or len(args) > 4:
                    self.fail("syntax", "RET(target block, block after it, levels, to start) needs the "
                              "target", t.col)
                block.items.append(b.Builtin(t.col, "RET", tuple(args)))
            self.expect_end("RET")
        elif name == "CALL" and self.tok.kind == IDENT and self.tok.text == "BLOCK":
            self.pos += 1
            self.call_block(block)
        elif name in ("CALL", "EXTCALL", "PCALL"):
            block.kind = "nc"
            block.items.append(commands.program_call(self, t))
            if self.tok.kind == IDENT and self.tok.text == "BLOCK":
                self.fail("unsupported", "CALL \"NAME\" BLOCK …: a section of another program is not "
                          "simulated")
            self.expect_end(name)
        elif name == "EXTERN":
            block.kind = "empty"  # declaration of a subprogram's signature: nothing to run
            self.pos = len(self.toks) - 1
        else:
            self.fail("syntax", f"{name} cannot start a block here", t.col)

    def section(self, block: b.Block, name: str) -> None:
        """``REPEAT label [label] [P=n]`` / ``REPEATB label [P=n]``: program section repetition."""
        labels = []
        while self.tok.kind == IDENT and not (self.tok.text == "P" and self.is_op("=", 1)):
            labels.append(self.tok.text)
            self.pos += 1
        count = None
        if self.tok.kind == IDENT and self.tok.text == "P":
            self.pos += 2
            count = self.expr()
        if not labels or len(labels) > (1 if name == "REPEATB" else 2):
            self.fail("syntax", f"{name} needs {'one label' if name == 'REPEATB' else 'one or two labels'}"
                      " and optionally P=n")
        self.expect_end(name)
        block.kind = "section"
        block.section = (labels[0], labels[1] if len(labels) > 1 else None, count, name == "REPEATB")

    def call_block(self, block: b.Block) -> None:
        """``CALL BLOCK start TO end``: the section of this program from label ``start`` to label
        ``end`` runs once, as ``REPEAT start end P=1`` does."""
        labels = []
        for k in range(2):
            if self.tok.kind != IDENT:
                self.fail("syntax", "CALL BLOCK needs a start and an end label: CALL BLOCK START TO END")
            labels.append(self.tok.text)
            self.pos += 1
            if k == 0:
                if not (self.tok.kind == IDENT and self.tok.text == "TO"):
                    self.fail("syntax", "CALL BLOCK start TO end: TO expected")
                self.pos += 1
        self.expect_end("CALL BLOCK")
        block.kind = "section"
        block.section = (labels[0], labels[1], None, False)

    def jump(self) -> b.Jump:
        t = self.tok
        if t.kind != IDENT or t.text not in _JUMPS:
            self.fail("syntax", f"expected GOTOF/GOTOB/GOTO/GOTOC, found {self.describe(t)}")
        self.pos += 1
        tgt = self.tok
        if t.text == "GOTOS":                      # back to the program's first block
            return b.Jump("GOTOS", "", None, t.col)
        if tgt.kind == IDENT and getattr(self.variables.get(tgt.text), "type", "") == "STRING":
            self.pos += 1                         # GOTOF DEST: the label DEST holds, at run time
            return b.Jump(t.text, tgt.text, None, tgt.col, variable=True)
        if tgt.kind == IDENT:
            self.pos += 1
            m = _BLOCKNO.match(tgt.text)
            if m:
                return b.Jump(t.text, tgt.text, int(m.group(1)), tgt.col)
            return b.Jump(t.text, tgt.text, None, tgt.col)
        if (tgt.kind == OP and tgt.text == "(") or (tgt.kind == STR and self.is_op("<<", 1)):
            node = self.expr()                    # GOTOF ("LB"<<R1): a destination computed at run time
            return b.Jump(t.text, "(expression)", None, tgt.col, variable=True, expr=node)
        if tgt.kind == STR:
            self.pos += 1
            return b.Jump(t.text, tgt.value.upper(), None, tgt.col)
        if tgt.kind == NUM and isinstance(tgt.value, int):  # GOTOF 90: the block N90 (or :90)
            self.pos += 1
            return b.Jump(t.text, f"N{tgt.value}", tgt.value, tgt.col)
        self.fail("syntax", f"{t.text} needs a label or block number")
        raise AssertionError  # unreachable

    def target(self, t: Token) -> b.Target:
        name = t.text
        if name.startswith("$"):  # a system variable: nck.py writes it
            p = ExprParser(self.toks, self.pos, self.variables.__contains__)
            try:
                node = p.system(t)
            except ParseError as exc:
                raise ProgramError(exc.kind, exc.message, self.src.at(exc.col)) from None
            self.pos = p.pos
            if not sysvars.lookup(name).writable:
                self.fail("read_only", f"{name} is read-only for a part program", t.col)
            return b.Target(name=name, index=node.args)
        if name == "R" and self.is_op("["):
            self.pos += 1
            idx = self.expr()
            self.expect_op("]")
            return b.Target(r_expr=idx)
        if len(name) > 1 and name[0] == "R" and name[1:].isdigit():
            i = int(name[1:])
            if i >= 1000:
                self.fail("index_range", f"{name} is outside R0..R999", t.col)
            return b.Target(r=i)
        if name in self.variables:
            idx: list[Node] = []
            if self.is_op("["):
                self.pos += 1
                idx.append(self.expr())
                while self.is_op(","):
                    self.pos += 1
                    idx.append(self.expr())
                self.expect_op("]")
            return b.Target(name=name, index=tuple(idx))
        self.fail("undefined_variable", f"{name} is not defined (DEF) before use", t.col)
        raise AssertionError

    definition = declarations.definition
    proc_header = declarations.proc_header

    # -- NC words ----------------------------------------------------------------------------
    def nc_items(self, block: b.Block) -> None:
        block.kind = "nc"
        items = block.items
        while self.tok.kind != END:
            t = self.tok
            if t.kind != IDENT:
                if t.kind == OP and t.text == "(":
                    self.fail("syntax", "unexpected '(': in Siemens mode a comment starts with ';' "
                              "('( … )' comments belong to the ISO dialect, G291, not simulated)")
                self.fail("syntax", f"unexpected {self.describe(t)}")
            name = t.text
            if name in _JUMPS:
                block.jump = self.jump()
                self.expect_end("the jump")
                break
            self.pos += 1
            if name in COMMANDS and commands.is_command_start(self, name):
                items.append(commands.read(self, t))
            elif name in ("AX", "SPOS", "SPOSA") and self.is_op("["):   # AX[X]=, SPOS[n]=
                items.append(commands.bracketed(self, t))
            elif self.is_op("=") or (self.is_op("[") and (name in self.variables or name == "R"
                                                         or name.startswith("$"))):
                item = self.assignment(t)      # a $ system variable: sysvars decides (as when read)
                items.extend(item if isinstance(item, list) else (item,))
            elif self.is_op("("):
                items.append(self.call_with_args(t))
            else:
                item = self.plain(t, block)
                if item is not None:
                    items.append(item)
        groups: dict[int, b.GCode] = {}
        for it in items:
            if isinstance(it, b.GCode) and it.code.group >= 0:
                prev = groups.get(it.code.group)
                if prev is not None and prev.code.name != it.code.name:
                    self.fail(
                        "modal_conflict",
                        f"{it.code.name} and {prev.code.name} belong to the same "
                        f"G group ({it.code.group_name}); one per block",
                        it.col,
                    )
                groups[it.code.group] = it

    def assignment(self, t: Token) -> b.Item | list[b.Item]:
        name = t.text
        if (name == "R" or (name[0] == "R" and name[1:].isdigit()) or name in self.variables
                or name.startswith("$")):
            target = self.target(t)
            self.expect_op("=")
            if target.name is not None and self.tok.kind == IDENT and self.tok.text in ("SET", "REP") \
                    and self.is_op("(", 1):
                return arrays.fill(self, t, target)
            return b.Assign(t.col, target, self.expr())
        self.pos += 1  # '='
        return self.address(t, name)

    def address(self, t: Token, name: str) -> b.Word:
        """``NAME=value`` for an address (axis, F, S2, M2, T, D, I, CR ...)."""
        if self.g.is_axis(name) and name not in _ORIENT:
            mode, node = self.moded_value()
            return b.Word(t.col, name, "axis", node, None, mode)
        if name in _INTERP or name in _ORIENT:
            mode, node = self.moded_value()
            return b.Word(t.col, name, _INTERP.get(name, "orient"), node, None, mode)
        if name in _INTERP_UNSUPPORTED:
            self.fail("unsupported", f"{name}= is not simulated", t.col)
        if name in _SINGLE:
            return b.Word(t.col, name, _SINGLE[name], self.expr())
        m = _SPINDLE_ADDR.match(name)
        if m:
            kind = "speed" if m.group(1) == "S" else "m"
            return b.Word(t.col, name, kind, self.expr(), int(m.group(2)))
        if name in ("SPOS", "SPOSA") or (name.startswith("SPOS") and name[4:].isdigit()):
            mode, node = self.moded_value()
            return b.Word(t.col, name, "spos", node, None, mode)
        if (m := _H_ADDR.match(name)) is not None:   # H7=1: auxiliary function with extension
            return b.Word(t.col, name, "aux", self.expr(), int(m.group(1)))
        if name in CODES or name in STATEMENTS:
            self.fail("syntax", f"{name} takes no value", t.col)
        self.fail("unknown_word", self.unknown_word_message(name), t.col)
        raise AssertionError

    def moded_value(self) -> tuple[str | None, Node]:
        t = self.tok
        if t.kind == IDENT and t.text in _MODES and self.is_op("(", 1):
            self.pos += 2
            node = self.expr()
            self.expect_op(")")
            if self.tok.kind == OP and self.tok.text not in (",",):
                self.fail("syntax", f"{t.text}(...) must be the whole value")
            return t.text, node
        return None, self.expr()

    def modal_call(self, t: Token) -> b.Call:
        """``MCALL CYCLE81(...)`` (a drilling cycle called after every following positioning
        block) or ``MCALL`` alone (off): a cycle call named ``MCALL`` / ``MCALL CYCLE81``;
        ``MCALL L10`` / ``MCALL NAME(args)`` of a subprogram: a call with ``how`` "MCALL"."""
        if self.tok.kind == END:
            return b.Call(t.col, "MCALL", (), cycle=True)
        target = self.tok
        simulated = {*DRILLING, *MODAL_CYCLES}
        if target.kind == IDENT and target.text in self.g.programs and target.text not in simulated:
            # MCALL L10 / MCALL NAME(args): a subprogram (a simulated cycle stays the cycle, as in a call)
            self.pos += 1
            args = self.arguments() if self.is_op("(") else ()
            return b.Call(target.col, target.text, tuple(args), how="MCALL")
        if target.kind != IDENT or not self.is_op("(", 1) or target.text not in simulated:
            self.fail("unsupported", "MCALL is simulated for the drilling, boring and tapping cycles "
                      f"({', '.join(sorted(simulated))}) and the subprograms beside the "
                      "program only", target.col)
        self.pos += 1
        call = self.call_with_args(target)
        return b.Call(t.col, f"MCALL {call.name}", call.args, cycle=True)

    def call_with_args(self, t: Token) -> b.Item:
        name = t.text
        if name in UNSUPPORTED_WORDS:
            self.fail("unsupported", f"{name} is not simulated", t.col)
        if (name in CODES and name not in _BUILTINS) or name in ACCEPTED_WORDS or name in self.variables:
            self.fail("syntax", f"{name} takes no arguments", t.col)
        args = self.arguments()
        if name in _BUILTINS:
            if name == "SETMS" and len(args) > 1:
                self.fail("syntax", "SETMS takes at most one spindle number", t.col)
            return b.Builtin(t.col, name, tuple(args))
        standard = name in DRILLING or name in PATTERNS or (
            (name in MILLING or name in TURNING) and name not in self.g.programs)
        return b.Call(t.col, name, tuple(args), cycle=name in self.g.cycles or standard)

    def arguments(self, loose: bool = False) -> tuple[Node | None, ...]:
        """``(a, , b)``: expressions and empty places (None). ``loose``: a name the program does
        not define, alone in its place (an axis ``X``, a mode constant ``_FINISH``), is kept as
        text."""
        self.expect_op("(")
        args: list[Node | None] = []
        if not self.is_op(")"):
            while True:
                tok = self.tok
                if self.is_op(",") or self.is_op(")"):
                    args.append(None)
                elif loose and (n := self._constant_sum()):
                    args.append(Node("str", tok.col, "+".join(self.peek(k).text for k in range(0, n, 2))))
                    self.pos += n
                else:
                    args.append(self.expr())
                if not self.is_op(","):
                    break
                self.pos += 1
        self.expect_op(")")
        return tuple(args)

    def _constant_sum(self) -> int:
        """How many tokens from here make one loose argument: a name the program does not
        define (``_FINISH``), or a sum of such names that begin with ``_`` (the mode constants
        of the cycles' definition files, ``_FINISH+_TOP_SURFACE_SMOOTH_ON``), up to the
        argument's end; 0 when it is something else."""
        k = 0
        while True:
            tok = self.peek(k) if k else self.tok
            if tok.kind != IDENT or tok.text in self.variables or tok.text.startswith("$") \
                    or (tok.text[0] == "R" and tok.text[1:].isdigit()) or (k and tok.text[0] != "_"):
                return 0
            if self.is_op(",", k + 1) or self.is_op(")", k + 1):
                return k + 1
            if not (self.is_op("+", k + 1) and tok.text.startswith("_")):
                return 0
            k += 2

    def plain(self, t: Token, block: b.Block) -> b.Item | None:
        """A word without '=': G code, keyword, address+number, or a call by name."""
        name = t.text
        m = _GCODE.match(name)
        if m:
            code_name = f"G{int(m.group(1))}"
            code = CODES.get(code_name)
            if code is not None:
                if code.status == "unsupported":
                    self.fail("unsupported", f"{code_name} is not simulated by vmach", t.col)
                if code.group == 3:            # G110/G111/G112: the pole, with the block's words
                    return self.frame(Token(t.kind, code_name, t.col))
                return b.GCode(t.col, code)
            if name in self.g.gcodes or code_name in self.g.gcodes:
                return b.GCode(t.col, _machine_code(code_name), machine=True)
            self.fail(
                "unknown_gcode",
                f"{name} is not a Sinumerik G code nor declared by the machine",
                t.col,
            )
        code = CODES.get(name)
        if code is not None:
            if code.status == "unsupported":
                self.fail("unsupported", f"{name} is not simulated by vmach", t.col)
            if code.group == 3:
                return self.frame(t)
            return b.GCode(t.col, code)
        if name == "SETMS":                             # SETMS alone: the configured master
            return b.Builtin(t.col, name)
        if name == "MCALL":
            return self.modal_call(t)
        if name in UNSUPPORTED_WORDS:
            self.fail("unsupported", f"{name} is not simulated", t.col)
        if _BLOCKNO.match(name):
            self.fail("syntax", "a block number must come first in the block", t.col)
        m = _ADDR_NUM.match(name)
        if m or (len(name) == 1 and self.short_value_follows()):
            if m:
                letter, value = m.group(1), self.literal(m.group(2), t.col)
            else:
                letter, value = name, self.signed_number()
            return self.letter_word(t, letter, value)
        if self.g.is_axis(name):
            self.fail("syntax", f"axis {name} needs a value: {name}=...", t.col)
        if name in self.variables or (name[0] == "R" and name[1:].isdigit()):
            self.fail("syntax", f"{name} is not a statement; assign it with {name}=...", t.col)
        if name in _SINGLE or name in _INTERP:
            self.fail("syntax", f"{name} needs a value", t.col)
        if not name.startswith("$") and re.match(r"^[A-Z_][A-Z0-9_]*$", name):
            return b.Call(t.col, name, (), cycle=name in self.g.cycles)
        self.fail("unknown_word", self.unknown_word_message(name), t.col)
        return None

    def short_value_follows(self) -> bool:
        """After a one-letter address: a number, or a sign right before one (``X 10``, ``X -10``).

        Anything else (``X +``, ``X * 3``, ``X -(1)``) is not a short value; an expression needs ``X=``.
        """
        t = self.tok
        return t.kind == NUM or (t.kind == OP and t.text in ("+", "-") and self.peek().kind == NUM)

    def signed_number(self) -> float | int:
        """Read the short value that :meth:`short_value_follows` has seen."""
        sign = 1
        if self.tok.kind == OP and self.tok.text in ("+", "-"):
            sign = -1 if self.tok.text == "-" else 1
            self.pos += 1
        if self.tok.kind != NUM:
            self.fail("syntax", f"expected a number, found {self.describe(self.tok)}")
        v = self.tok.value
        self.pos += 1
        return sign * v  # type: ignore[operator]

    def letter_word(self, t: Token, letter: str, value: float | int) -> b.Item:
        node = _num_node(value, t.col)
        if self.g.is_axis(letter):
            return b.Word(t.col, letter, "axis", node)
        if letter in _SINGLE:
            if letter == "P":
                return b.Word(t.col, letter, "repeat", node)
            return b.Word(t.col, letter, _SINGLE[letter], node)
        if letter in ("I", "J", "K"):
            return b.Word(t.col, letter, "interp", node)
        if letter == "L":
            return b.Call(t.col, f"L{int(value)}" if float(value).is_integer() else f"L{value}")
        self.fail("unknown_word", self.unknown_word_message(letter, t.text), t.col)
        raise AssertionError

    def frame(self, t: Token) -> b.FrameCmd:
        words: list[b.Word] = []
        rpl = None
        while self.tok.kind != END:
            wt = self.tok
            if wt.kind != IDENT:
                self.fail("syntax", f"unexpected {self.describe(wt)} in {t.text}")
            self.pos += 1
            if wt.text == "RPL" and t.text in ("ROT", "AROT") and self.is_op("="):
                self.pos += 1
                rpl = self.expr()
                continue
            if wt.text == "AX" and self.is_op("["):     # ATRANS AX[X]=10, AX[variable]=...
                words.append(commands.axis_address(self, wt))
                continue
            if wt.text in ("AP", "RP") and t.text in POLES and self.is_op("="):
                self.pos += 1
                words.append(b.Word(wt.col, wt.text, "polar", self.expr()))
                continue
            if self.is_op("="):
                self.pos += 1
                if not self.g.is_axis(wt.text):
                    self.fail("unknown_axis", f"{wt.text} is not an axis of this machine", wt.col)
                words.append(b.Word(wt.col, wt.text, "axis", self.expr()))
                continue
            m = _ADDR_NUM.match(wt.text)
            if m and self.g.is_axis(m.group(1)):
                value = self.literal(m.group(2), wt.col)
                words.append(b.Word(wt.col, m.group(1), "axis", _num_node(value, wt.col)))
                continue
            if len(wt.text) == 1 and self.g.is_axis(wt.text) and self.short_value_follows():
                words.append(b.Word(wt.col, wt.text, "axis", _num_node(self.signed_number(), wt.col)))
                continue
            if self.g.is_axis(wt.text):
                self.fail("syntax", f"axis {wt.text} needs a value: {wt.text}=...", wt.col)
            self.fail(
                "syntax",
                f"{t.text} takes axis values only (a frame instruction needs its own block)",
                wt.col,
            )
        if t.text in ("TRANS", "ATRANS") and rpl is not None:
            self.fail("syntax", f"RPL belongs to ROT/AROT, not {t.text}", t.col)
        return b.FrameCmd(t.col, t.text, tuple(words), rpl)

    def unknown_word_message(self, name: str, full: str | None = None) -> str:
        pool = list(CODES) + list(self.g.cycles) + sorted(self.g.axes) + list(COMMANDS)
        close = difflib.get_close_matches(name, pool, n=1, cutoff=0.8)
        hint = f"; did you mean {close[0]}?" if close else ""
        return f"unknown word {full or name!r}{hint}"


def _machine_code(name: str) -> Code:
    return Code(name, -1, "machine", False, "codes")


def parse_program(
    text: str, path: str, control: ControlSpec, programs: frozenset[str] = frozenset(),
    known: dict | None = None, known_macros: dict[str, str] | None = None,
) -> b.Program:
    """Parse a whole program; never raises for bad text (findings collect the problems).
    ``programs``: the names of the programs beside it (``NAME`` of ``NAME.SPF``), which words
    without separators do not split. ``known``: variables defined before the program (global
    user data, ``definitions.py``); ``known_macros``: macros of the macro files (name -> text)."""
    lines = text.splitlines()
    table = dict(known_macros or {})
    grammar = Grammar(control, programs)
    variables: dict = dict(known or {})
    blocks: list[b.Block] = []
    findings: list[Finding] = []
    proc: b.ProcHeader | None = None
    for lineno, raw in enumerate(lines, start=1):
        code, _comment = split_comment(raw)
        if not code.strip():
            continue
        if (defined := macros.definition(code)) is not None:
            table[defined[0]] = defined[1]
            continue
        code = macros.expand(code, table)
        src = SourceRef(path, lineno, 1, raw)
        block = b.Block(index=len(blocks), line=lineno, text=raw)
        parser = BlockParser(grammar, variables, src)
        try:
            parser.parse(block, code)
        except ProgramError as exc:
            block.kind = "bad"
            block.items = []
            block.error = _explain(exc, parser, src, code)
            findings.append(block.error)
        if block.kind == "proc" and block.proc is not None:
            if blocks or proc is not None:
                findings.append(
                    error(
                        "proc_not_first",
                        f"PROC {block.proc.name} must be the first block of its file "
                        "(a subprogram is a file of its own)",
                        src.at(_col_of(raw, "PROC")),
                    )
                )
            if proc is None:
                proc = block.proc
        blocks.append(block)
    name = proc.name if proc else _stem(path)
    return b.Program(path, name, lines, blocks, findings, proc, variables)


def _explain(exc: ProgramError, parser: BlockParser, src: SourceRef, code: str) -> Finding:
    """Turn a parse error into a finding; recognise plain text that lost its ';'."""
    words = code.split()
    if len(words) >= 2 and all(w[:1].isalpha() for w in words[:2]):
        first = words[0].upper()
        known = (
            first in CODES
            or first in STATEMENTS
            or first in COMMANDS
            or first in parser.g.cycles
            or first in parser.variables
            or parser.g.is_axis(first)
            or _ADDR_NUM.match(first)
            or _BLOCKNO.match(first)
            or _GCODE.match(first)
            or not first.isalpha()
        )
        if not known and words[1].isalpha():
            return error(
                "syntax",
                "this line is not NC code (plain text without ';' to make it a comment)",
                src.at(code.index(words[0]) + 1),
            )
    return exc.finding


def _col_of(raw: str, word: str) -> int:
    i = raw.upper().find(word)
    return i + 1 if i >= 0 else 1


def _stem(path: str) -> str:
    import os

    return os.path.splitext(os.path.basename(path))[0].upper()
