"""LONGHOLE, SLOT1 (straight slots) and SLOT2 (circumferential slots) on a circle, as the
control mills them.

The features lie on the circle of radius RAD about (CPA, CPO), the first at STA1 degrees,
then every INDA degrees (0: 360/NUM). Between features the tool rises to the retraction plane.

- LONGHOLE: holes as wide as the tool, LENG long, their length radial and their middle on
  the circle. The tool sinks at most MID per stroke at FFD, alternately at either end, and
  travels the hole at FFP1 until it is at the depth over the whole length.
- SLOT1: slots WID wide and LENG long, their length radial and their middle on the circle;
  SLOT2: slots WID wide whose centre line is the circle's arc from the slot's angle on over
  AFSL degrees (the angle between the centres of its two round ends). Roughing (VARI 0 or 1)
  sinks at FFD at one end of the centre line, level by level (at most MID deep), and mills
  outlines about the centre line from the line out to the walls less FAL (floor DP + _FALD
  for SLOT1), at most 80 % of the tool diameter apart; finishing (VARI 0 or 2) mills the
  outline itself at FFP2 (0: FFP1), level by level at most MIDF deep, and the floor at DP.

The depth is RFP − DPR when DPR is given (not 0), else DP. Phases: ``slot i/n roughing depth
j/m ring k/l``, ``slot i/n finishing depth j/m``, ``hole i/n stroke k``.
"""

from __future__ import annotations

import math

from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.cycles.path import TINY, levels, reverse, ring_arc, stadium, steps

#: most features one call may make
MAX_FEATURES = 10_000


def _angles(ctx: Context) -> list[float]:
    c = ctx.call
    n = c["NUM"]
    if n != int(n) or not 1 <= n <= MAX_FEATURES:
        raise ctx.fail(f"NUM must be a whole number, 1 to {MAX_FEATURES}", num=n)
    n = int(n)
    step = c["INDA"] if c["INDA"] else 360.0 / n
    return [math.radians(c["STA1"] + k * step) for k in range(n)]


def _radial(ctx: Context, t: float, half: float):
    """The centre line of a radial feature at angle t: from half inside the circle to half out."""
    cx, cy, rad = ctx.mm("CPA"), ctx.mm("CPO"), abs(ctx.mm("RAD"))
    u = (math.cos(t), math.sin(t))
    return ((cx + (rad - half) * u[0], cy + (rad - half) * u[1]),
            (cx + (rad + half) * u[0], cy + (rad + half) * u[1]))


def longhole(ctx: Context) -> None:
    h = ctx.heights()
    r = ctx.tool_radius()
    length = abs(ctx.mm("LENG"))
    if length < 2 * r - TINY:
        raise ctx.fail(f"the hole length {length:g} is less than the tool diameter {2 * r:g}",
                       leng=length, tool_diameter=2 * r)
    f_depth, f_plane = ctx.feed("FFD"), ctx.feed("FFP1")
    depths = levels(h.rfp, h.depth, abs(ctx.mm("MID")))
    angles = _angles(ctx)
    ctx.count(len(angles) * len(depths), "holes and strokes")
    p = ctx.path
    for i, t in enumerate(angles, 1):
        ends = _radial(ctx, t, length / 2 - r)
        ctx.approach(h, *ends[0])
        for k, z in enumerate(depths, 1):
            p.phase(f"hole {i}/{len(angles)} stroke {k}/{len(depths)}")
            p.feed(f_depth, n=z)
            p.feed(f_plane, *ends[k % 2])
        ctx.retract(h)


def slot1(ctx: Context) -> None:
    r = ctx.tool_radius()
    length, width = abs(ctx.mm("LENG")), abs(ctx.mm("WID"))
    if width < 2 * r - TINY or length < width - TINY:
        raise ctx.fail(f"the slot {length:g} × {width:g} is narrower than the tool diameter {2 * r:g} "
                       "or shorter than wide", leng=length, wid=width, tool_diameter=2 * r)
    half = (length - width) / 2
    lines = [_radial(ctx, t, half) for t in _angles(ctx)]
    _slots(ctx, r, width, [(line[0], lambda w, ln=line, cw=False: stadium(ln[0], ln[1], w, cw))
                           for line in lines])


