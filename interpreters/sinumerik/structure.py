"""Phase 2: the structure of a parsed program and the static checks on it.

- pairs IF/ELSE/ENDIF, WHILE/ENDWHILE, FOR/ENDFOR, REPEAT/UNTIL, LOOP/ENDLOOP (``partner``);
- resolves every jump to a block index the way the control searches (GOTOF forward from the
  next block, GOTOB backward from the current one, GOTO/GOTOC forward then backward);
- reports labels defined twice, missing or wrong-direction jump targets, unbalanced control
  structures, DEF after the first statement, block numbers that do not increase, and blocks no
  path of control can reach.
"""

from __future__ import annotations

import re

from interpreters.sinumerik.blocks import Block, Jump, Program, Word
from vmach.findings import Finding, error, warning
from vmach.source import SourceRef

_OPENERS = {
    "if": "endif",
    "while": "endwhile",
    "for": "endfor",
    "repeat": "until",
    "loop": "endloop",
}
_CLOSERS = {v: k for k, v in _OPENERS.items()}
_END_M = {2, 17, 30}
_EXECUTABLE = {
    "nc",
    "if",
    "else",
    "endif",
    "while",
    "endwhile",
    "for",
    "endfor",
    "repeat",
    "until",
    "loop",
    "endloop",
    "case",
    "bad",
    "label",
}


def src(program: Program, block: Block, col: int = 1) -> SourceRef:
    return SourceRef(program.path, block.line, col, block.text)


def ends_program(block: Block) -> str | None:
    """'M30', 'M2', 'M17' or 'RET' when the block unconditionally ends its program level."""
    for it in block.items:
        if isinstance(it, Word) and it.kind == "m" and it.index is None and it.expr.op == "num":
            if it.expr.value in _END_M:
                return f"M{it.expr.value}"
        elif getattr(it, "name", None) == "RET" and it.__class__.__name__ == "Keyword":
            return "RET"
    return None


def find_target(program: Program, at: int, jump: Jump) -> int | None:
    """Block index the jump lands on, searching as the control does; None when not found."""
    if jump.how == "GOTOS":
        return 0
    if jump.variable:
        return None                        # known at run time only (dynamic_target)
    cands = (
        program.numbers.get(jump.number, [])
        if jump.number is not None
        else program.labels.get(jump.target, [])
    )
    if not cands:
        return None
    fwd = [i for i in cands if i > at]
    back = [i for i in cands if i <= at]
    if jump.how == "GOTOF":
        return fwd[0] if fwd else None
    if jump.how == "GOTOB":
        return back[-1] if back else None
    if fwd:
        return fwd[0]
    return back[-1] if back else None


def analyse(program: Program) -> list[Finding]:
    """Fill partners, labels, numbers and jump targets; return the static findings."""
    out: list[Finding] = []
    blocks = program.blocks
    program.labels = {}
    program.numbers = {}
    last_number: tuple[int, Block] | None = None
    for blk in blocks:
        if blk.label:
            prev = program.labels.setdefault(blk.label, [])
            if prev:
                first = blocks[prev[0]]
                out.append(     # no alarm on the control: a jump takes the first in its direction
                    warning(
                        "duplicate_label",
                        f"label {blk.label} is already defined at line {first.line}; a jump "
                        "lands on the nearest one in its search direction",
                        src(program, blk, blk.label_col),
                        first_line=first.line,
                    )
                )
            prev.append(blk.index)
        if blk.number is not None:
            program.numbers.setdefault(blk.number, []).append(blk.index)
            if last_number is not None and blk.number <= last_number[0]:
                out.append(
                    warning(
                        "block_number_order",
                        f"block number N{blk.number} follows N{last_number[0]} (line {last_number[1].line})",
                        src(program, blk, blk.number_col),
                        previous=last_number[0],
                        number=blk.number,
                    )
                )
            last_number = (blk.number, blk)
    out += _pair(program)
    out += _defs_first(program)
    out += _jumps(program)
    out += _unreachable(program)
    return out


