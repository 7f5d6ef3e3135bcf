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
from interpreters.sinumerik.structure import analyse, dynamic_target, find_target
from vmach import canon
from vmach.canon import ControlSpec, RunOptions, RunResult
from vmach.errors import ProgramError
from vmach.files import contained, decode_text, read_program_bytes
from vmach.findings import Finding, warning
from vmach.source import SourceRef

PROGRAM_SUFFIXES = (".SPF", ".MPF")


@dataclass(slots=True)
class Loaded:
    program: b.Program
    findings: list[Finding]
    ops: list[Callable[[], int]] | None = None
    archive: dict[str, str] = field(default_factory=dict)  # later programs of its file (archive.py)


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
    return Loaded(program, findings, archive=others)


def _entry(directory: Path, name: str) -> Path | None:
    """The entry ``NAME.SPF`` or ``NAME.MPF`` of ``directory`` (case-insensitive, SPF first),
    wherever it leads."""
    if not name or any(ch in name for ch in "/\\:") or name in (".", ".."):
        return None
    wanted = {name.upper() + s for s in PROGRAM_SUFFIXES}
    try:
        entries = sorted(os.listdir(directory))
    except OSError:
        return None
    for suffix in PROGRAM_SUFFIXES:  # SPF before MPF
        for entry in entries:
            if entry.upper() == name.upper() + suffix and entry.upper() in wanted:
                p = directory / entry
                if p.is_file() or p.is_symlink():  # a link is judged by where it leads
                    return p
    return None


def program_names(directory: Path) -> frozenset[str]:
    """``NAME`` of every ``NAME.SPF``/``NAME.MPF`` in ``directory`` (upper case)."""
    try:
        entries = os.listdir(directory)
    except OSError:
        return frozenset()
    return frozenset(e[:-4].upper() for e in entries if e[-4:].upper() in PROGRAM_SUFFIXES)
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
                self.call(name, args, src, repeat, how)
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

            def variable():
                tgt = dynamic_target(program, blk, jump, env.vars[name])
                if tgt is None:
                    if jump.how == "GOTOC":
                        return blk.index + 1
                    raise ProgramError("undefined_label", f"{jump.how} {name}: no destination "
                                       f"{env.vars[name]!r}", source)
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