def slot2(ctx: Context) -> None:
    r = ctx.tool_radius()
    width = abs(ctx.mm("WID"))
    rad = abs(ctx.mm("RAD"))
    span = math.radians(ctx.call["AFSL"])
    if width < 2 * r - TINY or rad <= width / 2 or not 0 < span < 2 * math.pi:
        raise ctx.fail("the slot must be at least the tool diameter wide, lie outside the circle's "
                       "centre and span more than 0 and less than 360 degrees", wid=width, rad=rad)
    centre = (ctx.mm("CPA"), ctx.mm("CPO"))
    feats = []
    for t in _angles(ctx):
        start = (centre[0] + rad * math.cos(t), centre[1] + rad * math.sin(t))
        feats.append((start, lambda w, t=t: ring_arc(centre, rad, t, t + span, w, False)))
    _slots(ctx, r, width, feats)


def _slots(ctx: Context, r: float, width: float, feats) -> None:
    """Rough and finish each slot: ``feats`` is (plunge point, outline at distance w)."""
    c = ctx.call
    h = ctx.heights()
    vari = int(c["VARI"]) % 10
    if vari not in (0, 1, 2):
        raise ctx.fail(f"VARI {int(c['VARI'])} is no machining type of the cycle", vari=c["VARI"])
    fal = abs(ctx.mm("FAL"))
    fald = abs(ctx.mm("FALD")) if "FALD" in c.values else 0.0
    wall = width / 2 - r
    if vari == 2:
        fal = fald = 0.0
    if wall - fal < -TINY:
        raise ctx.fail(f"the finishing allowance {fal:g} leaves no room for the tool", fal=fal)
    f_depth, f_plane = ctx.feed("FFD", "FFP1"), ctx.feed("FFP1")
    if "STA2" in c.values and c["STA2"]:
        ctx.simplified("oscillating insertion (_STA2) is not simulated: the tool inserts vertically at FFD")
    f_finish = ctx.feed("FFP2", "FFP1")
    cw = c["CDIR"] == 2
    rough = levels(h.rfp, h.depth + fald, abs(ctx.mm("MID"))) if vari in (0, 1) else []
    finish = levels(h.rfp, h.depth, abs(ctx.mm("MIDF"))) if vari in (0, 2) else []
    rings = steps(max(wall - fal, 0.0), 1.6 * r)
    ctx.count(len(feats) * (len(rough) * len(rings) + len(finish)), "slots, levels and rings")
    p = ctx.path
    for i, (plunge, outline) in enumerate(feats, 1):
        slot = f"slot {i}/{len(feats)}"
        ctx.approach(h, *plunge)
        for j, z in enumerate(rough, 1):
            p.phase(f"{slot} roughing depth {j}/{len(rough)} insertion")
            p.feed(f_depth, *plunge, n=z)
            for k, w in enumerate(rings, 1):
                p.phase(f"{slot} roughing depth {j}/{len(rough)} ring {k}/{len(rings)}")
                s, segs = outline(w)
                p.loop(f_plane, s, segs)
            p.feed(f_plane, *plunge)
        for j, z in enumerate(finish, 1):
            p.phase(f"{slot} finishing depth {j}/{len(finish)}")
            p.feed(f_depth, *plunge, n=z)
            ws = rings if (j == len(finish) and fald > 0) else [wall]
            for w in ws:
                s, segs = outline(w)
                if cw:
                    s, segs = reverse(s, segs)
                p.loop(f_finish, s, segs)
            p.feed(f_finish, *plunge)
        ctx.retract(h)

