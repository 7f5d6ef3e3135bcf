"""POCKET3 (rectangular pocket) and POCKET4 (circular pocket), as the control mills them.

The pocket is cleared from the centre out in rings parallel to its outline (at most MIDA
apart, 80 % of the tool diameter when MIDA is 0), level by level from the reference plane
down (levels at most MID deep, all equal):

- VARI units 1, roughing: down to DP + FALD, the walls left FAL thick;
- VARI units 2, finishing: one level at DP, the rings out to the outline itself.

Each level begins with the insertion (VARI tens): 0 straight down at the centre at FFD;
1 on a helix of radius RAD1 about the centre, DP1 per turn, then a full circle at the depth;
2 (POCKET3) oscillating along the pocket's length, sinking at most RAD1 degrees. The cycle
starts over the centre at the retraction plane, ends there too. A pre-machined pocket
(AP1, AP2, AD) is read; the rings still start at the centre (moves through air).

The corner radius CRAD must be at least the tool radius, and the tool must fit the pocket
(after FAL): otherwise ``cycle_parameter``, as the control alarms. Every move carries the
phase: ``approach``, ``roughing depth i/n insertion``, ``roughing depth i/n ring k/m``,
``finishing ring k/m``, ``retraction``.
"""

from __future__ import annotations

import math

from interpreters.sinumerik.cycles.common import Context, clockwise
from interpreters.sinumerik.cycles.path import TINY, circle, levels, place, rounded_rect, steps


def rectangular(ctx: Context) -> None:
    """POCKET3."""
    c = ctx.call
    h = ctx.heights(relative=False)
    r = ctx.tool_radius()
    length, width, crad, centre, angle = ctx.rectangle("pocket")
    if crad < r - TINY:
        raise ctx.fail(f"the tool radius {r:g} is larger than the corner radius {crad:g}",
                       tool_radius=r, crad=crad)
    cw = clockwise(c["CDIR"], inside=True)

    def ring(allow: float):
        hx, hy = length / 2 - r - allow, width / 2 - r - allow
        if min(hx, hy) < -TINY:
            raise ctx.fail(f"the tool (radius {r:g}) does not fit the pocket with the allowance {allow:g}",
                           tool_radius=r)
        hx, hy = max(hx, 0.0), max(hy, 0.0)
        inner = min(hx, hy)
        return [rounded_rect(centre, hx - inner + t, hy - inner + t, crad - r - allow - inner + t, angle, cw)
                for t in steps(inner, _mida(ctx, r))], (hx, hy)

    _mill(ctx, h, r, ring, centre, angle)


def circular(ctx: Context) -> None:
    """POCKET4."""
    h = ctx.heights(relative=False)
    r = ctx.tool_radius()
    prad = abs(ctx.mm("PRAD"))
    centre = (ctx.mm("PA"), ctx.mm("PO"))
    cw = clockwise(ctx.call["CDIR"], inside=True)

    def ring(allow: float):
        rho = prad - r - allow
        if rho < -TINY:
            raise ctx.fail(f"the tool (radius {r:g}) does not fit the pocket of radius {prad:g}",
                           tool_radius=r, prad=prad)
        rho = max(rho, 0.0)
        return [circle(centre, t, cw) for t in steps(rho, _mida(ctx, r))], (rho, rho)

    _mill(ctx, h, r, ring, centre, 0.0)


def _mida(ctx: Context, r: float) -> float:
    mida = abs(ctx.mm("MIDA")) if "MIDA" in ctx.call.values else 0.0
    if mida == 0:
        return 1.6 * r
    if mida > 2 * r + TINY:
        raise ctx.fail(f"the infeed width MIDA {mida:g} is more than the tool diameter {2 * r:g}",
                       mida=mida, tool_diameter=2 * r)
    return mida


