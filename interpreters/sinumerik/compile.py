"""Compile one block into a closure ``op() -> next block index`` (or END_LEVEL/CALL/STOP).

Control blocks become tiny closures over their compiled condition and their partner index;
NC blocks evaluate their items left to right into :class:`Values` and hand them to
:meth:`Machine.apply`. A block holding only assignments skips all of that.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik import commands, endless
from interpreters.sinumerik.arrays import unravel
from interpreters.sinumerik.execute import Values
from interpreters.sinumerik.expr import EvalError, compile_expr, eq, num, scope_of
from interpreters.sinumerik.structure import find_target
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef

if TYPE_CHECKING:
    from interpreters.sinumerik.running import Running

END_LEVEL, CALL, STOP, SECTION = -1, -2, -3, -4


def compile_block(it: Running, program: b.Program, blk: b.Block) -> Callable[[], int]:
    i = blk.index
    nxt = i + 1
    kind = blk.kind
    env = it.env
    src = SourceRef(program.path, blk.line, 1, blk.text)
    if env.sys is not None:
        env.sys.src = src   # the NCK names this block in its findings and recorded writes

    def unbalanced(what: str) -> Callable[[], int]:
        return _alarm("unbalanced_block", what, src)

    if kind in ("empty", "label", "proc"):
        return lambda: nxt
    if kind == "bad":
        finding = blk.error

        def bad():
            raise ProgramError(finding.kind, finding.message, finding.source)

        return bad
    if kind == "def":
        inits = []
        for d in blk.defs:
            if d.init is not None:
                inits.append((it.setter(b.Target(name=d.name)), compile_expr(d.init, env)))
            for k, node in enumerate(d.init_list):   # row order: the last index fastest
                if node is not None:
                    idx = b.Target(name=d.name, index=tuple(_const(i, d.col) for i in unravel(k, d.dims)))
                    inits.append((it.setter(idx), compile_expr(node, env)))

        def define():
            for setter, f in inits:
                setter(f())
            return nxt

        return define
    if kind == "if":
        cond = compile_expr(blk.cond, env)
        if blk.partner < 0:
            return unbalanced("IF without ENDIF")
        other = blk.partner2 + 1 if blk.partner2 >= 0 else blk.partner
        return lambda: nxt if cond() else other
    if kind == "else":
        if blk.partner2 < 0:
            return unbalanced("ELSE without IF/ENDIF")
        end = blk.partner2
        return lambda: end
    if kind in ("endif", "repeat", "loop"):
        return lambda: nxt
    if kind == "while":
        if blk.partner < 0:
            return unbalanced("WHILE without ENDWHILE")
        cond = compile_expr(blk.cond, env)
        out = blk.partner + 1
        return lambda: nxt if cond() else out
    if kind in ("endwhile",):
        if blk.partner < 0:
            return unbalanced("ENDWHILE without WHILE")
        back = blk.partner
        if endless.no_way_out(program, back, i):           # WHILE TRUE: a run-in loop until reset
            return endless.back_jump(it, program, blk, back, src)
        return lambda: back
    if kind == "until":
        if blk.partner < 0:
            return unbalanced("UNTIL without REPEAT")
        cond = compile_expr(blk.cond, env)
        body = blk.partner + 1
        return lambda: nxt if cond() else body
    if kind == "endloop":
        if blk.partner < 0:
            return unbalanced("ENDLOOP without LOOP")
        body = blk.partner + 1
        if endless.no_way_out(program, blk.partner, i):    # a run-in loop until reset
            return endless.back_jump(it, program, blk, body, src)
        return lambda: body
    if kind == "for":
        return _for(it, program, blk, src)
    if kind == "endfor":
        return _endfor(it, program, blk, src)
    if kind == "section":
        return _section(it, program, blk, src)
    if kind == "case":
        sel = compile_expr(blk.cond, env)
        cases = [(compile_expr(v, env), it.jump_target(program, blk, j)) for v, j in blk.cases]
        default = it.jump_target(program, blk, blk.default) if blk.default else (lambda: nxt)

        def case():
            x = sel()
            for value, target in cases:
                if eq(x, value()):
                    return target()
            return default()

        return case
    return _nc(it, program, blk, src)


def _alarm(kind: str, what: str, src: SourceRef) -> Callable[[], int]:
    """An op that stops the run with the control's alarm when the block is reached."""

    def op():
        raise ProgramError(kind, what, src)

    return op


