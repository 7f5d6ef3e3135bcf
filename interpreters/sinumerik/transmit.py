"""Face-end transformation TRANSMIT … TRAFOOF on the turn-mill (Programming Manual Job
Planning, "Milling on turned parts: TRANSMIT").

While TRANSMIT is active the program's X and Y are Cartesian coordinates on the face, and the
control moves the transverse axis X (a radius) and the spindle's rotary axis instead:

    X = √(x² + y²),     C = atan2(y, x)      (degrees; the tool at polar angle +C, as the
                                              turn-mill's C1 convention puts it, docs/kinematics.md)

machine Y stays at 0 (TRANSMIT with the Y axis off the centre is ``unsupported``); C is the
modulo rotary axis, unwrapped to the turn nearest its last value. A straight line or an arc of
the face is not a line in X and C: it is written as straight feeds sampled so that C turns at
most ``tol.angle_step`` between two (the polar interpolation between samples then deviates from
the face path by far less than ``tol.chord``; arcs first become chords within ``tol.chord``).
**The centre** (x = y = 0) is the pole: a path through it reaches X = 0 with C unchanged, C then
turns by 180° at the pole, and the path goes on — as the control's pole transition does; a path
passing close by the centre turns C fast, in as many samples as the angle step needs.
Programming the rotary axis directly while TRANSMIT is active is an error, as on the control.

The interpreter keeps its positions in the Cartesian face coordinates (as for TRACYL) and marks
the start and end in its stream; tracyl.apply rewrites the motion between the marks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from interpreters.sinumerik import tracyl
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef
from vmach.tol import tol


@dataclass(frozen=True)
class Mark(tracyl.Mark):
    """Start (``active``) or end of TRANSMIT; ``state["c"]``: the rotary axis's last value."""

    state: dict = field(default_factory=dict, compare=False)
    name = "TRANSMIT"

    def rewrite(self, c, here: dict) -> list:
        if isinstance(c, canon.ArcFeed):
            lines = tracyl.chords(c, here, lambda axes: axes)
        else:
            lines = [c]
        out = []
        for line in lines:
            for axes in self._samples(here, line.axes):
                out.append(replace(line, axes=axes) if not isinstance(line, canon.ArcFeed)
                           else canon.LinearFeed(line.source, axes=axes, feed=line.feed))
            here = dict(line.axes)
        return out

    def _samples(self, here: dict, end: dict) -> list[dict]:
        """Machine axes along the face line from ``here`` to ``end`` (Cartesian)."""
        x0, y0, x1, y1 = here["X"], here["Y"], end["X"], end["Y"]
        dx, dy = x1 - x0, y1 - y0
        length2 = dx * dx + dy * dy
        t_pole = -(x0 * dx + y0 * dy) / length2 if length2 > 0 else -1.0
        through = 0.0 < t_pole < 1.0 and abs(x0 * dy - y0 * dx) / math.sqrt(length2) < 1e-9
        # the angle turns fastest where the line passes closest to the centre: |dθ/dt| ≤ L·d/r²
        r_min = math.hypot(x0 + t_pole * dx, y0 + t_pole * dy) if 0.0 < t_pole < 1.0 else \
            min(math.hypot(x0, y0), math.hypot(x1, y1))
        rate = abs(x0 * dy - y0 * dx) / r_min ** 2 if r_min > 1e-12 and not through else 0.0
        n = max(1, math.ceil(math.degrees(rate) / tol.angle_step))
        ts = [i / n for i in range(1, n + 1)]
        if through:
            ts = sorted({*ts, t_pole})
        out = []
        for t in ts:
            p = {k: here.get(k, v) + (v - here.get(k, v)) * t for k, v in end.items()}
            if t == 1.0:
                p = dict(end)
            out.append(self._machine(p, pole=through and t == t_pole))
        return out

    def _machine(self, axes: dict, pole: bool = False) -> dict:
        out = dict(axes)
        x, y = axes["X"], axes["Y"]
        c = self.state.get("c", self.c0)
        if not pole and math.hypot(x, y) > 1e-12:
            a = math.degrees(math.atan2(y, x))
            c = c + (a - c + 180.0) % 360.0 - 180.0
            if abs(abs(a - self.state.get("c", self.c0)) % 360.0 - 180.0) < 1e-9:
                c = self.state.get("c", self.c0) + 180.0       # out of the pole: turn positive
        self.state["c"] = c
        out["X"], out["Y"], out[self.rotary] = math.hypot(x, y), self.y0, c
        return out

    def end(self, machine) -> Mark:
        """TRAFOOF: positions back to machine axes: X the radius, C at the face angle's turn
        nearest C at the start (the end mark keeps it; :meth:`begin` adds the whole turns the
        section really made to what follows)."""
        pos = dict(machine.pos)
        x, y = pos["X"], pos["Y"]
        pos["X"], pos["Y"] = math.hypot(x, y), self.y0
        pos[self.rotary] = self.c0 + (math.degrees(math.atan2(y, x)) - self.c0 + 180.0) % 360.0 - 180.0 \
            if math.hypot(x, y) > 1e-12 else self.c0
        machine.pos = pos
        machine.tracyl = None
        return Mark(False, self.rotary, 0.0, pos[self.rotary])

    def begin(self, before, turns: dict):
        if self.active:                     # earlier sections' turns move this start too
            self.state["c"] = self.c0 + turns.get(self.rotary, 0.0)
            return self
        if before is not None and "c" in before.state:
            lag = before.state["c"] - turns.get(self.rotary, 0.0) - self.c0
            turns[self.rotary] = turns.get(self.rotary, 0.0) + 360.0 * round(lag / 360.0)
        return None


def activate(machine, args, src: SourceRef) -> Mark:
    """TRANSMIT or TRANSMIT(n): the start mark; positions become Cartesian on the face."""
    if len(args) > 1:
        raise ProgramError("syntax", "TRANSMIT takes at most the transformation number", src)
    rotary = tracyl.spindle_axis(machine, "TRANSMIT", src)
    pos = dict(machine.pos)
    if abs(pos["Y"]) > 1e-9:
        raise ProgramError("unsupported", f"TRANSMIT with the Y axis off the centre (Y = {pos['Y']:g}) is "
                           "not simulated (Y0 first)", src)
    c = pos[rotary]
    r = pos["X"]
    pos["X"], pos["Y"] = r * math.cos(math.radians(c)), r * math.sin(math.radians(c))
    machine.pos = pos
    mark = Mark(True, rotary, 0.0, c, 0.0, tuple(pos.items()))
    machine.tracyl = mark
    return mark
