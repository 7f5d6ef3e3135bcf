"""CYCLE97, thread cutting (840D "Cycles" manual, Turning cycles): a longitudinal or taper
thread, outside or inside, in roughing cuts, a finishing cut and idle passes, for each start.

As the control runs it: the cut runs from SPL brought forward by the run-in APP to FPL
carried on by the run-out ROP, along the thread's diameter line (DM1 at SPL, DM2 at FPL); the
cycle's starting point lies on the run-in, ``_VRT`` (1 mm) off the larger (outside) or
smaller (inside) thread diameter, and is where the tool returns after each cut (G0 off in X,
G0 back in Z) and at the end. TDEP less FAL is divided into NRC roughing depths, equal
(VARI 1, 2: constant infeed) or growing with the square root of the cut's number (VARI 3,
4: constant cutting cross-section); then FAL in one cut and NID idle passes at TDEP. With
IANG the infeed follows a flank: each cut starts d·tan(|IANG|) back along Z at depth d (on
alternate flanks for a negative IANG). NUMT starts repeat the whole; NSP turns only the
spindle's start angle. Lengths in mm (inches under G70/G700), X a radius on the stream.
"""

from __future__ import annotations

import math

from interpreters.sinumerik.cycles.boring import COARSE
from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.turning import threads
from vmach.errors import ProgramError


def cycle97(ctx: Context) -> None:
    c, m = ctx.call, ctx.machine
    if m.plane != "G18":
        raise ctx.fail("turning cycles work in the Z-X plane (G18 first)")
    lead = abs(ctx.mm("PIT"))
    if c["MPIT"]:
        table = COARSE.get(abs(c["MPIT"]))
        if table is None:
            raise ctx.fail(f"MPIT {c['MPIT']:g} is no metric coarse thread (3 to 60)", mpit=c["MPIT"])
        if lead and abs(lead - table * ctx.scale) > 1e-9:
            raise ctx.fail(f"PIT {c['PIT']:g} and MPIT {c['MPIT']:g} contradict each other")
        lead = lead or table
    if lead <= 0:
        raise ctx.fail("give the lead, PIT or MPIT")
    spl, fpl = ctx.mm("SPL"), ctx.mm("FPL")
    r1, r2 = ctx.mm("DM1") / 2, ctx.mm("DM2") / 2
    if abs(fpl - spl) < 1e-9:
        raise ctx.fail("the thread has no length (SPL = FPL)")
    if abs(r2 - r1) > abs(fpl - spl):
        raise ProgramError("unsupported", "CYCLE97: a face thread (taper over 45°) is not simulated",
                           ctx.src)
    vari = int(c["VARI"])
    if vari not in (1, 2, 3, 4):
        raise ctx.fail(f"VARI {vari} is no machining type (1 to 4)", vari=vari)
    tdep, fal = abs(ctx.mm("TDEP")), abs(ctx.mm("FAL"))
    nrc, nid, numt = int(c["NRC"]), int(c["NID"]), int(c["NUMT"])
    if tdep <= 0 or fal > tdep:
        raise ctx.fail(f"the thread depth TDEP {tdep:g} must be above 0 and not below FAL {fal:g}")
    if nrc < 1 or nid < 0 or numt < 1:
        raise ctx.fail("NRC and NUMT must be at least 1, NID not negative")
    ctx.count(numt * (nrc + 1 + nid), "thread cuts")
    side = 1.0 if vari in (1, 3) else -1.0           # outside: the depth takes from the radius
    step = 1.0 if fpl > spl else -1.0
    z0, z1 = spl - step * abs(ctx.mm("APP")), fpl + step * abs(ctx.mm("ROP"))

    def radius(z: float) -> float:
        return r1 + (r2 - r1) * (z - spl) / (fpl - spl)

    lift = (max(r1, r2) if side > 0 else min(r1, r2)) + side * (abs(ctx.mm("VRT")) or 1.0)
    rough = tdep - fal
    cuts = [(rough * (k / nrc if vari in (1, 2) else math.sqrt(k / nrc)), "roughing")
            for k in range(1, nrc + 1)]
    if fal > 0:
        cuts.append((tdep, "finishing"))
    cuts += [(tdep, "idle pass")] * nid
    flank = math.tan(math.radians(abs(c["IANG"])))
    p = ctx.path
    p.phase("approach")
    p.rapid(a=z0, b=lift)
    for start in range(1, numt + 1):
        for k, (depth, what) in enumerate(cuts, 1):
            shift = depth * flank * (1 if c["IANG"] >= 0 or k % 2 else -1)
            za = z0 - step * shift
            xa, xb = radius(za) - side * depth, radius(z1) - side * depth
            p.phase(f"start {start}/{numt} cut {k}/{len(cuts)} ({what})")
            p.rapid(a=za, b=lift)
            p.rapid(b=xa)
            length = math.hypot(z1 - za, xb - xa)
            p.feed(threads.path_feed(m, lead, abs(z1 - za), length, ctx.name, ctx.src), a=z1, b=xb)
            p.rapid(b=lift)
            p.rapid(a=z0)
    threads.say_envelope(m, ctx.src)
