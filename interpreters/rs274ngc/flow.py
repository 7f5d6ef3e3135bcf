"""O-word control flow: subroutines, loops and branches, as LinuxCNC 2.9 runs them.

LinuxCNC's model (interp_o_word.cc, convert_control_functions) is a small state machine, and
this module follows it rather than a structured reading, so that programs with misplaced
labels behave (and fail) the same way:

* Labels of sub/endsub/call/return are global; the others are local to the subroutine they
  are in, i.e. qualified by its name (``"#10"`` in the main program, ``"name#10"`` in a
  subroutine). A table remembers, per qualified label, the first O-word seen with it (kind,
  line, and the count of a ``repeat``); reusing a label elsewhere is a duplicate.
* A branch or loop that is not taken sets *skipping* to its label: following lines are read
  but not executed, up to the next O-word **with that label**, whatever its kind; that
  O-word is then handled as if executed (it may stop the skipping, or not). Reading such a
  line evaluates its condition (errors included); other lines are not evaluated at all.
* A few global flags carry over between structures, as in LinuxCNC: ``executed_if`` (has a
  branch of the current if run), ``doing_break`` and ``doing_continue``. The latter two are
  not always reset by LinuxCNC, which this reproduces (see DEVIATIONS.md for what shows).

Subroutines are found, in this order: already defined (a ``sub`` met earlier, which is then
skipped up to its ``endsub``), the file ``<name>.ngc`` in the directory of the main program
(never elsewhere), or further down the current file. Calls pass ``[args]`` in ``#1``..``#30``
and start a fresh scope of named locals; ``endsub``/``return`` may return ``[value]`` in
``#<_value>`` (``#<_value_returned>`` tells whether one was given).
"""

from __future__ import annotations

import re
from pathlib import Path

from interpreters.rs274ngc.context import RESTORE_ON_RETURN, VALID
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.expr import evaluate, to_integer
from interpreters.rs274ngc.lexer import n_label
from interpreters.rs274ngc.program import load_program
from vmach.files import leads_outside

_SAFE_NAME = re.compile(r"[a-z0-9_][a-z0-9_.\-]*")
#: LinuxCNC runs the main program and at most 9 nested calls (INTERP_SUB_ROUTINE_LEVELS)
MAX_CALL_LEVELS = 10
_CONDITIONS = frozenset(("if", "elseif", "while", "repeat"))
_GLOBAL = frozenset(("sub", "endsub", "call", "return", "program", "m98", "m99"))
_SUB_LINES = ("sub", "program")


class Frame:
    """One call level: where to continue after the return, the sub's name, saved #1..#30
    (None for an M98 call, whose #1..#30 are the caller's), how it was called ("call",
    "m98" or "" for the main program) and the repeats left of an ``M98 … L`` it runs."""

    __slots__ = ("prog", "pc", "name", "saved", "call_type", "m98_count", "context",
                 "context_status")

    def __init__(self, prog=None, pc=0, name="", saved=None, call_type=""):
        self.prog = prog
        self.pc = pc
        self.name = name
        self.saved = saved
        self.call_type = call_type
        self.m98_count = -1
        self.context = None  # the modal state M70/M73 saved (context.py)
        self.context_status = 0  # context.VALID | context.RESTORE_ON_RETURN


class Label:
    """What the label table holds for one qualified label (LinuxCNC's offset_map entry)."""

    __slots__ = ("kind", "prog", "index", "count")

    def __init__(self, kind: str, prog, index: int):
        self.kind = kind
        self.prog = prog
        self.index = index
        self.count = -1  # repeat: iterations left; -1 = to be computed


