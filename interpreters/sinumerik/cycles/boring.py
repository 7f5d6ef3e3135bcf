"""Boring, reaming and tapping at the current position: CYCLE85–CYCLE89, CYCLE84 (rigid
tapping) and CYCLE840 (tapping with a compensating chuck), called once or with MCALL.

Like the drilling cycles, they work along the plane's normal at the current position of the
plane: rapid to RFP + SDIS, in to the depth, out, rapid to RTP (program coordinates, mm).

- CYCLE85: in at FFR, dwell DTB, out at RFF (0: FFR) to RFP + SDIS.
- CYCLE86: in at F, dwell DTB, oriented spindle stop, out at rapid to RTP, the spindle on
  again (SDIR). The control first lifts the bar off the wall by RPA/RPO/RPAP; vmach's tools
  are solids of revolution (a lifted-off bar would cut the bore), so it retracts on the axis.
- CYCLE87: in at F, spindle stop, program stop (M0), out at rapid, the spindle on (SDIR).
- CYCLE88: as CYCLE87 with a dwell DTB at the depth.
- CYCLE89: in at F, dwell DTB, out at F.
- CYCLE84: the pitch PIT (or the metric size MPIT, ISO coarse), in at pitch × SST (pitch per
  revolution under G95), dwell DTB, the spindle reversed, out at pitch × SST1 (0: SST); the
  spindle afterwards as SDAC says. _VARI 1/2 (chip breaking, swarf removal) tap in strokes of
  _DAM, backing off _VRT (1 mm) or to RFP + SDIS between them.
- CYCLE840: in at F (or pitch × speed when a pitch is given), dwell, spindle reversed (SDR 0)
  or as SDR says, out at the same feed; the spindle afterwards as SDAC says.

Phases: ``approach``, ``in``, ``out``, ``stroke k``, ``retraction``.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from interpreters.sinumerik.cycles.common import Context, Heights
from interpreters.sinumerik.drilling import PLANE_AXN
from vmach import canon
from vmach.errors import ProgramError

#: ISO metric coarse pitch by nominal size (mm)
COARSE = {float(k): v for k, v in tomllib.loads(
    Path(__file__).with_name("threads.toml").read_text(encoding="utf-8"))["metric_coarse"].items()}
DIRECTIONS = {3: "cw", 4: "ccw", 5: "stop"}


def bore(ctx: Context) -> None:
    """CYCLE85 … CYCLE89."""
    c, name = ctx.call, ctx.name
    h = _start(ctx)
    p = ctx.path
    f_in = ctx.feed("FFR") if name == "CYCLE85" else ctx.feed()
    p.phase("in")
    p.feed(f_in, n=h.depth)
    if c["DTB"] if "DTB" in c.values else 0:
        ctx.machine.sink.append(canon.Dwell(p.src, seconds=c["DTB"]))
    if name in ("CYCLE85", "CYCLE89"):
        p.phase("out")
        p.feed(ctx.feed("RFF", "FFR") if name == "CYCLE85" else f_in, n=h.safe)
        ctx.retract(h)
        return
    _spindle(ctx, "stop")
    if name == "CYCLE86":
        if c["RPA"] or c["RPO"] or c["RPAP"]:
            ctx.simplified("the lift-off (RPA, RPO, RPAP) is not moved: vmach's tools are solids of "
                           "revolution, a bar lifted off its wall would cut it; it retracts on its axis")
        ctx.retract(h)
    else:
        ctx.machine.sink.append(canon.Pause(p.src))
        ctx.retract(h)
    _spindle(ctx, DIRECTIONS.get(int(c["SDIR"]), "cw"))


def tap(ctx: Context) -> None:
    """CYCLE84 and CYCLE840."""
    c, m = ctx.call, ctx.machine
    h = _start(ctx)
    p = ctx.path
    pitch = abs(ctx.mm("PIT")) if c["PIT"] else COARSE.get(abs(c["MPIT"]), 0.0)
    if c["MPIT"] and not c["PIT"] and not pitch:
        raise ctx.fail(f"MPIT {c['MPIT']:g} is no metric coarse thread (3 to 48)", mpit=c["MPIT"])
    speed = m.spindles.get(m.master, [0.0, "stop"])[0]
    if ctx.name == "CYCLE84":
        if not pitch:
            raise ctx.fail("rigid tapping needs the pitch, PIT or MPIT")
        s_in = c["SST"] or speed
        s_out = c["SST1"] or s_in
    else:
        s_in = s_out = speed
    per_rev = m.feed_mode == "per_rev"
    if pitch and (per_rev or s_in > 0):
        f_in = pitch if per_rev else pitch * s_in
        f_out = pitch if per_rev else pitch * s_out
    else:
        f_in = f_out = ctx.feed()
    here = m.spindles.get(m.master, [0.0, "cw"])[1]
    vari = int(c["VARI"]) if "VARI" in c.values else 0
    dam = abs(ctx.mm("DAM")) if "DAM" in c.values else 0.0
    z = h.safe
    stroke = 0
    while z > h.depth:
        stroke += 1
        ctx.count(stroke, "tapping strokes")
        z = max(h.depth, z - dam) if vari in (1, 2) and dam > 0 else h.depth
        p.phase(f"in, stroke {stroke}" if vari in (1, 2) and dam > 0 else "in")
        p.feed(f_in, n=z)
        if z > h.depth:
            p.phase(f"back-off, stroke {stroke}")
            back = h.safe if vari == 2 else z + (abs(ctx.mm("VRT")) or 1.0)
            p.feed(f_out, n=back)
            p.feed(f_in, n=z)
    if c["DTB"]:
        m.sink.append(canon.Dwell(p.src, seconds=c["DTB"]))
    sdr = int(c["SDR"]) if "SDR" in c.values else 0
    _spindle(ctx, DIRECTIONS.get(sdr) or ("ccw" if here == "cw" else "cw"))
    p.phase("out")
    p.feed(f_out, n=h.safe)
    ctx.retract(h)
    _spindle(ctx, DIRECTIONS.get(int(c["SDAC"]), here))


def _start(ctx: Context) -> Heights:
    if ctx.machine.cutcom.engaged:
        raise ProgramError("cutcom", f"{ctx.name} while tool radius compensation is active (G40 first)",
                           ctx.src)
    axn = ctx.call.values.get("AXN", 0)
    if axn and axn != PLANE_AXN.get(ctx.machine.plane):
        raise ProgramError("unsupported", f"{ctx.name}: a tool axis _AXN={axn:g} other than the "
                           "plane's normal is not simulated", ctx.src)
    h = ctx.heights()
    ctx.path.phase("approach")
    ctx.path.rapid(n=h.safe)
    return h


def _spindle(ctx: Context, direction: str) -> None:
    m = ctx.machine
    st = m.spindles.get(m.master)
    if st is None:
        return
    st[1] = direction
    m.sink.append(canon.Spindle(ctx.path.src, spindle=m.master, speed=st[0], direction=direction))
