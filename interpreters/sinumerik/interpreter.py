"""Phase 3: run a checked program. Each block is compiled once into a closure that does its work
and returns the index of the next block; control structures use the partners and jump targets
that ``structure.analyse`` resolved, so a loop iteration costs a few closure calls.

Program levels (main program, subprogram calls) form a stack; R parameters are global, DEF
variables belong to their level. A block limit stops endless loops; a depth limit stops endless
recursion.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from interpreters.sinumerik import archive, definitions, tracyl
from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.commands import Recorder, not_found
from interpreters.sinumerik.compile import CALL, SECTION, STOP, compile_block
from interpreters.sinumerik.cutcom import flatten
from interpreters.sinumerik.execute import Machine
from interpreters.sinumerik.expr import Env, EvalError, Node, compile_expr, element, num, r_index, scope_of
from interpreters.sinumerik.nck import Nck
from interpreters.sinumerik.parser import parse_program
from interpreters.sinumerik.sandbox import Sandbox
from interpreters.sinumerik.selection import selection_data
from interpreters.sinumerik.structure import analyse, dynamic_target, find_target
from vmach import canon
from vmach.canon import ControlSpec, RunOptions, RunResult
from vmach.errors import ProgramError
from vmach.files import contained, decode_text, read_program_bytes
from vmach.findings import Finding, info, warning
from vmach.source import SourceRef

PROGRAM_SUFFIXES = (".SPF", ".MPF")


@dataclass(slots=True)
class Loaded:
    program: b.Program
    findings: list[Finding]
    ops: list[Callable[[], int]] | None = None
    archive: dict[str, str] = field(default_factory=dict)  # later programs of its file (archive.py)
    data: tuple = ()            # archive.DataSection: its file's _INI sections, run before it


@dataclass(slots=True)
class Level:
    loaded: Loaded
    vars: dict
    pc: int = 0
    for_end: dict = field(default_factory=dict)
    saved: dict | None = None
    back: list = field(default_factory=list)  # (param name, Target) copied back at return
    repeat: int = 1
    call_src: SourceRef | None = None
    start: int = 0                  # a repeated program section (REPEAT): blocks start..stop-1
    stop: int | None = None
    passed: tuple = ()              # which PROC parameters the call gave ($P_SUBPAR)


def read_program(path: Path, display: str, control: ControlSpec, text: str | None = None) -> Loaded:
    """The program in ``path`` (or ``text``, a section of it), parsed and analysed, with the global
    user data of its directory's definition files known."""
    gud = definitions.load(path, display, control)
    text = decode_text(read_program_bytes(path, display)) if text is None else text
    main, others, notes = archive.split(text, display)
    program = parse_program(main, display, control, program_names(path.resolve().parent) | frozenset(others),
                            known=gud.variables, known_macros=gud.macros)
    findings = notes + list(program.findings) + analyse(program)
    data = tuple(archive.data_sections(text)) if "%" in text else ()
    return Loaded(program, findings, archive=others, data=data)


def _entry(directory: Path, name: str) -> Path | None:
    """The entry ``NAME.SPF`` or ``NAME.MPF`` of ``directory`` (case-insensitive, SPF first),
    or the file as the control's file system names it, ``_N_NAME_SPF`` / ``_N_NAME_MPF`` (a
    machine builder's archive copied from the control), wherever it leads."""
    if not name or any(ch in name for ch in "/\\:") or name in (".", ".."):
        return None
    try:
        entries = sorted(os.listdir(directory))
    except OSError:
        return None
    upper = name.upper()
    for suffix in PROGRAM_SUFFIXES:  # SPF before MPF
        wanted = (upper + suffix, "_N_" + upper + "_" + suffix[1:])
        for entry in entries:
            if entry.upper() in wanted:
                p = directory / entry
                if p.is_file() or p.is_symlink():  # a link is judged by where it leads
                    return p
    return None


