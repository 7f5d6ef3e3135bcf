"""Phase 3b: the effect of one NC block on the control's state, and the canonical commands it
emits, in a fixed order (as LinuxCNC's ``interp_execute.cc`` fixes its own):

 1. MSG                          7. spindle M3/M4/M5, ``M<n>=3`` ...
 2. modal G codes (plane, G90/91, 8. coolant M7/M8/M9
    units, feed type, DIAMON,    9. frame instructions (TRANS, ROT ...)
    G54..., G64 ...)            10. dwell G4
 3. SETMS                       11. machine cycles and machine G codes
 4. feed F                      12. motion (G0/G1/G2/G3 with the block's axis words)
 5. spindle speeds S, ``S<n>=``  13. M0/M1, then subprogram calls, then M2/M30/M17/RET
 6. tool T (and D), D alone

Word values were evaluated left to right before this (assignments take effect in place).
"""

from __future__ import annotations

import math

from interpreters.sinumerik import (
    circles,
    cycles,
    frame_words,
    increments,
    orientation,
    polar,
    surface,
    targets,
    tracyl,
    turning,
)
from interpreters.sinumerik.corners import WORDS as CORNER_WORDS
from interpreters.sinumerik.corners import Corners
from interpreters.sinumerik.cutcom import Compensator
from interpreters.sinumerik.drilling import CYCLES as DRILLING
from interpreters.sinumerik.drilling import PATTERNS, drill, pattern
from interpreters.sinumerik.frames import IDENTITY, Frames
from interpreters.sinumerik.turning import nose, threads
from vmach import canon
from vmach.canon import AxisSpec, ControlSpec
from vmach.errors import ProgramError
from vmach.findings import warning
from vmach.source import SourceRef

PLANES = {"G17": ("X", "Y", "Z"), "G18": ("Z", "X", "Y"), "G19": ("Y", "Z", "X")}
FEED_MODES = {
    "G93": "inverse_time",
    "G94": "per_minute",
    "G95": "per_rev",
    "G96": "per_rev",
    "G97": "per_rev",
    "G971": "per_minute",
    "G972": "per_minute",
    "G973": "per_rev",
    "G942": "per_minute",
    "G952": "per_rev",
}
INCH = 25.4
# G group 10 → canonical path mode (G641...G645 round corners: continuous path too)
PATH_MODES = {
    "G60": "exact",
    "G64": "continuous",
    "G641": "continuous",
    "G642": "continuous",
    "G643": "continuous",
    "G644": "continuous",
    "G645": "continuous",
}


class Values:
    """Everything one block programmed, values already evaluated.

    List fields start as the shared empty tuple; a block that has such words gets a fresh list
    (see ``compile._nc``), so a plain motion block allocates only what it uses.
    """

    __slots__ = (
        "gcodes",
        "axes",
        "interp",
        "feed",
        "speeds",
        "ms",
        "tool",
        "edge",
        "frame",
        "frame_values",
        "rpl",
        "setms",
        "msg",
        "cycles",
        "repeat",
        "call",
        "end",
    )

    def __init__(self) -> None:
        self.gcodes = self.axes = self.speeds = self.ms = self.cycles = ()  # type: ignore[assignment]
        self.interp = self.frame_values = _EMPTY
        self.feed = self.tool = self.edge = self.frame = self.rpl = None
        self.setms = self.msg = self.repeat = self.call = self.end = None


_EMPTY: dict = {}


