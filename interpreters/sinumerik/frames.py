"""Coordinate systems: settable zero offsets (G54...), the programmable frame (TRANS, ROT ...),
diameter programming and modulo rotary axes. Pure Python, no numpy (interpreters stay light).

Machine value of a geometry point p given in the current program coordinates::

    machine = settable + t + R · p          (programmable frame = Trans(t) · Rot(R))

(a settable frame that rotates or mirrors, ``$P_UIFR``, chains before it: see :class:`Frames`).

TRANS, ROT, SCALE and MIRROR *replace* the whole programmable frame (as the control does);
ATRANS adds a translation in the current, possibly rotated, system (t += R·a); AROT adds a
rotation (R = R·Ra), ASCALE a scale (R = R·diag(s)), AMIRROR a mirror (R = R·diag(±1)). R is
then a general linear map (rotation, scale, mirror), inverted for the way back.
ROT with several axes turns about Z, then the new Y, then the new X (RPY, the control's default
frame angle mode). ``RPL=`` turns in the working plane (about Z for G17, Y for G18, X for G19).
Axes other than the geometry axes are only translated.
"""

from __future__ import annotations

import math

Matrix = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def matmul(a: Matrix, b: Matrix) -> Matrix:
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))  # type: ignore[return-value]


def apply(m: Matrix, v: tuple[float, float, float]) -> tuple[float, float, float]:
    return (
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    )


