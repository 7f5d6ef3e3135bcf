# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""The canonical calls the interpreter makes, written two ways.

1. The trace LinuxCNC's standalone interpreter ``rs274 -g`` prints: one line per call with an
   output counter, the N column and the call with ``%.4f`` numbers in *program* units
   (saicanon.cc's formats).
2. vmach's canonical commands (:mod:`vmach.canon`): mm, machine-axis values after the work
   offsets (G54.., G92, XY rotation) are applied, each with its :class:`SourceRef`.

The class keeps the small model of the machine that both need (units, offsets, motion
control mode, spindle, coolant), as saicanon.cc keeps its "dummy world".
"""

from __future__ import annotations

import dataclasses
import math
from types import MemberDescriptorType

from vmach import canon as vc
from vmach.source import SourceRef

PLANE_NAMES = {170: "XY", 180: "XZ", 190: "YZ"}
#: (first, second, normal) axes of the arc plane for vmach.canon.ArcFeed
PLANE_AXES = {170: ("X", "Y", "Z"), 180: ("Z", "X", "Y"), 190: ("Y", "Z", "X")}
_LETTERS = "XYZABC"


class Deferred:
    """A canonical call held back by cutter radius compensation (LinuxCNC's ``enqueue_*``)."""

    __slots__ = ("call", "args", "src")

    def __init__(self, call, args: tuple, src: SourceRef):
        self.call = call
        self.args = args
        self.src = src

    def emit(self, out: Output) -> None:
        self.call(*self.args)


def _slot_setters(cls, names: tuple[str, ...]):
    """The slot setters of a frozen, slotted dataclass whose fields are exactly ``names``,
    in order, so that ``object.__new__(cls)`` and the setters build what ``cls(*values)``
    builds, without the frozen ``__init__``'s ``object.__setattr__`` per field (a third of
    the time). None when the class has other fields, a ``__post_init__`` or no slots: then
    the caller uses the constructor."""
    if not dataclasses.is_dataclass(cls) or hasattr(cls, "__post_init__"):
        return None
    if tuple(f.name for f in dataclasses.fields(cls)) != names:
        return None
    slots = [getattr(cls, name, None) for name in names]
    if not all(type(slot) is MemberDescriptorType for slot in slots):
        return None
    return tuple(slot.__set__ for slot in slots)


SOURCE_SETTERS = _slot_setters(SourceRef, ("path", "line", "column", "text"))
FEED_SETTERS = _slot_setters(vc.LinearFeed, ("source", "axes", "feed"))
TRAVERSE_SETTERS = _slot_setters(vc.Traverse, ("source", "axes"))


def _feed_maker():
    if FEED_SETTERS is None:
        return vc.LinearFeed
    new = object.__new__
    cls = vc.LinearFeed
    set_source, set_axes, set_feed = FEED_SETTERS

    def make(source: SourceRef, axes: dict[str, float], feed: float) -> vc.LinearFeed:
        cmd = new(cls)
        set_source(cmd, source)
        set_axes(cmd, axes)
        set_feed(cmd, feed)
        return cmd

    return make


def _traverse_maker():
    if TRAVERSE_SETTERS is None:
        return vc.Traverse
    new = object.__new__
    cls = vc.Traverse
    set_source, set_axes = TRAVERSE_SETTERS

    def make(source: SourceRef, axes: dict[str, float]) -> vc.Traverse:
        cmd = new(cls)
        set_source(cmd, source)
        set_axes(cmd, axes)
        return cmd

    return make


#: ``vc.LinearFeed(source, axes, feed)`` and ``vc.Traverse(source, axes)``, built faster
new_feed = _feed_maker()
new_traverse = _traverse_maker()
_FEED_TRACE = "%5d %sSTRAIGHT_FEED(%.4f, %.4f, %.4f, %.4f, %.4f, %.4f)"
_TRAVERSE_TRACE = "%5d %sSTRAIGHT_TRAVERSE(%.4f, %.4f, %.4f, %.4f, %.4f, %.4f)"


class Output:
    """Receives canonical calls; collects trace lines and/or vmach commands.

    trace : keep the rs274 trace lines in :attr:`lines`.
    commands : keep vmach canonical commands in :attr:`commands`.
    axes : machine axis names in model order (from the ControlSpec) with their home values.
    """

    def __init__(self, trace: bool, commands: bool, axes: dict[str, float]):
        self.trace = trace
        self.want = commands
        self.lines: list[str] = []
        self.commands: list[vc.Command] = vc.CommandList()  # held to tol.max_commands
        self.count = 0
        self.nlabel = "N..... "
        self.src = SourceRef("<init>", 1)
        self.axes = dict(axes)
        self._xyz = list(self.axes) == ["X", "Y", "Z"]
        #: rotary axes (A B C) a non-strict control accepts; they join the canonical axes
        #: from the first time the program moves them
        self.extra_axes: set[str] = set()
        self.extra_used: set[str] = set()
        # world model (saicanon): its idea of the position, in program units, knows
        # nothing of rotation or tool offsets; the interpreter re-reads it after M6/M61
        self.ppos = [0.0] * 6
        self.unit = 1.0  # mm per program unit
        self.g5x = [0.0] * 6
        self.g92 = [0.0] * 6
        self.abc_zero = True
        self.rotation = 0.0
        self.mode = "continuous"
        self.tolerance = 0.0
        self.naivecam = 0.0
        self.speed = 0.0
        self.direction = "stop"
        self.mist = False
        self.flood = False
        # what the canonical stream last said, per kind of state: state commands are
        # emitted when the state changes, spindle changes once per block (S and M3 together)
        self.said: dict[str, object] = {
            "plane": 170, "feed_mode": "per_minute", "coolant": "off",
            "spindle": (0.0, "stop"), "frame": ((0.0,) * 6, 0.0, 1.0),
        }
        self.spindle_dirty = False
        #: calls waiting behind a move cutter radius compensation holds back (LinuxCNC's
        #: queue of canonical calls, emptied by ``CompMixin.dequeue``): while it is not
        #: empty, comments, feed, dwell, coolant and spindle calls wait in it too
        self.queue: list = []

    # -- plumbing -------------------------------------------------------------------------

    def _p(self, body: str) -> None:
        self.count += 1
        self.lines.append(f"{self.count:5d} {self.nlabel}{body}")

    def _defer(self, call, *args) -> None:
        """Hold a call back behind the queued moves (see :attr:`queue`)."""
        self.queue.append(Deferred(call, args, self.src))

    def _c(self, cmd: vc.Command) -> None:
        if self.spindle_dirty:
            self.flush()
        self.commands.append(cmd)

    def flush(self) -> None:
        """Emit a pending spindle change (called at the end of every block)."""
        self.spindle_dirty = False
        state = (self.speed, self.direction)
        if self.want and self.said["spindle"] != state:
            self.said["spindle"] = state
            self.commands.append(vc.Spindle(self.src, spindle=1, speed=self.speed,
                                            direction=self.direction))

    def machine(self, p) -> dict[str, float]:
        """Program coordinates (x y z a b c) -> machine axis values in mm / degrees."""
        u = self.unit
        g92 = self.g92
        g5x = self.g5x
        x = p[0] + g92[0]
        y = p[1] + g92[1]
        if self.rotation:
            t = math.radians(self.rotation)
            x, y = x * math.cos(t) - y * math.sin(t), x * math.sin(t) + y * math.cos(t)
        if self._xyz and not self.extra_used and not (p[3] or p[4] or p[5]) and self.abc_zero:
            return {"X": (x + g5x[0]) * u, "Y": (y + g5x[1]) * u,
                    "Z": (p[2] + g92[2] + g5x[2]) * u}
        out = dict(self.axes)
        out["X"] = (x + g5x[0]) * u
        out["Y"] = (y + g5x[1]) * u
        out["Z"] = (p[2] + g92[2] + g5x[2]) * u
        for i in (3, 4, 5):
            name = _LETTERS[i]
            if name in out or (name in self.extra_axes and p[i] + g92[i] + g5x[i] != 0.0):
                out[name] = p[i] + g92[i] + g5x[i]
                self.extra_used.add(name)
            elif name in self.extra_used:
                out[name] = p[i] + g92[i] + g5x[i]
        return out

    def _frame(self) -> None:
        if not self.want:
            return
        origin = self.machine([0.0] * 6)
        key = (tuple(origin.get(a, 0.0) for a in _LETTERS), self.rotation, self.unit)
        if self.said["frame"][:2] == key[:2]:
            return
        self.said["frame"] = key
        t = math.radians(self.rotation)
        c, s = math.cos(t), math.sin(t)
        self._c(vc.SetFrame(self.src, origin=origin,
                            rotation=(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)))

    # -- setup calls ----------------------------------------------------------------------

    def use_length_units(self, metric: bool) -> None:
        if self.trace:
            self._p("USE_LENGTH_UNITS(CANON_UNITS_MM)" if metric else
                    "USE_LENGTH_UNITS(CANON_UNITS_INCHES)")
        new = 1.0 if metric else 25.4
        if new != self.unit:
            f = self.unit / new
            self.ppos = [v * f if i < 3 else v for i, v in enumerate(self.ppos)]
            self.g5x = [v * f if i < 3 else v for i, v in enumerate(self.g5x)]
            self.g92 = [v * f if i < 3 else v for i, v in enumerate(self.g92)]
            self.unit = new

    def set_g5x_offset(self, index: int, v) -> None:
        if self.trace:
            self._p("SET_G5X_OFFSET(%d, %.4f, %.4f, %.4f, %.4f, %.4f, %.4f)" % (index, *v[:6]))
        self.ppos = [self.ppos[i] + self.g5x[i] - v[i] for i in range(6)]
        self.g5x = list(v[:6])
        self.abc_zero = not any(self.g5x[3:]) and not any(self.g92[3:])
        self._frame()

    def set_g92_offset(self, v) -> None:
        if self.trace:
            self._p("SET_G92_OFFSET(%.4f, %.4f, %.4f, %.4f, %.4f, %.4f)" % tuple(v[:6]))
        self.ppos = [self.ppos[i] + self.g92[i] - v[i] for i in range(6)]
        self.g92 = list(v[:6])
        self.abc_zero = not any(self.g5x[3:]) and not any(self.g92[3:])
        self._frame()

    def set_xy_rotation(self, r: float) -> None:
        if self.trace:
            self._p("SET_XY_ROTATION(%.4f)" % r)
        changed = r != self.rotation
        self.rotation = r
        if changed:
            self._frame()

    def simple(self, name: str) -> None:
        """A call without arguments and without effect on vmach commands."""
        if self.trace:
            self._p(name + "()")

    def set_feed_reference(self) -> None:
        if self.trace:
            self._p("SET_FEED_REFERENCE(CANON_XYZ)")

    def comment(self, text: str, program: bool = False) -> None:
        if self.queue:
            return self._defer(self.comment, text, program)
        if self.trace:
            self._p('COMMENT("%s")' % text)
        if program and self.want:
            self._c(vc.Comment(self.src, text=text))

    def message(self, text: str) -> None:
        if self.trace:
            self._p('MESSAGE("%s")' % text)
        if self.want:
            self._c(vc.Message(self.src, text=text))

    def print_text(self, text: str) -> None:
        """(PRINT,...) goes straight to rs274's stdout, without a counter."""
        if self.trace:
            self.lines.append(text)

    def select_plane(self, plane: int) -> None:
        if self.trace:
            self._p("SELECT_PLANE(CANON_PLANE_%s)" % PLANE_NAMES[plane])
        if self.want and self.said["plane"] != plane:
            self.said["plane"] = plane
            self._c(vc.PlaneSelect(self.src, plane=PLANE_AXES[plane]))

    def set_feed_mode(self, mode: int, interp_mode: int) -> None:
        if self.queue:
            return self._defer(self.set_feed_mode, mode, interp_mode)
        if self.trace:
            self._p("SET_FEED_MODE(0, %d)" % mode)
        name = ("per_minute", "inverse_time", "per_rev")[interp_mode]
        if self.want and self.said["feed_mode"] != name:
            self.said["feed_mode"] = name
            self._c(vc.FeedMode(self.src, mode=name))

    def set_feed_rate(self, rate: float) -> None:
        if self.queue:
            return self._defer(self.set_feed_rate, rate)
        if self.trace:
            self._p("SET_FEED_RATE(%.4f)" % rate)

    def set_motion_control_mode(self, mode: str, tolerance: float = 0.0) -> None:
        if self.trace:
            if mode == "continuous":
                self._p("SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, %f)" % tolerance)
            elif mode == "exact_path":
                self._p("SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)")
            else:
                self._p("SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP)")
        self.mode = mode
        self.tolerance = tolerance if mode == "continuous" else 0.0

    def set_naivecam_tolerance(self, tolerance: float) -> None:
        if self.trace:
            self._p("SET_NAIVECAM_TOLERANCE(%.4f)" % tolerance)
        self.naivecam = tolerance

    # -- motion -----------------------------------------------------------------------------

    def straight_traverse(self, p) -> None:
        if self.trace:
            self.count += 1
            self.lines.append(_TRAVERSE_TRACE % (self.count, self.nlabel, *p))
        self.ppos = list(p)
        if self.want:
            if self.spindle_dirty:
                self.flush()
            self.commands.append(new_traverse(self.src, self.machine(p)))

    def straight_feed(self, p, feed: float) -> None:
        if self.trace:
            self.count += 1
            self.lines.append(_FEED_TRACE % (self.count, self.nlabel, *p))
        self.ppos = list(p)
        if self.want:
            if self.spindle_dirty:
                self.flush()
            self.commands.append(new_feed(self.src, self.machine(p), feed))

    def straight_feed_command(self, p, feed: float) -> None:
        """A linear feed for vmach's stream only (a NURBS_FEED's sampled path)."""
        if self.want:
            if self.spindle_dirty:
                self.flush()
            self.commands.append(new_feed(self.src, self.machine(p), feed))

    def probe_command(self, p, feed: float, required: bool) -> None:
        """A straight probe move toward ``p`` for vmach's stream (canon.ProbeMove: verify stops
        it at contact with the stock)."""
        if self.want:
            if self.spindle_dirty:
                self.flush()
            self._c(vc.ProbeMove(self.src, axes=self.machine(p), feed=feed, required=required))

    def traverse_command(self, p) -> None:
        """A rapid move for vmach's stream only (a probe's back-off)."""
        if self.want:
            if self.spindle_dirty:
                self.flush()
            self.commands.append(new_traverse(self.src, self.machine(p)))

    def arc_feed_command(self, p, center, clockwise: bool, feed: float) -> None:
        """An XY arc for vmach's stream only (a NURBS_FEED's sampled path); ``center`` (x, y)."""
        if self.want:
            if self.spindle_dirty:
                self.flush()
            cm = self.machine([center[0], center[1], *p[2:]])
            self._c(vc.ArcFeed(self.src, axes=self.machine(p), plane=PLANE_AXES[170],
                               center=(cm[PLANE_AXES[170][0]], cm[PLANE_AXES[170][1]]),
                               clockwise=clockwise, turns=0, feed=feed))

    def rigid_tap(self, p, back, feed: float) -> None:
        """RIGID_TAP: in to ``p`` and out again to ``back`` (the start), synchronised with the
        spindle; vmach's stream gets the two feeds."""
        if self.trace:
            self._p("RIGID_TAP(%.4f, %.4f, %.4f)" % (p[0], p[1], p[2]))
        if self.want:
            if self.spindle_dirty:
                self.flush()
            self.commands.append(new_feed(self.src, self.machine(p), feed))
            self.commands.append(new_feed(self.src, self.machine(back), feed))

    def arc_feed(self, plane: int, e1, e2, c1, c2, rotation: int, e3, abc, feed: float) -> None:
        if self.trace:
            self._p("ARC_FEED(%.4f, %.4f, %.4f, %.4f, %d, %.4f, %.4f, %.4f, %.4f)"
                    % (e1, e2, c1, c2, rotation, e3, abc[0], abc[1], abc[2]))
        end = _unplane(plane, e1, e2, e3) + list(abc)
        self.ppos = end
        if self.want:
            center = _unplane(plane, c1, c2, e3) + list(abc)
            cm = self.machine(center)
            first, second, _ = PLANE_AXES[plane]
            self._c(vc.ArcFeed(
                self.src, axes=self.machine(end), plane=PLANE_AXES[plane],
                center=(cm[first], cm[second]), clockwise=rotation < 0,
                turns=abs(rotation) - 1, feed=feed))

    def dwell(self, seconds: float) -> None:
        if self.queue:
            return self._defer(self.dwell, seconds)
        if self.trace:
            self._p("DWELL(%.4f)" % seconds)
        if self.want:
            self._c(vc.Dwell(self.src, seconds=seconds))

    # -- spindle, coolant ------------------------------------------------------------------

    def _spindle(self) -> None:
        self.spindle_dirty = self.want

    def set_spindle_speed(self, speed: float) -> None:
        if self.queue:
            return self._defer(self.set_spindle_speed, speed)
        if self.trace:
            self._p("SET_SPINDLE_SPEED(0, %.4f)" % speed)
        self.speed = speed
        self._spindle()

    def spindle(self, direction: str) -> None:
        if self.queue:
            return self._defer(self.spindle, direction)
        if self.trace:
            self._p({"cw": "START_SPINDLE_CLOCKWISE(0)", "ccw": "START_SPINDLE_COUNTERCLOCKWISE(0)",
                     "stop": "STOP_SPINDLE_TURNING(0)"}[direction])
        self.direction = direction
        self._spindle()

    def orient_spindle(self, angle: float, mode: int) -> None:
        """M19 with R or P: the spindle stops at ``angle`` degrees (mode 0 either way, 1
        clockwise, 2 counterclockwise)."""
        if self.queue:
            return self._defer(self.orient_spindle, angle, mode)
        if self.trace:
            self._p("ORIENT_SPINDLE(0, %.4f, %d)" % (angle, mode))
        self.direction = "stop"
        self._spindle()

    def wait_orient(self, timeout: float) -> None:
        if self.queue:
            return self._defer(self.wait_orient, timeout)
        if self.trace:
            self._p("SPINDLE.0.WAIT_ORIENT_COMPLETE(%.4f)" % timeout)

    def set_spindle_mode(self) -> None:
        if self.queue:
            return self._defer(self.set_spindle_mode)
        if self.trace:
            self._p("SET_SPINDLE_MODE(0 0.0000)")

    def coolant(self, mist: bool | None = None, flood: bool | None = None) -> None:
        if self.queue:
            return self._defer(self.coolant, mist, flood)
        if mist is not None:
            if self.trace:
                self._p("MIST_ON()" if mist else "MIST_OFF()")
            self.mist = mist
        if flood is not None:
            if self.trace:
                self._p("FLOOD_ON()" if flood else "FLOOD_OFF()")
            self.flood = flood
        mode = ("mist+flood" if self.flood else "mist") if self.mist else (
            "flood" if self.flood else "off")
        if self.want and self.said["coolant"] != mode:
            self.said["coolant"] = mode
            self._c(vc.Coolant(self.src, mode=mode))

    def overrides(self, enable: bool) -> None:
        if self.trace:
            if enable:
                self._p("ENABLE_FEED_OVERRIDE()")
                self._p("ENABLE_SPEED_OVERRIDE(0)")
            else:
                self._p("DISABLE_FEED_OVERRIDE()")
                self._p("DISABLE_SPEED_OVERRIDE(0)")

    # -- tools ----------------------------------------------------------------------------

    def select_tool(self, tool: int) -> None:
        if self.trace:
            self._p("SELECT_TOOL(%d)" % tool)

    def change_tool(self, index: int, tool: int) -> None:
        if self.trace:
            self._p("CHANGE_TOOL(%d)" % index)
        if self.want:
            self._c(vc.ToolChange(self.src, tool=str(tool), number=tool))

    def change_tool_number(self, index: int, tool: int) -> None:
        if self.trace:
            self._p("CHANGE_TOOL_NUMBER(%d)" % index)
        if self.want:
            self._c(vc.ToolChange(self.src, tool=str(tool), number=tool))

    def use_tool_length_offset(self, v, h: int) -> None:
        if self.trace:
            self._p("USE_TOOL_LENGTH_OFFSET(%.4f %.4f %.4f, %.4f %.4f %.4f, %.4f %.4f %.4f)"
                    % (v[0], v[1], v[2], v[3], v[4], v[5], 0.0, 0.0, 0.0))
        if self.want:
            self._c(vc.ToolOffset(self.src, offset=h))

    def set_tool_table_entry(self, index: int, tool) -> None:
        if self.trace:
            o = tool.offset
            self._p("SET_TOOL_TABLE_ENTRY(%d, %d, %.4f %.4f %.4f %.4f %.4f %.4f %.4f %.4f %.4f, "
                    "%.4f, %.4f, %d)" % (index, tool.number, *o[:9], tool.frontangle,
                                         tool.backangle, tool.orientation))

    # -- program flow ------------------------------------------------------------------------

    def program_stop(self, optional: bool) -> None:
        if self.trace:
            self._p("OPTIONAL_PROGRAM_STOP()" if optional else "PROGRAM_STOP()")
        if self.want:
            self._c(vc.Pause(self.src, optional=optional))

    def program_end(self, code: str) -> None:
        if self.trace:
            self._p("PROGRAM_END()")
        if self.want:
            self._c(vc.ProgramEnd(self.src, code=code))

    def finish(self, end: bool = True) -> None:
        """The closing ``%``: FINISH() (and, unless the run fails there, ProgramEnd)."""
        if self.trace:
            self._p("FINISH()")
        if self.want and end:
            self._c(vc.ProgramEnd(self.src, code="%"))


def _unplane(plane: int, first: float, second: float, normal: float) -> list[float]:
    """(first, second, normal) of the arc plane -> [x, y, z]."""
    if plane == 170:
        return [first, second, normal]
    if plane == 180:  # first Z, second X, normal Y
        return [second, normal, first]
    return [normal, first, second]  # G19: first Y, second Z, normal X