def _pair(program: Program) -> list[Finding]:
    out: list[Finding] = []
    stack: list[Block] = []
    for blk in program.blocks:
        k = blk.kind if blk.kind != "bad" else blk.shape  # a bad IF still opens its structure
        if k in _OPENERS:
            stack.append(blk)
        elif k == "else":
            if not stack or _shape(stack[-1]) != "if":
                out.append(error("unbalanced_block", "ELSE without IF", src(program, blk)))
            elif stack[-1].partner2 >= 0:
                out.append(error("unbalanced_block", "second ELSE for the same IF", src(program, blk)))
            else:
                stack[-1].partner2 = blk.index
                blk.partner = stack[-1].index
        elif k in _CLOSERS:
            want = _CLOSERS[k]
            if not stack or _shape(stack[-1]) != want:
                open_txt = f" (open: {_shape(stack[-1]).upper()} at line {stack[-1].line})" if stack else ""
                out.append(
                    error(
                        "unbalanced_block",
                        f"{k.upper()} without {want.upper()}{open_txt}",
                        src(program, blk),
                    )
                )
                continue
            opener = stack.pop()
            opener.partner = blk.index
            blk.partner = opener.index
            if opener.partner2 >= 0:
                program.blocks[opener.partner2].partner2 = blk.index  # ELSE -> ENDIF
    for blk in stack:
        k = _shape(blk)
        out.append(
            error(
                "unbalanced_block",
                f"{k.upper()} at line {blk.line} is never closed by {_OPENERS[k].upper()}",
                src(program, blk),
            )
        )
    return out


def _shape(blk: Block) -> str:
    """The structure statement a block is, also when the rest of it did not parse."""
    return blk.kind if blk.kind != "bad" else blk.shape


def _defs_first(program: Program) -> list[Finding]:
    out = []
    seen_statement = False
    for blk in program.blocks:
        if blk.kind == "def" and seen_statement:
            out.append(
                error(
                    "def_position",
                    "DEF must come before the first statement of the program",
                    src(program, blk),
                )
            )
        elif blk.kind not in ("def", "proc", "empty", "bad"):
            seen_statement = True
    return out


def _jumps(program: Program) -> list[Finding]:
    out: list[Finding] = []
    for blk in program.blocks:
        if blk.section is not None:
            for name in blk.section[:2]:
                if name is not None and not program.labels.get(name):
                    out.append(error("undefined_label", f"REPEAT: label {name} does not exist",
                                     src(program, blk, 1), target=name))
        jumps = (
            ([blk.jump] if blk.jump else [])
            + [j for _, j in blk.cases]
            + ([blk.default] if blk.default else [])
        )
        for j in jumps:
            tgt = find_target(program, blk.index, j)
            if tgt is not None or j.variable:
                continue
            what = f"block number N{j.number}" if j.number is not None else f"label {j.target}"
            cands = (
                program.numbers.get(j.number, [])
                if j.number is not None
                else program.labels.get(j.target, [])
            )
            where = src(program, blk, j.col)
            if j.how == "GOTOC":
                out.append(
                    warning(
                        "undefined_label",
                        f"{j.how} {j.target}: {what} does not exist; the jump does nothing",
                        where,
                        target=j.target,
                    )
                )
            elif cands:
                other = program.blocks[cands[0]]
                direction = "behind" if j.how == "GOTOF" else "ahead"
                out.append(
                    error(
                        "jump_direction",
                        f"{j.how} {j.target}: {what} lies {direction} (line {other.line}); "
                        f"{j.how} searches only {'forward' if j.how == 'GOTOF' else 'backward'}",
                        where,
                        target=j.target,
                        target_line=other.line,
                    )
                )
            else:
                out.append(
                    error(
                        "undefined_label",
                        f"{j.how} {j.target}: {what} does not exist",
                        where,
                        target=j.target,
                    )
                )
    return out


def dynamic_target(program: Program, blk: Block, jump: Jump, value) -> int | None:
    """Where ``jump`` to a STRING variable lands when the variable holds ``value`` (a label,
    or a block number ``N100``/``100``); None when nowhere."""
    text = str(value).strip().upper()
    m = re.match(r"^N?(\d+)$", text)
    fixed = Jump(jump.how, text, int(m.group(1)) if m else None, jump.col)
    return find_target(program, blk.index, fixed)