class Machine:
    """The control's state as the interpreter sees it, and the command sink."""

    def __init__(self, control: ControlSpec, out: list):
        self.control = control
        self.out = out
        self.specs: dict[str, AxisSpec] = {a.name: a for a in control.axes}
        self.names: list[str] = [a.name for a in control.axes]
        for g in control.geometry:
            if g not in self.specs:
                self.add_axis(g)
        self.pos: dict[str, float] = {n: self.specs[n].home for n in self.names}
        self.geometry = control.geometry
        self.frames = Frames(control.geometry)
        self.motion = "G0"
        self.plane = "G17"
        self.plane_ab = ("X", "Y")        # the plane's first two axes (kept with ``plane``)
        self.absolute = True
        self.inch = False
        self.feed_mode = "per_minute"
        self.feed = 0.0
        self.diameter = False
        self.diam90 = False
        self.offset_code = "G500"
        self.path_mode = "G64"
        self.master = control.master_spindle
        self.spindles: dict[int, list] = {s: [0.0, "stop"] for s in control.spindles}
        self.surface = surface.Surface()  # G96 constant cutting speed
        self.coolant: set[str] = set()
        self.tool: str | None = None
        self.edge = 0                   # active D number (D1 after a tool change)
        #: (tool, D) -> radius (mm) for tool radius compensation; None: no tool library
        self.tool_radius_of = None
        #: (tool, D) -> the tool library's data of the offset (RunOptions.tool_data), or None
        self.tool_data_of = None
        self.cutcom = Compensator(self)
        self.corners = Corners(self)
        self.mcall: tuple | None = None   # (cycle, args) called after every positioning block
        self.mcall_new = False            # set in the MCALL block itself (no call there)
        self.pole: tuple[float, float] | None = None   # polar coordinates' pole, program plane, mm
        self.tracyl = None                # the active TRACYL's start mark (tracyl.Mark)
        self.traori, self.ori, self.unknown = None, orientation.Modes(), set()   # orientation.py
        #: the fast path (:meth:`straight`) may run: no inch, diameter, rotated frame,
        #: compensation, chamfer, MCALL or TRACYL (kept by :meth:`refresh_plain`)
        self.plain = True
        #: a Slot or a TRACYL mark went into the command stream (resolved when the run ends)
        self.placeholders = False
        self.notes: list = []             # warnings the block effects found (left_active)
        #: the last move with motion in the plane (start, end machine values, arc centre in the
        #: program plane or None, machine clockwise), for CT's tangent
        self.last_move: tuple | None = None
        #: where motion commands go: ``out``, or the place of a block held for a chamfer
        self.sink: list = out
        self.incr_offset = increments.traverses_offset(control)   # SD42440 (increments.py)
        self.stale: dict[str, Frames] = {}
        self.thread_lead: tuple[str, float] | None = None   # G33's lead: ("K", mm/rev)

    def settable_frame(self, code: str) -> tuple[dict[str, float], tuple]:
        """Translations and linear part G500/G54... select: the model's zero offsets (the NCK's
        settable frames replace this when a run has one, see ``nck.Nck.settable_frame``)."""
        return ({} if code == "G500" else dict(self.control.zero_offsets.get(code, {})), IDENTITY)

    @property
    def plane_axes(self) -> tuple[str, str, str]:
        """(first, second, normal) axis names of the working plane."""
        return PLANES[self.plane]

    def add_axis(self, name: str) -> None:
        kind = "rotary" if name[0] in "ABC" else "linear"
        self.specs[name] = AxisSpec(name, kind)
        self.names.append(name)
        if hasattr(self, "pos"):
            self.pos[name] = 0.0

    def modal_state(self) -> dict:
        return {
            k: getattr(self, k)
            for k in (
                "motion",
                "plane",
                "absolute",
                "inch",
                "feed_mode",
                "diameter",
                "diam90",
                "offset_code",
                "path_mode",
            )
        } | {"frames": (dict(self.frames.settable), dict(self.frames.trans), self.frames.rot,
                        self.frames.slin)}

    def restore(self, state: dict, src: SourceRef) -> None:
        frames = state.pop("frames")
        increments.frame_changes(self)
        if PATH_MODES[state["path_mode"]] != PATH_MODES[self.path_mode]:
            self.out.append(canon.PathMode(src, mode=PATH_MODES[state["path_mode"]]))
        for k, v in state.items():
            setattr(self, k, v)
        self.plane_ab = PLANES[self.plane][:2]
        self.frames.settable, self.frames.trans, self.frames.rot, self.frames.slin = frames
        self.frames.refresh()
        self.emit_frame(src)
        self.out.append(canon.PlaneSelect(src, plane=PLANES[self.plane]))
        self.out.append(canon.FeedMode(src, mode=self.feed_mode))
        self.refresh_plain()

    def emit_frame(self, src: SourceRef) -> None:
        self.out.append(
            canon.SetFrame(src, origin=self.frames.origin(self.names), rotation=self.frames.rotation_flat())
        )

    # ------------------------------------------------------------------------------------
    def apply(self, v: Values, src: SourceRef) -> str | None:
        """Carry out the block; return 'M2', 'M30' or 'M17' when it ends its program level."""
        out = self.out
        if v.msg is not None:
            out.append(canon.Message(src, text=v.msg))
        dwell = False
        suppress = False
        block_exact = False
        comp = None
        for col, code in v.gcodes:
            name = code.name
            grp = code.group
            if grp == 1:
                self.motion = name
            elif grp == 2:
                dwell = True
            elif grp == 6:
                if name != self.plane:
                    if self.cutcom.engaged:
                        raise ProgramError("cutcom", f"{name}: the plane cannot change while tool radius "
                                           "compensation is active (G40 first)", src.at(col))
                    self.plane = name
                    self.plane_ab = PLANES[name][:2]
                    out.append(canon.PlaneSelect(src, plane=PLANES[name]))
            elif grp == 14:
                self.absolute = name == "G90"
            elif grp == 13:
                self.inch = name in ("G70", "G700")
            elif grp == 15:
                mode = FEED_MODES[name]
                if mode != self.feed_mode:
                    self.feed_mode = mode
                    out.append(canon.FeedMode(src, mode=mode))
                surface.feed_group(self, name, src)
            elif grp == 29:
                self.diameter = name in ("DIAMON", "DIAM90")
                self.diam90 = name == "DIAM90"
                if self.diameter and not self.control.transverse and self.control.strict_axes:
                    raise ProgramError(
                        "no_transverse_axis",
                        f"{name}: the machine has no transverse axis",
                        src.at(col),
                    )
            elif grp == 8:
                self.offset_code = name
                increments.frame_changes(self)
                self.frames.set_settable(*self.settable_frame(name))
                self.emit_frame(src)
            elif grp == 9:
                suppress = True
            elif grp == 10:
                if PATH_MODES[name] != PATH_MODES[self.path_mode]:
                    out.append(canon.PathMode(src, mode=PATH_MODES[name]))
                self.path_mode = name
            elif grp == 11:
                block_exact = True
            elif grp in (25, 50, 51, 53, 100):
                if name == "TRACYL":
                    raise ProgramError("syntax", "TRACYL needs the working diameter: TRACYL(d)", src.at(col))
                if orientation.code(self, name, src.at(col)) and self.tracyl is not None:
                    out.append(tracyl.deactivate(self))
                    self.placeholders = True
            elif grp == 7:
                comp = (name, col)
            elif grp == 17:
                self.cutcom.approach = name
            elif grp == 18:
                self.cutcom.corner = name
        if v.setms is not None:
            if v.setms not in self.spindles:
                if self.control.strict_axes:
                    raise ProgramError(
                        "unknown_spindle",
                        f"SETMS({v.setms}): the machine has no spindle {v.setms}",
                        src,
                    )
                self.spindles[v.setms] = [0.0, "stop"]
            self.master = v.setms
            out.append(canon.MasterSpindle(src, spindle=v.setms))
        if v.feed is not None and not dwell:
            if v.feed < 0:
                raise ProgramError("invalid_value", f"negative feed F{v.feed}", src)
            self.feed = v.feed * (INCH if self.inch and self.feed_mode != "inverse_time" else 1.0)
        changed: dict[int, None] = {}
        for spindle, value in v.speeds:
            if dwell:               # G4 S… / S<n>=…: a dwell in revolutions, no speed
                continue
            s = self.master if spindle is None else spindle
            self._spindle(s, src)[0] = surface.speed(self, s, float(value), src)
            if value < 0:
                raise ProgramError("invalid_value", f"negative spindle speed {value}", src)
            changed[s] = None
        if v.tool is not None:
            t = v.tool
            number = int(t) if not isinstance(t, str) else None
            name = t if isinstance(t, str) else str(int(t))
            self.tool = name
            self.edge = 1 if v.edge is None else v.edge
            out.append(canon.ToolChange(src, tool=name, number=number, offset=v.edge))
        elif v.edge is not None:
            self.edge = v.edge
            out.append(canon.ToolOffset(src, offset=v.edge))
        if comp is not None:
            if comp[0] == "G40":
                self.cutcom.deselect()
            else:
                self.cutcom.select(comp[0], self.tool_radius(comp[0], src.at(comp[1])), src.at(comp[1]))
                self.cutcom.shift = nose.shift(self)
        elif v.edge is not None and self.cutcom.state == "on":
            self.cutcom.radius = self.tool_radius("D", src)
            self.cutcom.shift = nose.shift(self)
        end = None
        pause = None
        for spindle, m, col in v.ms:
            if spindle is not None:
                if m not in (3, 4, 5):
                    out.append(canon.CycleCall(src, name=f"M{spindle}={m}"))
                    continue
                s = spindle
            elif m in (3, 4, 5):
                s = self.master
            elif m in (7, 8):
                self.coolant.add("mist" if m == 7 else "flood")
                out.append(
                    canon.Coolant(src, mode="+".join(c for c in ("mist", "flood") if c in self.coolant))
                )
                continue
            elif m == 9:
                self.coolant.clear()
                out.append(canon.Coolant(src, mode="off"))
                continue
            elif m in (0, 1):
                pause = m
                continue
            elif m in (2, 30, 17):
                end = f"M{m}"
                if m != 17:
                    self.end_contour(src)
                continue
            elif m == 6:
                continue  # tools change at T on this control (tool change mode "T")
            else:
                out.append(canon.CycleCall(src, name=f"M{m}"))
                continue
            st = self._spindle(s, src.at(col))
            st[1] = {3: "cw", 4: "ccw", 5: "stop"}[m]
            changed[s] = None
        for s in changed:
            st = self.spindles[s]
            out.append(canon.Spindle(src, spindle=s, speed=st[0], direction=st[1]))
        if v.frame is not None:
            self.frame(v, src)
        if dwell:
            if v.feed is not None:
                out.append(canon.Dwell(src, seconds=float(v.feed)))
            else:
                self._dwell_revolutions(v.speeds, src)
        for name, args in v.cycles:
            if name in DRILLING:
                drill(self, name, args, src)
            elif name in PATTERNS:
                pattern(self, name, args, src, cycles.modal)
            elif name in cycles.NAMES:
                cycles.run(self, name, args, src)
            elif name in turning.NAMES:
                turning.run(self, name, args, src)
            elif name in ("TRACYL", "TRAORI", "CYCLE800", "TRANSMIT"):
                out.extend(orientation.start(self, name, args, src))
                self.placeholders = True
            elif name.startswith("MCALL"):
                self.mcall = (name[6:], args) if name != "MCALL" else None
                self.mcall_new = True
            else:
                out.append(canon.CycleCall(src, name=name, args=tuple(args)))
        corner = None
        if v.interp and any(k in v.interp for k in CORNER_WORDS):
            corner = {k: float(v.interp[k][0]) * (INCH if self.inch else 1.0)
                      for k in CORNER_WORDS if k in v.interp}
            if "RNDM" in corner:
                self.corners.modal = max(0.0, corner.pop("RNDM"))
            if "FRCM" in corner:
                self.corners.feed_modal = max(0.0, corner.pop("FRCM"))
        polar_words = None
        if v.interp and ("AP" in v.interp or "RP" in v.interp):
            polar_words = {k: v.interp[k] for k in ("AP", "RP") if k in v.interp}
            v.axes = polar.words(self, polar_words, v.axes, src)
        arc_words = v.interp and any(k not in CORNER_WORDS and k not in ("AP", "RP") for k in v.interp)
        ori = arc_words and orientation.words(self, v, src)       # A3= … (an error without TRAORI)
        if v.axes or (arc_words and (ori or self.motion in ("G2", "G3", "CIP", "CT"))):
            g9 = block_exact and PATH_MODES[self.path_mode] != "exact"
            if g9:  # G9: exact stop at the end of this block only
                out.append(canon.PathMode(src, mode="exact"))
            self.move(v, src, suppress, corner or {}, polar_words is not None)
            if g9:
                out.append(canon.PathMode(src, mode="continuous"))
        self.mcall_new = False
        if pause is not None:
            out.append(canon.Pause(src, optional=pause == 1))
        self.refresh_plain()
        return end

    def refresh_plain(self) -> None:
        """Whether the fast path may take the next plain block (after any state change)."""
        self.plain = not (self.inch or self.diameter or self.frames.rotated or self.cutcom.engaged
                          or self.corners.held is not None or self.corners.modal
                          or self.mcall is not None or self.tracyl is not None or self.traori or self.unknown)

    def _dwell_revolutions(self, speeds, src: SourceRef) -> None:
        """``G4 S…`` (revolutions of the master spindle) or ``G4 S<n>=…`` (of spindle n, as
        seconds at its programmed speed when n is not the master; Fundamentals, "Dwell time")."""
        if not speeds:
            raise ProgramError("syntax", "G4 needs F (seconds) or S (revolutions)", src)
        spindle, revs = speeds[0]
        if spindle is None or spindle == self.master:
            self.out.append(canon.Dwell(src, revolutions=float(revs)))
            return
        speed, state = self.spindles.get(spindle, (0.0, "stop"))
        if state == "stop" or speed <= 0:
            raise ProgramError("invalid_value", f"G4 S{spindle}={revs:g}: a dwell in revolutions of spindle "
                               f"{spindle}, which is not turning", src)
        self.out.append(canon.Dwell(src, seconds=float(revs) * 60.0 / speed))

    def _spindle(self, s: int, src: SourceRef) -> list:
        if s not in self.spindles:
            if self.control.strict_axes:
                raise ProgramError("unknown_spindle", f"the machine has no spindle {s}", src)
            self.spindles[s] = [0.0, "stop"]
        return self.spindles[s]

    def program_point(self) -> tuple[float, float, float]:
        """The last programmed position of the geometry axes, program coordinates (mm)."""
        return self.frames.to_program(tuple(self.pos[n] for n in self.geometry))

    def machine_axes(self, axes, p3) -> dict:
        """``axes`` (every axis, machine values) with the geometry axes at the program point
        ``p3`` (mm) through the frame."""
        out = dict(axes)
        for n, v in zip(self.geometry, self.frames.to_machine(tuple(p3)), strict=True):
            out[n] = v
        return out

    def machine_plane(self, c, base3) -> tuple[float, float]:
        """Machine values in the working plane of the program-plane point ``c`` (an arc
        centre) at the height of the program point ``base3``."""
        g = self.geometry
        ia, ib = g.index(self.plane_ab[0]), g.index(self.plane_ab[1])
        p = list(base3)
        p[ia], p[ib] = c
        m = self.frames.to_machine(tuple(p))
        return (m[ia], m[ib])

    def machine_cw(self, cw: bool) -> bool:
        """The machine's direction of an arc programmed clockwise (``cw``) or not in the
        working plane: a mirroring frame turns the plane over (G2 runs counter-clockwise)."""
        g = self.geometry
        a, b = PLANES[self.plane][:2]
        return cw != (self.frames.rotated and self.frames.mirrors(g.index(a), g.index(b)))

    def tool_radius(self, code: str, src: SourceRef) -> float:
        """Radius (mm) of the active tool's D offset, for tool radius compensation."""
        if self.edge == 0:
            return 0.0                  # D0: no offset
        if self.tool is None:
            raise ProgramError("no_tool_radius", f"{code}: no tool is selected (T...)", src)
        if self.tool_radius_of is None:
            raise ProgramError("no_tool_radius", f"{code}: the radius of tool {self.tool} D{self.edge} "
                               "is not known; give a tool library (--tools)", src, tool=self.tool)
        r = self.tool_radius_of(self.tool, self.edge)
        if r is None:
            raise ProgramError("no_tool_radius", f"{code}: the tool library has no D{self.edge} for tool "
                               f"{self.tool}", src, tool=self.tool, edge=self.edge)
        return float(r)

    # ------------------------------------------------------------------------------------
    frame = frame_words.frame              # (self, v: Values, src)

    # ------------------------------------------------------------------------------------
    def end_contour(self, src: SourceRef) -> None:
        """Program end: a held chamfer block runs to its end, compensation ends; what is still
        switched on is a ``left_active`` warning (the next program would inherit it)."""
        left = []
        if self.cutcom.engaged:
            left.append(("G41/G42", "tool radius compensation (no G40)"))
        if self.mcall is not None:
            left.append(("MCALL", f"the modal call MCALL {self.mcall[0]} (no MCALL to end it)"))
        left += [(m.name, f"{m.name} (no TRAFOOF)") for m in (self.tracyl, self.traori) if m]
        for what, text in left:
            self.notes.append(warning("left_active", f"the program ends with {text} still active", src,
                                      what=what))
        self.corners.flush(self.send)
        self.cutcom.finish()

    def send(self, cmd, start3, end3, centre, src: SourceRef) -> None:
        """A move, after chamfers and roundings: compensated, or written."""
        if self.cutcom.engaged:
            self.cutcom.take(cmd, start3, end3, centre, src)
        else:
            self.sink.append(cmd)

    def move(self, v: Values, src: SourceRef, suppress: bool, corner: dict | None = None,
             about_pole: bool = False) -> None:
        """Emit the block's motion (v.axes holds (Word, value) in textual order)."""
        if self.tracyl is not None:
            for word, _ in v.axes:
                if word.name == self.tracyl.rotary:
                    raise ProgramError("syntax", f"{word.name} is the cylinder's unwrapped Y while TRACYL "
                                       "is active (TRAFOOF first)", src.at(word.col))
        if (self.traori is not None or self.unknown) and orientation.move(self, v, src, suppress):
            return                                      # under TRAORI (right after it: checked)
        new = None
        if not (suppress or self.inch or self.diameter or self.frames.rotated):
            new = self._plain_targets(v.axes)
        if new is None:
            new = self._targets(v, src, suppress)
        orientation.learned(self, v.axes, new, suppress)
        for word, _ in v.axes if self.stale else ():
            self.stale.pop(word.name, None)
        motion = self.motion
        centre = None
        if motion == "G1":
            if self.feed <= 0:
                raise ProgramError("zero_feed", "feed move with F0 (no feed programmed)", src)
            cmd = canon.LinearFeed(src, axes=new, feed=self.feed)
        elif motion == "G0":
            cmd = canon.Traverse(src, axes=new)
        elif motion in ("G33", "G34", "G35"):
            cmd = threads.move(self, v, src, new)
        else:
            cmd, centre = self.arc(v, src, new, suppress, about_pole)
        a, b = self.plane_ab
        if centre is not None or new[a] != self.pos[a] or new[b] != self.pos[b]:
            self.last_move = (self.pos, new, centre, getattr(cmd, "clockwise", False))
        if self.cutcom.engaged or corner or self.corners.holding or self.corners.modal > 0:
            if suppress:
                raise ProgramError("cutcom", "G53/G153/SUPA while tool radius compensation, a chamfer "
                                   "or a rounding is active", src)
            g = self.geometry
            start3 = self.program_point()
            end3 = self.frames.to_program(tuple(new[n] for n in g))
            self.corners.take(cmd, start3, end3, centre, src, corner or {}, self.send)
        else:
            self.sink.append(cmd)
        self.pos = new
        if self.mcall is not None and not self.mcall_new:
            cycles.modal(self, src)   # MCALL: after each positioning block

    def tangent(self) -> tuple[float, float] | None:
        """Unit tangent (program plane) at the end of the last move in the plane: CT leaves
        along it. None before any."""
        if self.last_move is None:
            return None
        start, end, centre, cw = self.last_move
        g = self.geometry
        a, b = PLANES[self.plane][:2]
        ia, ib = g.index(a), g.index(b)
        pe = self.frames.to_program(tuple(end[n] for n in g))
        if centre is not None:
            u = (pe[ia] - centre[0], pe[ib] - centre[1])
            t = (u[1], -u[0]) if self.machine_cw(cw) else (-u[1], u[0])
        else:
            ps = self.frames.to_program(tuple(start[n] for n in g))
            t = (pe[ia] - ps[ia], pe[ib] - ps[ib])
        n = math.hypot(*t)
        return (t[0] / n, t[1] / n) if n > 1e-12 else None

    def straight(self, words: list, src: SourceRef) -> bool:
        """Fast path for blocks of G0/G1 axis words only; False when it does not apply."""
        if not self.plain:
            return False
        new = self._plain_targets(words)
        if new is None:
            return False
        for word, _ in words if self.stale else ():
            self.stale.pop(word.name, None)
        if self.motion == "G1":
            if self.feed <= 0:
                raise ProgramError("zero_feed", "feed move with F0 (no feed programmed)", src)
            self.out.append(canon.LinearFeed(src, axes=new, feed=self.feed))
        else:
            self.out.append(canon.Traverse(src, axes=new))
        a, b = self.plane_ab
        pos = self.pos
        if new[a] != pos[a] or new[b] != pos[b]:
            self.last_move = (pos, new, None, False)
        self.pos = new
        return True

    def general_move(self, words: list, src: SourceRef) -> None:
        v = Values()
        v.axes = words
        self.move(v, src, False)
        self.refresh_plain()

    _plain_targets = targets.plain_targets
    _targets = targets.targets

    def arc(self, v: Values, src: SourceRef, new: dict, suppress: bool, about_pole: bool = False,
            in_program: bool = False) -> tuple:
        """The block's ArcFeed and its centre (a, b) in program coordinates of the plane.
        ``in_program``: the ArcFeed itself in program coordinates (end, centre, direction as
        programmed; any frame, for the orientation transformation to map: orientation.py)."""
        g = self.geometry
        plane = PLANES[self.plane]
        a_name, b_name, _ = plane
        ia, ib = g.index(a_name), g.index(b_name)
        frames = self.frames
        start = tuple(self.pos[n] for n in g)
        ps = start if suppress else frames.to_program(start)
        pe = tuple(new[n] for n in g)
        pe = pe if suppress else frames.to_program(pe)
        scale = INCH if self.inch else 1.0
        letters = {"X": "I", "Y": "J", "Z": "K"}
        la, lb = letters[a_name], letters[b_name]
        cw = self.motion == "G2"
        if not suppress and frames.rotated and not frames.similar(ia, ib) and not in_program:
            raise ProgramError("unsupported", "a circle under a frame that scales the plane's axes "
                               "differently (an ellipse) is not simulated", src)
        if self.motion == "CIP":
            (ca, cb), cw = circles.through(ps, pe, circles.intermediate(self, v, ps, src), ia, ib, src)
        elif self.motion == "CT":
            (ca, cb), cw = circles.tangential(ps, pe, self.tangent(), ia, ib, src)
        elif about_pole:
            ca, cb = polar.pole(self)              # G2/G3 AP= RP=: about the pole
        elif "AR" in v.interp:
            (ca, cb), pe = circles.opening(self, v, ps, pe, cw, ia, ib, scale, src)
            if pe is not None:                     # centre and angle: the end point follows
                m = frames.to_machine(pe) if not suppress else pe
                for i, n in enumerate(g):
                    new[n] = m[i]
            pe = tuple(new[n] for n in g)
            pe = pe if suppress else frames.to_program(pe)
        elif "CR" in v.interp:
            r = float(v.interp["CR"][0]) * scale
            c = circles.centre_from_radius(ps[ia], ps[ib], pe[ia], pe[ib], r, cw, src)
            ca, cb = c
        else:
            if la not in v.interp and lb not in v.interp:
                raise ProgramError("arc_error", f"{self.motion} needs {la}/{lb} or CR=", src)
            vals = []
            for letter, i in ((la, ia), (lb, ib)):
                val, mode = v.interp.get(letter, (0.0, None))
                val = float(val) * scale
                vals.append(val if mode == "AC" else ps[i] + val)
            ca, cb = vals
        r0 = math.hypot(ps[ia] - ca, ps[ib] - cb)
        r1 = math.hypot(pe[ia] - ca, pe[ib] - cb)
        if r0 < 1e-9:
            raise ProgramError("arc_error", "circle with zero radius", src)
        allowed = max(0.01, 0.001 * r0)
        if abs(r1 - r0) > allowed:
            raise ProgramError(
                "arc_error",
                f"end point is not on the circle: radius {r0:.4f} at the start, {r1:.4f} at the end",
                src,
                start_radius=r0,
                end_radius=r1,
            )
        centre3 = list(ps)
        centre3[ia], centre3[ib] = ca, cb
        cm = centre3 if suppress else frames.to_machine(tuple(centre3))
        turns = int(v.interp.get("TURN", (0, None))[0])
        if self.feed <= 0:
            raise ProgramError("zero_feed", "feed move with F0 (no feed programmed)", src)
        if in_program:
            prog = dict(new)
            prog.update(zip(g, pe, strict=True))
            return canon.ArcFeed(src, axes=prog, plane=plane, center=(ca, cb), clockwise=cw, turns=turns,
                                 feed=self.feed), (ca, cb)
        cmd = canon.ArcFeed(src, axes=new, plane=plane, center=(cm[ia], cm[ib]),
                            clockwise=cw if suppress else self.machine_cw(cw), turns=turns, feed=self.feed)
        return cmd, (ca, cb)
