"""CYCLE71 (face milling) and CYCLE61 (face milling, SINUMERIK Operate), as the control
mills them.

The area is the rectangle from the corner (PA, PO) over LENG along the plane's first axis
and WID along the second (their signs give the direction), turned by STA degrees about the
corner (CYCLE71). The tool runs in straight passes (VARI tens: 1 along the length one way,
2 along the width one way, 3 along the length to and fro, 4 along the width to and fro) at
FFP1, at most MIDA apart (0: 80 % of the tool diameter), its edge FDP1 beyond the area's
sides on the first and last pass; each pass starts and ends with the tool a radius plus FDP
clear of the area. Level by level from the reference plane (at most MID deep, all equal):

- VARI units 1, roughing: down to DP + FALD;
- VARI units 2, finishing: one level at DP.

One-way passes return at rapid over the reference plane plus SDIS; to-and-fro passes step
over beside the area at the depth. Phases: ``approach``, ``roughing depth i/n pass k/m``,
``finishing pass k/m``, ``retraction``.
"""

from __future__ import annotations

import math

from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.cycles.path import levels, place, steps


def face(ctx: Context) -> None:
    c = ctx.call
    h = ctx.heights(relative=False)
    r = ctx.tool_radius()
    vari = int(c["VARI"])
    unit, way = vari % 10, vari // 10 % 10
    if unit not in (1, 2) or way not in (1, 2, 3, 4):
        raise ctx.fail(f"VARI {vari} is no machining type of the cycle", vari=vari)
    length, width = ctx.mm("LENG"), ctx.mm("WID")
    if length == 0 or width == 0:
        raise ctx.fail("give the area's length and width", leng=length, wid=width)
    corner = (ctx.mm("PA"), ctx.mm("PO"))
    angle = math.radians(c["STA"]) if "STA" in c.values else 0.0
    mida = abs(ctx.mm("MIDA")) or 1.6 * r
    if mida > 2 * r:
        raise ctx.fail(f"the infeed width MIDA {mida:g} is more than the tool diameter {2 * r:g}",
                       mida=mida, tool_diameter=2 * r)
    fdp, fdp1 = abs(ctx.mm("FDP")), abs(ctx.mm("FDP1")) if "FDP1" in c.values else 0.0
    f = ctx.feed("FFP1")
    if "LIM" in c.values and c["LIM"]:
        ctx.simplified("the limits (_LIM) are not simulated: the area is faced to its corners")
    along = way in (1, 3)                        # passes along the length
    lo_a, hi_a = sorted((0.0, length))
    lo_b, hi_b = sorted((0.0, width))
    if not along:
        lo_a, hi_a, lo_b, hi_b = lo_b, hi_b, lo_a, hi_a
    first, last = lo_b + r - fdp1, hi_b - r + fdp1
    if last < first:
        first = last = (lo_b + hi_b) / 2
    passes = [first + s for s in steps(last - first, mida)]
    ends = (lo_a - r - fdp, hi_a + r + fdp)

    def at(u: float, v: float):
        return place((u, v) if along else (v, u), corner, angle)

    if unit == 1:
        depths = levels(h.rfp, h.depth + abs(ctx.mm("FALD")), abs(ctx.mm("MID")))
        label = "roughing"
    else:
        depths = [h.depth]
        label = "finishing"
    ctx.count(len(depths) * len(passes), "depth levels and passes")
    p = ctx.path
    ctx.approach(h, *at(ends[0], passes[0]))
    for i, z in enumerate(depths, 1):
        level = f"{label} depth {i}/{len(depths)}" if len(depths) > 1 else label
        side = 0
        for k, v in enumerate(passes, 1):
            p.phase(f"{level} pass {k}/{len(passes)}")
            if k == 1 or way in (1, 2):
                if k > 1:
                    p.rapid(n=h.safe)
                p.rapid(*at(ends[0], v))
                p.feed(f, n=z)
                side = 0
            else:
                p.feed(f, *at(ends[side], v))
            side = 1 - side
            p.feed(f, *at(ends[side], v))
        p.phase(f"{level} lift")
        p.rapid(n=h.safe)
    ctx.retract(h)
