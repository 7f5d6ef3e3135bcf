"""Resolve the orientation transformation in a canonical stream: every
:class:`~vmach.canon.OrientedMove` (a TRAORI block: tip and tool vector in the workpiece frame)
becomes straight moves of axis values, and every ``nan`` ("where the machine is now", after
TRAORI or TRAFOOF) the actual value — so that the move table, the stock, collisions, limits and
cycle time work on axis values exactly as for an axis program.

A block is sampled so that between two rows the tool vector turns by at most ``step`` degrees
(``tol.angle_step``; ORIVECT: on the great circle; ORIAXES: the rotary axes linearly) and every
rotary axis moves at most ``step`` degrees (refined near the pole, where the outer axis turns
fast), and an arc's tip within ``tol.chord`` — or within the tolerance a
``CYCLE832(tol, …)`` before it gave the control (its compressor may leave the path by that
much; 0 resets); each sample is solved by
:class:`vmach.machine.traori.Orienter` (its rule chooses between the two solutions, continuing
from the sample before). Findings, at the block's line:

- ``unreachable`` (error): no rotary position gives the programmed vector; the block does not
  move the machine.
- ``orientation_flip`` (warning): a rotary axis jumps more than :data:`FLIP` degrees between
  two samples although the tool vector turns at most ``step`` between them (the vector passes
  close by the pole, or the solution changes branch or unwinds at a travel limit) — on the
  machine a large, fast, unexpected motion beside the part. Choosing the outer axis when a
  block starts at the pole is not one.
- ``unsupported`` (error): TRAORI on a model without two rotary axes.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from vmach import canon
from vmach.findings import Finding, error, warning
from vmach.machine.traori import Orienter, orienter
from vmach.motion.table import arc_points
from vmach.tol import tol

#: a rotary step between two samples (degrees) that makes a block an orientation flip
FLIP = 10.0
#: most samples of one block (a turn near the pole is refined up to this)
MOST = 20_000


def needs_resolving(commands) -> bool:
    return any(isinstance(c, (canon.Transformation, canon.OrientedMove)) for c in commands)


def resolve(commands, model, *, step: float = tol.angle_step, chord: float = tol.chord,
            ends_only: bool = False) -> tuple[list, list[Finding]]:
    """The stream with oriented moves solved and unknown values filled (see the module
    docstring), and the findings. Streams without a transformation come back as they are.
    ``ends_only``: of each oriented block only its end row (the programmed pose, for the
    post-processor check, which pairs poses with blocks)."""
    if not needs_resolving(commands):
        return commands, []
    o = orienter(model)
    names = list(model.axes)
    base_chord = chord
    last: dict = {}
    cur = {a.name: a.home for a in model.control.axes}
    out: list = []
    found: list[Finding] = []
    for c in commands:
        if isinstance(c, canon.MOTIONS):
            axes = dict(c.axes)
            unknown = [k for k, v in axes.items() if v != v]
            for k in unknown:
                axes[k] = cur.get(k, 0.0)
            c = replace(c, axes=axes) if unknown else c
            cur.update(axes)
        elif isinstance(c, canon.Transformation) and c.name != "TRAFOOF" and o is None:
            found.append(error("unsupported", f"{c.name}: {model.name} has no two rotary axes to "
                               "orient the tool with", c.source, machine=model.name))
        elif isinstance(c, canon.PathTolerance):      # the control's, for what follows
            chord = max(base_chord, c.tolerance) if c.tolerance > 0 else base_chord
        elif isinstance(c, canon.OrientedMove):
            out.append(c)
            if o is None:
                continue
            rows, finding = _block(o, c, cur, names, step, chord, last)
            if finding is not None:
                found.append(finding)
            for axes in rows[-1:] if ends_only else rows:
                out.append(canon.Traverse(c.source, axes=axes) if c.motion == "traverse"
                           else canon.LinearFeed(c.source, axes=axes, feed=c.feed))
            if rows:
                cur.update(rows[-1])
            continue
        out.append(c)
    return out, found


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _slerp(t0: np.ndarray, t1: np.ndarray, f: np.ndarray) -> np.ndarray:
    """(n, 3) unit vectors on the great circle from t0 to t1 at fractions f (n,)."""
    ang = math.acos(max(-1.0, min(1.0, float(t0 @ t1))))
    if ang < 1e-12:
        return np.tile(t1, (len(f), 1))
    perp = t1 - (t0 @ t1) * t0
    if np.linalg.norm(perp) < 1e-12:               # opposite: any great circle; about the
        perp = np.cross(t0, [1.0, 0.0, 0.0])        # first axis not along t0
        if np.linalg.norm(perp) < 1e-6:
            perp = np.cross(t0, [0.0, 1.0, 0.0])
    perp = _unit(perp)
    a = f[:, None] * ang
    return np.cos(a) * t0 + np.sin(a) * perp


def _turning(c: canon.OrientedMove, t0: np.ndarray, t1: np.ndarray, tangent=None):
    """The tool vector as a function of the fraction (callable f (n,) → (n, 3) unit vectors) and
    the angle (degrees) it turns through: the great circle (ORIVECT), or a cone (ORICONCW/CCW
    about ``c.cone``, ORICONIO through ``c.cone``, ORICONTO leaving t0 along ``tangent``, the
    way the orientation went at the end of the block before): azimuth about the cone's axis
    uniformly, the angle to the axis linearly from the start's to the end's. (None, 0) for a
    cone that does not join them."""
    great = math.degrees(math.acos(max(-1.0, min(1.0, float(t0 @ t1)))))
    if c.interpolation == "cone_to" and great > 1e-9:
        if tangent is None:
            return None, 0.0
        n = np.cross(tangent, t1 - t0)
        if np.linalg.norm(n) < 1e-12:                 # t1 ahead on the great circle: ORIVECT
            return (lambda f: _slerp(t0, t1, f)), great
        u = _unit(n) if n @ t0 >= 0 else -_unit(n)
        ccw = float(np.cross(u, t0) @ tangent) > 0
        return _turning(replace(c, interpolation="cone_ccw" if ccw else "cone_cw", cone=tuple(u)), t0, t1)
    if c.cone is None or not c.interpolation.startswith("cone"):
        return (lambda f: _slerp(t0, t1, f)), great
    if c.interpolation == "cone_io":
        m = _unit(c.cone)
        n = np.cross(m - t0, t1 - t0)
        if np.linalg.norm(n) < 1e-9:
            return None, 0.0
        u = _unit(n)
        u = u if u @ t0 >= 0 else -u
    else:
        u = _unit(c.cone)
    e1 = t0 - (t0 @ u) * u
    e_end = t1 - (t1 @ u) * u
    if np.linalg.norm(e1) < 1e-9 or np.linalg.norm(e_end) < 1e-9:
        return None, 0.0
    e1 = _unit(e1)
    e2 = np.cross(u, e1)
    az = math.atan2(float(t1 @ e2), float(t1 @ e1)) % (2 * math.pi)      # counter-clockwise
    if c.interpolation == "cone_io":
        mid = math.atan2(float(m @ e2), float(m @ e1)) % (2 * math.pi)
        sweep = az if mid <= az else az - 2 * math.pi
    elif c.interpolation == "cone_ccw":
        sweep = az if az > 1e-12 else 2 * math.pi
    else:
        sweep = az - 2 * math.pi if az > 1e-12 else -2 * math.pi
    p0 = math.acos(max(-1.0, min(1.0, float(t0 @ u))))
    p1 = math.acos(max(-1.0, min(1.0, float(t1 @ u))))

    def at(f):
        a, p = f * sweep, p0 + f * (p1 - p0)
        ring = np.cos(a)[:, None] * e1 + np.sin(a)[:, None] * e2
        return np.cos(p)[:, None] * u + np.sin(p)[:, None] * ring

    return at, math.degrees(abs(sweep) * max(math.sin(p0), math.sin(p1)) + abs(p1 - p0))


def _path(c: canon.OrientedMove, start: np.ndarray, end: np.ndarray, geo, chord: float):
    """Tip as a function of the fraction: (callable f (n,) → (n, 3), chords the path needs).
    An arc with a ``frame`` lies in the frame's plane: computed in program coordinates, then
    mapped to the workpiece (a swivelled plane's circle)."""
    if c.motion != "arc":
        return (lambda f: start + f[:, None] * (end - start)), 1
    if c.frame is None:
        return _arc(c, start, end, geo, chord)
    origin, lin = np.array(c.frame[:3]), np.array(c.frame[3:]).reshape(3, 3)
    scale = abs(np.linalg.det(lin)) ** (1 / 3) or 1.0
    at, chords = _arc(c, np.linalg.solve(lin, start - origin), np.linalg.solve(lin, end - origin), geo,
                      chord / scale)
    return (lambda f: origin + at(f) @ lin.T), chords


def _arc(c: canon.OrientedMove, start: np.ndarray, end: np.ndarray, geo, chord: float):
    """The arc of ``c`` (plane, centre in the coordinates of start and end) as ``_path``."""
    col = {g: i for i, g in enumerate(geo)}
    arc = canon.ArcFeed(c.source, plane=c.plane, center=c.center, clockwise=c.clockwise, turns=c.turns)
    pts = arc_points(start, end, arc, col, chord)
    ia, ib = col[c.plane[0]], col[c.plane[1]]
    ca, cb = c.center
    ang = np.unwrap(np.arctan2(pts[:, ib] - cb, pts[:, ia] - ca))
    a0, sweep = ang[0], ang[-1] - ang[0]
    r0, r1 = math.hypot(*(start[[ia, ib]] - c.center)), math.hypot(*(end[[ia, ib]] - c.center))

    def at(f):
        p = start + f[:, None] * (end - start)
        a, r = a0 + f * sweep, r0 + f * (r1 - r0)
        p[:, ia], p[:, ib] = ca + r * np.cos(a), cb + r * np.sin(a)
        return p

    return at, len(pts) - 1


def _block(o: Orienter, c: canon.OrientedMove, cur: dict, names: list, step: float, chord: float,
           last: dict | None = None):
    """Rows (axis dicts) for one oriented block, and a finding or None. ``last``: the previous
    block's end (``q``, ``tip``, ``axis``), reused when the machine is still there."""
    model = o.model
    q0 = np.array([cur.get(n, 0.0) for n in names], float)
    if last is not None and last.get("q") is not None and np.array_equal(last["q"], q0):
        tip0, t0 = last["tip"], last["axis"]
    else:
        pose = model.fk(q0[None])
        tip0, t0 = pose.tip[0], pose.axis[0]
    geo = [names[i] for i in o.linear]
    tip1 = np.array([c.axes.get(g, math.nan) for g in geo], float)
    if c.frame is not None:              # program coordinates, nan where the tip stays
        origin, lin = np.array(c.frame[:3]), np.array(c.frame[3:]).reshape(3, 3)
        tip1 = origin + lin @ np.where(np.isnan(tip1), np.linalg.solve(lin, tip0 - origin), tip1)
    tip1 = np.where(np.isnan(tip1), tip0, tip1)
    ro, ri = o.rotary_names
    prev = (q0[o.outer], q0[o.inner])
    programmed = (c.axes.get(ro, math.nan), c.axes.get(ri, math.nan))
    by_vector = c.vector is not None
    if by_vector:
        if not np.linalg.norm(c.vector) > 1e-12:
            return [], error("invalid_value", "the programmed tool vector is zero", c.source)
        t1 = _unit(c.vector)
        end = prev
        if c.interpolation == "axes" or c.prefer is not None or o.at_pole(t0):
            e_o, e_i, reach, _ = o.rotaries(t1[None], prev, c.prefer)   # else: the last sample
            if not reach[0]:
                return [], _unreachable(c, t1)
            end = (float(e_o[0]), float(e_i[0]))
    else:
        end = tuple(p if p == p else q for p, q in zip(programmed, prev, strict=True))
        qe = q0.copy()
        qe[o.outer], qe[o.inner] = end
        t1 = o.vector(qe[None])[0]
    vector_mode = c.interpolation != "axes" and (by_vector or not math.isclose(t0 @ t1, 1.0))
    turning, turn = _turning(c, t0, t1, (last or {}).get("tangent"))
    if last is not None:
        last["tangent"] = None
    if turning is None:
        return [], error("invalid_value", "the cone does not take the tool from its start to its end "
                         "orientation (the axis is along one of them, the three orientations of "
                         "ORICONIO do not span a cone, or ORICONTO follows no change of "
                         "orientation)", c.source)
    along, chords = _path(c, tip0, tip1, geo, chord)
    spread = turn if vector_mode else max(abs(end[0] - prev[0]), abs(end[1] - prev[1]))
    n = n0 = max(chords, math.ceil(spread / step), 1)
    at_pole = o.at_pole(t0)                          # the first step chooses the outer axis:
    if at_pole and vector_mode:                      # the one of the block's end, as the rule
        prev = (end[0], prev[1])                     # takes it from the start (no later flip)
    while True:
        f = np.arange(1, n + 1) / n
        if vector_mode:
            so, si, reach, _ = o.rotaries(turning(f), prev)
            if not reach.all():
                return [], _unreachable(c, t1)
        else:
            so = prev[0] + f * (end[0] - prev[0])
            si = prev[1] + f * (end[1] - prev[1])
        moves = np.abs(np.diff(np.stack([np.r_[prev[0], so], np.r_[prev[1], si]]), axis=1))
        worst = float(max(moves[0, int(at_pole):].max(initial=0.0), moves[1].max(initial=0.0)))
        if worst <= step * (1 + 1e-9) or n >= min(MOST, 16 * n0) or not vector_mode:
            break
        n = min(MOST, 16 * n0, math.ceil(n * worst / step * 1.05))
    q = np.tile(q0, (n, 1))
    q[:, o.outer], q[:, o.inner] = so, si
    if last is not None:
        last["q"] = None
    if not c.hold_axes:
        q = o.linear_axes(q, along(f))
        if last is not None:
            last.update(q=q[-1].copy(), tip=tip1, axis=t1)
    if last is not None and vector_mode and turn > 1e-9:    # the orientation's way at the end
        d = t1 - turning(np.array([1.0 - 1e-6]))[0]
        d = d - (d @ t1) * t1
        last["tangent"] = _unit(d) if np.linalg.norm(d) > 1e-15 else None
    rows = []
    for r in q:
        axes = dict(cur)
        axes.update({k: v for k, v in c.axes.items() if k not in names and v == v})
        axes.update(zip(names, map(float, r), strict=True))
        rows.append(axes)
    finding = None
    if vector_mode and worst > FLIP:
        k = int(moves[1].max(initial=0.0) > moves[0, int(at_pole):].max(initial=0.0))
        axis = (ro, ri)[k]
        travel = float(moves[k].sum())
        finding = warning("orientation_flip", f"{axis} jumps {worst:.3f}° between two orientations "
                          f"{turn / n:.3f}° apart ({travel:.3f}° in all while the tool vector turns "
                          f"{turn:.3f}°): the path passes close by the pole, or the solution changes "
                          "branch or unwinds at a travel limit — a large unexpected motion on the "
                          "machine", c.source,
                          axis=axis, step=worst, travel=travel, vector_turn=turn)
    return rows, finding


def _unreachable(c: canon.OrientedMove, t) -> Finding:
    return error("unreachable", "no position of the rotary axes gives the tool vector "
                 f"({t[0]:.6f}, {t[1]:.6f}, {t[2]:.6f}); the block does not move the machine",
                 c.source, vector=[float(x) for x in t])
