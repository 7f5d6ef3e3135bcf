"""The orientation transformation (Sinumerik TRAORI) of any machine with two rotary axes:
tool tip and tool vector in the workpiece frame → axis values, as the control's generic
five-axis transformation computes them.

Every chain of two rotary joints — table-table, head-head or one of each (vmach's s5d, h5d,
hybrid5, mill5ac) — turns the tool in the workpiece frame as

    R(q) = Rot(u_o, θ_o) · Rot(u_i, θ_i) · R₀          a(q) = R(q)·e_z = Rot(u_o, θ_o)·Rot(u_i, θ_i)·v₀

with ``u_o`` the *outer* rotary axis (fixed in the workpiece frame), ``u_i`` the inner one
(carried by the outer), both as unit vectors in the workpiece frame at the zero pose and signed
so that a positive axis value turns the tool positively relative to the part (an axis that
turns the table has its vector reversed: domain §2's Rot(k, −C)), and v₀ the tool vector with
both rotary axes at zero. :func:`orienter` reads u_o, u_i, v₀ and the order from the model's own
forward kinematics, so nothing is written twice.

Inverse (for a unit vector t):

- the outer turn keeps the component along u_o, so θ_i solves
  ``u_o·Rot(u_i, θ_i)·v₀ = u_o·t``, i.e. ``P cos θ_i + Q sin θ_i = u_o·t − S`` with
  P = u_o·v₀ − (u_o·u_i)(u_i·v₀), Q = u_o·(u_i × v₀), S = (u_o·u_i)(u_i·v₀): two roots
  θ_i = φ ± arccos(…), φ = atan2(Q, P) — none (``unreachable``) when |…| > 1;
- then θ_o turns w = Rot(u_i, θ_i)·v₀ onto t about u_o:
  ``θ_o = atan2(u_o·(w × t), w·t − (u_o·w)(u_o·t))``; when t is along u_o
  (|t − (u_o·t)u_o| ≤ 1e-12, the pole: B = 0 on s5d) θ_o is free and **keeps its previous value**
  (the control's default; ``singular`` marks the pose).

**Choice of solution** (stated rule): of the two roots, each axis value taken at the turn
(±360°) nearest its previous value, the one inside the travel limits that moves the rotary axes
least (sum of |Δθ|) wins; a tie (within 1e-9°) goes to the larger inner angle (the domain's
B ∈ [0°, 180°]). With neither inside the limits the nearer is kept and the limit check downstream
reports it.

Linear axes then follow exactly: with the rotary axes fixed the tip is affine in the three
linear (or, on a hybrid, virtual) axes, ``tip = A·lin + b``; A and b come from four forward
kinematics rows, and ``lin = A⁻¹(tip − b)`` — FK of the result equals the programmed pose to
round-off (tested to 1e-9), on every model, without the numeric solver. A hybrid's drives follow
from the virtual axes as for any axis program.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: |t − (u_o·t)·u_o| below which the tool vector is along the outer axis (the pole).
POLE = 1e-12
#: slack on |cos θ_i| ≤ 1 before a vector counts as out of reach (round-off of unit vectors).
REACH = 1e-9


def rot(u: np.ndarray, deg: np.ndarray) -> np.ndarray:
    """Rodrigues: (n, 3, 3) rotations about unit u (3,) by deg (n,) degrees."""
    t = np.radians(np.atleast_1d(np.asarray(deg, float)))
    c, s = np.cos(t), np.sin(t)
    k = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + s[:, None, None] * k + (1.0 - c)[:, None, None] * (k @ k)


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (n, 3) or (3,) arrays (numpy's ``cross`` costs ~50 µs a call
    in bookkeeping; this is a few array operations)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _turn(u: np.ndarray, v: np.ndarray, deg: np.ndarray) -> np.ndarray:
    """Rows v (n, 3) or (3,) turned about unit u by deg (n,) degrees (Rodrigues, vectorised)."""
    t = np.radians(np.asarray(deg, float))[:, None]
    v = np.broadcast_to(v, (t.shape[0], 3))
    c = np.cos(t)
    return v * c + cross(u, v) * np.sin(t) + u * (v @ u)[:, None] * (1.0 - c)


@dataclass(frozen=True, eq=False)
class Orienter:
    """A model's orientation transformation (see the module docstring).

    outer, inner : column of the outer / inner rotary axis in ``model.axes``.
    u_outer, u_inner : (3,) unit axis vectors in the workpiece frame (zero pose, signed).
    v0 : (3,) tool vector with both rotary axes at zero. linear : (3,) columns of X Y Z.
    limits : (2, 2) travel [min, max] of (outer, inner), degrees (±inf when free).
    modulo : (2,) bool — outer, inner is a modulo axis.
    """

    model: object
    outer: int
    inner: int
    u_outer: np.ndarray
    u_inner: np.ndarray
    v0: np.ndarray
    linear: tuple[int, int, int]
    limits: np.ndarray
    modulo: np.ndarray

    @property
    def _limits(self) -> list:
        return self.limits.tolist()

    @property
    def rotary_names(self) -> tuple[str, str]:
        axes = self.model.axes
        return axes[self.outer], axes[self.inner]

    def vector(self, q: np.ndarray) -> np.ndarray:
        """Tool vectors (n, 3) of axis rows q (n, k) (only the rotary columns matter)."""
        q = np.atleast_2d(q)
        w = _turn(self.u_inner, self.v0, q[:, self.inner])
        return _turn(self.u_outer, w, q[:, self.outer])

    def candidates(self, t: np.ndarray):
        """Both roots for unit vectors t (n, 3): (outer (n, 2), inner (n, 2)) degrees in
        (−180, 180], ``reach`` (n,) bool and ``pole`` (n,) bool (outer free: NaN there)."""
        uo, ui, v0 = self.u_outer, self.u_inner, self.v0
        oi, iv = float(uo @ ui), float(ui @ v0)
        p = float(uo @ v0) - oi * iv
        qq = float(uo @ cross(ui, v0))
        s = oi * iv
        rho, phi = math.hypot(p, qq), math.atan2(qq, p)
        ot = t @ uo
        c = (ot - s) / rho if rho > 1e-15 else np.where(np.abs(ot - s) < REACH, 1.0, 2.0)
        reach = np.abs(c) <= 1.0 + REACH
        d = np.arccos(np.clip(c, -1.0, 1.0))
        inner = np.degrees(np.stack([phi + d, phi - d], axis=1))
        inner = (inner + 180.0) % 360.0 - 180.0
        inner[inner == -180.0] = 180.0
        pole = np.linalg.norm(t - ot[:, None] * uo, axis=1) <= POLE
        outer = np.empty_like(inner)
        for j in (0, 1):
            w = _turn(ui, v0, inner[:, j])
            y = cross(w, t) @ uo
            x = np.einsum("ij,ij->i", w, t) - (w @ uo) * ot
            outer[:, j] = np.degrees(np.arctan2(y, x))
        outer[pole] = np.nan
        return outer, inner, reach, pole

    def choose(self, outer: np.ndarray, inner: np.ndarray, previous: tuple[float, float],
               prefer: tuple[str, int] | None = None):
        """The rule of the module docstring for one pose: (outer, inner) degrees from the two
        roots (2,) each (outer NaN at the pole), given the previous (outer, inner).
        ``prefer`` (axis name, ±1): among roots inside the travel, the higher (+1) or lower
        (−1) value of that axis wins instead of the least motion (CYCLE800's direction)."""
        best = None
        limits = self._limits
        for j in (0, 1):
            vals = []
            for k, (cand, prev) in enumerate(((outer[j], previous[0]), (inner[j], previous[1]))):
                if cand != cand:
                    vals.append(prev)
                    continue
                v = prev + ((cand - prev + 180.0) % 360.0 - 180.0)
                lo, hi = limits[k]
                if not self.modulo[k] and not lo - 1e-9 <= v <= hi + 1e-9:
                    for alt in (v - 360.0, v + 360.0):
                        if lo - 1e-9 <= alt <= hi + 1e-9:
                            v = alt
                vals.append(v)
            inside = all(limits[k][0] - 1e-9 <= vals[k] <= limits[k][1] + 1e-9
                         for k in (0, 1) if not self.modulo[k])
            cost = abs(vals[0] - previous[0]) + abs(vals[1] - previous[1])
            key = (not inside, round(cost, 9), -inner[j])
            if prefer is not None and prefer[0] in self.rotary_names:
                key = (not inside, -prefer[1] * vals[self.rotary_names.index(prefer[0])], *key[1:])
            if best is None or key < best[0]:
                best = (key, vals)
        return best[1][0], best[1][1]

    def rotaries(self, t: np.ndarray, previous: tuple[float, float],
                 prefer: tuple[str, int] | None = None):
        """Rotary values along a sequence of unit vectors t (n, 3), each chosen by the rule from
        the one before (the first from ``previous``): (outer (n,), inner (n,), reach (n,) bool,
        pole (n,) bool)."""
        outer, inner, reach, pole = self.candidates(t)
        out = np.empty((len(t), 2))
        prev = previous
        oc, ic = outer.tolist(), inner.tolist()
        for n, ok in enumerate(reach.tolist()):
            if ok:
                prev = self.choose(oc[n], ic[n], prev, prefer)
            out[n] = prev
        return out[:, 0], out[:, 1], reach, pole

    def at_pole(self, t: np.ndarray) -> bool:
        """Whether the unit vector t (3,) lies along the outer axis (its value is free)."""
        return float(np.linalg.norm(t - (t @ self.u_outer) * self.u_outer)) <= POLE

    def linear_axes(self, q: np.ndarray, tip: np.ndarray) -> np.ndarray:
        """q (n, k) with its three linear columns set so that the tip is ``tip`` (n, 3) for the
        rotary values q holds (affine solve, see the module docstring)."""
        q = np.array(np.atleast_2d(q), float)
        n = q.shape[0]
        rows = np.repeat(q, 4, axis=0)
        lin = list(self.linear)
        rows[:, lin] = 0.0
        for j, c in enumerate(lin):
            rows[j + 1::4, c] = 1.0
        pts = self.model.fk(rows).tip.reshape(n, 4, 3)
        b = pts[:, 0]
        a = np.stack([pts[:, j + 1] - b for j in range(3)], axis=2)      # (n, 3, 3) columns
        q[:, lin] = np.linalg.solve(a, (np.asarray(tip, float) - b)[:, :, None])[:, :, 0]
        return q


def orienter(model) -> Orienter | None:
    """The model's orientation transformation, or None when it has not exactly two rotary axes
    and the three geometry axes (TRAORI needs a five-axis machine)."""
    axes = tuple(model.axes)
    rot_cols = [i for i, r in enumerate(model.rotary) if r]
    geo = tuple(model.control.geometry)
    if len(rot_cols) != 2 or not all(g in axes for g in geo):
        return None
    lin = tuple(axes.index(g) for g in geo)
    q0 = model.q()
    q0[:, rot_cols] = 0.0
    r0 = model.tool2work(q0)[0, :3, :3]
    us = []
    for c in rot_cols:
        q = q0.copy()
        q[:, c] = 90.0
        m = model.tool2work(q)[0, :3, :3] @ r0.T
        us.append(np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]]) / 2.0)
    q = q0.copy()
    q[:, rot_cols[0]], q[:, rot_cols[1]] = 40.0, 70.0
    got = model.tool2work(q)[0, :3, :3]
    first_outer = rot(us[0], 40.0)[0] @ rot(us[1], 70.0)[0] @ r0
    o, i = (0, 1) if np.allclose(got, first_outer, atol=1e-9) else (1, 0)
    limits = np.array(model.limits, float)[[rot_cols[o], rot_cols[i]]] if hasattr(model, "limits") else None
    if limits is None or limits.shape != (2, 2):
        limits = np.array([[-np.inf, np.inf]] * 2)
    specs = {a.name: a for a in model.control.axes}
    modulo = np.array([specs[axes[rot_cols[k]]].modulo is not None for k in (o, i)])
    limits = np.where(modulo[:, None], np.array([-np.inf, np.inf]), np.nan_to_num(limits, nan=np.inf))
    return Orienter(model, rot_cols[o], rot_cols[i], us[o], us[i], r0[:, 2].copy(), lin, limits, modulo)
