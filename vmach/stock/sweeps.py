"""What the true tools sweep along the other paths of a program.

The final part is the blank minus what every path's true motion sweeps: material that some
other path's tool passes through is gone from it, whatever the path at hand does there. A fan
cutter (:mod:`vmach.stock.fan`) takes, near a flat face's rim, a band of the face chain that
its true tool leaves (the flank's foot where the tool's centre runs off the contact); where
another path's true tool sweeps that band — a finishing cutter whose body passes through the
foot a roughing or facing pass leaves on its allowance — the fan may take it first
(:func:`vmach.stock.fan.plan_fans`, ``others``).

:class:`Sweeps` holds every path's sampled machine axes and poses, and answers whether points
lie inside another path's true tool at a moment of its motion: the moment its tool's plane
through its axis and a rotation axis ω passes the point (found between two sampled poses, the
machine axes interpolated linearly as the control does, and run through the kinematics). A
point at height u above the side's extreme line lies inside the tool there if it lies within
``sqrt(2Ru)`` of that plane: so points inside are found to within what the sampling of that
moment misses, never wrongly. All lengths mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: points tested against the poses of a path at a time (bounds the (points, poses) arrays)
BLOCK = 1 << 20


@dataclass(frozen=True)
class Motion:
    """One path: ``q`` (n, k) machine axes of its samples, ``fk`` (q (m, k) -> pose with tip,
    axis (m, 3)), ``tips`` and unit ``axes`` (n, 3) its poses, and its tool's true radius
    along the axis: heights ``zs`` (h,) and radii ``rs`` (h,) mm (:func:`vmach.stock.cusps.outline`)."""

    q: np.ndarray
    fk: object
    tips: np.ndarray
    axes: np.ndarray
    zs: np.ndarray
    rs: np.ndarray


class Sweeps:
    """The motions of a program's paths, in order (:class:`Motion` each)."""

    def __init__(self, motions: list[Motion]):
        self.motions = list(motions)

    def others(self, path: int):
        """The callable ``(groups (g, k, 3), omega (3,)) -> (g,) bool`` of :meth:`holds_all`
        for every path but ``path``."""
        return lambda groups, omega: self.holds_all(groups, omega, skip=path)

    def holds(self, points: np.ndarray, omega: np.ndarray, skip: int | None = None) -> np.ndarray:
        """(p,) bool: points (p, 3) inside the true tool of a path (but ``skip``) at the
        moment its plane through the tool axis and ``omega`` (unit) passes them."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        om = np.asarray(omega, dtype=float)
        out = np.zeros(len(points), bool)
        for window in WINDOWS:
            for j, m in enumerate(self.motions):
                if j == skip or len(m.tips) < 2 or out.all():
                    continue
                left = np.nonzero(~out)[0]
                pi, i = _crossings(m, points[left], om, window)
                out[left[pi[_inside(m, points[left], om, pi, i)]]] = True
        return out

    def holds_all(self, groups: np.ndarray, omega: np.ndarray, skip: int | None = None) -> np.ndarray:
        """(g,) bool: groups of points (g, k, 3) whose every point :meth:`holds` — each
        group's first point asked first, the others only where it is held."""
        groups = np.asarray(groups, dtype=float)
        out = self.holds(groups[:, 0], omega, skip)
        if out.any() and groups.shape[1] > 1:
            idx = np.nonzero(out)[0]
            rest = groups[idx, 1:]
            out[idx] = self.holds(rest.reshape(-1, 3), omega, skip).reshape(rest.shape[:2]).all(axis=1)
        return out


#: half-widths (radians) of the windows of a path's steps, by the azimuth of their tips about
#: omega, in which a point's crossings are looked for, narrow first: a tool's plane through
#: its axis and omega passes a point near the tip's azimuth (a crossing outside the widest is
#: missed: a rim taken for not swept, never the other way). Most points held are held
#: within 1° (the program's finishing cutter: half of its crossings lie within 0.4°, some up
#: to 5.5°, off-centre as its Y is); the wide window is searched only for the points the
#: narrow one leaves, a quarter as many candidates to sift first.
WINDOWS = (np.radians(1.0), np.radians(4.0))


