"""What the true tools sweep along the other paths of a program.

The final part is the blank minus what every path's true motion sweeps: material that some
other path's tool passes through is gone from it, whatever the path at hand does there. A fan
cutter (:mod:`vmach.stock.fan`) takes, near a flat face's rim, a band of the face chain that
its true tool leaves (the flank's foot where the tool's centre runs off the contact); where
another path's true tool sweeps that band — a finishing cutter whose body passes through the
foot a roughing or facing pass leaves on its allowance — the fan may take it first
(:func:`vmach.stock.fan.plan_fans`, ``cover``).

:class:`Sweeps` holds every path's sampled machine axes and poses, and answers whether points
lie inside another path's true tool at a moment of its motion: the moment its tool's plane
through its axis and a rotation axis ω passes the point (found between two sampled poses, the
machine axes interpolated linearly as the control does, and run through the kinematics). A
point at height u above the side's extreme line lies inside the tool there if it lies within
``sqrt(2Ru)`` of that plane: so points inside are found to within what the sampling of that
moment misses, never wrongly.

The other way round, material a path's cutters *leave* (the feet of a flat face's rim,
:mod:`vmach.stock.feet`) is gone only if another path's cutters take it — not merely its true
tool, whose sampled poses may leave the same foot at the same place. :meth:`Coverage.recut`
therefore asks the sampled poses around each crossing (what every cutter holds whole), and
this path's own poses too, on its other passes (beyond ``gap`` mm of tip travel). All
lengths mm.

What a strategy (:mod:`vmach.stock.strategies`) may ask is one explicit, optional coverage
index, :class:`Coverage` (``Sweeps.coverage(path)``): a caller that streams the program path by
path passes none, and every strategy still holds its bound — it only claims less.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

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
        # each path's tip travel (mm) from its first pose to each pose (n,)
        self.travel = [np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(m.tips, axis=0), axis=1))]
                       for m in self.motions]
        self._indexes: dict[tuple, tuple[_Index, ...] | None] = {}
        self._trees: dict[int, cKDTree] = {}      # each path's tips, for at_poses

    def _index(self, j: int, om: np.ndarray) -> tuple[_Index, ...] | None:
        """Path j's :class:`_Index` parts about ``om``, made once (a path cut in chunks asks often)."""
        key = (j, *np.round(om, 12).tolist())
        if key not in self._indexes:
            self._indexes[key] = _index(self.motions[j], om)
        return self._indexes[key]

    def at_poses(self, points: np.ndarray, skip: int, margin: np.ndarray, near: int = 8) -> np.ndarray:
        """(p,) bool: points (p, 3) inside the true tool, by ``margin`` (p,) mm, at one of the
        ``near`` sampled poses nearest them (by the tip) of a path but ``skip`` — poses every
        cutter holds whole. Only ever too few: a point some farther pose holds is not found."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        out = np.zeros(len(points), bool)
        mg = np.maximum(np.asarray(margin, dtype=float), 1e-6)
        for j, m in enumerate(self.motions):
            if j == skip or len(m.tips) == 0 or out.all():
                continue
            if j not in self._trees:
                self._trees[j] = cKDTree(m.tips)
            left = np.nonzero(~out)[0]
            k = min(near, len(m.tips))
            reach = float(m.zs[-1]) + float(m.rs.max())
            dist, idx = self._trees[j].query(points[left], k=k, distance_upper_bound=reach)
            dist, idx = dist.reshape(len(left), k), idx.reshape(len(left), k)
            ok = np.isfinite(dist)
            idx = np.where(ok, idx, 0)
            inside = in_tool(points[left][:, None, :] - m.tips[idx], m.axes[idx], m.zs, m.rs,
                             mg[left][:, None], mg[left][:, None]) & ok
            out[left[inside.any(axis=1)]] = True
        return out

    def coverage(self, path: int) -> Coverage:
        """What every path but ``path`` sweeps, as that path's cuts ask (:class:`Coverage`)."""
        return Coverage(self, path)

    def holds(self, points: np.ndarray, omega: np.ndarray, skip: int | None = None,
              margin: np.ndarray | float = 0.0, own: tuple | None = None, spread: int = 0) -> np.ndarray:
        """(p,) bool: points (p, 3) inside the true tool of a path (but ``skip``) at the
        moment its plane through the tool axis and ``omega`` (unit) passes them, by at least
        ``margin`` (mm, scalar or (p,)) from its surface. ``own`` = (path, steps (p,) int,
        gap mm, near): that path's steps count only where its tip has travelled more than
        ``gap`` from the point's own step (the same pass is not a recut) — or, with ``near``,
        only those within it, and no other path's. ``spread``: instead of the true tool at
        the crossing, at the sampled poses ``spread`` on either side of it (what the path's
        cutters hold whole: :func:`_inside_poses`)."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        om = np.asarray(omega, dtype=float)
        margin = np.broadcast_to(np.asarray(margin, dtype=float), (len(points),))
        out = np.zeros(len(points), bool)
        for window in WINDOWS:
            for j, m in enumerate(self.motions):
                if j == skip or len(m.tips) < 2 or out.all() or (own is not None and own[3] and j != own[0]):
                    continue
                left = np.nonzero(~out)[0]
                ix = self._index(j, om)
                pi, i = _crossings(m, points[left], om, window, ix)
                if own is not None and j == own[0]:
                    far = np.abs(self.travel[j][i] - self.travel[j][np.asarray(own[1])[left[pi]]]) > own[2]
                    pi, i = pi[far != own[3]], i[far != own[3]]
                if spread:
                    inside = _inside_poses(m, points[left][pi], i, margin[left][pi], spread)
                else:
                    t = None if ix is None else ix[0].t
                    inside = _inside(m, points[left], om, pi, i, margin[left][pi], t)
                out[left[pi[inside]]] = True
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


class Coverage:
    """The coverage index: what the true tools of a program's other paths sweep, for the cuts
    of one path (``path``) of :class:`Sweeps`, whose poses the stock is given from the path's
    pose ``offset`` on. Three questions:

    - :meth:`swept`: groups of points every point of which another path's tool sweeps (fans'
      rim bands);
    - :meth:`at_poses`: points another path's sampled poses hold (cusp poses' fin heights);
    - :meth:`recut`: points another path, or this one beyond ``gap``, sweeps with a margin
      (the feet of a flat face's rim).
    """

    def __init__(self, sweeps: Sweeps, path: int, offset: int = 0):
        self.sweeps, self.path, self.offset = sweeps, path, int(offset)

    def swept(self, groups: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """(g,) bool: groups (g, k, 3) every point of which another path's true tool sweeps
        about ``omega`` (3,) (:meth:`Sweeps.holds_all`)."""
        return self.sweeps.holds_all(groups, omega, skip=self.path)

    def at_poses(self, points: np.ndarray, margin: np.ndarray) -> np.ndarray:
        """Points another path's sampled poses hold (:meth:`Sweeps.at_poses`)."""
        return self.sweeps.at_poses(points, self.path, margin)

    def shifted(self, offset: int) -> Coverage:
        """The same for a stretch of the path given from its pose ``offset`` on."""
        return Coverage(self.sweeps, self.path, self.offset + int(offset))

    def recut(self, points: np.ndarray, steps: np.ndarray, omega: np.ndarray, margin: np.ndarray,
              gap: float, near: bool = False) -> np.ndarray:
        """(p,) bool: points (p, 3) that some path's true tool sweeps at least ``margin`` (p,)
        mm inside its surface — this path's only at steps whose tip has travelled more than
        ``gap`` mm from the point's step (``steps`` (p,), poses as given). ``near``: instead,
        points this path's own tool sweeps within ``gap`` of it (the pass that makes them)."""
        own = (self.path, np.asarray(steps, dtype=int) + self.offset, gap, near)
        return self.sweeps.holds(points, omega, margin=margin, own=own, spread=RECUT_SPREAD)


#: half-widths (radians) of the windows of a path's steps, by the azimuth of their tips about
#: omega, in which a point's crossings are looked for, narrow first: a tool's plane through
#: its axis and omega passes a point near the tip's azimuth (a crossing outside the widest is
#: missed: a rim taken for not swept, never the other way). Most points held are held
#: within 1.5° (the program's finishing cutter: half of its crossings lie within 0.4°, some up
#: to 6.6°, off-centre as its Y is); the wide window is searched only for the points the
#: narrow one leaves. Each is widened by half the largest turn of a step in the index part
#: searched (:func:`_index`; the program's finishing turns: 1.1°).
WINDOWS = (np.radians(1.5), np.radians(7.5))


def by_axis(om: np.ndarray, ok: np.ndarray | None = None) -> list[tuple[np.ndarray, np.ndarray]]:
    """Rows of ``om`` (k, 3) grouped by the line they lie along: [(unit axis (3,), indices
    (g,)), ...] — sign-free (a crossing about ω is one about −ω) and to 1e-9 of a unit
    vector, so that the poses of one rotation ask about one axis (and :meth:`Sweeps._index`
    indexes each path once for it). ``ok`` (k,) bool: the rows to group (the others have no
    axis: a step that does not turn)."""
    om = np.asarray(om, dtype=float).reshape(-1, 3)
    rows = np.arange(len(om)) if ok is None else np.nonzero(ok)[0]
    if len(rows) == 0:
        return []
    unit = om[rows] / np.linalg.norm(om[rows], axis=1, keepdims=True)
    unit *= np.where(unit[np.arange(len(unit)), np.argmax(np.abs(unit), axis=1)] < 0, -1.0, 1.0)[:, None]
    key, inv = np.unique(np.round(unit, 9), axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    return [(k / np.linalg.norm(k), rows[inv == g]) for g, k in enumerate(key)]


def _planes(m: Motion, om: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit normals (n, 3) of each pose's plane through its axis and omega, and which
    poses have one (axis not along omega)."""
    t = np.cross(om, m.axes)
    size = np.linalg.norm(t, axis=1)
    ok = size > 1e-9
    t[ok] /= size[ok, None]
    return t, ok


@dataclass(frozen=True)
class _Index:
    """Steps of a path for one omega, as :func:`_crossings` searches them: each pose's plane
    normal ``t`` (n, 3) (:func:`_planes`), the frame ``e1``, ``e2`` (3,) across omega, the
    steps with a plane at both ends ``order`` sorted by ``key`` (height bin · 8 + their
    tips' mid azimuth), the bins' ``size`` mm and ``span``, and ``turn``: half the largest
    step's turn about omega (radians)."""

    t: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    key: np.ndarray
    order: np.ndarray
    size: float
    span: int
    turn: float


#: a step is indexed apart from the rest (:func:`_index`) when its half-turn, its rise along
#: omega or its tool's extent along omega exceeds this many times the 90th percentile of the
#: path's, plus 0.5° or 1 mm (any split is sound: each part is searched with its own largest)
OUTLIER = 2.0


def _index(m: Motion, om: np.ndarray) -> tuple[_Index, ...] | None:
    """The :class:`_Index` parts of ``m`` about ``om`` (None: no step has a plane): the
    path's ordinary steps, and apart from them the few whose turn, rise along omega or tool
    extent along it is well over the path's usual (``OUTLIER``: a rapid, an index
    of the rotary axis) — each part's search window and height span are its own largest
    step's, so that a path's one long move (a rapid within a finishing path) does not widen
    every search."""
    t, ok = _planes(m, om)
    e1 = np.cross(om, [1.0, 0.0, 0.0] if abs(om[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(om, e1)
    phi = np.arctan2(m.tips @ e2, m.tips @ e1)
    d = np.angle(np.exp(1j * (phi[1:] - phi[:-1])))                  # each step's turn
    mid = np.mod(phi[:-1] + 0.5 * d, 2.0 * np.pi)
    good = np.nonzero(ok[:-1] & ok[1:])[0]
    if len(good) == 0:
        return None
    length, radius = float(m.zs[-1]), float(m.rs.max())
    # each step's turn, rise and its tool's extent along omega about its tip
    h = m.tips @ om
    along = np.abs(m.axes @ om)
    ext = radius + length * np.maximum(along[:-1], along[1:])[good]
    rise = np.abs(h[1:] - h[:-1])[good]
    half = 0.5 * np.abs(d[good])
    odd = np.zeros(len(good), bool)
    for x, least in ((half, np.radians(0.5)), (rise, 1.0), (ext, 1.0)):
        odd |= x > OUTLIER * np.percentile(x, 90) + least
    parts = []
    for part in (~odd, odd):
        if not part.any():
            continue
        g = good[part]
        size = max(float(ext[part].max()) / 2.0, 1e-3)
        hb = np.floor(0.5 * (h[:-1] + h[1:])[g] / size).astype(np.int64)
        span = int(np.ceil((float(ext[part].max()) + 0.5 * float(rise[part].max())) / size)) + 1
        key = hb * 8 + mid[g]                                         # sorted by (bin, azimuth)
        by = np.argsort(key)
        parts.append(_Index(t, e1, e2, key[by], g[by], size, span, float(half[part].max())))
    return tuple(parts)


def _crossings(m: Motion, points: np.ndarray, om: np.ndarray, window: float = WINDOWS[-1],
               ix: tuple[_Index, ...] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(point, step) index pairs where a step of ``m`` (pose i to i+1) carries the tool's
    plane through its axis and ``omega`` across the point, the tool within reach of it:
    among the steps whose tips' azimuth about omega (through the origin: the work frame's
    rotary axes) lies within ``window`` (radians) of the point's, widened by half the
    largest turn of a step in its index part, and whose tool reaches the point's height
    along omega (steps binned by that height, bins half the tool's extent along omega).
    ``ix``: ``m``'s index parts about ``om`` (:func:`_index`), if made already."""
    none = np.zeros(0, int), np.zeros(0, int)
    ix = _index(m, om) if ix is None else ix
    if ix is None or len(points) == 0:
        return none
    reach = float(m.zs[-1]) + float(m.rs.max())
    # the points' azimuth about omega (every part shares the frame e1, e2)
    pphi = np.mod(np.arctan2(points @ ix[0].e2, points @ ix[0].e1), 2.0 * np.pi)
    out_p, out_i = [], []
    for part in ix:
        _part_crossings(m, points, pphi, om, window, part, reach, out_p, out_i)
    if not out_p:
        return none
    return np.concatenate(out_p), np.concatenate(out_i)


def _part_crossings(m: Motion, points: np.ndarray, pphi: np.ndarray, om: np.ndarray, window: float,
                    ix: _Index, reach: float, out_p: list, out_i: list) -> None:
    """:func:`_crossings` over one index part (``pphi`` (p,): the points' azimuth about
    omega in its frame), appending to ``out_p``, ``out_i``."""
    t, key, order, size, span = ix.t, ix.key, ix.order, ix.size, ix.span
    wide = window + ix.turn
    pb = np.floor((points @ om) / size).astype(np.int64)
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


def _inside(m: Motion, points: np.ndarray, om: np.ndarray, pi: np.ndarray, i: np.ndarray,
            margin: np.ndarray | float = 0.0, t: np.ndarray | None = None) -> np.ndarray:
    """(c,) bool: for (point, step) pairs (:func:`_crossings`), whether the point lies inside
    the true tool, by ``margin`` (mm, scalar or (c,)) at least, where the step carries the
    tool's plane across it: the machine axes interpolated linearly at the fraction of the
    step where that plane's offset from the point changes sign (linearly between the step's
    ends), and run through the kinematics."""
    out = np.zeros(len(pi), bool)
    if len(pi) == 0:
        return out
    if t is None:
        t, _ = _planes(m, om)
    p = points[pi]
    f0 = np.einsum("ij,ij->i", p - m.tips[i], t[i])
    f1 = np.einsum("ij,ij->i", p - m.tips[i + 1], t[i + 1])
    s = np.where(f0 != f1, f0 / np.where(f0 != f1, f0 - f1, 1.0), 0.5)
    pose = m.fk(m.q[i] + (m.q[i + 1] - m.q[i]) * s[:, None])
    axis = np.asarray(pose.axis, dtype=float)
    axis = axis / np.linalg.norm(axis, axis=1, keepdims=True)
    return in_tool(p - np.asarray(pose.tip, dtype=float), axis, m.zs, m.rs, margin, np.maximum(margin, 1e-6))


#: sampled poses on either side of a crossing at which :meth:`Coverage.recut` looks for a point
RECUT_SPREAD = 4


def _inside_poses(m: Motion, points: np.ndarray, i: np.ndarray, margin: np.ndarray,
                  spread: int) -> np.ndarray:
    """(c,) bool: points (c, 3) inside the true tool of ``m``, by ``margin`` (c,), at one of
    its sampled poses ``i - spread + 1`` to ``i + spread`` (c,) — the poses its cutters hold
    whole (placed, or in a fan, a column or a translation hull; a pose cut as its fin has
    its neighbours' fins hold the rest of it)."""
    off = np.arange(-spread + 1, spread + 1)
    j = np.clip(i[:, None] + off[None, :], 0, len(m.tips) - 1)                          # (c, k)
    mg = np.maximum(np.asarray(margin, dtype=float), 1e-6)[:, None]
    return in_tool(points[:, None, :] - m.tips[j], m.axes[j], m.zs, m.rs, mg, mg).any(axis=1)


def in_tool(local: np.ndarray, axis: np.ndarray, zs: np.ndarray, rs: np.ndarray,
            along: np.ndarray | float = 0.0, across: np.ndarray | float = 0.0) -> np.ndarray:
    """(...) bool: points at ``local`` (..., 3) from a tool's tip inside the true tool of unit
    ``axis`` (..., 3) and radius ``rs`` at heights ``zs`` (:func:`vmach.stock.cusps.outline`),
    by ``along`` mm from its ends and ``across`` mm from its side (scalars or broadcasting)."""
    z = np.einsum("...i,...i->...", local, axis)
    radial2 = np.einsum("...i,...i->...", local, local) - z * z
    r = np.interp(z, zs, rs) - across
    return (z >= along) & (z <= zs[-1] - along) & (radial2 < r * r) & (r > 0.0)
