"""CYCLE76 (rectangular spigot), CYCLE77 (circular spigot) and CYCLE79 (multi-edge), as the
control mills them.

The spigot is milled from its blank (AP1 × AP2, or the blank diameter AP1; not given: the
spigot plus a tool diameter all round) inwards in rings parallel to its outline, at most 80 %
of the tool diameter apart, level by level from the reference plane down (levels at most MID
deep, all equal). The tool goes down beside the blank (a tool radius clear of it), mills the
rings from the outside in and leaves radially:

- VARI 1, roughing: down to the foot + FALD, the walls left FAL thick;
- VARI 2, finishing: one ring on the outline itself, level by level.

CYCLE79's blank is a cylinder of diameter AP1 (not given: the corner circle plus two tool
diameters); its rings are the multi-edge offset outwards (flats moved out, corner radius
grown by the same amount), the outermost one clear of the blank's circle.

The depth is RFP − DPR when DPR is given (not 0), else DP. Phases as the pockets:
``approach``, ``roughing depth i/n ring k/m``, ``finishing depth i/n``, ``retraction``.
"""

from __future__ import annotations

import math

from interpreters.sinumerik.cycles.common import Context, clockwise
from interpreters.sinumerik.cycles.path import (
    TINY,
    circle,
    levels,
    place,
    rounded_polygon,
    rounded_rect,
    steps,
)


def rectangular(ctx: Context) -> None:
    """CYCLE76."""
    c = ctx.call
    h = ctx.heights()
    r = ctx.tool_radius()
    length, width, crad, centre, angle = ctx.rectangle("spigot")
    blank = (abs(ctx.mm("AP1")) or length + 4 * r, abs(ctx.mm("AP2")) or width + 4 * r)
    if blank[0] < length or blank[1] < width:
        raise ctx.fail("the blank (AP1, AP2) is smaller than the spigot", ap1=blank[0], ap2=blank[1])
    cw = clockwise(c["CDIR"], inside=False)
    excess = max(blank[0] - length, blank[1] - width) / 2

    def ring(allow: float, e: float):
        return rounded_rect(centre, length / 2 + r + allow + e, width / 2 + r + allow + e,
                            crad + r + allow + e, angle, cw)

    outside = place((length / 2 + excess + 2 * r, 0.0), centre, angle)
    _mill(ctx, h, r, ring, excess, outside)


def circular(ctx: Context) -> None:
    """CYCLE77."""
    h = ctx.heights()
    r = ctx.tool_radius()
    diameter = abs(ctx.mm("PRAD"))
    if diameter <= 0:
        raise ctx.fail("give the spigot's diameter PRAD")
    blank = abs(ctx.mm("AP1")) or diameter + 4 * r
    if blank < diameter:
        raise ctx.fail("the blank diameter AP1 is smaller than the spigot", ap1=blank)
    centre = (ctx.mm("PA"), ctx.mm("PO"))
    cw = clockwise(ctx.call["CDIR"], inside=False)

    def ring(allow: float, e: float):
        return circle(centre, diameter / 2 + r + allow + e, cw)

    outside = (centre[0] + blank / 2 + 2 * r, centre[1])
    _mill(ctx, h, r, ring, (blank - diameter) / 2, outside)


def polygon(ctx: Context) -> None:
    """CYCLE79."""
    c = ctx.call
    h = ctx.heights()
    r = ctx.tool_radius()
    n = int(c["NUM"])
    if n < 3:
        raise ctx.fail(f"a multi-edge needs 3 or more edges, not {n}", num=n)
    size = abs(ctx.mm("SWL"))
    if size <= 0:
        raise ctx.fail("give the width across flats or the edge length SWL")
    apothem = size / 2 if c["UMODE"] == 0 else size / (2 * math.tan(math.pi / n))
    crad = abs(ctx.mm("CRAD"))
    if crad > apothem + TINY:
        raise ctx.fail(f"the corner radius {crad:g} is more than the multi-edge allows", crad=crad)
    corner = (apothem - crad) / math.cos(math.pi / n) + crad
    blank = abs(ctx.mm("AP1")) or 2 * corner + 4 * r
    if blank / 2 < corner - TINY:
        raise ctx.fail("the blank diameter AP1 is smaller than the multi-edge's corners", ap1=blank)
    centre = (ctx.mm("PA"), ctx.mm("PO"))
    angle = math.radians(c["STA"])
    cw = clockwise(c["CDIR"], inside=False)

    def ring(allow: float, e: float):
        return rounded_polygon(centre, n, apothem + r + allow + e, crad + r + allow + e, angle, cw)

    outside = place((blank / 2 + 2 * r, 0.0), centre, angle)
    _mill(ctx, h, r, ring, max(blank / 2 - apothem, 0.0), outside)


def _mill(ctx: Context, h, r: float, ring, excess: float, outside) -> None:
    c = ctx.call
    unit = int(c["VARI"]) % 10
    if unit not in (1, 2):
        raise ctx.fail(f"VARI {int(c['VARI'])} is no machining type of the cycle", vari=c["VARI"])
    f_plane = ctx.feed("FFP1")
    f_depth = ctx.feed("FFD", "FFP1")
    fal, fald = abs(ctx.mm("FAL")), abs(ctx.mm("FALD"))
    if unit == 1:
        extra = [e for e in reversed(steps(max(excess - fal, 0.0), 1.6 * r))]
        loops = [ring(fal, e) for e in extra]
        depths = levels(h.rfp, h.depth + fald, abs(ctx.mm("MID")))
        label = "roughing"
    else:
        loops = [ring(0.0, 0.0)]
        depths = levels(h.rfp, h.depth, abs(ctx.mm("MID")))
        label = "finishing"
    ctx.count(len(depths) * len(loops), "depth levels and rings")
    p = ctx.path
    ctx.approach(h, *outside)
    for i, z in enumerate(depths, 1):
        level = f"{label} depth {i}/{len(depths)}" if len(depths) > 1 else label
        p.phase(f"{level} infeed")
        p.feed(f_depth, n=z)
        for k, (s, segs) in enumerate(loops, 1):
            p.phase(f"{level} ring {k}/{len(loops)}" if len(loops) > 1 else level)
            p.loop(f_plane, s, segs)
        p.phase(f"{level} away from the spigot")
        p.feed(f_plane, *outside)
    ctx.retract(h)
