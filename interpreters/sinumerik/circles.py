"""Circle forms of the Sinumerik dialect, in program coordinates of the working plane (mm):
the centre given (I/J/K), by its radius (CR=), by an opening angle (AR=), through an
intermediate point (CIP, I1= J1= K1=) or tangent to the path before it (CT)."""

from __future__ import annotations

import math

from vmach.errors import ProgramError
from vmach.source import SourceRef


def intermediate(machine, v, ps, src: SourceRef) -> tuple:
    """CIP's intermediate point (I1= J1= K1=), program coordinates: absolute under G90 or
    with AC, from the start under G91 or with IC."""
    scale = 25.4 if machine.inch else 1.0
    out = list(ps)
    given = False
    for i, letter in enumerate(("I1", "J1", "K1")):
        if letter in v.interp:
            val, mode = v.interp[letter]
            val = float(val) * scale
            inc = mode == "IC" or (mode is None and not machine.absolute)
            out[i] = ps[i] + val if inc else val
            given = True
    if not given:
        raise ProgramError("arc_error", "CIP needs the intermediate point I1= J1= K1=", src)
    return tuple(out)


def opening(machine, v, ps, pe, cw: bool, ia: int, ib: int, scale: float, src: SourceRef):
    """G2/G3 with AR= (opening angle, degrees): the centre from the end point, or the end
    point from the centre (I/J). Returns (centre, new end or None)."""
    ar = float(v.interp["AR"][0])
    letters = {"X": "I", "Y": "J", "Z": "K"}
    la, lb = letters[machine.plane_axes[0]], letters[machine.plane_axes[1]]
    if not 0 < ar < 360:
        raise ProgramError("arc_error", f"AR={ar:g}: the opening angle must lie between 0 and 360", src)
    if la in v.interp or lb in v.interp:
        vals = []
        for letter, i in ((la, ia), (lb, ib)):
            val, mode = v.interp.get(letter, (0.0, None))
            val = float(val) * scale
            vals.append(val if mode == "AC" else ps[i] + val)
        c = (vals[0], vals[1])
        t = math.radians(-ar if cw else ar)
        u = (ps[ia] - c[0], ps[ib] - c[1])
        end = list(pe)
        end[ia] = c[0] + u[0] * math.cos(t) - u[1] * math.sin(t)
        end[ib] = c[1] + u[0] * math.sin(t) + u[1] * math.cos(t)
        return c, tuple(end)
    chord = math.hypot(pe[ia] - ps[ia], pe[ib] - ps[ib])
    if chord < 1e-12:
        raise ProgramError("arc_error", "AR= with the end point at the start", src)
    r = chord / (2.0 * math.sin(math.radians(ar) / 2.0))
    # a CR= of the same circle: negative for more than 180°
    return centre_from_radius(ps[ia], ps[ib], pe[ia], pe[ib], r if ar <= 180 else -r, cw, src), None


def through(ps, pe, pm, ia: int, ib: int, src: SourceRef):
    """Centre (plane) and direction of the circle from ps through pm to pe (CIP)."""
    k = 3 - ia - ib
    if abs(pm[k] - ps[k]) > 1e-6 or abs(pe[k] - ps[k]) > 1e-6:
        raise ProgramError("unsupported", "CIP with the three points off the working plane (a circle in "
                           "space) is not simulated", src)
    ax, ay, bx, by, cx, cy = ps[ia], ps[ib], pm[ia], pm[ib], pe[ia], pe[ib]
    d = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    if abs(d) < 1e-12 * max(1.0, ax * ax + ay * ay + bx * bx + by * by + cx * cx + cy * cy):
        raise ProgramError("arc_error", "CIP: the three points lie on a line", src)
    a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    ux = (a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / d
    uy = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d
    return (ux, uy), d < 0                  # the turn start -> middle -> end: clockwise when d < 0


def tangential(ps, pe, tangent, ia: int, ib: int, src: SourceRef):
    """Centre and direction of the circle leaving ps along ``tangent`` to pe (CT)."""
    if tangent is None:
        raise ProgramError("arc_error", "CT needs a path before it to be tangent to", src)
    d = (pe[ia] - ps[ia], pe[ib] - ps[ib])
    n = (-tangent[1], tangent[0])                 # left of the tangent
    dn = d[0] * n[0] + d[1] * n[1]
    if abs(dn) < 1e-9:
        raise ProgramError("arc_error", "CT: the end point lies on the tangent (a straight line)", src)
    rho = (d[0] * d[0] + d[1] * d[1]) / (2.0 * dn)   # signed: > 0 centre on the left (counter-clockwise)
    return (ps[ia] + rho * n[0], ps[ib] + rho * n[1]), rho < 0


def centre_from_radius(xa, ya, xb, yb, r, cw, src):
    """Centre of the arc from (xa, ya) to (xb, yb) with radius r (r < 0: more than 180°)."""
    dx, dy = xb - xa, yb - ya
    chord = math.hypot(dx, dy)
    if chord < 1e-12:
        raise ProgramError("arc_error", "CR= cannot describe a full circle", src)
    if chord > 2 * abs(r) + 1e-9:
        raise ProgramError("arc_error", f"CR={r}: the end point is farther than the diameter", src)
    h = math.sqrt(max(r * r - chord * chord / 4.0, 0.0))
    mx, my = (xa + xb) / 2.0, (ya + yb) / 2.0
    # left normal of the chord; a clockwise minor arc has its centre on the right
    nx, ny = -dy / chord, dx / chord
    side = -1.0 if cw else 1.0
    if r < 0:
        side = -side
    return mx + side * h * nx, my + side * h * ny