def successors(program: Program, i: int) -> list[int]:
    """Blocks control can pass to from block ``i`` (static, both outcomes of conditions)."""
    blocks = program.blocks
    blk = blocks[i]
    nxt = [i + 1] if i + 1 < len(blocks) else []
    k = blk.kind
    if k == "nc":
        if ends_program(blk):
            return []
        if blk.jump is not None and blk.jump.variable:   # any label or block number, or on
            return sorted({i for v in (*program.labels.values(), *program.numbers.values()) for i in v}) + nxt
        if blk.jump is not None:
            t = find_target(program, i, blk.jump)
            tg = [t] if t is not None else []
            if blk.cond is not None or blk.jump.how == "GOTOC" or t is None:
                return tg + nxt
            return tg
        return nxt
    if k == "if":
        if blk.partner2 >= 0:  # ELSE: the else branch starts after it
            return nxt + ([blk.partner2 + 1] if blk.partner2 + 1 < len(blocks) else [])
        return nxt + ([blk.partner] if blk.partner >= 0 else [])
    if k == "else":
        end = blk.partner2
        return [end] if end >= 0 else nxt
    if k in ("while", "for"):
        end = blk.partner
        return nxt + ([end + 1] if end >= 0 and end + 1 < len(blocks) else [])
    if k in ("endwhile", "endfor"):
        return [blk.partner] if blk.partner >= 0 else nxt
    if k == "until":
        return nxt + ([blk.partner + 1] if blk.partner >= 0 else [])
    if k == "endloop":
        return [blk.partner + 1] if blk.partner >= 0 else nxt
    if k == "case":
        tg = [t for _, j in blk.cases if (t := find_target(program, i, j)) is not None]
        if blk.default is not None:
            t = find_target(program, i, blk.default)
            return tg + ([t] if t is not None else nxt)
        return tg + nxt
    if k == "section" and blk.section is not None:   # REPEAT / CALL BLOCK: the section runs first
        return sorted(program.labels.get(blk.section[0], [])) + nxt
    return nxt


#: cycles whose first parameter may name a contour section "START:END" of the program
CONTOUR_CYCLES = frozenset({"CYCLE72", "CYCLE62", "CYCLE63", "CYCLE64"})


def _contour_sections(program: Program) -> list[tuple[int, int]]:
    """(first, last) block indices of the sections a contour cycle's literal "START:END" names."""
    out = []
    for blk in program.blocks:
        for it in blk.items:
            args = getattr(it, "args", ())
            if getattr(it, "name", None) not in CONTOUR_CYCLES or not args or args[0] is None:
                continue
            node = args[0]
            if getattr(node, "op", None) != "str" or ":" not in str(node.value):
                continue
            a, b = (x.strip().upper() for x in str(node.value).split(":", 1))
            starts, ends = program.labels.get(a, []), program.labels.get(b, [])
            if starts and ends:
                out.append((min(starts), max(ends)))
    return out


def _unreachable(program: Program) -> list[Finding]:
    blocks = program.blocks
    if not blocks:
        return []
    seen = [False] * len(blocks)
    todo = [0]
    while todo:
        i = todo.pop()
        if seen[i]:
            continue
        seen[i] = True
        todo.extend(j for j in successors(program, i) if not seen[j])
    for first, last in _contour_sections(program):     # read by a contour cycle, not run
        for k in range(first, last + 1):
            seen[k] = True
    out: list[Finding] = []
    i = 0
    while i < len(blocks):
        if not seen[i] and blocks[i].kind in _EXECUTABLE:
            j = i
            while j + 1 < len(blocks) and not seen[j + 1]:
                j += 1
            first, last = blocks[i], blocks[j]
            span = f"line {first.line}" if i == j else f"lines {first.line}-{last.line}"
            out.append(
                warning(
                    "unreachable_block",
                    f"no path of control reaches {span}",
                    src(program, first),
                    first_line=first.line,
                    last_line=last.line,
                )
            )
            i = j + 1
        else:
            i += 1
    return out
