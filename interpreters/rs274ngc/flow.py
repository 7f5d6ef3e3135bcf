"""O-word control flow: subroutines and structured loops/branches (interp_o_word.cc).

Labels (``o100``, ``o<name>``) of sub/endsub/call/return are global; the others are local to
the subroutine they appear in. A block that is not taken is *skipped*: lines are read up to
the next O-word with the same label of an expected kind; only the conditions of O-words of
that label are evaluated on the way, as LinuxCNC reads them (errors included).

Subroutines are found, in this order: already defined (a ``sub`` met earlier, which is then
skipped up to its ``endsub``), the file ``<name>.ngc`` in the directory of the main program
(never elsewhere), or further down the current file. Calls pass ``[args]`` in ``#1``..``#30``
and start a fresh scope of named locals; ``endsub``/``return`` may return ``[value]`` in
``#<_value>`` (``#<_value_returned>`` tells whether one was given).
"""

from __future__ import annotations

import re
from pathlib import Path

from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.expr import evaluate
from interpreters.rs274ngc.lexer import n_label

_SAFE_NAME = re.compile(r"[a-z0-9_][a-z0-9_.\-]*")
#: LinuxCNC runs the main program and at most 9 nested calls (INTERP_SUB_ROUTINE_LEVELS)
MAX_CALL_LEVELS = 10
_CONDITIONS = frozenset(("if", "elseif", "while", "repeat"))


class Frame:
    """One call level.

    prog, pc : where to continue after the return (unused for the main program).
    labels : label -> (kind of the opening O-word, line index), for matching checks.
    stack : open control structures, innermost last: [kind, label, line index, count].
    """

    __slots__ = ("prog", "pc", "name", "saved", "labels", "stack")

    def __init__(self, prog=None, pc=0, name="", saved=None):
        self.prog = prog
        self.pc = pc
        self.name = name
        self.saved = saved
        self.labels: dict[str, tuple[str, int]] = {}
        self.stack: list[list] = []


