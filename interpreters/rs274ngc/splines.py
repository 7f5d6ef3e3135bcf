# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""Splines and NURBS in the XY plane: G5 (cubic), G5.1 (quadratic), G5.2/G5.3 (NURBS),
as LinuxCNC 2.9 reads them (interp_convert.cc ``convert_spline``/``convert_nurbs``).

All three end in one NURBS_FEED of control points (x, y, weight) and an order k: rs274
prints ``NURBS_FEED(count, ...)``. For vmach's canonical stream the curve is sampled as
LinuxCNC's motion planner samples it (emccanon.cc): at 4 × (number of control points)
equal steps of the knot parameter (clamped uniform knots), each step joined by a biarc —
two tangent arcs (or a line when an arc would be straight) through the sample points with
the curve's tangents there. Where no biarc exists LinuxCNC emits nothing for that step;
vmach emits a straight feed to the sample point instead. Lengths in program units.
"""

from __future__ import annotations

import math

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError

_DU = 1e-5
_SMALL = 0.000001


class SplineMixin:
    """G5 G5.1 G5.2 G5.3 for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    nurbs_points: list[tuple[float, float, float]]
    nurbs_order = 3

    def convert_spline(self, motion: int, block: blk.Block) -> None:
        """G5 (P Q: end tangent, I J: start tangent, else the last G5's) and G5.1 (I J:
        the middle control point), relative to the start."""
        s = self.s
        w = block.words
        if s.comp_side:
            raise NgcError("spline_comp")
        self._spline_checks(block)
        x0, y0 = s.pos[0], s.pos[1]
        if motion == 51:
            if "i" not in w or "j" not in w:
                raise NgcError("g51_ij_missing")
            end = self.find_ends(block)
            points = [(x0, y0, 1.0), (x0 + w["i"], y0 + w["j"], 1.0), (end[0], end[1], 1.0)]
            k = 3
        else:
            if "i" in w and "j" in w:
                i, j = w["i"], w["j"]
            elif "i" in w or "j" in w:
                raise NgcError("g5_ij_both")
            else:
                i, j = s.spline_ij
            end = self.find_ends(block)
            if block.p == -1.0 or block.q == -1.0:
                raise NgcError("g5_pq_missing")
            points = [(x0, y0, 1.0), (x0 + i, y0 + j, 1.0),
                      (end[0] + block.p, end[1] + block.q, 1.0), (end[0], end[1], 1.0)]
            s.spline_ij = (-block.p, -block.q)
            k = 4
        s.motion = motion
        self._nurbs_feed(points, k, block)

    def _spline_checks(self, block: blk.Block) -> None:
        s = self.s
        w = block.words
        if s.feed_mode == 0 and s.feed == 0.0:
            raise NgcError("arc_zero_feed")
        if s.feed_mode == 1 and "f" not in w:
            raise NgcError("inverse_time_arc_feed")
        if s.plane != 170:
            raise NgcError("spline_plane")
        if any(letter in w for letter in "zabc"):
            raise NgcError("spline_axes")

    def convert_nurbs(self, motion: int, block: blk.Block) -> None:
        """G5.2 X Y P(weight) [L(order)]: one control point per block, the current point
        first; G5.3 ends the curve and feeds along it."""
        s = self.s
        w = block.words
        if motion == 52:
            x, y = "x" in w, "y" in w
            if x != y:
                raise NgcError("nurbs_xy")
            points = self.nurbs_points
            if not x and block.p > 0 and points:
                raise NgcError("nurbs_p_first")
            if block.p <= 0 and points:
                raise NgcError("nurbs_weight")
            if s.feed_mode == 0 and s.feed == 0.0:
                raise NgcError("nurbs_zero_feed")
            if s.motion != 52:
                points.clear()
            if not points:
                weight = block.p if not x and block.p > 0 else 1.0
                points.append((s.pos[0], s.pos[1], weight))
                self.nurbs_order = 3
            if block.l != -1 and block.l > 3:
                self.nurbs_order = block.l
            if x:
                end = self.find_ends(block)
                points.append((end[0], end[1], block.p))
            s.motion = 52
            return
        if s.motion != 52:
            raise NgcError("nurbs_g53_without_g52")
        points = self.nurbs_points
        if len(points) < self.nurbs_order:
            raise NgcError("nurbs_too_few", order=self.nurbs_order)
        self._nurbs_feed(list(points), self.nurbs_order, block)
        points.clear()
        s.motion = -1

    def _nurbs_feed(self, points: list[tuple[float, float, float]], k: int,
                    block: blk.Block) -> None:
        s = self.s
        out = self.out
        if out.trace:
            out._p("NURBS_FEED(%d, ...)" % len(points))
        if out.want:
            feed = self.feed_for_output(block)
            z, abc = s.pos[2], s.pos[3:6]
            for kind, end, center, clockwise in sample_nurbs(points, k):
                if kind == "line":
                    out.straight_feed_command([end[0], end[1], z, *abc], feed)
                else:
                    out.arc_feed_command([end[0], end[1], z, *abc], center, clockwise, feed)
        s.pos[0], s.pos[1] = points[-1][0], points[-1][1]
        out.ppos = list(s.pos)