def _mill(ctx: Context, h, r: float, ring, centre, angle: float) -> None:
    """Roughing or finishing, level by level, each level's rings from the centre out."""
    c = ctx.call
    vari = int(c["VARI"])
    unit, insertion = vari % 10, vari // 10 % 10
    if unit not in (1, 2) or insertion not in (0, 1, 2) or (insertion == 2 and ctx.name == "POCKET4"):
        raise ctx.fail(f"VARI {vari} is no machining type of the cycle", vari=vari)
    f_plane = ctx.feed("FFP1")
    f_depth = ctx.feed("FFD", "FFP1")
    if c["AP1"] or c["AD"]:
        ctx.simplified("the pre-machined pocket (AP1, AP2, AD) is not used: the rings start at the "
                       "centre and pass through its air")
    if unit == 1:
        loops, half = ring(abs(ctx.mm("FAL")))
        depths = levels(h.rfp, h.depth + abs(ctx.mm("FALD")), abs(ctx.mm("MID")))
        label = "roughing"
    else:
        loops, half = ring(0.0)
        depths = [h.depth]
        label = "finishing"
    ctx.count(len(depths) * len(loops), "depth levels and rings")
    p = ctx.path
    start = loops[0][0]
    ctx.approach(h, *start)
    top = h.safe
    for i, z in enumerate(depths, 1):
        level = f"{label} depth {i}/{len(depths)}" if len(depths) > 1 else label
        p.phase(f"{level} insertion")
        _insert(ctx, insertion, top, z, f_depth, start, centre, angle, half)
        for k, (s, segs) in enumerate(loops, 1):
            p.phase(f"{level} ring {k}/{len(loops)}")
            p.loop(f_plane, s, segs)
        p.phase(f"{level} back to the centre")
        p.feed(f_plane, *start)
        top = z
    ctx.retract(h)


def _insert(ctx: Context, how: int, top: float, z: float, f: float, start, centre, angle, half) -> None:
    """From ``top`` down to the level ``z``, ending at ``start``."""
    p = ctx.path
    if how == 0:
        p.feed(f, *start, n=z)
        return
    c = ctx.call
    if how == 1:
        rad, pitch = abs(ctx.mm("RAD1")), abs(ctx.mm("DP1"))
        if rad <= 0 or pitch <= 0:
            raise ctx.fail("helical insertion needs the helix radius RAD1 and the depth per turn DP1")
        if rad > min(half) + TINY:
            raise ctx.fail(f"the helix radius {rad:g} does not fit the pocket", rad1=rad)
        s = (centre[0] + rad, centre[1])
        p.feed(f, *s)
        halves = max(1, math.ceil(2 * (top - z) / pitch - 1e-9))
        ctx.count(halves, "helix half-turns")
        cw = clockwise(c["CDIR"], inside=True)
        for k in range(1, halves + 1):
            end = s if k % 2 == 0 else (centre[0] - rad, centre[1])
            p.arc(f, end, centre, cw, n=top - (top - z) * k / halves)
        last = (centre[0] - rad, centre[1]) if halves % 2 else s
        other = s if halves % 2 else (centre[0] - rad, centre[1])
        p.arc(f, other, centre, cw)
        p.arc(f, last, centre, cw)
        p.feed(f, *start)
        return
    slope = math.tan(math.radians(abs(c["RAD1"])))
    if slope <= 0 or abs(c["RAD1"]) >= 90:
        raise ctx.fail("oscillating insertion needs the largest insertion angle RAD1 (degrees)")
    hx = half[0]
    if hx <= TINY:
        raise ctx.fail("oscillating insertion needs a pocket longer than the tool")
    ends = [place((hx, 0.0), centre, angle), place((-hx, 0.0), centre, angle)]
    p.feed(f, *ends[0])
    zz, k = top, 0
    while zz > z + TINY:
        zz = max(z, zz - 2 * hx * slope)
        k += 1
        ctx.count(k, "oscillating strokes")
        p.feed(f, *ends[k % 2], n=zz)
    p.feed(f, *ends[(k + 1) % 2])
    p.feed(f, *start)