class FlowMixin:
    """O-word handling for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    def init_flow(self) -> None:
        self.frames: list[Frame] = [Frame()]
        self.subs: dict[str, tuple] = {}  # name -> (Program, line index of the sub line)
        self.seeking: tuple | None = None
        self.test_value = 0.0  # the condition or return value of the O-line last read
        self.call_args: list[float] | tuple = ()
        self.defining = False  # skipping a subroutine definition

    # -- dispatch -----------------------------------------------------------------------------

    def control(self, line):
        """Execute an O-line: as LinuxCNC reads the whole line first, its condition or
        arguments are evaluated (and may fail) before any check of the label."""
        o = line.o
        if o.value_error is not None:
            raise o.value_error
        if o.value is not None:
            self.test_value = evaluate(o.value, self)
        elif o.args:
            self.call_args = [evaluate(a, self) for a in o.args]
        else:
            self.call_args = ()
        if o.trailing_error is not None:
            raise o.trailing_error
        handler = getattr(self, "o_" + o.kind)
        return handler(line, o)

    def read_skipped(self, line, o, name: str, defining: bool) -> None:
        """What LinuxCNC evaluates of an O-line it reads while skipping to label ``name``:
        the condition of an if/elseif/while/repeat of that label (not while skipping a
        subroutine definition) and the value of that subroutine's endsub/return."""
        if o.name != name:
            return
        kind = o.kind
        if kind in _CONDITIONS:
            if defining:
                return
        elif kind not in ("endsub", "return") or not defining:
            return
        if o.value_error is not None:
            raise o.value_error
        if o.value is not None:
            self.defining = defining
            try:
                self.test_value = evaluate(o.value, self)
            finally:
                self.defining = False

    def _check_label(self, line, o, kinds: tuple[str, ...]) -> None:
        labels = self.frames[-1].labels
        seen = labels.get(o.name)
        if seen is None:
            raise NgcError("undefined_label", line=line.number, text=line.raw.strip())
        if seen[0] not in kinds:
            raise NgcError("no_matching_label", line=line.number, text=line.raw.strip(),
                           found=seen[0], other=seen[1] + 1)

    def _open_label(self, line, o, kind: str) -> None:
        labels = self.frames[-1].labels
        seen = labels.get(o.name)
        if seen is not None and seen[1] != self.index and seen[0] != "do":
            raise NgcError("duplicate_label" if kind == "if" else "duplicate_loop_label",
                           line=line.number, other=seen[1] + 1, text=line.raw.strip())
        labels[o.name] = (kind, self.index)

    def skip_to(self, name: str, kinds: tuple[str, ...], nested_sub: bool = False):
        """Read lines without executing them up to O-word ``name`` of one of ``kinds``.

        As LinuxCNC reads every O-word of the label it skips to, the conditions of that
        label's lines are evaluated on the way (and may fail; see :meth:`read_skipped`).
        """
        prog = self.prog
        n = len(prog.raw)
        pc = self.pc
        while pc < n:
            line = prog.lines[pc] or prog.line(pc)
            self.index = pc
            self.line = line
            pc += 1
            if line.skip_error is not None:
                self.pc = pc
                raise line.skip_error
            if line.o_error and (line.o_error is True or not nested_sub):
                self.pc = pc
                raise line.error
            o = line.o
            if o is None:
                continue
            if nested_sub and o.kind == "sub":
                self.pc = pc
                raise NgcError("nested_sub_definition", o.col)
            if o.name == name:
                self.pc = pc
                self.read_skipped(line, o, name, nested_sub)
            if o.name == name and o.kind in kinds:
                self.pc = pc
                out = self.out
                if out.trace:
                    out.nlabel = n_label(line.raw)
                if out.want:
                    out.src = prog.ref(self.index)
                return line
        self.pc = pc
        self.end_of_file()

    # -- subroutines --------------------------------------------------------------------------

    def o_sub(self, line, o):
        name = o.name
        if len(self.frames) > 1:
            raise NgcError("nested_sub_definition", o.col)
        known = self.subs.get(name)
        if known is not None:
            prog, index = known
            if prog is self.prog and index == self.index:
                raise NgcError("sub_illegal_location", file=self.prog.path, line=line.number,
                               name=name)
            raise NgcError("sub_redefined", file=self.prog.path, line=line.number, name=name,
                           other=prog.path)
        self.subs[name] = (self.prog, self.index)
        self.skip_to(name, ("endsub",), nested_sub=True)

    def o_call(self, line, o):
        args = self.call_args
        if len(self.frames) >= min(self.options.max_call_depth, MAX_CALL_LEVELS):
            raise NgcError("call_depth", o.col)
        prog, index = self.find_sub(line, o)
        saved = self.pars.num[1:31]
        num = self.pars.num
        for i in range(30):
            num[1 + i] = args[i] if i < len(args) else 0.0
        self.frames.append(Frame(self.prog, self.pc, o.name, saved))
        self.pars.locals.append({})
        self.prog = prog
        self.pc = index + 1

    def find_sub(self, line, o):
        name = o.name
        known = self.subs.get(name)
        if known is not None:
            return known
        if not _SAFE_NAME.fullmatch(name) or ".." in name:
            raise NgcError("sub_outside_program", o.col, name=name)
        path = self.directory / f"{name}.ngc"
        if path.is_file():
            key = str(path)
            prog = self.programs.get(key)
            if prog is None:
                from interpreters.rs274ngc.interp import load_program

                shown = str(Path(self.path).parent / f"{name}.ngc")
                prog = self.programs[key] = load_program(shown)
            for i in range(len(prog.raw)):
                ln = prog.line(i)
                if ln.o is not None and ln.o.kind == "sub" and ln.o.name == name:
                    self.subs[name] = (prog, i)
                    return prog, i
        # search further down the current file
        here_prog, here_pc, here_index = self.prog, self.pc, self.index
        self.seeking = (name, line.number, self.prog.path)
        self.skip_to(name, ("sub",))
        self.seeking = None
        found = (self.prog, self.index)
        self.subs[name] = found
        self.prog, self.pc, self.index = here_prog, here_pc, here_index
        self.line = line
        return found

    def o_endsub(self, line, o):
        return self._return(line, o)

    def o_return(self, line, o):
        return self._return(line, o)

    def _return(self, line, o):
        value = None if o.value is None else self.test_value
        if len(self.frames) == 1:
            if o.kind == "endsub":
                raise NgcError("not_in_sub", line=line.number, text=line.raw.strip())
            return None
        frame = self.frames.pop()
        self.pars.locals.pop()
        self.pars.num[1:31] = frame.saved
        g = self.pars.globals
        g["_value"] = 0.0 if value is None else value
        g["_value_returned"] = 0.0 if value is None else 1.0
        self.prog = frame.prog
        self.pc = frame.pc
        return None

    # -- branches -------------------------------------------------------------------------------

    def o_if(self, line, o):
        self._open_label(line, o, "if")
        frame = self.frames[-1]
        if self.test_value != 0.0:
            frame.stack.append(["if", o.name, self.index, 0])
            return None
        while True:
            ln = self.skip_to(o.name, ("elseif", "else", "endif"))
            kind = ln.o.kind
            if kind == "endif":
                return None
            if kind == "else" or self.test_value != 0.0:
                frame.stack.append(["if", o.name, self.index, 0])
                return None

    def o_elseif(self, line, o):
        """Reached after a taken branch (its condition was evaluated all the same)."""
        self._check_label(line, o, ("if",))
        self._pop(o.name)
        self.skip_to(o.name, ("endif",))

    def o_else(self, line, o):
        self.o_elseif(line, o)

    def o_endif(self, line, o):
        self._check_label(line, o, ("if",))
        self._pop(o.name)

    def _pop(self, name: str):
        stack = self.frames[-1].stack
        for k in range(len(stack) - 1, -1, -1):
            if stack[k][1] == name:
                entry = stack[k]
                del stack[k:]
                return entry
        return None

    def _top(self, name: str):
        stack = self.frames[-1].stack
        for k in range(len(stack) - 1, -1, -1):
            if stack[k][1] == name:
                del stack[k + 1 :]
                return stack[k]
        return None

    # -- loops --------------------------------------------------------------------------------

    def o_do(self, line, o):
        self._open_label(line, o, "do")
        entry = self._top(o.name)
        if entry is None or entry[2] != self.index:
            self.frames[-1].stack.append(["do", o.name, self.index, 0])

    def o_while(self, line, o):
        frame = self.frames[-1]
        entry = self._top(o.name)
        if entry is not None and entry[0] == "do":
            if self.test_value != 0.0:
                self.pc = entry[2] + 1
            else:
                self._pop(o.name)
            return None
        self._open_label(line, o, "while")
        if self.test_value != 0.0:
            if entry is None or entry[2] != self.index:
                frame.stack.append(["while", o.name, self.index, 0])
            return None
        if entry is not None:
            self._pop(o.name)
        self.skip_to(o.name, ("endwhile",))
        return None

    def o_endwhile(self, line, o):
        self._check_label(line, o, ("while",))
        entry = self._top(o.name)
        if entry is None:
            return None
        self.pc = entry[2]
        return None

    def o_repeat(self, line, o):
        self._open_label(line, o, "repeat")
        count = round(self.test_value)
        if count <= 0:
            self.skip_to(o.name, ("endrepeat",))
            return None
        self.frames[-1].stack.append(["repeat", o.name, self.index, count])
        return None

    def o_endrepeat(self, line, o):
        self._check_label(line, o, ("repeat",))
        entry = self._top(o.name)
        if entry is None:
            return None
        entry[3] -= 1
        if entry[3] > 0:
            self.pc = entry[2] + 1
        else:
            self._pop(o.name)
        return None

    def o_break(self, line, o):
        entry = self._pop(o.name)
        kind = entry[0] if entry is not None else None
        closer = {"while": ("endwhile",), "repeat": ("endrepeat",), "do": ("while",)}.get(
            kind, ("endwhile", "endrepeat"))
        self.skip_to(o.name, closer)

    def o_continue(self, line, o):
        entry = self._top(o.name)
        if entry is None:
            self.skip_to(o.name, ("endwhile", "endrepeat", "while"))
            return None
        if entry[0] == "repeat":
            entry[3] -= 1
            if entry[3] > 0:
                self.pc = entry[2] + 1
            else:
                self._pop(o.name)
                self.skip_to(o.name, ("endrepeat",))
            return None
        self.pc = entry[2]
        return None
