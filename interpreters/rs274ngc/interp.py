"""The RS274/NGC interpreter: reads lines, runs control flow, executes blocks.

The phases follow LinuxCNC (rs274ngc_pre.cc ``Interp::read``/``Interp::execute`` driven by
``rs274``'s driver.cc): initialise (the preamble of canonical calls), open the file (a first
line ``%`` switches to percent mode), then for every line read it, parse and check it, run
O-word control functions, store the parameter settings of the line, and execute the block in
LinuxCNC's order (:mod:`interpreters.rs274ngc.execute`). The program ends at M2/M30, or at
the closing ``%`` in percent mode; running off the end of the file is an error.
"""

from __future__ import annotations

import gc
from pathlib import Path

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.comp import CompMixin
from interpreters.rs274ngc.config import NgcConfig
from interpreters.rs274ngc.context import ContextMixin
from interpreters.rs274ngc.cycles import CycleMixin
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.execute import ExecuteMixin
from interpreters.rs274ngc.fastpath import FastPathMixin
from interpreters.rs274ngc.flow import FlowMixin
from interpreters.rs274ngc.lathe_cycles import LatheCycleMixin
from interpreters.rs274ngc.lexer import Line, n_label
from interpreters.rs274ngc.mcodes import MCodeMixin
from interpreters.rs274ngc.motion import MotionMixin
from interpreters.rs274ngc.offsets import OffsetMixin
from interpreters.rs274ngc.output import Output
from interpreters.rs274ngc.program import Program, load_program
from interpreters.rs274ngc.splines import SplineMixin
from interpreters.rs274ngc.state import Params, Settings, ToolTable, rotate
from interpreters.rs274ngc.threading import ThreadingMixin
from vmach.canon import ControlSpec, RunOptions
from vmach.findings import Finding, error
from vmach.source import SourceRef

END = 1
#: errors after which even rs274 -n 0 cannot go on
_FATAL = frozenset(("block_limit", "unreadable", "file_ended", "file_ended_percent",
                    "seeking_o_word", "percent_while_skipping"))