class FlowMixin:
    """O-word handling for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    def init_flow(self) -> None:
        self.frames: list[Frame] = [Frame()]
        self.subs: dict[str, tuple] = {}  # name -> (Program, line index of the sub line)
        self.seeking: tuple | None = None
        self.test_value = 0.0  # the condition or return value of the O-line last read
        self.call_args: list[float] | tuple = ()
        self.defining: str | None = None  # the subroutine whose definition is skipped
        self.is_defining = False  # reading a value of that definition
        self.skipping: str | None = None  # the qualified label skipped to
        self.labels: dict[str, Label] = {}
        self.executed_if = False
        self.doing_break = False
        self.doing_continue = False
        #: LinuxCNC's [RS274NGC]DISABLE_FANUC_STYLE_SUB (M98, M99 and bare O-numbers refused)
        self.fanuc_disabled = False

    def o_name(self, o) -> str:
        """The label of an O-line: as written, or the number computed when the line is read
        (``o#1 call``, ``o[#2*10] call``, M98's P word); M99 returns from the running sub."""
        if o.name_value is None:
            if o.kind == "m99":
                return self.frames[-1].name
            return o.name
        v = self._read_value(o.name_value, self.defining is not None)
        return str(to_integer(v) if o.kind == "m98" else int(v))

    def qualified(self, o) -> str:
        name = self.o_name(o) if o.dynamic else o.name
        if o.kind in _GLOBAL:
            return name
        if len(self.frames) > 1:
            return self.frames[-1].name + "#" + name
        return (self.defining or "") + "#" + name

    # -- reading and dispatch -------------------------------------------------------------------

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
        getattr(self, o.handler)(line, o, self.qualified(o))
        if self.skipping is not None:
            self.skip()

    def skip(self) -> None:
        """Read lines without executing them while a label is skipped to: an O-word of that
        label is read (its condition evaluated) and handled, which may end the skipping."""
        prog = self.prog
        n = len(prog.raw)
        out = self.out
        while self.skipping is not None:
            pc = self.pc
            if pc >= n:
                self.end_of_file()
            line = prog.lines[pc] or prog.line(pc)
            self.index = pc
            self.line = line
            self.pc = pc + 1
            if line.slash and self.block_delete:
                continue
            if line.skip_error is not None:
                raise line.skip_error
            if line.percent and self.percent:
                out.finish(end=False)
                raise NgcError("percent_while_skipping", name=self.skipping)
            defining = self.defining is not None
            if line.o_error and (line.o_error is True or not defining):
                raise line.error
            o = line.o
            if o is None:
                continue
            kind = o.kind
            if defining and (kind == "sub" or kind == "program"):
                raise NgcError("nested_sub_definition", o.col)
            if kind == "m99" and len(self.frames) == 1:
                continue  # M99 in the main program is a stop, not an O-line
            name = self.qualified(o)
            if name != self.skipping or kind == "call" or kind == "m98":
                continue
            if kind in _CONDITIONS or kind == "endsub" or kind == "return":
                if defining and kind in _CONDITIONS:
                    continue
                if o.value_error is not None:
                    raise o.value_error
                if o.value is not None:
                    self.test_value = self._read_value(o.value, defining)
            elif defining:
                continue
            if out.trace:
                out.nlabel = n_label(line.raw)
            if out.want:
                out.src = prog.ref(pc)
            getattr(self, "o_" + kind)(line, o, name)
            if self.prog is not prog:
                prog = self.prog
                n = len(prog.raw)

    def _read_value(self, value, defining: bool) -> float:
        if not defining:
            return evaluate(value, self)
        self.is_defining = True  # LinuxCNC reads undefined named parameters as 0 here
        try:
            return evaluate(value, self)
        finally:
            self.is_defining = False

    # -- the label table ------------------------------------------------------------------------

    def _text(self, line) -> str:
        return line.raw.rstrip()  # LinuxCNC keeps the indentation

    def _find(self, line, name: str, kinds: tuple[str, ...], kind_error: str) -> Label:
        """The label an elseif/else/endif/break/continue/endwhile/endrepeat refers to."""
        label = self.labels.get(name)
        if label is None:
            raise NgcError("undefined_label", line=line.number, text=self._text(line))
        if label.kind not in kinds:
            raise NgcError(kind_error, line=line.number, text=self._text(line), name=name,
                           found=label.kind, other=label.index + 1)
        return label

    def _open(self, line, name: str, kind: str, duplicate: str) -> Label:
        """Record the label of an if/while/repeat, or check it is this very line."""
        label = self.labels.get(name)
        if label is None:
            label = self.labels[name] = Label(kind, self.prog, self.index)
        elif label.index != self.index and (kind != "while" or label.kind != "do"):
            raise NgcError(duplicate, line=line.number, other=label.index + 1,
                           text=self._text(line))
        return label

    def _back_to(self, label: Label) -> None:
        """Continue at the line of ``label`` (which is read and executed again)."""
        self.prog = label.prog
        self.pc = label.index

    # -- subroutines --------------------------------------------------------------------------

    def o_sub(self, line, o, name):
        if len(self.frames) > 1:  # a definition inside a called subroutine: LinuxCNC runs on
            return None
        known = self.subs.get(name)
        if known is not None:
            prog, index = known
            if prog is self.prog and index == self.index:
                raise NgcError("sub_illegal_location", file=self.prog.path, line=line.number,
                               name=name)
            raise NgcError("sub_redefined", file=self.prog.path, line=line.number, name=name,
                           other=prog.path)
        self.subs[name] = (self.prog, self.index)
        self.defining = name
        self.skipping = name
        return None

    def o_program(self, line, o, name):
        """A bare program number (O1000): LinuxCNC goes on, unless in an O-word call."""
        self._fanuc_allowed(o)
        if len(self.frames) > 1 and self.frames[-1].call_type != "m98":
            raise NgcError("fanuc_sub_not_m98", o.col)
        return None

    def o_call(self, line, o, name):
        args = self.call_args
        if len(self.frames) >= min(self.options.max_call_depth, MAX_CALL_LEVELS):
            raise NgcError("call_depth", o.col)
        prog, index = self.find_sub(line, o, name)
        self._check_sub_style(prog, index, "call")
        saved = self.pars.num[1:31]
        num = self.pars.num
        for i in range(30):
            num[1 + i] = args[i] if i < len(args) else 0.0
        self.frames.append(Frame(self.prog, self.pc, name, saved, "call"))
        self.pars.locals.append({})
        self.prog = prog
        self.pc = index + 1

    def o_m98(self, line, o, name):
        """``M98 P… [L…]`` (interp_o_word.cc execute_call): #1..#30 stay the caller's; with
        L the M98 line is returned to until its count (kept in the caller's frame) runs
        out; ``L0`` enters the call level without running the sub, as LinuxCNC does."""
        self._fanuc_allowed(o)
        if len(self.frames) >= min(self.options.max_call_depth, MAX_CALL_LEVELS):
            raise NgcError("call_depth", o.col)
        caller = self.frames[-1]
        back = self.pc
        count = None
        if o.loop is not None:
            count = evaluate(o.loop, self)
            if caller.m98_count == -1:
                caller.m98_count = int(count + 0.5) if count >= 0 else int(count - 0.5)
            caller.m98_count -= 1
            if caller.m98_count > 0:
                back = self.index  # read the M98 line again for the next repeat
            else:
                caller.m98_count = -1
        frame = Frame(self.prog, back, name, None, "m98")
        if count == 0.0:
            self.frames.append(frame)
            self.pars.locals.append({})
            return
        prog, index = self.find_sub(line, o, name)
        self._check_sub_style(prog, index, "m98")
        self.frames.append(frame)
        self.pars.locals.append({})
        self.prog = prog
        self.pc = index + 1

    def o_m99(self, line, o, name):
        self._fanuc_allowed(o)
        return self._return(line, o)

    def _fanuc_allowed(self, o) -> None:
        """[RS274NGC]DISABLE_FANUC_STYLE_SUB refuses M98, M99 and bare O-numbers."""
        if self.fanuc_disabled:
            raise NgcError("fanuc_disabled_" + o.kind)

    def _check_sub_style(self, prog, index: int, call_type: str) -> None:
        """Fanuc ``O1`` programs are called with M98, ``O1 sub`` subroutines with ``call``;
        LinuxCNC reports a mix at the sub's line."""
        kind = prog.line(index).o.kind
        if (kind == "program") != (call_type == "m98"):
            self.prog, self.index = prog, index
            self.line = prog.line(index)
            raise NgcError("fanuc_sub_not_m98" if kind == "program" else "sub_not_o_call")

    def find_sub(self, line, o, name: str):
        """Where the subroutine ``name`` starts: (Program, index of its sub line)."""
        known = self.subs.get(name)
        if known is not None:
            return known
        found = self.sub_file(name, o.col)
        if found is not None:
            path, shown = found
            key = str(path)
            prog = self.programs.get(key)
            if prog is None:
                prog = self.programs[key] = load_program(shown)
            for i in range(len(prog.raw)):
                ln = prog.line(i)
                if ln.o is not None and ln.o.kind in _SUB_LINES and ln.o.name == name:
                    self.subs[name] = (prog, i)
                    return prog, i
        # search further down the current file
        here_prog, here_pc, here_index = self.prog, self.pc, self.index
        self.seeking = (name, line.number, self.prog.path)
        self._seek_sub(name)
        self.seeking = None
        found = (self.prog, self.index)
        self.subs[name] = found
        self.prog, self.pc, self.index = here_prog, here_pc, here_index
        self.line = line
        return found

    def sub_file(self, name: str, col: int = 0) -> tuple[Path, str] | None:
        """The file ``name.ngc`` a call of a subroutine not yet defined reads, as (path, the
        path findings show), or None. The one place subroutine files are resolved: the main
        program's directory, then the SUBROUTINE_PATH directories of an INI file the user
        named (``--ini``); never elsewhere. A name with a path separator or ``..``, or a file
        there that is a link (or a chain of links) leading out of its directory, is refused
        (``subprogram_outside``) and never opened."""
        if not _SAFE_NAME.fullmatch(name) or ".." in name:
            raise NgcError("subprogram_outside", col, name=name)
        dirs = [self.directory]
        if self.config is not None:
            dirs += [d for d in self.config.subroutine_dirs if d != self.directory]
        for d in dirs:
            path = d / f"{name}.ngc"
            if leads_outside(path, d):
                raise NgcError("subprogram_outside", col, name=name)
            if path.is_file():
                shown = Path(self.path).parent / path.name if d == self.directory else path
                return path, str(shown)
        return None

    def _seek_sub(self, name: str) -> None:
        prog = self.prog
        n = len(prog.raw)
        pc = self.pc
        while pc < n:
            line = prog.lines[pc] or prog.line(pc)
            self.index = pc
            self.line = line
            pc += 1
            if line.skip_error is not None:
                raise line.skip_error
            if line.percent and self.percent:
                self.out.finish(end=False)
                raise NgcError("percent_while_skipping", name=name)
            if line.o_error:
                raise line.error
            o = line.o
            if o is not None and o.kind in _SUB_LINES and self.o_name(o) == name:
                self.pc = pc
                return
        self.pc = pc
        self.end_of_file()

    def o_endsub(self, line, o, name):
        return self._return(line, o)

    def o_return(self, line, o, name):
        return self._return(line, o)

    def _return(self, line, o):
        if len(self.frames) == 1:
            if self.defining is None:
                raise NgcError("not_in_sub", line=line.number, text=self._text(line))
            if o.kind == "endsub":  # the end of a definition
                self.defining = None
                self.skipping = None
            return None
        value = None if o.value is None else self.test_value
        call_type = self.frames[-1].call_type
        if call_type == "m98" and o.kind != "m99":
            raise NgcError("fanuc_sub_not_m99")
        if call_type == "call" and o.kind == "m99":
            raise NgcError("sub_not_endsub")
        frame = self.frames.pop()
        self.pars.locals.pop()
        if frame.saved is not None:
            self.pars.num[1:31] = frame.saved
        if frame.context_status == VALID | RESTORE_ON_RETURN:  # M73
            self.restore_context(frame.context)
        g = self.pars.globals
        g["_value"] = 0.0 if value is None else value
        g["_value_returned"] = 0.0 if value is None else 1.0
        self.prog = frame.prog
        self.pc = frame.pc
        return None

    # -- branches -------------------------------------------------------------------------------

    def o_if(self, line, o, name):
        self._open(line, name, "if", "duplicate_label")
        if self.test_value != 0.0:
            self.skipping = None
            self.executed_if = True
        else:
            self.skipping = name
            self.executed_if = False

    def o_elseif(self, line, o, name):
        self._find(line, name, ("if",), "no_matching_if_label")
        if self.executed_if:
            self.skipping = name
        elif self.test_value != 0.0:
            self.skipping = None
            self.executed_if = True

    def o_else(self, line, o, name):
        self._find(line, name, ("if",), "no_matching_if_label")
        if self.executed_if:
            self.skipping = name
        elif self.skipping == name:
            self.executed_if = True
            self.skipping = None

    def o_endif(self, line, o, name):
        self._find(line, name, ("if",), "no_matching_endif_label")
        self.skipping = None
        self.executed_if = True

    # -- loops --------------------------------------------------------------------------------

    def o_do(self, line, o, name):
        self.skipping = None
        if name not in self.labels:
            self.labels[name] = Label("do", self.prog, self.index)

    def o_while(self, line, o, name):
        label = self._open(line, name, "while", "duplicate_loop_label")
        self.skipping = None
        if label.kind == "while":
            if self.test_value == 0.0:
                self.skipping = name
        elif self.test_value != 0.0 and not self.doing_break:  # the end of a do loop
            self._back_to(label)
        else:
            self.doing_break = False

    def o_repeat(self, line, o, name):
        label = self._open(line, name, "repeat", "duplicate_loop_label")
        self.skipping = None
        if label.count == -1:
            label.count = round(self.test_value)
        if label.count > 0:
            label.count -= 1
        else:
            self.skipping = name
            label.count = -1

    def o_break(self, line, o, name):
        self._find(line, name, ("while", "do"), "no_matching_loop_label")
        self.skipping = name
        self.doing_break = True

    def o_continue(self, line, o, name):
        self._find(line, name, ("while", "do"), "no_matching_loop_label")
        if self.skipping == name:
            return
        self.skipping = name
        self.doing_continue = True

    def o_endwhile(self, line, o, name):
        self._end_loop(line, name, "while")

    def o_endrepeat(self, line, o, name):
        self._end_loop(line, name, "repeat")

    def _end_loop(self, line, name: str, kind: str) -> None:
        label = self._find(line, name, (kind,), "no_matching_label")
        if self.skipping == name:
            self.skipping = None
            if self.doing_continue:
                self.doing_continue = False
                self._back_to(label)
        else:
            self._back_to(label)
