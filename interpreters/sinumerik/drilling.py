"""Standard drilling cycles CYCLE81, CYCLE82, CYCLE83 with their classic parameter lists
(SINUMERIK 840D sl "Cycles" manual), called once or modally with ``MCALL``.

The cycle drills at the current position of the working plane, along its normal (Z for G17,
Y for G18, X for G19; program coordinates, mm, the drill toward −normal):

- CYCLE81(RTP, RFP, SDIS, DP, DPR): G0 to RFP + SDIS, G1 at the programmed F to the depth,
  G0 to RTP. The depth is RFP − DPR when DPR is given (it wins over DP), else DP.
- CYCLE82(RTP, RFP, SDIS, DP, DPR, DTB): the same with a dwell of DTB seconds at the depth.
- CYCLE83(RTP, RFP, SDIS, DP, DPR, FDEP, FDPR, DAM, DTB, DTS, FRF, VARI): deep-hole drilling
  in strokes. The first ends at RFP − FDPR (or FDEP) at F·FRF; each following stroke is the
  last one less DAM while that stays above DAM, then DAM. VARI=0 (chip breaking) backs off
  1 mm at rapid after each stroke; VARI=1 (swarf removal) retracts at rapid to RFP + SDIS,
  dwells DTS seconds and returns at rapid to the last depth less an anticipation distance
  (0.6 mm up to 30 mm depth, else depth/50, at most 7 mm). DTB dwells at the final depth.

SINUMERIK Operate appends parameters: CYCLE81/82(…, DTB, GMODE, DMODE, AMODE) (CYCLE81 gets
the dwell DTB too) and CYCLE83(…, VARI, _AXN, _MDEP, _VRT, _DTD, _DIS1, GMODE, DMODE, AMODE):
_MDEP is the smallest stroke (the degression by DAM stops there instead of at DAM), _VRT the
chip-breaking back-off (0: 1 mm), _DTD the dwell at the final depth (0: DTB), _DIS1 the
anticipation distance (0: as above). DMODE and AMODE record how the input screen showed the
values and change nothing here; GMODE=1 (depth to the drill's diameter), an _AXN other than
the plane's normal and dwells in revolutions (negative) are ``unsupported``.

Hole patterns position the tool (rapid, in the plane, at the current height) at each hole and
run the modal drilling cycle (``MCALL``) there:

- HOLES1(SPCA, SPCO, STA1, FDIS, DBH, NUM): a row from the reference point (SPCA, SPCO) at
  STA1 degrees to the plane's first axis, the first hole FDIS from it, then every DBH; from the
  row's end nearer the current position.
- HOLES2(CPA, CPO, RAD, STA1, INDA, NUM): a circle about (CPA, CPO) of radius RAD, the first
  hole at STA1 degrees, then every INDA degrees (0: 360/NUM).

Parameters left out (``CYCLE81(10,0,2,,5)``) are 0. A depth that is not below RFP, or a
cycle without DP and DPR, a pattern of no holes or more than MAX_HOLES, is a
``cycle_parameter`` error at the calling block.
"""

from __future__ import annotations

import math

from interpreters.sinumerik.polar import plane_point
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef

CYCLES = {      # the classic lists, then what SINUMERIK Operate appends
    "CYCLE81": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB", "GMODE", "DMODE", "AMODE"),
    "CYCLE82": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB", "GMODE", "DMODE", "AMODE"),
    "CYCLE83": ("RTP", "RFP", "SDIS", "DP", "DPR", "FDEP", "FDPR", "DAM", "DTB", "DTS", "FRF", "VARI",
                "AXN", "MDEP", "VRT", "DTD", "DIS1", "GMODE", "DMODE", "AMODE"),
}
#: the tool axis _AXN names (1, 2, 3: the first, second, third geometry axis) for each plane
PLANE_AXN = {"G17": 3, "G18": 2, "G19": 1}
PATTERNS = {
    "HOLES1": ("SPCA", "SPCO", "STA1", "FDIS", "DBH", "NUM"),
    "HOLES2": ("CPA", "CPO", "RAD", "STA1", "INDA", "NUM"),
}
#: most holes one pattern may have
MAX_HOLES = 100_000
#: most strokes one CYCLE83 may make (a DAM of 1e-9 must be an error, not a hang)
MAX_STROKES = 100_000