def _planes(m: Motion, om: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit normals (n, 3) of each pose's plane through its axis and omega, and which
    poses have one (axis not along omega)."""
    t = np.cross(om, m.axes)
    size = np.linalg.norm(t, axis=1)
    ok = size > 1e-9
    t[ok] /= size[ok, None]
    return t, ok


def _crossings(m: Motion, points: np.ndarray, om: np.ndarray,
               window: float = WINDOWS[-1]) -> tuple[np.ndarray, np.ndarray]:
    """(point, step) index pairs where a step of ``m`` (pose i to i+1) carries the tool's
    plane through its axis and ``omega`` across the point, the tool within reach of it:
    among the steps whose tips' azimuth about omega (through the origin: the work frame's
    rotary axes) lies within ``window`` (radians) of the point's and whose tool reaches the point's height
    along omega (steps binned by that height, bins half the tool's extent along omega)."""
    t, ok = _planes(m, om)
    e1 = np.cross(om, [1.0, 0.0, 0.0] if abs(om[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(om, e1)
    phi = np.arctan2(m.tips @ e2, m.tips @ e1)
    d = np.angle(np.exp(1j * (phi[1:] - phi[:-1])))                  # each step's turn
    mid = np.mod(phi[:-1] + 0.5 * d, 2.0 * np.pi)
    good = np.nonzero(ok[:-1] & ok[1:])[0]
    none = np.zeros(0, int), np.zeros(0, int)
    if len(good) == 0 or len(points) == 0:
        return none
    length, radius = float(m.zs[-1]), float(m.rs.max())
    reach = length + radius
    # the tool's extent along omega about its tip, and the steps binned by their tips' height
    h = m.tips @ om
    ext = radius + length * float(np.abs(m.axes @ om).max())
    size = max(ext / 2.0, 1e-3)
    hb = np.floor(0.5 * (h[:-1] + h[1:])[good] / size).astype(np.int64)
    span = int(np.ceil((ext + 0.5 * float(np.abs(h[1:] - h[:-1]).max())) / size)) + 1
    key = hb * 8 + mid[good]                                          # sorted by (bin, azimuth)
    by = np.argsort(key)
    key, order = key[by], good[by]
    wide = window + 0.5 * float(np.abs(d[good]).max())
    pphi = np.mod(np.arctan2(points @ e2, points @ e1), 2.0 * np.pi)
    pb = np.floor((points @ om) / size).astype(np.int64)
    out_p, out_i = [], []
    for k in range(-span, span + 1):
        base = (pb + k) * 8
        for shift in (0.0, 2.0 * np.pi, -2.0 * np.pi):                  # the window, wrapped
            lo = np.maximum(pphi - wide + shift, 0.0)
            hi = np.minimum(pphi + wide + shift, 2.0 * np.pi)
            if np.all(hi < lo):
                continue
            start = np.searchsorted(key, base + lo)
            stop = np.searchsorted(key, base + hi, side="right")
            count = np.where(hi >= lo, np.maximum(stop - start, 0), 0)
            if count.sum() == 0:
                continue
            pi = np.repeat(np.arange(len(points)), count)
            i = order[np.arange(len(pi)) + np.repeat(start - np.r_[0, np.cumsum(count)[:-1]], count)]
            for a in range(0, len(pi), BLOCK):
                pa, ia = pi[a : a + BLOCK], i[a : a + BLOCK]
                r0, r1 = points[pa] - m.tips[ia], points[pa] - m.tips[ia + 1]
                f0 = np.einsum("ij,ij->i", r0, t[ia])
                f1 = np.einsum("ij,ij->i", r1, t[ia + 1])
                near = ((np.einsum("ij,ij->i", r0, r0) <= reach * reach)
                        | (np.einsum("ij,ij->i", r1, r1) <= reach * reach))
                keep = (f0 * f1 <= 0.0) & near
                out_p.append(pa[keep])
                out_i.append(ia[keep])
    if not out_p:
        return none
    return np.concatenate(out_p), np.concatenate(out_i)


def _inside(m: Motion, points: np.ndarray, om: np.ndarray, pi: np.ndarray, i: np.ndarray) -> np.ndarray:
    """(c,) bool: for (point, step) pairs (:func:`_crossings`), whether the point lies inside
    the true tool where the step carries the tool's plane across it: the machine axes
    interpolated linearly at the fraction of the step where that plane's offset from the
    point changes sign (linearly between the step's ends), and run through the kinematics."""
    out = np.zeros(len(pi), bool)
    if len(pi) == 0:
        return out
    t, _ = _planes(m, om)
    p = points[pi]
    f0 = np.einsum("ij,ij->i", p - m.tips[i], t[i])
    f1 = np.einsum("ij,ij->i", p - m.tips[i + 1], t[i + 1])
    s = np.where(f0 != f1, f0 / np.where(f0 != f1, f0 - f1, 1.0), 0.5)
    pose = m.fk(m.q[i] + (m.q[i + 1] - m.q[i]) * s[:, None])
    axis = np.asarray(pose.axis, dtype=float)
    axis = axis / np.linalg.norm(axis, axis=1, keepdims=True)
    local = p - np.asarray(pose.tip, dtype=float)
    z = np.einsum("ij,ij->i", local, axis)
    radial2 = np.einsum("ij,ij->i", local, local) - z * z
    r = np.interp(z, m.zs, m.rs)
    return (z >= 0.0) & (z <= m.zs[-1]) & (radial2 < (r - 1e-6) ** 2) & (r > 1e-6)
