"""The virtual NCK: the control state a program reads and writes through system variables.

One object per run, fed by the machine model through :class:`vmach.canon.ControlSpec`
(``machine_data``: machine, setting, swivel and PLC data) and :class:`vmach.canon.RunOptions`
(``tool_data``), and by the interpreter's own state (:class:`execute.Machine`). One handler per
kind of variable (see ``sysvars.toml``):

- ``machine_data``, ``setting_data``, ``swivel``: the model's value; one the model does not give
  reads as the documented default with an ``info`` finding (``machine_data_default``) naming it,
  once per variable. Setting and swivel data may be written; the value written is read back.
- ``plc``: PLC data and I/O read zero unless the model gives a value; every write is recorded in
  the trace (:class:`vmach.canon.SetVariable`).
- ``program``: modal state (``$P_GG``), tool, feed, spindle, end point; a run is never a block
  search, test or dry run (``$P_SEARCH``, ``$P_ISTEST``, ``$P_DRYRUN`` read 0).
- ``frame``: settable frames ``$P_UIFR[n]`` (n = 0 G500, 1..4 G54..G57, 5..99 G505..G599) start
  from the model's zero offsets, are written with frame functions and take effect when their
  G code is next programmed (as on the control); the active frames read back.
- ``main_run``: the interpreter runs without lag, so actual values (``$AA_IM`` machine, ``$AA_IW``
  work) are the programmed end points, ``$AC_TIME`` is 0; ``$AC_MARKER`` and ``$AC_PARAM`` hold
  what was written; ``$AC_TIMER`` and the run times follow the estimated machining time
  (``nckclock.py``).
- ``tool``: ``$TC_DPk[T, D]`` and ``$TC_TPk[T]`` from the tool library; writes override it, and a
  written radius (``$TC_DP6``) is the one tool radius compensation uses.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from interpreters.sinumerik import nckclock, sysframes
from interpreters.sinumerik.expr import EvalError
from interpreters.sinumerik.frames import Matrix
from interpreters.sinumerik.nckclock import Clock
from interpreters.sinumerik.sysframes import SETTABLE, Frame, settable_code, settable_index
from interpreters.sinumerik.sysvars import CATALOG, GROUPS, SysVar, lookup
from vmach import canon
from vmach.canon import ControlSpec, RunOptions
from vmach.findings import Finding, info
from vmach.source import SourceRef

INCH = 25.4
#: library tool kind -> $TC_DP1 tool type (Sinumerik tool type numbers)
TOOL_TYPES = {"flat": 120, "face": 140, "ball": 110, "bull": 121, "chamfer": 155, "drill": 200}
#: $P_GG for a group vmach does not keep: its first code, the control's usual reset value
UNTRACKED_GROUP = 1
LOOSE_AXIS = re.compile(r"^[ABCUVWXYZ]\d*$")
#: a machine axis name as the control's MD 10000 gives them by default: the channel axis's
#: letters and a number (X1, Z1); vmach's models name each machine axis as its channel axis
MACHINE_AXIS = re.compile(r"^([A-Z]+)\d+$")


class Nck:
    """The state object; ``src`` is the block being compiled (set by ``compile_block``), so a
    finding or a recorded write names the line that reads or writes."""

    def __init__(self, control: ControlSpec, machine: Any, options: RunOptions, findings: list[Finding],
                 depth: Callable[[], int] | None = None, passed: Callable[[int], bool] | None = None):
        self.control = control
        self.machine = machine
        self.options = options
        self.findings = findings
        self.depth = depth or (lambda: 0)
        self.passed = passed or (lambda n: False)
        self.md = control.machine_data
        self.src = SourceRef("<program>", 1)
        self.written: dict[tuple[str, Any], Any] = {}
        self.unknowns: dict[str, Any] = {}    # written by a synchronised action (syncact.py)
        self.plc_reads: dict[tuple, int] = {}   # (name, index) -> reads of PLC data and inputs
        self.noted: set[str] = set()
        self.uifr: dict[int, Frame] = {}
        self.ifr: Frame = sysframes.NEUTRAL      # the active settable frame ($P_IFRAME)
        for code, offsets in control.zero_offsets.items():
            if code in SETTABLE or (code[1:].isdigit() and 505 <= int(code[1:]) <= 599):
                self.uifr[settable_index(code)] = Frame(tr=dict(offsets))
        self.library_radius = options.tool_radius
        rapid = self.md.get("$MA_MAX_AX_VELO", {})
        self.clock = Clock(machine.out, machine.pos, rapid if isinstance(rapid, dict) else {},
                           machine.geometry, machine.master)
        self.timers: dict[int, tuple[float, float | None]] = {}   # n -> (value, started at s)
        self.read_kind = {
            "machine_data": self._data, "setting_data": self._data, "swivel": self._data,
            "plc": self._plc, "program": self._program, "frame": self._frame,
            "main_run": self._main_run, "tool": self._tool,
        }
        self.programs: dict[str, Callable[[SysVar, tuple], Any]] = {
            "$P_GG": self._gg, "$P_TOOL": lambda v, i: machine.edge,
            "$P_TOOLNO": lambda v, i: _tool_number(machine.tool),
            "$P_TOOLR": lambda v, i: self._active_radius(),
            "$P_EP": lambda v, i: self._modulo(i[0], self._work(i[0])), "$P_F": lambda v, i: self._feed(),
            "$P_S": lambda v, i: machine.spindles.get(i[0] if i else machine.master, [0.0])[0],
            "$P_SEARCH": _zero, "$P_PROG_EVENT": _zero, "$P_DRYRUN": _zero, "$P_ISTEST": _zero,
            "$P_SEARCHL": _zero,
            "$P_SUBPAR": lambda v, i: int(self.passed(i[0])),
            "$P_AXN1": lambda v, i: machine.geometry[0], "$P_AXN2": lambda v, i: machine.geometry[1],
            "$P_AXN3": lambda v, i: machine.geometry[2], "$P_MSNUM": lambda v, i: machine.master,
            "$P_MC": lambda v, i: int(machine.mcall is not None), "$P_SMODE": lambda v, i: 1,
            "$P_CHANNO": lambda v, i: 1, "$P_STACK": lambda v, i: self.depth(),
            "$P_TRAFO": _zero, "$P_UIFRNUM": lambda v, i: settable_index(machine.offset_code),
            "$P_TOOLP": lambda v, i: _tool_number(machine.tool),
            "$P_TOOLL": lambda v, i: self._active_dp(2 + i[0]) if 1 <= i[0] <= 3 else 0.0,
            "$P_AD": lambda v, i: self._active_dp(i[0]),
            "$P_NUM_SPINDLES": lambda v, i: len(machine.spindles),
            "$P_TOOLEXIST": lambda v, i: int(self._edges(i[0]) > 0),
            "$P_TOOLND": lambda v, i: self._edges(i[0]),
        }

    # -- compiling: closures for a read and a write -------------------------------------------
    def reader(self, name: str, fs: list[Callable[[], Any]], col: int) -> Callable[[], Any]:
        var = lookup(name)
        src = self.src.at(col)
        read = self.read_kind[var.kind]
        shape = var.shape(len(fs))
        if not fs:
            return lambda: read(var, (), src)
        return lambda: read(var, self.index(var, shape, [f() for f in fs]), src)

    def writer(self, name: str, fs: list[Callable[[], Any]], col: int) -> Callable[[Any], None]:
        var = lookup(name)
        src = self.src.at(col)
        shape = var.shape(len(fs))

        def write(value):
            idx = self.index(var, shape, [f() for f in fs]) if fs else ()
            self.store(var, idx, value, src)

        return write

    def frame_function(self, name: str, fs: list[Callable[[], Any]]) -> Callable[[], Frame]:
        m = self.machine
        if name == "CRPL":
            return lambda: sysframes.crpl([f() for f in fs], m.geometry, m.plane_axes[2])
        return lambda: sysframes.make(name, [f() for f in fs], m.geometry)

    def chain(self, a: Any, b: Any) -> Frame:
        return sysframes.chain(a, b, self.machine.geometry)

    # -- indices ----------------------------------------------------------------------------
    def index(self, var: SysVar, shape: tuple[str, ...] | None, values: list) -> tuple:
        out = []
        for kind, v in zip(shape or (), values, strict=False):
            if kind == "axis":
                out.append(self.axis(v, var.name))
            elif kind == "any":
                out.append(self._any_index(v))
            elif kind == "comp":
                c = str(v).upper()
                if c not in sysframes.COMPONENTS:
                    raise EvalError("index_range", f"{var.name}: {v} is no frame component "
                                    f"({', '.join(sysframes.COMPONENTS)})")
                out.append(c)
            else:
                if isinstance(v, str) or v != int(v) or v < 0:
                    raise EvalError("index_range", f"{var.name}[{v}]: the index is a whole number ≥ 0")
                out.append(int(v))
        return tuple(out)

    def _any_index(self, v: Any) -> Any:
        """An index of a datum vmach does not list: an axis name if it names one, else the
        name or the whole number as written."""
        if isinstance(v, str):
            a = v.upper()
            try:
                return self.axis(a, "")
            except EvalError:
                return a
        return int(v) if v == int(v) else v

    def axis(self, v: Any, what: str) -> str:
        """An axis index: a name (``X``, ``AX2``) or a machine axis number (1-based)."""
        names = self.machine.names
        if isinstance(v, str):
            a = v.upper()
            if a in self.machine.specs:
                return a
            if a.startswith("AX") and a[2:].isdigit() and 1 <= int(a[2:]) <= len(names):
                return names[int(a[2:]) - 1]
            if a.startswith("SP") and a[2:].isdigit() and int(a[2:]) in self.control.spindles:
                return a                # a spindle as a machine axis (SPI(1) = SP1)
            if (m := MACHINE_AXIS.match(a)) and m.group(1) in self.machine.specs:
                return m.group(1)       # the machine axis X1 of channel axis X (MD 10000's names)
            if not self.control.strict_axes and LOOSE_AXIS.match(a):
                return a            # no machine given: any axis letter is an axis (as in words)
            raise EvalError("unknown_axis", f"{what}[{v}]: {v} is not an axis of this machine")
        if v == int(v) and 1 <= v <= len(names):
            return names[int(v) - 1]
        raise EvalError("unknown_axis", f"{what}[{v}]: the machine has no axis number {v}")

    # -- one handler per kind -----------------------------------------------------------------
    def _data(self, var: SysVar, idx: tuple, src: SourceRef) -> Any:
        key = idx[0] if len(idx) == 1 else idx
        got = self.written.get((var.name, key), _MISSING)
        if got is not _MISSING:
            return got
        table = self.md.get(var.name, _MISSING)
        if table is not _MISSING:
            if not idx and not isinstance(table, dict):
                return table
            if isinstance(table, dict) and key in table:
                return table[key]
        if var.default is None:   # not in vmach's list: only the model can give it
            where = f"{var.name}[{', '.join(map(str, idx))}]" if idx else var.name
            raise EvalError("unsupported", f"{where}: vmach has no default for this machine or setting "
                            "datum; give it in the model's [machine_data]")
        if var.kind != "plc" and var.name not in self.noted:
            self.noted.add(var.name)
            where = f"{var.name}[{', '.join(map(str, idx))}]" if idx else var.name
            md = f" (MD {var.md})" if var.md else ""
            self.findings.append(info("machine_data_default", f"{where}{md} is not in the machine model's "
                                      f"[machine_data]; read as the control's default {var.default!r}",
                                      src, name=var.name))
        return var.default

    def _edges(self, tool: int) -> int:
        """The cutting edges D1, D2 … the run's tool library gives tool number ``tool`` (0 when
        the library does not hold it, or no library was given)."""
        lookup = self.options.tool_data
        if lookup is None or tool <= 0:
            return 0
        n = 0
        while n < 12 and lookup(str(tool), n + 1) is not None:
            n += 1
        return n

    def _plc(self, var: SysVar, idx: tuple, src: SourceRef) -> Any:
        key = (var.name, idx)
        self.plc_reads[key] = self.plc_reads.get(key, 0) + 1
        return self._data(var, idx, src)

    def waited_on(self, blocks: int) -> tuple[str, int] | None:
        """(name, reads) of the PLC datum or input the program read most, when it read it in
        at least one block of 20 of the ``blocks`` run: a program that waits for the PLC or an
        input (``WHILE $A_DBB[11]==0``), which on vmach never changes."""
        if not self.plc_reads:
            return None
        (name, idx), count = max(self.plc_reads.items(), key=lambda kv: kv[1])
        if count * 20 < blocks:
            return None
        return (f"{name}[{', '.join(map(str, idx))}]" if idx else name), count

    def _program(self, var: SysVar, idx: tuple, src: SourceRef) -> Any:
        return self.programs[var.name](var, idx)

    def _main_run(self, var: SysVar, idx: tuple, src: SourceRef) -> Any:
        name = var.name
        if name == "$AC_F":
            return self._feed()
        if name == "$AA_IM" or name == "$VA_IM":
            return self._modulo(idx[0], self.machine.pos.get(idx[0], 0.0))
        if name == "$AA_IW":
            return self._modulo(idx[0], self._work(idx[0]))
        if name in ("$AC_SGEAR", "$AA_SCPAR"):
            return 1                # gear stage / parameter set 1: vmach models no gears
        if name == "$AA_S":        # actual speed: the programmed one, 0 while stopped
            speed, state = self.machine.spindles.get(idx[0] if idx else self.machine.master, (0.0, "stop"))
            return speed if state != "stop" else 0.0
        if name == "$AC_MSNUM":
            return self.machine.master
        if name in ("$AC_CYCLE_TIME", "$AC_OPERATING_TIME"):
            return self.clock.read()
        if name in nckclock.CALENDAR:
            return nckclock.calendar(name, self.clock.read())
        if name in nckclock.POWER_ON:
            return self.clock.read() / 60.0
        if name == "$AC_CUTTING_TIME":
            self.clock.now()
            return self.clock.cutting
        if name == "$AC_TIMER":
            value, since = self.timers.get(idx[0], (0.0, None))
            return value if since is None else value + self.clock.read() - since
        got = self.written.get((name, idx[0] if idx else ()), _MISSING)
        if got is not _MISSING:
            return got
        return self.unknowns.get(name, var.default)

    def unknown(self, name: str, value: Any) -> None:
        """Every element of ``name`` (``$AC_MARKER``) holds ``value`` (a ``syncact.Unknown``:
        a synchronised action may write it) until the program writes the element anew."""
        self.written = {k: v for k, v in self.written.items() if k[0] != name}
        self.unknowns[name] = value

    def _tool(self, var: SysVar, idx: tuple, src: SourceRef) -> Any:
        got = self.written.get((var.name, idx), _MISSING)
        if got is not _MISSING:
            return got
        k = int(var.name[6:])
        lookup = self.options.tool_data
        if var.name.startswith("$TC_TP"):
            data = lookup(str(idx[0]), 1) if lookup else None
            if data is None:
                return var.default
            return {1: 1, 2: data.get("name", str(idx[0])), 3: 1, 4: 1, 5: 1, 6: 1, 7: 1}.get(k, var.default)
        data = lookup(str(idx[0]), idx[1]) if lookup else None
        if data is None:
            return var.default
        return {1: TOOL_TYPES.get(str(data.get("type")), 120), 3: data.get("length", 0.0),
                6: data.get("radius", 0.0)}.get(k, var.default)

    def _frame(self, var: SysVar, idx: tuple, src: SourceRef) -> Any:
        name = var.name
        if name == "$P_BFRAME":                   # vmach models no basic frame
            frame = sysframes.NEUTRAL
        elif name == "$P_UIFR":
            frame = self._uifr(idx[0])
            idx = idx[1:]
        elif name == "$P_IFRAME":
            frame = self.ifr
        else:
            fr = self.machine.frames
            frame = sysframes.from_state(fr.trans, fr.rot, self.machine.geometry)
            if name == "$P_ACTFRAME":
                frame = self.chain(self.ifr, frame)
        return frame.get(idx[0], idx[1]) if idx else frame

    def _uifr(self, n: int) -> Frame:
        if settable_code(n) is None:
            raise EvalError("index_range", f"$P_UIFR[{n}] is outside 0..99")
        return self.uifr.get(n, sysframes.NEUTRAL)

    # -- writes ---------------------------------------------------------------------------------
    def store(self, var: SysVar, idx: tuple, value: Any, src: SourceRef) -> None:
        if var.name == "$P_PFRAME":
            self._set_pframe(value, idx, src)
            return
        if var.name == "$P_IFRAME":                # the active settable frame, at once
            frame = self.ifr.with_component(idx[0], idx[1], _real(value, var.name)) if idx else value
            if not isinstance(frame, Frame):
                raise EvalError("type_error", "$P_IFRAME takes a frame (CTRANS(...) ...)")
            self.machine.frames.set_settable(*self._activate(frame))
            self.machine.emit_frame(src)
            return
        if var.kind == "frame":                   # $P_UIFR
            if len(idx) == 1:
                if not isinstance(value, Frame):
                    raise EvalError("type_error", f"$P_UIFR[{idx[0]}] takes a frame (CTRANS(...) ...)")
                self._uifr(idx[0])
                self.uifr[idx[0]] = value
            else:
                self.uifr[idx[0]] = self._uifr(idx[0]).with_component(idx[1], idx[2], _real(value, var.name))
            return
        value = _convert(var, value)
        if var.kind == "tool":
            self.written[(var.name, idx)] = value
            if var.name == "$TC_DP6" and self.machine.tool_radius_of is None:
                self.machine.tool_radius_of = self.tool_radius
            return
        if var.name == "$AC_TIMER":   # a value >= 0 starts the timer there, a negative one stops it
            self.timers[idx[0]] = (value, self.clock.now() if value >= 0 else None)
            return
        key = idx[0] if len(idx) == 1 else idx
        self.written[(var.name, key)] = value
        if var.kind == "plc":
            text = f"{var.name}[{', '.join(map(str, idx))}]" if idx else var.name
            self.machine.sink.append(canon.SetVariable(src, name=text, value=value))

    def _set_pframe(self, value: Any, idx: tuple, src: SourceRef) -> None:
        """``$P_PFRAME = frame`` (or one component): the programmable frame, as TRANS/ROT ... set
        it (``Frames``: machine = settable + t + R·p)."""
        m = self.machine
        if idx:
            fr = m.frames
            value = sysframes.from_state(fr.trans, fr.rot, m.geometry).with_component(
                idx[0], idx[1], _real(value, "$P_PFRAME"))
        if not isinstance(value, Frame):
            raise EvalError("type_error", "$P_PFRAME takes a frame (CTRANS(...) ...)")
        m.frames.trans = value.offsets()
        m.frames.rot = value.linear(m.geometry)
        m.frames.refresh()
        m.emit_frame(src)
        m.refresh_plain()

    # -- what other parts of the interpreter ask ----------------------------------------------
    def settable_frame(self, code: str) -> tuple[dict[str, float], Matrix]:
        """Translations and linear part of the settable frame G500/G54... selects (for
        ``Frames.set_settable``)."""
        return self._activate(self.uifr.get(settable_index(code), sysframes.NEUTRAL))

    def _activate(self, frame: Frame) -> tuple[dict[str, float], Matrix]:
        self.ifr = frame
        return frame.offsets(), frame.linear(self.machine.geometry)

    def tool_radius(self, tool: str, d: int) -> float | None:
        """Tool radius for compensation: a written ``$TC_DP6`` first, else the library's."""
        number = _tool_number(tool)
        got = self.written.get(("$TC_DP6", (number, d)), _MISSING) if number else _MISSING
        if got is not _MISSING:
            return got
        return self.library_radius(tool, d) if self.library_radius is not None else None

    # -- state in program units ------------------------------------------------------------------
    def _work(self, axis: str) -> float:
        m = self.machine
        if axis in m.geometry and m.frames.rotated:
            p = m.frames.to_program(tuple(m.pos.get(a, 0.0) for a in m.geometry))
            v = p[m.geometry.index(axis)]
        else:
            v = m.pos.get(axis, 0.0) - m.frames.offset(axis)
        spec = m.specs.get(axis)
        if spec is not None and spec.kind == "linear":
            if m.diameter and axis == self.control.transverse:
                v *= 2.0
            if m.inch:
                v /= INCH
        return v

    def _modulo(self, axis: str, value: float) -> float:
        """An actual value as the control shows it: within 0 ≤ v < 360 on a modulo rotary axis
        (vmach's own values are unwrapped)."""
        spec = self.machine.specs.get(axis)
        if spec is None or spec.modulo is None:
            return value
        v = math.fmod(value, spec.modulo)
        return v + spec.modulo if v < 0 else v + 0.0

    def _feed(self) -> float:
        return self.machine.feed / INCH if self.machine.inch else self.machine.feed

    def _active_radius(self) -> float:
        m = self.machine
        if m.tool is None or m.tool_radius_of is None or not m.edge:
            return 0.0
        r = m.tool_radius_of(m.tool, m.edge)
        return float(r) if r is not None else 0.0

    def _active_dp(self, k: int) -> Any:
        """``$TC_DP<k>`` of the active tool and D number (0 without one)."""
        m = self.machine
        number = _tool_number(m.tool)
        if not number or not m.edge or not 1 <= k <= 25:
            return 0.0
        return self._tool(CATALOG[f"$TC_DP{k}"], (number, m.edge), self.src)

    def _gg(self, var: SysVar, idx: tuple) -> int:
        group = idx[0]
        m = self.machine
        current = {
            1: m.motion, 6: m.plane, 7: ("G40", "G41", "G42")[(0, 1, -1).index(m.cutcom.side)],
            8: m.offset_code, 10: m.path_mode, 13: "G70" if m.inch else "G71",
            14: "G90" if m.absolute else "G91",
            15: {"inverse_time": "G93", "per_minute": "G94", "per_rev": "G95"}.get(m.feed_mode, "G94"),
            29: "DIAM90" if m.diam90 else ("DIAMON" if m.diameter else "DIAMOF"),
        }.get(group)
        codes = GROUPS.get(group)
        if current is None or codes is None or current not in codes:
            if not 1 <= group <= 65:
                raise EvalError("index_range", f"$P_GG[{group}]: G groups are 1..65")
            return UNTRACKED_GROUP
        return codes.index(current) + 1


_MISSING = object()


def _zero(var, idx) -> int:
    return 0


def _tool_number(tool: Any) -> int:
    if tool is None:
        return 0
    text = str(tool).strip()
    return int(text) if text.isdigit() else 0


def _real(v: Any, name: str) -> float:
    if isinstance(v, str) or not hasattr(v, "__float__"):
        raise EvalError("type_error", f"{name} takes a number, not {v!r}")
    return float(v)


def _convert(var: SysVar, v: Any) -> Any:
    """A written value in the variable's type (REAL → INT rounds, as assignments do)."""
    if var.type in ("STRING", "AXIS"):
        if not isinstance(v, str):
            raise EvalError("type_error", f"{var.name} is {var.type}; it takes a string, not {v!r}")
        return v
    x = _real(v, var.name)
    if not math.isfinite(x):
        raise EvalError("domain_error", f"{var.name}: not a finite number")
    if var.type == "INT":
        return int(x + 0.5) if x >= 0 else -int(-x + 0.5)
    if var.type == "BOOL":
        return int(bool(x))
    return x
