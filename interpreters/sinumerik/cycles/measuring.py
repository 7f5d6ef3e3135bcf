"""The workpiece measuring cycles CYCLE978 (edge), CYCLE977 (hole, spigot, groove, web,
rectangle), CYCLE998 (angle of an edge), CYCLE979 (circle segment) and CYCLE976 (probe
calibration), as probe moves.

The probe (the active tool; its radius is the stylus ball's) is where the program put it: at
the measuring height in the hole, or over the spigot. Each probing point is reached at the
positioning feed ``POSITIONING`` (mm/min), _FA before the nominal contact; the measuring move
(:class:`vmach.canon.ProbeMove`) runs at ``MEASURING`` from there to _FA beyond it and the
probe goes back the way it came. In the plane the stylus touches a wall when its centre is a
ball radius from it; along the tool axis its tip touches the surface.

The control would measure; vmach cannot. The result is the nominal one (the setpoint, a
difference of 0): an ``info`` finding ``measurement`` per call says so and carries it, and
the result variables _OVR/_OVI get it where the directory's definition files define them (as
the control's measuring-cycle package does). In verify each measuring move stops at contact
with the simulated stock, and a move that meets nothing or hits it outside a measuring move
is a finding (:mod:`vmach.checks.probing`).
"""

from __future__ import annotations

import math

from interpreters.sinumerik.cycles.common import Context
from vmach.errors import ProgramError
from vmach.findings import info

#: feeds of the cycle's positioning and measuring moves, mm/min (the control takes them from
#: the probe's data; these are its usual values)
POSITIONING, MEASURING = 1000.0, 300.0
#: _OVR indices vmach writes: setpoint, actual (nominal), difference; _OVI: the cycle number
OVR_SET, OVR_ACT, OVR_DIFF = 0, 4, 16
FEATURES = {1: "hole", 2: "spigot", 3: "groove", 4: "web", 5: "rectangle inside", 6: "rectangle outside"}


def _direction(md: float) -> float:
    return -1.0 if int(md) == 2 else 1.0


class _Probe:
    """The probe's moves of one call, in program coordinates of the plane (a, b, n)."""

    def __init__(self, ctx: Context) -> None:
        self.ctx, self.p = ctx, ctx.path
        if ctx.machine.cutcom.engaged:
            raise ctx.fail("measuring while tool radius compensation is active (G40 first)")
        self.r = max(ctx.machine.tool_radius(ctx.name, ctx.src) or 0.0, 0.0)
        self.fa = abs(ctx.mm("FA"))
        if self.fa <= 0:
            raise ctx.fail("give the measuring path _FA")
        self.points = 0

    def along(self, axis: int, setval: float, sign: float) -> None:
        """Probe along program axis ``axis`` (0, 1 in the plane, 2 the tool axis) in the
        direction ``sign`` toward an edge at ``setval``; back to the start."""
        p = self.p
        start = p.here()
        contact = setval - sign * (self.r if axis < 2 else 0.0)
        q = list(start)
        q[axis] = contact - sign * self.fa
        self._point()
        if (q[axis] - start[axis]) * sign > 0:
            p.feed(POSITIONING, *q)
        q[axis] = contact + sign * self.fa
        p.probe(MEASURING, *q)
        p.feed(POSITIONING, *start)

    def radial(self, centre, u, distance: float, outside: bool, infeed: float) -> None:
        """Probe in the plane along the unit direction ``u`` (from ``centre`` outward) at a wall
        ``distance`` from the centre: from inside it (a hole) or, ``outside``, from beyond it
        after going down by ``infeed`` (a spigot); back to the centre."""
        p = self.p
        a, b, n = p.here()
        self._point()
        if outside:
            d0, d1 = distance + self.r + self.fa, distance + self.r - self.fa
        else:
            d0, d1 = distance - self.r - self.fa, distance - self.r + self.fa
        if d0 < 0 or (not outside and d1 <= 0):
            raise self.ctx.fail("the measuring path does not fit the feature with this probe",
                                distance=distance, probe_radius=self.r)
        p.feed(POSITIONING, centre[0] + d0 * u[0], centre[1] + d0 * u[1])
        if outside and infeed:
            p.feed(POSITIONING, n=n + infeed)
        p.probe(MEASURING, centre[0] + d1 * u[0], centre[1] + d1 * u[1])
        p.feed(POSITIONING, centre[0] + d0 * u[0], centre[1] + d0 * u[1])
        if outside and infeed:
            p.feed(POSITIONING, n=n)
        p.feed(POSITIONING, a, b)

    def _point(self) -> None:
        self.points += 1
        self.p.phase(f"probing point {self.points}")