def parameters(name: str, args, src: SourceRef) -> dict[str, float]:
    """The cycle's parameters by name (left out: 0)."""
    names = CYCLES.get(name) or PATTERNS[name]
    if len(args) > len(names):
        raise ProgramError("call_arguments", f"{name} takes {len(names)} parameters, got {len(args)}", src)
    out = {}
    for i, n in enumerate(names):
        v = args[i] if i < len(args) else None
        if v is not None and (isinstance(v, str) or isinstance(v, bool)):
            raise ProgramError("type_error", f"{name}: {n} needs a number", src)
        out[n] = float(v) if v is not None else 0.0
    return out


def drill(machine, name: str, args, src: SourceRef) -> None:
    """Emit the cycle's moves and dwells from the current position."""
    p = parameters(name, args, src)
    if machine.cutcom.engaged:
        raise ProgramError("cutcom", f"{name} while tool radius compensation is active (G40 first)", src)
    scale = 25.4 if machine.inch else 1.0
    rtp, rfp, sdis = p["RTP"] * scale, p["RFP"] * scale, abs(p["SDIS"]) * scale
    given = [a is not None for a in args] + [False] * len(CYCLES[name])
    if given[4] and p["DPR"] != 0:
        depth = rfp - abs(p["DPR"]) * scale
    elif given[3]:
        depth = p["DP"] * scale
    else:
        raise ProgramError("cycle_parameter", f"{name}: give the depth, DP or DPR", src)
    if depth >= rfp:
        raise ProgramError("cycle_parameter", f"{name}: the depth {depth:g} is not below the reference "
                           f"plane RFP {rfp:g}", src, depth=depth, rfp=rfp)
    if machine.feed <= 0:
        raise ProgramError("zero_feed", f"{name}: drilling with F0 (no feed programmed)", src)
    _operate(machine, name, p, src)
    go = _Mover(machine, src)
    go.rapid(rfp + sdis)
    if name == "CYCLE83":
        _strokes(go, p, rfp, sdis, depth, scale, machine.feed, name, src)
    else:
        go.feed(depth, machine.feed)
    dwell = p["DTD"] if name == "CYCLE83" and p["DTD"] > 0 else p["DTB"]
    if dwell > 0:
        machine.sink.append(canon.Dwell(src, seconds=dwell))
    go.rapid(rtp)


def _operate(machine, name: str, p: dict[str, float], src: SourceRef) -> None:
    """Refuse what SINUMERIK Operate's parameters ask that vmach does not simulate: a depth to
    the drill's diameter (GMODE=1, centering), a tool axis other than the plane's normal
    (_AXN), a dwell in revolutions (DTB < 0). DMODE and AMODE say how the values were entered in
    the input screen (display, absolute or incremental entry); DP and DPR carry the depth."""
    why = None
    if p["GMODE"] not in (0, -0.0):
        why = f"GMODE={p['GMODE']:g} (the depth to the drill's diameter)"
    elif p.get("AXN", 0) and p["AXN"] != PLANE_AXN.get(machine.plane):
        why = f"_AXN={p['AXN']:g} (a tool axis other than the working plane's normal)"
    elif p["DTB"] < 0 or p.get("DTD", 0) < 0:
        why = "a dwell in revolutions (DTB < 0)"
    if why is not None:
        raise ProgramError("unsupported", f"{name}: {why} is not simulated", src)