def _const(v, col):
    from interpreters.sinumerik.expr import Node

    return Node("num", col, v)


def _for(it, program, blk, src):
    env = it.env
    if blk.partner < 0:
        return _alarm("unbalanced_block", "FOR without ENDFOR", src)
    setter = it.setter(blk.for_target)
    start = compile_expr(blk.for_start, env)
    stop = compile_expr(blk.for_end, env)
    getter = _getter(it, blk.for_target)
    i, out = blk.index, blk.partner + 1

    def op():
        setter(start())
        end = num(stop())
        it.stack[-1].for_end[i] = end
        v = num(getter())
        return i + 1 if v < end or eq(v, end) else out

    return op


def _endfor(it, program, blk, src):
    if blk.partner < 0:
        return _alarm("unbalanced_block", "ENDFOR without FOR", src)
    head = program.blocks[blk.partner]
    if head.kind == "bad":              # its FOR did not parse: reaching this is that error
        return _alarm(head.error.kind, head.error.message, src)
    setter = it.setter(head.for_target)
    getter = _getter(it, head.for_target)
    h, body, nxt = head.index, head.index + 1, blk.index + 1

    def op():
        v = num(getter()) + 1
        setter(v)
        end = it.stack[-1].for_end.get(h)
        if end is None:
            raise ProgramError("unbalanced_block", "ENDFOR reached without passing its FOR", src)
        v = num(getter())
        return body if v < end or eq(v, end) else nxt

    return op


def _getter(it, target: b.Target):
    from interpreters.sinumerik.expr import Node

    if target.name is None:
        node = Node("r", 1, target.r if target.r is not None else target.r_expr)
    else:
        node = Node("var", 1, target.name, target.index)
    return compile_expr(node, it.env)


def _nc(it: Running, program: b.Program, blk: b.Block, src: SourceRef) -> Callable[[], int]:
    env = it.env
    nxt = blk.index + 1
    cond = compile_expr(blk.cond, env) if blk.cond is not None else None
    target = it.jump_target(program, blk, blk.jump) if blk.jump is not None else None
    items = blk.items
    if not items and cond is None and blk.jump is not None and not blk.jump.variable:
        back = find_target(program, blk.index, blk.jump)     # GOTOB START alone: until reset?
        if back is not None and back <= blk.index and endless.no_way_out(program, back, blk.index):
            return endless.back_jump(it, program, blk, back, src)

    if all(isinstance(x, b.Assign) for x in items):
        pairs = [(it.setter(x.target), compile_expr(x.expr, env), x.col) for x in items]
        if len(pairs) == 1 and target is None:
            setter, f, col = pairs[0]

            def assign1():
                try:
                    setter(f())
                except EvalError as exc:
                    raise ProgramError(exc.kind, exc.message, src.at(col)) from None
                return nxt

            return assign1

        def assign_block():
            for setter, f, col in pairs:
                try:
                    setter(f())
                except EvalError as exc:
                    raise ProgramError(exc.kind, exc.message, src.at(col)) from None
            if target is None:
                return nxt
            if cond is None or cond():
                return target()
            return nxt

        return assign_block

    positions: list = []    # the block's POS/POSA moves (commands.run_positions)
    steps = [(commands.step(it, x, src, positions), x.col) if isinstance(x, b.Command) else
             (commands.code_step(it, x.code, x.col, src), x.col)
             if isinstance(x, b.GCode) and x.code.status == "accepted" else _step(it, x, src) for x in items]
    machine = it.machine
    general = _general_nc(it, blk, src, steps, items, cond, target, nxt, positions)
    simple = all(
        (isinstance(x, b.Word) and x.kind in ("axis", "feed"))
        or (isinstance(x, b.GCode) and x.code.name in ("G0", "G1"))
        for x in items
    ) and any(isinstance(x, b.Word) and x.kind == "axis" for x in items)
    if not simple or cond is not None:
        return general
    axis_fs = [(x, compile_expr(x.expr, env)) for x in items if isinstance(x, b.Word) and x.kind == "axis"]
    feed_f = next(
        (compile_expr(x.expr, env) for x in items if isinstance(x, b.Word) and x.kind == "feed"), None
    )
    feed_col = next((x.col for x in items if isinstance(x, b.Word) and x.kind == "feed"), 1)
    code = next((x.code.name for x in items if isinstance(x, b.GCode)), None)

    def straight_block():
        if machine.inch or (code is None and machine.motion not in ("G0", "G1")):
            return general()
        vals = []
        for word, f in axis_fs:
            try:
                value = f()
            except EvalError as exc:
                raise ProgramError(exc.kind, exc.message, src.at(word.col)) from None
            vals.append((word, value))
        if feed_f is not None:
            try:
                feed = feed_f()
            except EvalError as exc:
                raise ProgramError(exc.kind, exc.message, src.at(feed_col)) from None
            if feed.__class__ not in (float, int) or feed < 0:
                return general()
            machine.feed = float(feed)
        if code is not None:
            machine.motion = code
        if not machine.straight(vals, src):
            machine.general_move(vals, src)
        ret = target() if target is not None else nxt
        mc = it.modal_call
        if mc is not None and len(it.stack) == mc[3]:
            it.pending = (mc[0], mc[1], mc[2], 1, ret, "")
            return CALL
        return ret

    return straight_block