def measure(ctx: Context) -> None:
    """The call's probe moves and nominal result."""
    c = ctx.call
    if not c.given:
        raise ProgramError("unsupported", f"{ctx.name} without values: the measuring cycles' older "
                           "form (their GUD parameters _MVAR, _SETVAL … set before the call) is not "
                           "simulated", ctx.src)
    probe = _Probe(ctx)
    name = ctx.name
    mvar = int(c["MVAR"])
    here = ctx.path.here()
    if name == "CYCLE978" or (name == "CYCLE976" and mvar % 10 == 1):
        axis = int(c["MA"])
        if axis not in (1, 2, 3):
            raise ctx.fail(f"_MA {axis} is no measuring axis (1, 2 or 3)", ma=axis)
        setval = ctx.mm("SETVAL")
        probe.along(axis - 1, setval, _direction(c["MD"]))
        what, result = f"the edge along {ctx.machine.plane_axes[axis - 1]}", setval
    elif name == "CYCLE998":
        ma = int(c["MA"])
        axis, offset = ma % 10 - 1, ma // 100 - 1
        if {axis, offset} != {0, 1}:
            raise ctx.fail(f"_MA {ma} names no measuring and offset axis of the plane", ma=ma)
        sign, setval, slope = _direction(c["MD"]), ctx.mm("SETVAL"), math.tan(math.radians(c["STA1"]))
        probe.along(axis, setval, sign)
        q = list(here)
        q[offset] += ctx.mm("ID")
        ctx.path.feed(POSITIONING, *q)
        probe.along(axis, setval + ctx.mm("ID") * slope, sign)
        ctx.path.feed(POSITIONING, *here)
        what, result = "the edge's angle", c["STA1"]
    else:
        feature, centre, dirs, result = _feature(ctx, mvar, here)
        outside = feature in (2, 4, 6)
        for u, distance in dirs:
            probe.radial(centre, u, distance, outside, ctx.mm("ID") if "ID" in c.values else 0.0)
        what = ("the ring gauge" if name == "CYCLE976" else f"the {FEATURES[feature]}")
    _report(ctx, what, result, probe.points)


def _feature(ctx: Context, mvar: int, here):
    """(feature, centre, [(direction, wall distance)], nominal size) of a CYCLE977/979/976 call."""
    c = ctx.call
    name = ctx.name
    feature = 1 if name == "CYCLE976" else mvar % 10
    if feature not in FEATURES or (name == "CYCLE979" and feature > 4):
        raise ctx.fail(f"_MVAR {mvar} is no measuring variant of the cycle", mvar=mvar)
    sta = math.radians(c["STA1"])
    if feature in (5, 6):
        a, b = abs(ctx.mm("SETV0")) / 2, abs(ctx.mm("SETV1")) / 2
        if a <= 0 or b <= 0:
            raise ctx.fail("give the rectangle's lengths _SETV0 and _SETV1")
        return feature, here[:2], [((1, 0), a), ((-1, 0), a), ((0, 1), b), ((0, -1), b)], (2 * a, 2 * b)
    size = abs(ctx.mm("SETVAL"))
    if size <= 0:
        raise ctx.fail("give the setpoint diameter or width _SETVAL")
    if feature in (3, 4):
        k = int(c["MA"]) - 1
        if k not in (0, 1):
            raise ctx.fail("_MA must be 1 or 2 for a groove or web", ma=c["MA"])
        u = (1.0, 0.0) if k == 0 else (0.0, 1.0)
        return feature, here[:2], [(u, size / 2), ((-u[0], -u[1]), size / 2)], size
    if name == "CYCLE979":
        n = 4 if mvar // 10 % 10 == 1 else 3
        step = math.radians(c["INCA"]) if c["INCA"] else 2 * math.pi / n
        centre = (ctx.mm("CPA"), ctx.mm("CPO"))
    else:
        n, step, centre = 4, math.pi / 2, here[:2]
    return feature, centre, [((math.cos(sta + k * step), math.sin(sta + k * step)), size / 2)
                             for k in range(n)], size


def _report(ctx: Context, what: str, result, points: int) -> None:
    """The info finding and the result variables (where defined) of a measurement."""
    values = result if isinstance(result, tuple) else (result,)
    shown = " × ".join(f"{v:g}" for v in values)
    ctx.machine.notes.append(info(
        "measurement", f"{ctx.name} measures {what} at {points} point(s): nominal result {shown} "
        "(the control would measure the part; vmach reports the programmed value)", ctx.src,
        cycle=ctx.name, nominal=list(values), points=points))
    gud = getattr(ctx.machine, "globals", {})
    ovr = gud.get("_OVR")
    if isinstance(ovr, list) and len(ovr) > OVR_DIFF:
        ovr[OVR_SET] = ovr[OVR_ACT] = float(values[0])
        ovr[OVR_DIFF] = 0.0
    ovi = gud.get("_OVI")
    if isinstance(ovi, list) and len(ovi) > 2:
        ovi[2] = int(ctx.name[5:])