def _strokes(go, p, rfp, sdis, depth, scale, feed, name, src) -> None:
    """CYCLE83's strokes down to ``depth``."""
    if p["FDPR"]:
        first = rfp - abs(p["FDPR"]) * scale
    elif p["FDEP"]:
        first = p["FDEP"] * scale
    else:
        first = depth
    inc = max(rfp - first, 0.0)
    if inc <= 0:
        raise ProgramError("cycle_parameter", f"{name}: the first depth is not below RFP", src)
    dam = abs(p["DAM"]) * scale
    least = abs(p["MDEP"]) * scale if p["MDEP"] else dam     # the smallest stroke
    frf = p["FRF"] if 0 < p["FRF"] <= 1 else 1.0
    total = rfp - depth
    lead = abs(p["DIS1"]) * scale if p["DIS1"] else 0.6 if total <= 30 else min(total / 50.0, 7.0)
    back = abs(p["VRT"]) * scale if p["VRT"] else 1.0
    z = rfp
    for stroke in range(MAX_STROKES):
        target = max(z - inc, depth)
        go.feed(target, feed * (frf if stroke == 0 else 1.0))
        z = target
        if z <= depth:
            return
        if p["VARI"] == 1:
            go.rapid(rfp + sdis)
            if p["DTS"] > 0:
                go.machine.sink.append(canon.Dwell(src, seconds=p["DTS"]))
            go.rapid(min(z + lead, rfp + sdis))
        else:
            go.rapid(z + back)
        if dam > 0:
            inc = inc - dam if inc - dam > least else least
    raise ProgramError("cycle_parameter", f"{name}: more than {MAX_STROKES} strokes", src)


def pattern(machine, name: str, args, src: SourceRef, modal=None) -> None:
    """Position at each hole of a HOLES1/HOLES2 pattern, drilling with the modal cycle
    (``modal(machine, src)`` runs it; by default a drilling cycle of this module)."""
    p = parameters(name, args, src)
    n = p["NUM"]
    if n != int(n) or not 1 <= n <= MAX_HOLES:
        raise ProgramError("cycle_parameter", f"{name}: NUM must be a whole number of holes, 1 to "
                           f"{MAX_HOLES}", src, num=n)
    n = int(n)
    scale = 25.4 if machine.inch else 1.0
    if name == "HOLES1":
        a = math.radians(p["STA1"])
        d = (math.cos(a), math.sin(a))
        along = [p["FDIS"] + k * p["DBH"] for k in range(n)]
        holes = [((p["SPCA"] + s * d[0]) * scale, (p["SPCO"] + s * d[1]) * scale) for s in along]
        here = plane_point(machine)
        if math.dist(here, holes[-1]) < math.dist(here, holes[0]):
            holes.reverse()
    else:
        step = p["INDA"] if p["INDA"] else 360.0 / n
        angles = [math.radians(p["STA1"] + k * step) for k in range(n)]
        holes = [((p["CPA"] + p["RAD"] * math.cos(t)) * scale, (p["CPO"] + p["RAD"] * math.sin(t)) * scale)
                 for t in angles]
    go = _Mover(machine, src)
    for hole in holes:
        go.rapid_plane(hole)
        if machine.mcall is not None:
            if modal is not None:
                modal(machine, src)
            else:
                drill(machine, machine.mcall[0], machine.mcall[1], src)


class _Mover:
    """Moves in program coordinates (the plane's normal, or within the plane), written as
    canonical commands; the machine's position follows."""

    def __init__(self, machine, src: SourceRef) -> None:
        self.machine, self.src = machine, src
        g = machine.geometry
        self.a, self.b, self.axis = (g.index(n) for n in machine.plane_axes)

    def _go(self, changes: dict[int, float]) -> dict:
        """The machine position with the program coordinates ``changes`` (index -> mm)."""
        m = self.machine
        p = list(m.program_point())
        for i, v in changes.items():
            p[i] = v
        m.pos = m.machine_axes(m.pos, p)
        return dict(m.pos)

    def rapid_plane(self, q: tuple[float, float]) -> None:
        """Rapid in the plane to q (program coordinates), the normal axis kept."""
        self.machine.sink.append(canon.Traverse(self.src, axes=self._go({self.a: q[0], self.b: q[1]})))

    def rapid(self, value: float) -> None:
        self.machine.sink.append(canon.Traverse(self.src, axes=self._go({self.axis: value})))

    def feed(self, value: float, feed: float) -> None:
        self.machine.sink.append(canon.LinearFeed(self.src, axes=self._go({self.axis: value}), feed=feed))