def _general_nc(it, blk, src, steps, items, cond, target, nxt, positions):
    machine = it.machine
    out = it.out

    lists = [name for name, kinds in _LISTS.items() if any(_item_kind(x) in kinds for x in items)]
    need_gcodes, need_axes, need_speeds, need_ms, need_cycles, need_interp, need_frame = (
        n in lists for n in ("gcodes", "axes", "speeds", "ms", "cycles", "interp", "frame_values")
    )

    def nc():
        modal = it.modal_call           # MCALL of a subprogram before this block (not made here)
        v = Values()
        if need_gcodes:
            v.gcodes = []
        if need_axes:
            v.axes = []
        if need_speeds:
            v.speeds = []
        if need_ms:
            v.ms = []
        if need_cycles:
            v.cycles = []
        if need_interp:
            v.interp = {}
        if need_frame:
            v.frame_values = {}
        for step, col in steps:
            try:
                step(v)
            except EvalError as exc:
                raise ProgramError(exc.kind, exc.message, src.at(col)) from None
        end = machine.apply(v, src) or v.end
        if positions:
            commands.run_positions(it, positions, src)
        call = v.call
        if call is not None:
            if end is not None:
                raise ProgramError("unsupported", "a subprogram call and a program end in one block", src)
            name, args, col, how = call
            repeat = v.repeat if v.repeat is not None else 1
            if repeat < 1:
                raise ProgramError("invalid_value", f"P{repeat}: the repeat count must be at least 1", src)
            ret = nxt
            if target is not None and (cond is None or cond()):
                ret = target()
            it.pending = (name, args, src.at(col), repeat, ret, how)
            return CALL
        if end is not None:
            if len(it.stack) == 1:
                out.append(canon.ProgramEnd(src, code=end))
                return STOP
            return END_LEVEL
        ret = target() if target is not None and (cond is None or cond()) else nxt
        if modal is not None and modal is it.modal_call and (v.axes or positions) \
                and len(it.stack) == modal[3]:
            it.pending = (modal[0], modal[1], modal[2], 1, ret, "")
            return CALL
        return ret

    return nc


#: which list of Values each kind of item appends to
_LISTS = {
    "gcodes": {"gcode"},
    "axes": {"axis", "axis_var"},
    "speeds": {"speed"},
    "ms": {"m"},
    "cycles": {"cycle", "machine_gcode", "aux", "spos", "builtin"},
    "interp": {"interp", "cr", "turn", "corner", "polar", "orient"},
    "frame_values": {"frame"},
}


