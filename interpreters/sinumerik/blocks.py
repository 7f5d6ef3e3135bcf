"""The parsed form of a Sinumerik program: blocks and the items inside them.

One :class:`Block` per source line that holds code or a label. Items keep their textual order,
because assignments inside a block take effect from left to right.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from interpreters.sinumerik.expr import Node
from interpreters.sinumerik.language import Code
from vmach.findings import Finding


@dataclass(frozen=True, slots=True)
class Jump:
    """``GOTOF``/``GOTOB``/``GOTO``/``GOTOC`` to a label, or to a block number (``number``);
    ``variable``: ``target`` names a STRING variable that holds the destination, or ``expr``
    computes it (``GOTOF ("LB"<<R1)``)."""

    how: str
    target: str
    number: int | None
    col: int
    variable: bool = False
    expr: Node | None = None


@dataclass(frozen=True, slots=True)
class Target:
    """Left side of an assignment: ``R85``, ``R[expr]``, ``NAME`` or ``NAME[i, j]``."""

    r: int | None = None
    r_expr: Node | None = None
    name: str | None = None
    index: tuple[Node, ...] = ()

    def describe(self) -> str:
        if self.name is not None:
            return self.name
        return f"R{self.r}" if self.r is not None else "R[...]"


@dataclass(frozen=True, slots=True)
class Assign:
    col: int
    target: Target
    expr: Node


@dataclass(frozen=True, slots=True)
class Word:
    """An address with its value.

    kind : "axis" "feed" "speed" "m" "tool" "edge" "aux" "interp" "cr" "turn" "repeat" "spos"
    index : extension number (spindle of ``S2=``/``M2=``), else None
    mode : None, "AC", "IC", "ACP", "ACN" or "DC"
    """

    col: int
    name: str
    kind: str
    expr: Node
    index: int | None = None
    mode: str | None = None


@dataclass(frozen=True, slots=True)
class GCode:
    col: int
    code: Code
    machine: bool = False  # declared by the machine model (not a Sinumerik standard code)


@dataclass(frozen=True, slots=True)
class FrameCmd:
    """TRANS / ATRANS / ROT / AROT with their axis values (empty: clear)."""

    col: int
    name: str
    words: tuple[Word, ...]
    rpl: Node | None = None


@dataclass(frozen=True, slots=True)
class Call:
    """Call of a subprogram or a machine cycle by name; ``repeat`` is the P count; ``how``:
    "CALL", "PCALL" or "EXTCALL" when the program names a file, "" for a call by name,
    "CALL_VAR" for ``CALL PNAME`` (``name`` the STRING variable, ``args`` its read)."""

    col: int
    name: str
    args: tuple[Node | None, ...] = ()
    cycle: bool = False
    repeat: Node | None = None
    how: str = ""


@dataclass(frozen=True, slots=True)
class Builtin:
    """Predefined procedure with arguments: SETMS(n), MSG("..."), WORKPIECE(...)."""

    col: int
    name: str
    args: tuple[Node | None, ...] = ()


@dataclass(frozen=True, slots=True)
class Keyword:
    """A word without value: an accepted no-op (STOPRE) or RET."""

    col: int
    name: str


@dataclass(frozen=True, slots=True)
class Command:
    """A predefined command of ``commands.toml``: ``STOPRE``, ``WAITM(1,1,2)``, ``ADIS=0.5``,
    ``FA[X]=1000``, ``POS[C]=ACP(90)``, ``SETAL(61000)``, ``CYCLE832(...)``.

    kind : its kind in the table; args : its values (None for an empty place); axis : the
    axis of ``NAME[axis]=``; mode : AC/IC/ACP/ACN/DC of a positioning value.
    """

    col: int
    name: str
    kind: str
    args: tuple[Node | None, ...] = ()
    axis: str | None = None
    mode: str | None = None


Item = Assign | Word | GCode | FrameCmd | Call | Builtin | Keyword | Command


@dataclass(frozen=True, slots=True)
class VarDef:
    """``DEF type name[dims]=init``."""

    col: int
    type: str
    name: str
    dims: tuple[int, ...] = ()
    init: Node | None = None
    init_list: tuple[Node | None, ...] = ()  # in row order; None: left as it is


@dataclass(frozen=True, slots=True)
class Param:
    """A PROC parameter; ``dims``: the sizes of an array parameter (0: any), else ()."""

    type: str
    name: str
    by_ref: bool = False
    dims: tuple[int, ...] = ()


@dataclass(frozen=True, slots=True)
class ProcHeader:
    col: int
    name: str
    params: tuple[Param, ...] = ()
    attributes: tuple[str, ...] = ()


@dataclass(slots=True)
class Block:
    """One block (line).

    kind : "nc" (words), "if", "else", "endif", "while", "endwhile", "for", "endfor",
        "repeat", "until", "loop", "endloop", "case", "def", "proc", "section" (REPEAT label /
        REPEATB: program section repetition), "bad" (did not parse),
        "label" (label only).
    """

    index: int
    line: int
    text: str
    kind: str = "nc"
    number: int | None = None
    number_col: int = 1
    label: str | None = None
    label_col: int = 1
    skip: bool = False
    items: list[Item] = field(default_factory=list)
    cond: Node | None = None
    jump: Jump | None = None
    cases: list[tuple[Node, Jump]] = field(default_factory=list)
    default: Jump | None = None
    for_target: Target | None = None
    for_start: Node | None = None
    for_end: Node | None = None
    defs: list[VarDef] = field(default_factory=list)
    proc: ProcHeader | None = None
    #: program section repetition (kind "section"): (label, end label or None, P or None, REPEATB)
    section: tuple | None = None
    # filled by structure analysis: index of the partner block (ENDIF for IF, ...)
    partner: int = -1
    partner2: int = -1  # ELSE of an IF
    error: Finding | None = None  # why a "bad" block did not parse
    #: the control structure a "bad" block opens or closes ("if", "endif", "while" ...), so that
    #: its partners still pair; "" for none
    shape: str = ""


@dataclass(slots=True)
class Program:
    """A parsed program file.

    path : the file as displayed in diagnostics
    blocks : the blocks in file order
    findings : parse and structure findings (errors and warnings)
    variables : DEF'd names (and PROC parameters) -> type
    """

    path: str
    name: str
    lines: list[str]
    blocks: list[Block]
    findings: list[Finding]
    proc: ProcHeader | None = None
    variables: dict[str, VarDef | Param] = field(default_factory=dict)
    labels: dict[str, list[int]] = field(default_factory=dict)
    numbers: dict[int, list[int]] = field(default_factory=dict)

    @property
    def has_errors(self) -> bool:
        return any(f.severity == "error" for f in self.findings)