class Interpreter(FastPathMixin, FlowMixin, ExecuteMixin, MotionMixin, CompMixin, CycleMixin,
                  OffsetMixin, ContextMixin, ThreadingMixin, SplineMixin, MCodeMixin,
                  LatheCycleMixin):
    """One run of one program."""

    #: take the fast paths (:mod:`interpreters.rs274ngc.fastpath`); False runs every line
    #: through the general path, which the tests compare them against
    fast_paths = True

    def __init__(self, path: str, control: ControlSpec, options: RunOptions, out: Output,
                 tools: ToolTable, block_delete: bool = False, config: NgcConfig | None = None,
                 var_params: dict[int, float] | None = None, continue_after_error: bool = False):
        self.path = str(path)
        self.directory = Path(path).resolve().parent
        self.spec = control
        self.options = options
        self.out = out
        self.tools = tools
        self.block_delete = block_delete
        self.s = Settings()
        self.pars = Params()
        self.params = self.pars.num  # for expr.py (see its context), never replaced
        self.programs: dict[str, Program] = {}
        self.prog: Program | None = None
        self.pc = 0  # index of the next line to read in self.prog
        self.index = 0  # index of the line being executed
        self.line: Line | None = None
        self.percent = False
        self.blocks = 0
        self.ended = False
        self.strict = control.strict_axes
        self.known_axes = {a.name for a in control.axes}
        #: the words of a simple line a strict machine accepts: its axes and F
        self.known_words = frozenset(c for c in "xyzabcf" if c == "f" or c.upper() in self.known_axes)
        self.comp_endpoint = (0.0, 0.0)  # interp_queue.cc's endpoint (comp.py)
        self.comp_endpoint_valid = False
        self.comp_stale_front = None  # what qc().front() reads once the queue is empty
        self.init_flow()
        #: the INI file's settings (``vmach run --ini``), None without one
        self.config = config
        #: parameters from a ``.var`` file (``--var-file``), None without one
        self.var_params = var_params
        #: rs274 ``-n 0``: an error is reported and the run goes on after the top-level call
        self.continue_after_error = continue_after_error
        #: the errors a run that goes on after errors met
        self.errors: list[Finding] = []
        self.readonly_named: set[str] = set()
        self.nurbs_points: list[tuple[float, float, float]] = []  # G5.2's control points

    # -- evaluation context (see expr.py) ----------------------------------------------------

    def par(self, i: int) -> float:
        if i < 1 or i >= 5602:
            raise NgcError("parameter_range")
        if 5420 <= i <= 5425:
            return self.s.pos[i - 5420]
        return self.pars.num[i]

    def named(self, name: str) -> float:
        v = self.named_value(name)
        if v is None:
            if self.is_defining:  # LinuxCNC reads endsub values of a definition leniently
                return 0.0
            raise NgcError("undefined_parameter", name=name)
        return v

    def declare_named(self, name: str) -> None:
        """LinuxCNC creates the parameter of ``#<name> = ...`` (as 0) when it reads the
        line, before the value: ``#<a> = [#<a> + 1]`` works on an undefined #<a>."""
        if self.named_value(name) is None:
            self.pars.store_named(name, 0.0)

    def exists(self, name: str) -> bool:
        return self.named_value(name) is not None

    def tool_diameter(self, tool: int) -> float:
        index = self.tools.index(tool)
        if index is None:
            return 0.0
        return self.tools.entry(index).diameter

    def named_value(self, name: str) -> float | None:
        if name.startswith("_"):
            if name in self.pars.globals:
                return self.pars.globals[name]
            fn = PREDEFINED.get(name)
            if fn is None:
                return self.ini_value(name) if name.startswith("_ini[") else None
            return float(fn(self))
        return self.pars.locals[-1].get(name)

    # -- running -----------------------------------------------------------------------------

    def preamble(self) -> None:
        """Interp::init as rs274 calls it (5 canonical calls), after reading the INI file's
        settings and the parameter file (config.py)."""
        out = self.out
        out.use_length_units(True)
        self.configure()
        s = self.s
        out.set_g5x_offset(s.origin_index, s.origin)
        out.set_g92_offset(s.axis_offset)
        out.set_xy_rotation(s.rotation)
        out.set_feed_reference()
        s.pos = list(out.ppos)

    def configure(self) -> None:
        """The INI file's [RS274NGC] settings, then the parameters of the .var file: the
        coordinate system in use (#5220), its offsets and rotation, and the G92 offsets when
        applied (#5210) and persistence is not disabled."""
        cfg = self.config
        s = self.s
        num = self.pars.num
        if cfg is not None:
            s.orient_offset = cfg.orient_offset
            self.fanuc_disabled = cfg.disable_fanuc_style_sub
        if self.var_params is None:
            return
        for i in range(1, len(num)):
            num[i] = self.var_params.get(i, 0.0)
        index = int(num[5220] + 0.0001)
        if not 1 <= index <= 9:
            index = 1
            num[5220] = 1.0
        if cfg is not None and cfg.disable_g92_persistence:
            for i in range(5210, 5220):
                num[i] = 0.0
        num[5599] = 1.0
        base = 5200 + 20 * index
        s.origin_index = index
        s.origin = [s.u2p(num[base + 1]), s.u2p(num[base + 2]), s.u2p(num[base + 3]),
                    num[base + 4], num[base + 5], num[base + 6]]
        if num[5210]:
            s.axis_offset = [s.u2p(num[5211]), s.u2p(num[5212]), s.u2p(num[5213]),
                             num[5214], num[5215], num[5216]]
        s.rotation = num[base + 10]

    def open(self) -> None:
        """Interp::open: load the main file; a first non-blank line ``%`` is percent mode."""
        self.prog = load_program(self.path)
        self.programs[self.path] = self.prog
        raw = self.prog.raw
        i = 0
        while i < len(raw) and not raw[i].strip():
            i += 1
        if i >= len(raw):
            self.line = None
            raise NgcError("file_ended_percent")
        if raw[i].strip() == "%":
            self.percent = True
            self.pc = i + 1
        else:
            self.pc = 0

    def run(self) -> tuple[bool, Finding | None]:
        """Run the program; returns (completed, the error that stopped it)."""
        self.preamble()
        try:
            self.open()
        except NgcError as exc:
            return False, self.finding(exc)
        self.out.simple("ON_RESET")
        finding = None
        completed = True
        collecting = gc.isenabled()
        gc.disable()  # a run allocates many long-lived commands: collecting only slows it
        try:
            while True:
                try:
                    self.main_loop()
                    break
                except NgcError as exc:
                    finding = self.finding(exc)
                except RecursionError:
                    finding = self.finding(NgcError("call_depth"))
                if not self.continue_after_error or finding.kind in _FATAL:
                    completed = False
                    break
                self.errors.append(finding)
                finding = None
                self.unwind()
        finally:
            if collecting:
                gc.enable()
        self.out.nlabel = "N..... "
        if self.config is None:  # with an INI file LinuxCNC closes lazily: one reset less
            self.out.simple("ON_RESET")
        self.out.simple("ON_RESET")
        return completed, finding

    def unwind(self) -> None:
        """Interp::unwind_call after an error: back to the main program after its top-level
        call, #1..#30 restored, the label table and any skipping dropped."""
        frames = self.frames
        while len(frames) > 1:
            frame = frames.pop()
            self.pars.locals.pop()
            if frame.saved is not None:
                self.pars.num[1:31] = frame.saved
            self.prog, self.pc = frame.prog, frame.pc
        self.subs.clear()
        self.labels.clear()
        self.defining = self.skipping = self.seeking = None
        self.is_defining = self.doing_break = self.doing_continue = False
        self.out.queue = []

    def main_loop(self) -> None:
        limit = self.options.max_blocks
        out = self.out
        trace = out.trace
        want = out.want
        fast_paths = self.fast_paths
        flat_run = self.flat_run
        fast_move = self.fast_move
        step = self.step
        while True:
            prog = self.prog
            pc = self.pc
            if pc >= len(prog.raw):
                self.end_of_file()
            line = prog.lines[pc]
            if line is None:
                if fast_paths and flat_run(prog, pc):
                    continue
                line = prog.line(pc)
            self.pc = pc + 1
            self.index = pc
            self.line = line
            if trace:
                out.nlabel = line.nlabel or _nlabel(line)
            if want:
                out.src = prog.refs[pc] or prog.ref(pc)
            self.blocks += 1
            if self.blocks > limit:
                raise NgcError("block_limit", limit=limit)
            fast = line.fast
            if fast is not None and fast_paths and fast_move(fast):
                continue
            status = step(line)
            if out.spindle_dirty:
                out.flush()
            if status == END:
                return

    def end_of_file(self) -> None:
        if self.prog.raw:
            self.index = len(self.prog.raw) - 1
            self.line = self.prog.line(self.index)
        if self.seeking is not None:
            name, line_no, path = self.seeking
            raise NgcError("seeking_o_word", file=path, name=name, line=line_no)
        raise NgcError("file_ended_percent" if self.percent else "file_ended")

    def step(self, line: Line):
        s = self.s
        if s.toolchange_flag:  # a tool change may move the controlled point: re-read it
            s.pos = list(self.out.ppos)
            s.toolchange_flag = False
        if line.slash and self.block_delete:  # before its N word is read (not its comments)
            return None
        if line.skip_error is not None:
            raise line.skip_error
        if line.percent:
            if self.percent:
                self.out.finish()
                return END
            raise NgcError("bad_character", 1, char="%")
        if line.blank:
            return None
        if line.o is not None or (line.error is not None and not line.items):
            if line.o is None:
                raise line.error
            o = line.o
            if not o.dynamic or o.kind != "m99" or len(self.frames) > 1:
                return self.control(line)
        if line.simple and self.fast_paths and self.simple_step(line):
            return None
        if line.assign and self.fast_paths:
            return self.assign(line)
        block = blk.read_block(line, self)
        blk.enhance(block, s.motion, s.plane)
        blk.check(block, s.incremental)
        if self.strict:
            self.check_axes(block)
        if not line.const:
            for i, v in block.settings:
                self.pars.num[i] = v
            for name, v in block.named:
                self.store_named(name, v)
        return self.execute_block(block)

    def check_axes(self, block: blk.Block) -> None:
        for letter in "xyzabc":
            if letter in block.words and letter.upper() not in self.known_axes:
                raise NgcError("unknown_axis", axis=letter.upper())

    def ini_value(self, name: str) -> float | None:
        """``#<_ini[section]key>``: the INI file's number, then a read-only global
        (interp_namedparams.cc fetch_ini_param); None without an INI file or that key."""
        cfg = self.config
        close = name.find("]", 6)
        if cfg is None or not cfg.features["INI_VARS"] or len(name) < 8 or close < 0:
            return None
        v = cfg.ini.number(name[5:close], name[close + 1:])
        if v is not None:
            self.pars.globals[name] = v
            self.readonly_named.add(name)
        return v

    def store_named(self, name: str, value: float) -> None:
        if name in self.readonly_named or (
                name in PREDEFINED and name not in ("_value", "_value_returned")):
            raise NgcError("named_parameter_readonly", name=name)
        self.pars.store_named(name, value)

    def finding(self, exc: NgcError) -> Finding:
        prog = self.prog
        if prog is None or not prog.raw:
            src = SourceRef(self.path, 1, 1, "")
        else:
            i = min(self.index, len(prog.raw) - 1)
            src = prog.ref(i, exc.column or 1)
        return error(exc.kind, exc.message, src)