def _item_kind(item) -> str:
    if isinstance(item, b.Word):
        return item.kind
    if isinstance(item, b.GCode):
        return "machine_gcode" if item.machine else "gcode"
    if isinstance(item, b.FrameCmd):
        return "frame"
    if isinstance(item, b.Call):
        return "cycle" if item.cycle else "call"
    if isinstance(item, b.Builtin):
        return "builtin"
    return "other"


def _step(it: Running, item, src: SourceRef) -> tuple[Callable[[Values], None], int]:
    env = it.env
    col = item.col
    if isinstance(item, b.Assign):
        setter = it.setter(item.target)
        f = compile_expr(item.expr, env)
        return (lambda v: setter(f())), col
    if isinstance(item, b.Word):
        f = compile_expr(item.expr, env)
        kind = item.kind
        if kind == "axis":
            return (lambda v: v.axes.append((item, _number(f(), item.name)))), col
        if kind == "axis_var":      # AX[variable]=value: the axis is chosen when the block runs
            axis = commands.runtime_axis(it, item)
            return (lambda v: v.axes.append((w := axis(), _number(f(), w.name)))), col
        if kind in ("interp", "cr", "turn", "corner", "polar", "orient"):
            name, mode = item.name, item.mode
            return (lambda v: v.interp.__setitem__(name, (_number(f(), name), mode))), col
        if kind == "feed":

            def feed(v):
                v.feed = float(_number(f(), "F"))

            return feed, col
        if kind == "speed":
            idx = item.index
            return (lambda v: v.speeds.append((idx, float(_number(f(), "S"))))), col
        if kind == "m":
            idx = item.index

            def m(v):
                val = _number(f(), item.name)
                if val != int(val) or val < 0:
                    raise EvalError("invalid_value", f"M functions are whole numbers, got {val}")
                v.ms.append((idx, int(val), col))

            return m, col
        if kind == "tool":

            def tool(v):
                val = f()
                if not isinstance(val, str):
                    val = _number(val, "T")
                    if val != int(val) or val < 0:
                        raise EvalError("invalid_value", f"T{val}: tool numbers are whole numbers")
                v.tool = val

            return tool, col
        if kind == "edge":

            def edge(v):
                val = _number(f(), "D")
                if val != int(val) or val < 0:
                    raise EvalError("invalid_value", f"D{val}: offset numbers are whole numbers")
                v.edge = int(val)

            return edge, col
        if kind == "repeat":

            def rep(v):
                v.repeat = int(_number(f(), "P"))

            return rep, col
        name = item.name
        return (lambda v: v.cycles.append((name, [f()]))), col  # H, SPOS: passed on as events
    if isinstance(item, b.GCode):
        code = item.code
        if item.machine:
            return (lambda v: v.cycles.append((code.name, []))), col
        return (lambda v: v.gcodes.append((col, code))), col
    if isinstance(item, b.FrameCmd):
        fs = [(_frame_axis(it, w), compile_expr(w.expr, env)) for w in item.words]
        rpl = compile_expr(item.rpl, env) if item.rpl is not None else None

        def frame(v):
            v.frame = item
            v.frame_values = {(n := a()): float(_number(g(), n)) for a, g in fs}
            v.rpl = float(_number(rpl(), "RPL")) if rpl is not None else None

        return frame, col
    if isinstance(item, b.Builtin):
        fs = [compile_expr(a, env) if a is not None else None for a in item.args]
        name = item.name
        if name == "RET":                   # RET("LABEL", …): where the caller goes on (interpreter.ret)

            def ret_to(v):
                it.ret_to = (tuple(f() if f is not None else None for f in fs), src.at(col))

            return ret_to, col
        if name == "SETMS":

            def setms(v):
                s = _number(fs[0](), "SETMS") if fs and fs[0] else it.control.master_spindle
                v.setms = int(s)

            return setms, col
        if name == "MSG":

            def msg(v):
                val = fs[0]() if fs and fs[0] else ""
                v.msg = val if isinstance(val, str) else str(val)

            return msg, col
        return (lambda v: v.cycles.append((name, [g() if g else None for g in fs]))), col
    if isinstance(item, b.Call):
        fs = [_argument(a, env) for a in item.args]
        targets = [_ref_target(a) for a in item.args]
        name, how = item.name, item.how
        if item.cycle:
            if name.startswith("MCALL"):    # MCALL alone or of a cycle ends a subprogram's MCALL

                def modal_cycle(v):
                    it.modal_call = None
                    v.cycles.append((name, [g() if g else None for g in fs]))

                return modal_cycle, col
            return (lambda v: v.cycles.append((name, [g() if g else None for g in fs]))), col
        if how == "MCALL":                  # MCALL NAME(args): called after each block that moves

            def modal_sub(v):
                it.machine.mcall = None
                it.modal_call = (name, [((g() if g else None), None) for g in fs], src.at(col),
                                 len(it.stack))

            return modal_sub, col
        if how == "CALL_VAR":       # CALL PNAME: the program the STRING variable names
            get = fs[0]

            def call_var(v):
                target = get()
                if target.__class__ is not str or not target.strip():
                    raise EvalError("type_error", f"CALL {name}: {name} holds no program name ({target!r})")
                v.call = (commands.program_name(target, "CALL"), [], col, "CALL")

            return call_var, col

        def call(v):
            v.call = (
                name,
                [((g() if g else None), t) for g, t in zip(fs, targets, strict=True)],
                col,
                how,
            )

        return call, col
    if isinstance(item, b.Keyword):
        if item.name == "RET":

            def ret(v):
                v.end = "RET"

            return ret, col
        return (lambda v: None), col
    raise AssertionError(f"unknown item {item!r}")


