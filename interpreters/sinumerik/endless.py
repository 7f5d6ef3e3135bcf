"""Programs that never end on their own: a warm-up or run-in program that repeats its blocks
until the operator resets the control (``LOOP … ENDLOOP`` or ``WHILE TRUE … ENDWHILE`` with no
way out, or a bare ``GOTOB START`` / ``GOTOS`` back over blocks with no way out).

Such a program is valid on the control, but a run would stop at the block limit. For a loop
that provably has no way out (:func:`no_way_out`: no block in it leaves it, ends the program
or returns), vmach compares the program's state each time the loop jumps back — R parameters,
the level's and the global variables, the system variables written, the axes' positions, the
spindles, the tool and the modal state. When one pass leaves it exactly as the pass before,
every further pass repeats the same motion: the run ends there, completed, with a warning
``endless_program`` naming the loop (the control runs it until reset).
"""

from __future__ import annotations

from collections.abc import Callable

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.running import Running
from interpreters.sinumerik.structure import successors
from vmach import canon
from vmach.findings import warning
from vmach.source import SourceRef

STOP = -3   # compile.STOP: the run ends


def no_way_out(program: b.Program, first: int, last: int) -> bool:
    """True when control, once in blocks ``first..last``, can never leave them: every block's
    static successors lie inside, and none ends the program or the level."""
    for i in range(first, last + 1):
        blk = program.blocks[i]
        nxt = [i + 1] if blk.kind == "while" and _always(blk.cond) else successors(program, i)
        if not nxt or any(not first <= s <= last for s in nxt):
            return False
        if any(isinstance(x, b.Keyword) and x.name == "RET" for x in blk.items):
            return False
    return True


def _always(cond) -> bool:
    """True for a condition that is a constant other than 0 (``WHILE TRUE``, ``WHILE 1``)."""
    return cond is not None and cond.op == "num" and cond.value != 0


def _state(it: Running) -> str:
    """The program's state as one string (exact: ``repr`` of every value)."""
    m = it.machine
    nck = getattr(it.env.sys, "written", None)
    return repr((it.env.r, it.env.vars, it.env.globals, nck, sorted(m.pos.items()),
                 sorted(m.spindles.items()), m.tool, m.edge, m.feed, m.modal_state()))


def back_jump(it: Running, program: b.Program, blk: b.Block, back: int, src: SourceRef) -> Callable[[], int]:
    """The step of a loop's jump back to block ``back``: ends the run when a pass changed
    nothing (see the module's docstring)."""
    last: list[str] = []

    def op() -> int:
        state = _state(it)
        if last and last[0] == state and len(it.stack) == 1:
            it.findings.append(warning(
                "endless_program", f"the blocks from line {program.blocks[back].line} to line {blk.line} "
                "repeat with the same state and no way out: the program runs until the control is reset; "
                "vmach ran them until one pass repeated the one before", src))
            it.machine.end_contour(src)
            it.out.append(canon.ProgramEnd(src, code="RESET"))
            return STOP
        last[:] = [state]
        return back

    return op