def program_stem(entry: str) -> str | None:
    """The program name of a file name: ``NAME`` of ``NAME.SPF``/``NAME.MPF`` and of the
    control's ``_N_NAME_SPF``/``_N_NAME_MPF`` (upper case), else None."""
    e = entry.upper()
    if e[-4:] in PROGRAM_SUFFIXES:
        return e[:-4]
    if e.startswith("_N_") and e[-4:] in ("_SPF", "_MPF") and len(e) > 7:
        return e[3:-4]
    return None


def program_names(directory: Path) -> frozenset[str]:
    """``NAME`` of every program file in ``directory`` (upper case, :func:`program_stem`)."""
    try:
        entries = os.listdir(directory)
    except OSError:
        return frozenset()
    return frozenset(s for e in entries if (s := program_stem(e)) is not None)
def names_a_path(name: str) -> bool:
    """True for a subprogram name that is a path (``CALL "../X"``, ``"/etc/x"``): vmach reads
    subprograms only beside the program, so such a name is refused as leading outside."""
    return any(ch in name for ch in "/\\") or name.startswith("..")


def find_subprogram(directory: Path, name: str) -> Path | None:
    """``NAME.SPF`` or ``NAME.MPF`` in ``directory`` (case-insensitive), never elsewhere."""
    p = _entry(directory, name)
    return p if p is not None and contained(p, directory) and p.is_file() else None


def linked_outside(directory: Path, name: str) -> Path | None:
    """The entry for ``name`` in ``directory`` when it is a link to a file outside it (which
    :func:`find_subprogram` refuses), else None."""
    p = _entry(directory, name)
    return p if p is not None and not contained(p, directory) else None