def _knots(n: int, k: int) -> list[int]:
    return [0 if i < k else (i - k + 1 if i <= n else n - k + 2) for i in range(n + k + 1)]


def _basis(i: int, k: int, u: float, knots: list[int]) -> float:
    """The B-spline basis N(i, k) at u, as LinuxCNC's Nmix computes it."""
    if k == 1:
        return 1.0 if knots[i] <= u <= knots[i + 1] else 0.0
    left = knots[i + k - 1] - knots[i]
    right = knots[i + k] - knots[i + 1]
    if left == 0 and right != 0:
        return (knots[i + k] - u) * _basis(i + 1, k - 1, u, knots) / right
    if right == 0 and left != 0:
        return (u - knots[i]) * _basis(i, k - 1, u, knots) / left
    if left == 0 and right == 0:
        return 0.0
    return ((u - knots[i]) * _basis(i, k - 1, u, knots) / left
            + (knots[i + k] - u) * _basis(i + 1, k - 1, u, knots) / right)


def _point(u: float, k: int, points, knots) -> tuple[float, float]:
    basis = [_basis(i, k, u, knots) for i in range(len(points))]
    den = sum(b * p[2] for b, p in zip(basis, points, strict=True))
    x = sum(p[0] * b * p[2] / den for b, p in zip(basis, points, strict=True))
    y = sum(p[1] * b * p[2] / den for b, p in zip(basis, points, strict=True))
    return x, y


def _tangent(u: float, k: int, points, knots, umax: float) -> tuple[float, float]:
    lo, hi = max(0.0, u - _DU), min(umax, u + _DU)
    x1, y1 = _point(lo, k, points, knots)
    x3, y3 = _point(hi, k, points, knots)
    return _unit((x3 - x1) / (hi - lo), (y3 - y1) / (hi - lo))


def _unit(x: float, y: float) -> tuple[float, float]:
    h = math.hypot(x, y)
    return (x / h, y / h) if h else (x, y)


def sample_nurbs(points: list[tuple[float, float, float]], k: int):
    """The moves that follow a NURBS curve: tuples ("line", end, None, None) or ("arc", end,
    center, clockwise), ends and centres as (x, y)."""
    n = len(points) - 1
    umax = n - k + 2
    div = len(points) * 4
    knots = _knots(n, k)
    p0 = _point(0.0, k, points, knots)
    t0 = _tangent(0.0, k, points, knots, umax)
    moves = []
    for step in range(1, div + 1):
        u = umax * step / div
        p1 = _point(u, k, points, knots)
        t1 = _tangent(u, k, points, knots, umax)
        moves.extend(_biarc(p0, t0, p1, t1))
        p0, t0 = p1, t1
    return moves


def _biarc(p0, ts, p4, te, r: float = 1.0):
    tsx, tsy = _unit(*ts)
    tex, tey = _unit(*te)
    vx, vy = p0[0] - p4[0], p0[1] - p4[1]
    c = vx * vx + vy * vy
    b = 2 * (vx * (r * tsx + tex) + vy * (r * tsy + tey))
    a = 2 * r * (tsx * tex + tsy * tey - 1)
    discr = b * b - 4 * a * c
    if discr < 0 or a == 0:
        return [("line", p4, None, None)]
    disq = math.sqrt(discr)
    beta1 = (-b - disq) / 2 / a
    beta2 = (-b + disq) / 2 / a
    if beta1 > 0 and beta2 > 0:
        return [("line", p4, None, None)]
    beta = max(beta1, beta2)
    alpha = beta * r
    ab = alpha + beta
    if ab == 0:
        return [("line", p4, None, None)]
    p1 = (p0[0] + alpha * tsx, p0[1] + alpha * tsy)
    p3 = (p4[0] - beta * tex, p4[1] - beta * tey)
    p2 = ((p1[0] * beta + p3[0] * alpha) / ab, (p1[1] * beta + p3[1] * alpha) / ab)
    tm = _unit(p3[0] - p2[0], p3[1] - p2[1])
    return [_arc(p0, p2, (tsx, tsy)), _arc(p2, p4, tm)]


def _arc(start, end, direction):
    """emccanon.cc arc(): the arc from ``start`` to ``end`` leaving ``start`` along
    ``direction``; a line when it would be (nearly) straight."""
    x, y = end[0] - start[0], end[1] - start[1]
    dx, dy = direction
    den = 2 * (y * dx - x * dy)
    if abs(den) <= _SMALL:
        return ("line", end, None, None)
    r = -(x * x + y * y) / den
    return ("arc", end, (start[0] + dy * r, start[1] - dx * r), r >= 0)
