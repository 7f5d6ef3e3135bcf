"""What every milling cycle reads the same way: lengths in mm, the final depth, the feeds,
the tool radius, the approach to and the retraction from the work."""

from __future__ import annotations

import math
from dataclasses import dataclass

from interpreters.sinumerik.cycles.parameters import Call
from interpreters.sinumerik.cycles.path import MAX_STEPS, TINY, Path
from vmach.errors import ProgramError
from vmach.findings import info
from vmach.source import SourceRef


@dataclass(frozen=True, slots=True)
class Heights:
    """The cycle's planes along the tool axis, program coordinates, mm: retraction plane,
    reference plane, safety clearance (no sign) and the final depth."""

    rtp: float
    rfp: float
    sdis: float
    depth: float

    @property
    def safe(self) -> float:
        return self.rfp + self.sdis


class Context:
    """One cycle call being expanded: its bound parameters, the machine, the moves."""

    def __init__(self, machine, call: Call, src: SourceRef) -> None:
        self.machine, self.call, self.src = machine, call, src
        self.name = call.spec.name
        self.scale = 25.4 if machine.inch else 1.0
        self.path = Path(machine, src)

    def mm(self, name: str) -> float:
        """A length parameter in mm."""
        return self.call[name] * self.scale

    def fail(self, message: str, **data) -> ProgramError:
        return ProgramError("cycle_parameter", f"{self.name}: {message}", self.src, **data)

    def heights(self, relative: bool = True) -> Heights:
        """RTP, RFP, SDIS and the depth: RFP − DPR when the call gives a DPR other than 0
        (cycles that have one), else DP. A depth not below RFP is a ``cycle_parameter``."""
        c = self.call
        rfp = self.mm("RFP")
        if relative and "DPR" in c.values and c.has("DPR") and c["DPR"] != 0:
            depth = rfp - abs(self.mm("DPR"))
        elif c.has("DP"):
            depth = self.mm("DP")
        else:
            raise self.fail("give the depth, DP" + (" or DPR" if "DPR" in c.values else ""))
        if depth >= rfp:
            raise self.fail(f"the depth {depth:g} is not below the reference plane RFP {rfp:g}",
                            depth=depth, rfp=rfp)
        return Heights(self.mm("RTP"), rfp, abs(self.mm("SDIS")), depth)

    def feed(self, *names: str) -> float:
        """The first of the named feed parameters the call gives (not 0), else the modal F;
        F0 is ``zero_feed``."""
        for n in names:
            if self.call[n] > 0:
                return self.call[n] * self.scale
        if self.machine.feed <= 0:
            raise ProgramError("zero_feed", f"{self.name}: no feed (the cycle's feed is 0 and no F "
                               "is programmed)", self.src)
        return self.machine.feed

    def tool_radius(self) -> float:
        """The active tool's radius (mm); a milling cycle without one is ``cycle_parameter``."""
        if self.machine.cutcom.engaged:
            raise ProgramError("cutcom", f"{self.name} while tool radius compensation is active "
                               "(G40 first)", self.src)
        r = self.machine.tool_radius(self.name, self.src)
        if r <= 0:
            raise self.fail("needs a tool with a radius (D0 or a radius of 0 is active)")
        return r

    def approach(self, h: Heights, a: float, b: float) -> None:
        """To the retraction plane, over (a, b) at rapid, down to the safety clearance."""
        p = self.path
        p.phase("approach")
        if p.here()[2] < h.rtp:
            p.rapid(n=h.rtp)
        p.rapid(a, b)
        p.rapid(n=h.safe)

    def retract(self, h: Heights) -> None:
        """Up to the retraction plane at rapid."""
        self.path.phase("retraction")
        self.path.rapid(n=max(h.rtp, h.safe))

    def simplified(self, what: str) -> None:
        """Say once per cycle and run (an ``info`` ``cycle_simplified`` at the first call) what
        of the cycle vmach does not simulate as the control runs it."""
        message = f"{self.name}: {what}"
        notes = self.machine.notes
        if not any(f.kind == "cycle_simplified" and f.message == message for f in notes):
            notes.append(info("cycle_simplified", message, self.src, cycle=self.name))

    def rectangle(self, what: str) -> tuple:
        """A rectangular pocket's or spigot's LENG, WID, CRAD (mm), its centre (PA, PO) and the
        angle STA (radians); ``cycle_parameter`` for no size or a corner radius of more than
        half the width."""
        length, width, crad = abs(self.mm("LENG")), abs(self.mm("WID")), abs(self.mm("CRAD"))
        if length <= 0 or width <= 0:
            raise self.fail(f"give the {what}'s length and width", leng=length, wid=width)
        if crad > min(length, width) / 2 + TINY:
            raise self.fail(f"the corner radius {crad:g} is more than half the width", crad=crad)
        return length, width, crad, (self.mm("PA"), self.mm("PO")), math.radians(self.call["STA"])

    def count(self, n: int, what: str) -> None:
        if n > MAX_STEPS:
            raise self.fail(f"more than {MAX_STEPS} {what}", count=n)


def clockwise(cdir: float, inside: bool) -> bool:
    """Whether the tool runs clockwise about a pocket (``inside``) or a spigot: CDIR 2 is G2,
    3 G3, 0 climb milling and 1 conventional with the spindle turning M3 (climbing runs
    counter-clockwise inside, clockwise outside)."""
    if cdir == 2:
        return True
    if cdir == 3:
        return False
    climb = cdir != 1
    return climb != inside