class Interpreter:
    def __init__(self, path: str | Path, control: ControlSpec, options: RunOptions):
        self.path = Path(path)
        self.directory = self.path.resolve().parent
        self.control = control
        self.options = options
        self.env = Env()
        self.out: list[canon.Command] = canon.CommandList()  # held to tol.max_commands
        self.findings: list[Finding] = []
        self.machine = Machine(control, self.out)
        self.machine.tool_radius_of = options.tool_radius
        self.machine.globals = self.env.globals     # the measuring cycles write _OVR/_OVI there
        self.machine.tool_data_of = options.tool_data
        self.nck = Nck(control, self.machine, options, self.findings, lambda: len(self.stack) - 1,
                       self.passed)
        self.env.sys = self.nck
        self.machine.settable_frame = self.nck.settable_frame
        if options.tool_radius is not None:
            self.machine.tool_radius_of = self.nck.tool_radius
        self.loaded: dict[str, Loaded] = {}
        self.stack: list[Level] = []
        self.pending: tuple | None = None
        self.modal_call: tuple | None = None   # MCALL NAME: called after each block that moves
        self.ret_to: tuple | None = None       # RET(target, …) of the level that ends
        self.blocks = 0
        self.archive: dict[str, tuple] = {}  # name -> (file, display, text): later programs of a file
        self.recorder = Recorder()      # commands without effect on geometry (no_effect infos)
        self.sandbox = Sandbox()        # WRITE/READ/DELETE/ISFILE files: in memory, empty at start
        self.env.files = self.sandbox

    # -- loading ---------------------------------------------------------------------------
    def load(self, path: Path, display: str) -> Loaded:
        key = str(path.resolve())
        if key not in self.loaded:
            self.loaded[key] = read_program(path, display, self.control)
            for name, text in self.loaded[key].archive.items():   # programs of an archive file
                self.archive.setdefault(name, (path, display, text))
        return self.loaded[key]

    def ops(self, loaded: Loaded) -> list[Callable[[], int]]:
        if loaded.ops is None:
            loaded.ops = [self.compile_block(loaded.program, blk) for blk in loaded.program.blocks]
        return loaded.ops

    # -- running ---------------------------------------------------------------------------
    def run(self) -> RunResult:
        display = str(self.path)
        try:
            self.define_globals()
            main = self.load(self.path, display)
            self.push(main, SourceRef(display, 1), [])
            self.push_data(main, display)
            self.loop()
            completed = True
        except ProgramError as exc:
            self.findings.append(exc.finding)
            completed = False
        commands = tracyl.apply(flatten(self.out)) if self.machine.placeholders else self.out
        notes = self.machine.notes + self.recorder.findings()
        return RunResult(commands, notes + self.findings, completed, self.blocks)

    def define_globals(self) -> None:
        """The global user data of the program's directory, with their initial values."""
        gud = definitions.load(self.path, str(self.path), self.control)
        self.findings.extend(gud.findings)
        env = self.env
        for name, d in gud.variables.items():
            env.globals[name] = _initial(d)
        for name, d in gud.variables.items():
            src = gud.sources[name]
            items = [(b.Target(name=name), d.init)] if d.init is not None else []
            items += [(b.Target(name=name, index=(Node("num", d.col, k),)), node)
                      for k, node in enumerate(d.init_list)]
            for target, node in items:
                try:
                    self.setter(target)(compile_expr(node, env)())
                except EvalError as exc:
                    raise ProgramError(exc.kind, exc.message, src) from None

    def push_data(self, main: Loaded, display: str) -> None:
        """The program's data, run before it: the data files beside it loaded when it is selected
        (``PART.TOA``, ``PART.RPA`` …, :func:`selection_data`), then the ``_INI`` sections of its
        own file (an archive) in file order, as the control loaded them when the archive was read
        in (archive.data_sections)."""
        data = selection_data(self.path, display) + [(display, d) for d in main.data]
        for shown, d in reversed(data):
            for line, what, count in d.skipped:
                self.findings.append(info("archive_section", f"{d.name}: {what} not loaded ({count} block(s) "
                                          "from here; vmach simulates channel 1 and takes machine data from "
                                          "the machine model)", SourceRef(shown, line), section=d.name,
                                          count=count))
            path = self.path if shown == display else self.directory / os.path.basename(shown)
            loaded = read_program(path, shown, self.control, d.text)
            self.findings.extend(f for f in loaded.findings if f.severity != "info")
            self.push(loaded, SourceRef(shown, d.line), [])

    def push(self, loaded: Loaded, src: SourceRef, args: list, repeat: int = 1) -> None:
        if len(self.stack) >= self.options.max_call_depth:
            raise ProgramError(
                "call_depth", f"more than {self.options.max_call_depth} nested program levels", src
            )
        program = loaded.program
        variables: dict = {}
        level = Level(loaded, variables, repeat=repeat, call_src=src)
        proc = program.proc
        if proc is not None:
            if len(args) > len(proc.params):
                raise ProgramError(
                    "call_arguments",
                    f"{proc.name} takes {len(proc.params)} argument(s), got {len(args)}",
                    src,
                )
            level.passed = tuple(a[0] is not None for a in args)
            for i, p in enumerate(proc.params):
                value, target = args[i] if i < len(args) else (None, None)
                if p.dims or isinstance(value, list):        # an array: passed by reference
                    variables[p.name] = _array_argument(p, value, src)
                    continue
                variables[p.name] = _convert(p.type, value if value is not None else _default(p.type), p.name)
                if p.by_ref and target is not None:
                    level.back.append((p.name, target))
            if "SAVE" in proc.attributes:
                level.saved = self.machine.modal_state()
        elif args:
            raise ProgramError(
                "call_arguments", f"{program.name} has no PROC header and takes no arguments", src
            )
        for name, d in program.variables.items():
            if isinstance(d, b.VarDef) and name not in variables and name not in self.env.globals:
                variables[name] = _initial(d)
        self.stack.append(level)
        self.env.vars = variables

    def pop(self, src: SourceRef) -> bool:
        """Leave the current level; True while levels remain."""
        level = self.stack[-1]
        if level.repeat > 1:
            level.repeat -= 1
            level.pc = level.start
            return True
        self.stack.pop()
        if self.modal_call is not None and len(self.stack) < self.modal_call[3]:
            self.modal_call = None          # the level that made the call modal has ended
        if level.saved is not None:
            self.machine.restore(level.saved, src)
        if self.stack:
            caller = self.stack[-1]
            self.env.vars = caller.vars
            for pname, target in level.back:
                self.assign(target, level.vars[pname])
        return bool(self.stack)

    def loop(self) -> None:
        limit = self.options.max_blocks
        while self.stack:
            level = self.stack[-1]
            ops = self.ops(level.loaded)
            n = len(ops) if level.stop is None else level.stop
            first = level.start
            pc = level.pc
            count = self.blocks
            try:
                while first <= pc < n:
                    count += 1
                    if count > limit:
                        blk = level.loaded.program.blocks[pc]
                        self.blocks = count - 1
                        if (waited := self.nck.waited_on(count)) is not None:
                            raise ProgramError(
                                "unsupported", f"the program waits on {waited[0]} (read {waited[1]} times "
                                f"in {limit} blocks), PLC data or an input the machine sets; vmach does not "
                                "simulate the PLC (it reads what the model or setup gives, else 0)",
                                self.src(level, blk), limit=limit, variable=waited[0])
                        raise ProgramError(
                            "block_limit",
                            f"stopped after {limit} blocks (--max-blocks); "
                            "the program probably loops forever",
                            self.src(level, blk),
                            limit=limit,
                        )
                    pc = ops[pc]()
            except EvalError as exc:
                self.blocks = count
                blk = level.loaded.program.blocks[pc]
                raise ProgramError(exc.kind, exc.message, self.src(level, blk)) from None
            self.blocks = count
            program = level.loaded.program
            if pc == CALL:
                name, args, src, repeat, ret, how = self.pending  # type: ignore[misc]
                level.pc = ret
                try:
                    self.call(name, args, src, repeat, how)
                except EvalError as exc:            # an argument the parameter cannot take
                    raise ProgramError(exc.kind, exc.message, src) from None
                continue
            if pc == SECTION:
                start, stop, repeat, src, ret = self.pending  # type: ignore[misc]
                level.pc = ret
                if len(self.stack) >= self.options.max_call_depth:
                    raise ProgramError("call_depth", f"more than {self.options.max_call_depth} nested "
                                       "program levels and repeated sections", src)
                self.stack.append(Level(level.loaded, level.vars, pc=start, repeat=repeat, call_src=src,
                                        start=start, stop=stop))
                continue
            if pc == STOP:
                self.stack.clear()
                return
            last = program.blocks[-1] if program.blocks else None
            src = self.src(level, last) if last else SourceRef(program.path, 1)
            if pc >= n and len(self.stack) == 1:
                self.findings.append(warning("missing_program_end", "the program ends without M30/M2", src))
                self.machine.end_contour(src)
                self.out.append(canon.ProgramEnd(src, code="EOF"))
            if not self.pop(src):
                return
            if self.ret_to is not None:
                self.return_to()

    def return_to(self) -> None:
        """``RET(target, after, levels, to start)`` (Fundamentals, "Parameterizable subprogram
        return jump"): ``levels`` program levels end (1 the default), and the program returned
        to goes on at the target block (a label or block number, searched as GOTO searches from
        its calling block) or the block after it (``after`` 1)."""
        (target, *rest), src = self.ret_to  # type: ignore[misc]
        self.ret_to = None
        after, levels, start = (list(rest) + [None, None, None])[:3]
        if start:
            raise ProgramError("unsupported", "RET(…, TRUE): a return to the program's start is not "
                               "simulated", src)
        levels = 1 if levels is None else int(levels)
        if not 1 <= levels <= len(self.stack):
            raise ProgramError("invalid_value", f"RET: {levels} return levels, {len(self.stack)} remain", src)
        for _ in range(levels - 1):
            self.pop(src)
        level = self.stack[-1]
        program = level.loaded.program
        at = program.blocks[max(level.pc - 1, 0)] if program.blocks else None
        tgt = dynamic_target(program, at, b.Jump("GOTO", "", None, src.column), target) if at else None
        if tgt is None:
            raise ProgramError("undefined_label", f"RET: no destination {target!r} in "
                               f"{program.name or program.path}", src)
        level.pc = tgt + (1 if after else 0)

    def src(self, level: Level, blk: b.Block, col: int = 1) -> SourceRef:
        return SourceRef(level.loaded.program.path, blk.line, col, blk.text)

    def call(self, name: str, args: list, src: SourceRef, repeat: int, how: str = "") -> None:
        """Call ``name`` (``how``: "CALL", "PCALL", "EXTCALL" when the program names a file,
        "" for a call by name)."""
        caller_dir = (
            Path(self.stack[-1].loaded.program.path).resolve().parent if self.stack else self.directory
        )
        if name in self.archive:                   # a later program of an archive file
            path, display, text = self.archive[name]
            key = f"{path.resolve()}#{name}"
            if key not in self.loaded:
                self.loaded[key] = read_program(path, display, self.control, text)
            self.push(self.loaded[key], src, args, repeat)
            return
        if names_a_path(name):
            raise ProgramError("subprogram_outside", f"{name}: a path; vmach reads subprograms only "
                               f"from {caller_dir}", src)
        path = find_subprogram(caller_dir, name)
        if path is None and (link := linked_outside(caller_dir, name)) is not None:
            raise ProgramError(
                "subprogram_outside", f"{name}: {link.name} leads outside the program's directory "
                f"(never read); vmach reads subprograms only from {caller_dir}", src
            )
        if path is None:
            kind, message = not_found(name, how, program_names(caller_dir), self.control)
            raise ProgramError(kind, f"{message} (in {caller_dir})", src, name=name)
        display = os.path.join(os.path.dirname(self.stack[-1].loaded.program.path), path.name)
        loaded = self.load(path, display)
        self.push(loaded, src, args, repeat)

    def passed(self, n: int) -> bool:
        """$P_SUBPAR[n]: the call gave parameter n (1-based) of the running PROC."""
        passed = self.stack[-1].passed if self.stack else ()
        return 1 <= n <= len(passed) and passed[n - 1]

    # -- assignments -------------------------------------------------------------------------
    def assign(self, target: b.Target, value) -> None:
        if target.name is None:
            i = target.r if target.r is not None else r_index(compile_expr(target.r_expr, self.env)())
            self.env.r[i] = _real(value, f"R{i}")
            return
        self.setter(target)(value)

    def setter(self, target: b.Target) -> Callable:
        env = self.env
        if target.name is None:
            r = env.r
            if target.r is not None:
                i = target.r

                def set_r(v):
                    r[i] = v if v.__class__ is float else _real(v, f"R{i}")

                return set_r
            fi = compile_expr(target.r_expr, env)

            def set_ri(v):
                i = r_index(fi())
                r[i] = _real(v, f"R{i}")

            return set_ri
        name = target.name
        if name.startswith("$"):
            return env.sys.writer(name, [compile_expr(x, env) for x in target.index], target.index[0].col
                                  if target.index else 1)
        scope = scope_of(name, env)
        if not target.index:

            def set_var(v):
                d = scope.vars
                old = d[name]
                if v.__class__ is old.__class__ and v.__class__ is not list:
                    d[name] = v
                    return
                if isinstance(old, list):
                    raise EvalError("type_error", f"{name} is an array; give an index")
                d[name] = _like(old, v, name)

            return set_var
        fs = [compile_expr(x, env) for x in target.index]

        def set_elem(v):
            lst, i = element(scope.vars[name], [f() for f in fs], name)
            lst[i] = _like(lst[i], v, name)

        return set_elem

    # -- compiling blocks ------------------------------------------------------------------
    def compile_block(self, program: b.Program, blk: b.Block) -> Callable[[], int]:
        return compile_block(self, program, blk)

    def jump_target(self, program: b.Program, blk: b.Block, jump: b.Jump) -> Callable[[], int]:
        """A closure giving the landing index, or raising the control's alarm when missing."""
        if jump.variable:                         # GOTOF DEST: DEST's value at run time
            env, name, source = self.env, jump.target, SourceRef(program.path, blk.line, jump.col, blk.text)
            get = compile_expr(jump.expr, env) if jump.expr is not None else (lambda: env.vars[name])

            def variable():
                try:
                    value = get()
                except EvalError as exc:
                    raise ProgramError(exc.kind, exc.message, source) from None
                tgt = dynamic_target(program, blk, jump, value)
                if tgt is None:
                    if jump.how == "GOTOC":
                        return blk.index + 1
                    raise ProgramError("undefined_label", f"{jump.how} {name}: no destination "
                                       f"{value!r}", source)
                return tgt

            return variable
        tgt = find_target(program, blk.index, jump)
        if tgt is not None:
            return lambda: tgt
        if jump.how == "GOTOC":
            nxt = blk.index + 1
            return lambda: nxt
        source = SourceRef(program.path, blk.line, jump.col, blk.text)

        def missing():
            raise ProgramError(
                "undefined_label"
                if not (program.labels.get(jump.target) or program.numbers.get(jump.number or -1))
                else "jump_direction",
                f"{jump.how} {jump.target}: jump destination not found",
                source,
            )

        return missing


