"""Cylinder surface transformation TRACYL(d) … TRAFOOF (Programming Manual Job Planning,
"Cylinder surface transformation").

While TRACYL is active the program's Y is the *unwrapped* cylinder surface at the working
diameter d (mm along the circumference), X the radial infeed and Z the axis; the control
turns the rotary axis instead of moving Y:

    C = C₀ + Y · 360 / (π · d)      (degrees),     machine Y stays where it was

with Y = 0 at C ≡ 0 (the multiple of 360° nearest the rotary axis when TRACYL starts). The
rotary axis is the control's modulo rotary axis (the turn-mill's C1); programming it directly
while TRACYL is active is an error, as on the control.

The interpreter keeps its positions in the unwrapped coordinates and marks where TRACYL starts
and ends in its command stream; :func:`apply` then rewrites the motion between the marks into
machine axes — lines through the linear map, arcs in a plane with Y (G17, G19) as chords of at
most ``tol.chord`` (their image is not a circle), arcs in Z/X as they are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef
from vmach.tol import tol


@dataclass(frozen=True)
class Mark:
    """Start (``active``) or end of TRACYL in the command stream.

    rotary : the rotary axis; k : degrees per mm of Y; c0 : its angle at Y = 0 (degrees);
    y0 : the machine Y kept; start : the unwrapped position where TRACYL starts (every axis).
    """

    active: bool
    rotary: str = ""
    k: float = 0.0
    c0: float = 0.0
    y0: float = 0.0
    start: tuple = ()
    name = "TRACYL"

    def rewrite(self, c, here: dict) -> list:
        """A motion between the marks in machine axes (``here``: where it starts, unwrapped)."""
        if isinstance(c, canon.ArcFeed) and "Y" in c.plane[:2]:
            return chords(c, here, lambda axes: _machine(axes, self))
        return [replace(c, axes=_machine(c.axes, self))]

    def end(self, machine) -> Mark:
        """TRAFOOF: positions back to machine axes; the end mark."""
        return deactivate(machine)

    def begin(self, before: Mark | None, turns: dict) -> Mark | None:
        """This mark met in :func:`apply` after ``before`` (the active start mark or None):
        the mark active from here on; ``turns`` may learn whole turns the section made."""
        return self if self.active else None


def activate(machine, args, src: SourceRef) -> Mark:
    """TRACYL(d[, n]) in the block: returns the start mark (positions become unwrapped)."""
    if not args or args[0] is None or isinstance(args[0], str):
        raise ProgramError("syntax", "TRACYL needs the working diameter: TRACYL(d)", src)
    if len(args) > 2:
        raise ProgramError("unsupported", "TRACYL with groove wall offset (a third parameter) is not "
                           "simulated", src)
    d = float(args[0]) * (25.4 if machine.inch else 1.0)
    if not d > 1.0 or not math.isfinite(d):
        raise ProgramError("invalid_value", f"TRACYL({args[0]}): the working diameter must be larger "
                           "than 1", src)
    rotary = spindle_axis(machine, "TRACYL", src)
    k = 360.0 / (math.pi * d)
    c = machine.pos[rotary]
    c0 = 360.0 * round(c / 360.0)
    pos = dict(machine.pos)
    y0 = pos["Y"]
    pos["Y"] = (c - c0) / k
    machine.pos = pos
    mark = Mark(True, rotary, k, c0, y0, tuple(pos.items()))
    machine.tracyl = mark
    return mark


def spindle_axis(machine, name: str, src: SourceRef) -> str:
    """The modulo rotary axis a transformation of the turn-mill (TRACYL, TRANSMIT) turns;
    ``unsupported`` without one (and Y), or while compensation, another transformation or a
    rotated frame is active."""
    rotary = next((a.name for a in machine.control.axes if a.kind == "rotary" and a.modulo), None)
    if rotary is None or "Y" not in machine.pos:
        raise ProgramError("unsupported", f"{name}: the machine has no modulo rotary axis (and Y) "
                           "for the transformation", src)
    if machine.cutcom.engaged or machine.tracyl is not None or machine.frames.rotated or machine.traori:
        raise ProgramError("unsupported", f"{name} while compensation, another transformation or a "
                           "rotated frame is active is not simulated (G40, TRAFOOF, ROT first)", src)
    return rotary


def deactivate(machine) -> Mark:
    """TRAFOOF: positions back to machine axes; returns the end mark."""
    m = machine.tracyl
    if type(m) is not Mark:                       # another transformation of this kind (TRANSMIT)
        return m.end(machine)
    pos = dict(machine.pos)
    pos[m.rotary] = m.c0 + pos["Y"] * m.k
    pos["Y"] = m.y0
    machine.pos = pos
    machine.tracyl = None
    return Mark(False)


def apply(commands: list) -> list:
    """The command stream with TRACYL's marks removed and the motion between them in machine
    axes."""
    if not any(isinstance(c, Mark) for c in commands):
        return commands
    out: list = []
    mark: Mark | None = None
    here: dict = {}
    turns: dict = {}        # whole turns a rotary axis made that the interpreter did not see
    for c in commands:
        if isinstance(c, Mark):
            if c.active:
                here = dict(c.start)
            mark = c.begin(mark, turns)
            continue
        if mark is None or not isinstance(c, canon.MOTIONS):
            if turns and isinstance(c, canon.MOTIONS):
                c = replace(c, axes={k: v + turns.get(k, 0.0) for k, v in c.axes.items()})
            out.append(c)
            continue
        out.extend(mark.rewrite(c, here))
        here = dict(c.axes)
    return out


def _machine(axes, m: Mark) -> dict:
    out = dict(axes)
    out[m.rotary] = m.c0 + axes["Y"] * m.k
    out["Y"] = m.y0
    return out


def chords(arc: canon.ArcFeed, here: dict, convert) -> list:
    """An arc (from ``here``) as straight feeds within ``tol.chord``, each end point's axes put
    through ``convert`` (program → machine axes)."""
    a, b, n = arc.plane
    ca, cb = arc.center
    r = math.hypot(here[a] - ca, here[b] - cb)
    t0 = math.atan2(here[b] - cb, here[a] - ca)
    t1 = math.atan2(arc.axes[b] - cb, arc.axes[a] - ca)
    sweep = (t0 - t1) % (2 * math.pi) if arc.clockwise else (t1 - t0) % (2 * math.pi)
    if sweep < 1e-12:
        sweep = 2 * math.pi
    sweep += 2 * math.pi * arc.turns
    step = 2.0 * math.acos(max(-1.0, 1.0 - tol.chord / r)) if r > tol.chord else math.pi / 2
    count = max(1, math.ceil(sweep / step))
    sign = -1.0 if arc.clockwise else 1.0
    out = []
    for i in range(1, count + 1):
        f = i / count
        axes = dict(arc.axes)
        if i < count:
            t = t0 + sign * sweep * f
            axes = {k: here[k] + (arc.axes[k] - here[k]) * f for k in arc.axes}
            axes[a], axes[b] = ca + r * math.cos(t), cb + r * math.sin(t)
        out.append(canon.LinearFeed(arc.source, axes=convert(axes), feed=arc.feed))
    return out