def _frame_axis(it: Running, word: b.Word) -> Callable[[], str]:
    """The axis a frame instruction's word names: fixed, or chosen at run time (``AX[_A]=``)."""
    if word.kind == "axis_var":
        resolve = commands.runtime_axis(it, word)
        return lambda: resolve().name
    name = word.name
    return lambda: name


def _argument(node, env):
    """A call argument's getter: a variable named alone passes its value as it is (an array
    passes the array itself, for a PROC's array parameter)."""
    if node is None:
        return None
    if node.op == "var" and not node.args:
        name = node.value
        scope = scope_of(name, env)         # a GUD variable lives in the global scope
        return lambda: scope.vars[name]
    return compile_expr(node, env)


def _ref_target(node) -> b.Target | None:
    if node is None:
        return None
    if node.op == "r" and isinstance(node.value, int):
        return b.Target(r=node.value)
    if node.op == "var":
        return b.Target(name=node.value, index=node.args)
    return None


def _number(v, name: str):
    if v.__class__ is str:
        raise EvalError("type_error", f"{name} needs a number, not the string {v!r}")
    return v


def _section(it, program, blk, src):
    """REPEAT / REPEATB: run blocks start..stop-1 of this program P times, then go on after
    the statement (the control's search: the label toward the program start first, then toward
    its end; the end label, or ENDLABEL, after it; REPEAT with one label alone ends before
    itself)."""
    label, end_label, count, single = blk.section
    at = blk.index
    cands = program.labels.get(label, [])
    back = [i for i in cands if i < at]
    ahead = [i for i in cands if i > at]
    start = back[-1] if back else (ahead[0] if ahead else None)
    if start is None:
        return _alarm("undefined_label", f"REPEAT{'B' if single else ''} {label}: label not found", src)
    if single:
        stop = start + 1
    else:
        name = end_label or "ENDLABEL"
        ends = [i for i in program.labels.get(name, []) if i >= start]
        if end_label is not None and not ends:
            return _alarm("undefined_label", f"REPEAT {label} {end_label}: label not found", src)
        if ends and (end_label is not None or ends[0] < at or start > at):
            stop = ends[0] + 1
        elif start < at:
            stop = at                       # from the label up to the REPEAT statement
        else:
            return _alarm("undefined_label", f"REPEAT {label}: no end of the section (ENDLABEL)", src)
    times = compile_expr(count, it.env) if count is not None else (lambda: 1)
    nxt = blk.index + 1

    def section():
        n = times()
        if n.__class__ is str or n != int(n) or n < 1:
            raise ProgramError("invalid_value", f"P={n}: the repeat count must be a whole number >= 1", src)
        it.pending = (start, stop, int(n), src, nxt)
        return SECTION

    return section