def _nlabel(line: Line) -> str:
    line.nlabel = n_label(line.raw)
    return line.nlabel


def _pocket(it, index: int) -> float:
    """The pocket (P of the tool table) of a tool table index; -1 for none."""
    return it.tools.entry(index).pocket if index > 0 else -1


def _abs(axis: int):
    """#<_abs_x>..#<_abs_c>: the position in machine coordinates, in program units
    (interp_namedparams.cc NP_ABS_X..)."""

    def value(it) -> float:
        s = it.s
        p = s.pos[axis] + s.axis_offset[axis]
        if axis < 2:
            x, y = rotate(s.pos[0] + s.axis_offset[0], s.pos[1] + s.axis_offset[1], s.rotation)
            p = x if axis == 0 else y
        return p + s.origin[axis] + s.tool_offset[axis]

    return value


def _coord_system(it) -> float:
    i = it.s.origin_index
    return (530 + 10 * i) if i <= 6 else (590 + i - 6)


PREDEFINED = {
    "_vmajor": lambda it: 2.9,
    "_vminor": lambda it: 0.0,
    "_line": lambda it: it.index + 1,
    "_motion_mode": lambda it: it.s.motion,
    "_plane": lambda it: it.s.plane,
    "_ccomp": lambda it: (400, 410, 420)[it.s.comp_side],
    "_metric": lambda it: it.s.metric,
    "_imperial": lambda it: not it.s.metric,
    "_absolute": lambda it: not it.s.incremental,
    "_incremental": lambda it: it.s.incremental,
    "_inverse_time": lambda it: it.s.feed_mode == 1,
    "_units_per_minute": lambda it: it.s.feed_mode == 0,
    "_units_per_rev": lambda it: it.s.feed_mode == 2,
    "_coord_system": _coord_system,
    "_tool_offset": lambda it: any(it.s.tool_offset),
    "_retract_r_plane": lambda it: it.s.retract_r,
    "_retract_old_z": lambda it: not it.s.retract_r,
    "_spindle_rpm_mode": lambda it: 1,
    "_spindle_css_mode": lambda it: 0,
    "_ijk_absolute_mode": lambda it: it.s.ijk_absolute,
    "_lathe_diameter_mode": lambda it: it.s.diameter_mode,
    "_lathe_radius_mode": lambda it: not it.s.diameter_mode,
    "_spindle_on": lambda it: it.s.spindle != "stop",
    "_spindle_cw": lambda it: it.s.spindle == "cw",
    "_mist": lambda it: it.s.mist,
    "_flood": lambda it: it.s.flood,
    "_speed_override": lambda it: it.s.speed_override,
    "_feed_override": lambda it: it.s.feed_override,
    "_adaptive_feed": lambda it: 0,
    "_feed_hold": lambda it: 0,
    "_feed": lambda it: it.s.feed,
    "_rpm": lambda it: it.s.speed,
    "_x": lambda it: it.s.pos[0],
    "_y": lambda it: it.s.pos[1],
    "_z": lambda it: it.s.pos[2],
    "_a": lambda it: it.s.pos[3],
    "_b": lambda it: it.s.pos[4],
    "_c": lambda it: it.s.pos[5],
    **{"_abs_" + "xyzabc"[i]: _abs(i) for i in range(6)},
    "_current_tool": lambda it: it.tools.spindle.number,
    "_current_pocket": lambda it: _pocket(it, it.s.current_pocket),
    "_selected_tool": lambda it: it.s.selected_tool,
    "_selected_pocket": lambda it: _pocket(it, it.s.selected_pocket) if it.s.t_seen else -1,
    "_value": lambda it: 0.0,
    "_value_returned": lambda it: 0.0,
    "_task": lambda it: 0,
    "_call_level": lambda it: len(it.frames) - 1,
    "_remap_level": lambda it: 0,
}