def rot_axis(axis: int, deg: float) -> Matrix:
    """Rotation by ``deg`` degrees about geometry axis 0 (X), 1 (Y) or 2 (Z), right-handed."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    if axis == 0:
        return ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))
    if axis == 1:
        return ((c, 0.0, s), (0.0, 1.0, 0.0), (-s, 0.0, c))
    return ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))


def inverse(m: Matrix) -> Matrix:
    """Inverse of a 3×3 matrix (adjugate over determinant; the frames' maps are regular)."""
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    adj = ((e * i - f * h, c * h - b * i, b * f - c * e),
           (f * g - d * i, a * i - c * g, c * d - a * f),
           (d * h - e * g, b * g - a * h, a * e - b * d))
    return tuple(tuple(x / det for x in row) for row in adj)  # type: ignore[return-value]


def diagonal(values: tuple[float, float, float]) -> Matrix:
    return ((values[0], 0.0, 0.0), (0.0, values[1], 0.0), (0.0, 0.0, values[2]))


def rpy(rx: float, ry: float, rz: float) -> Matrix:
    """Z, then new Y, then new X (intrinsic): R = Rz · Ry · Rx."""
    return matmul(matmul(rot_axis(2, rz), rot_axis(1, ry)), rot_axis(0, rx))


class Frames:
    """Settable frame plus programmable frame, per axis.

    geometry : the three geometry axis names; others : every other axis name.
    settable, slin : the settable frame's translation per axis and linear part (a settable
    frame that rotates or mirrors, ``$P_UIFR[n]=CROT(...)``; identity for a plain offset).
    trans, rot : the programmable frame's. The map used is their chain:
    ``machine = settable + slin·(trans + rot·p)``; ``lin`` = slin·rot, ``off`` the translation.
    """

    def __init__(self, geometry: tuple[str, str, str]):
        self.geometry = geometry
        self.settable: dict[str, float] = {}
        self.slin: Matrix = IDENTITY
        self.trans: dict[str, float] = {}
        self.rot: Matrix = IDENTITY
        self.lin: Matrix = IDENTITY      # slin · rot
        self.back: Matrix = IDENTITY     # inverse of lin
        self.rotated = False
        self.off: dict[str, float] = {}

    # -- state ---------------------------------------------------------------------------
    def refresh(self) -> None:
        """Recompute the per-axis translation cache after any change."""
        self.off = {
            a: self.settable.get(a, 0.0) + self.trans.get(a, 0.0) for a in {*self.settable, *self.trans}
        }
        self.lin = self.rot
        if self.slin != IDENTITY:
            g = self.geometry
            turned = apply(self.slin, tuple(self.trans.get(n, 0.0) for n in g))  # type: ignore[arg-type]
            for i, n in enumerate(g):
                self.off[n] = self.settable.get(n, 0.0) + turned[i]
            self.lin = matmul(self.slin, self.rot)
        self.rotated = self.lin != IDENTITY
        self.back = inverse(self.lin) if self.rotated else IDENTITY

    def set_settable(self, offsets: dict[str, float], linear: Matrix = IDENTITY) -> None:
        self.settable = dict(offsets)
        self.slin = linear
        self.refresh()

    def offset(self, axis: str) -> float:
        """Pure translation of a non-geometry axis (or of a geometry axis without rotation)."""
        return self.off.get(axis, 0.0)

    def trans_abs(self, values: dict[str, float]) -> None:
        self.trans = dict(values)
        self.rot = IDENTITY
        self.refresh()

    def trans_add(self, values: dict[str, float]) -> None:
        g = self.geometry
        a = tuple(values.get(n, 0.0) for n in g)
        ra = apply(self.rot, a)  # type: ignore[arg-type]
        for i, n in enumerate(g):
            if ra[i]:
                self.trans[n] = self.trans.get(n, 0.0) + ra[i]
        for n, v in values.items():
            if n not in g:
                self.trans[n] = self.trans.get(n, 0.0) + v
        self.refresh()

    def rot_abs(self, m: Matrix) -> None:
        self.trans = {}
        self.rot = m
        self.refresh()

    def rot_add(self, m: Matrix) -> None:
        self.rot = matmul(self.rot, m)
        self.refresh()

    def linear_abs(self, m: Matrix) -> None:
        """SCALE / MIRROR: the programmable frame becomes the linear map m alone."""
        self.rot_abs(m)

    def plane_map(self, ia: int, ib: int) -> tuple[float, float, float, float]:
        """The frame's 2×2 block in the plane of geometry axes ia, ib: (a, b, c, d) row-major."""
        r = self.lin
        return r[ia][ia], r[ia][ib], r[ib][ia], r[ib][ib]

    def mirrors(self, ia: int, ib: int) -> bool:
        """Whether the frame turns the plane over (an arc's direction changes)."""
        a, b, c, d = self.plane_map(ia, ib)
        return a * d - b * c < 0

    def similar(self, ia: int, ib: int) -> bool:
        """Whether the frame maps circles of the plane to circles (scales it evenly)."""
        a, b, c, d = self.plane_map(ia, ib)
        n1, n2 = math.hypot(a, c), math.hypot(b, d)
        return abs(n1 - n2) <= 1e-12 * max(n1, n2) and abs(a * b + c * d) <= 1e-12 * max(n1, n2) ** 2

    def plane_scale(self, ia: int, ib: int) -> float:
        """Length factor of the frame in the plane (when :meth:`similar`)."""
        a, _, c, _ = self.plane_map(ia, ib)
        return math.hypot(a, c)

    def origin(self, axes: list[str]) -> dict[str, float]:
        return {a: self.offset(a) for a in axes}

    def rotation_flat(self) -> tuple[float, ...]:
        return tuple(v for row in self.lin for v in row)

    # -- conversions ---------------------------------------------------------------------
    def to_program(self, machine: tuple[float, float, float]) -> tuple[float, float, float]:
        """Geometry machine values -> program coordinates."""
        g = self.geometry
        d = tuple(machine[i] - self.offset(g[i]) for i in range(3))
        if not self.rotated:
            return d  # type: ignore[return-value]
        return apply(self.back, d)  # type: ignore[arg-type]

    def to_machine(self, p: tuple[float, float, float]) -> tuple[float, float, float]:
        """Program geometry coordinates -> machine values."""
        g = self.geometry
        q = apply(self.lin, p) if self.rotated else p
        return tuple(q[i] + self.offset(g[i]) for i in range(3))  # type: ignore[return-value]


def modulo_target(current: float, target: float, mode: str, modulo: float = 360.0) -> float:
    """Unwrapped end position of a modulo rotary axis.

    current : unwrapped position now (degrees); target : programmed position (degrees)
    mode : "ACP" positive direction, "ACN" negative, "DC" shortest way (ties go positive),
        "AC" within the modulo range (toward the larger or smaller value, never across 0).
    """
    cur = current % modulo
    t = target % modulo
    if mode == "ACP":
        d = (t - cur) % modulo
    elif mode == "ACN":
        d = -((cur - t) % modulo)
    elif mode == "DC":
        d = (t - cur) % modulo
        if d > modulo / 2:
            d -= modulo
    else:
        d = t - cur
    if abs(d) < 1e-12 or abs(abs(d) - modulo) < 1e-9:  # already there (up to rounding)
        d = 0.0
    return current + d