def _array_argument(p: b.Param, value, src: SourceRef) -> list:
    """The caller's array itself for the array parameter ``p`` (``VAR REAL A[3]``): what the
    subprogram writes, the caller reads."""
    if not p.dims or not isinstance(value, list):
        what = "an array" if isinstance(value, list) else "no array"
        raise ProgramError("type_error", f"{p.name}: {what} passed to a parameter that takes "
                           f"{'an array' if p.dims else 'a value'}", src)
    inner = value
    for n in p.dims:
        if not isinstance(inner, list) or (n and len(inner) != n):
            raise ProgramError("type_error", f"{p.name}: the array passed has not the sizes "
                               f"{list(p.dims)} of the parameter", src)
        inner = inner[0] if inner else None
    return value


def _default(typ: str):
    return {"INT": 0, "REAL": 0.0, "BOOL": False, "STRING": "", "CHAR": 0, "AXIS": ""}[typ]


def _initial(d: b.VarDef):
    if not d.dims:
        return _default(d.type)

    def make(dims):
        if len(dims) == 1:
            return [_default(d.type) for _ in range(dims[0])]
        return [make(dims[1:]) for _ in range(dims[0])]

    return make(list(d.dims))


def _real(v, name: str) -> float:
    if isinstance(v, str):
        raise EvalError("type_error", f"{name} takes a number, not the string {v!r}")
    return float(v)


def _convert(typ: str, v, name: str):
    if typ in ("STRING", "AXIS"):
        if not isinstance(v, str):
            raise EvalError("type_error", f"{name} is {typ}; it takes a string, not {v!r}")
        return v
    v = num(v) if not isinstance(v, str) else _real(v, name)
    if typ == "INT":
        return int(v + 0.5) if v >= 0 else -int(-v + 0.5)  # REAL -> INT rounds
    if typ == "BOOL":
        return bool(v)
    return float(v)


def _like(old, v, name: str):
    if isinstance(old, bool):
        return _convert("BOOL", v, name)
    if isinstance(old, int):
        return _convert("INT", v, name)
    if isinstance(old, str):
        return _convert("STRING", v, name)
    return _convert("REAL", v, name)


__all__ = ["Interpreter", "find_subprogram", "linked_outside", "read_program"]
