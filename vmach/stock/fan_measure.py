"""Measuring a fan or column cutter: where the tool's side lines at ±ω run (:func:`side_lines`,
:func:`side_samples`), how far a convex hull reaches beyond the surface they sweep
(:func:`reaches`), which of those places another pose of the path cuts anyway (:func:`covered`),
and the material M below every face plane that a fan leaves (:func:`material_points`).
See :mod:`vmach.stock.fan` for why a fan is right and when it applies. Lengths mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vmach.stock.fan import Prism
from vmach.stock.halfplanes import face_lines, polygon

#: M's face planes are moved this far outward (mm): the cutter is ε smaller than H \ M, so the
#: faces of H that lie in a sampled face plane (the first and last pose) are never nearly
#: coplanar with M's.
EPS = 1e-6
#: The bridge is measured at samples of the side's surface; between samples it can be a
#: little larger (up to 6 % on the helix tests), so the measure is taken 10 % larger.
SAMPLING_MARGIN = 1.1


def _exit(p: np.ndarray, d: np.ndarray, planes: np.ndarray, limit: float) -> np.ndarray:
    """Distance along unit directions d (m, 3) from points p (m, 3) to where the rays leave
    the convex region {x : n·x <= c} (planes (f, 4)), clipped to [0, limit]. A ray that
    starts outside and enters later gets its exit distance (the segment then covers the
    inside part, and more)."""
    if len(p) > 1024:
        return np.concatenate([_exit(p[i : i + 1024], d[i : i + 1024], planes, limit)
                               for i in range(0, len(p), 1024)])
    nd = d @ planes[:, :3].T                                   # (m, f)
    slack = planes[:, 3][None, :] - p @ planes[:, :3].T        # (m, f)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(nd > 1e-15, slack / nd, np.inf)
    return np.clip(t.min(axis=1), 0.0, limit)


@dataclass(frozen=True)
class SideLines:
    """The tool's side lines at ±omega for every pose of a path (see :func:`side_samples`):
    starts p, ends q (2, n, 3) — from the face to where the cutter ends; inside (2, n) —
    length of each line inside the blank; axes (n, 3); omega (3,)."""

    p: np.ndarray
    q: np.ndarray
    inside: np.ndarray
    axes: np.ndarray
    omega: np.ndarray


def side_lines(frames_: np.ndarray, omega: np.ndarray, tool: Prism, reach: np.ndarray,
               blank: np.ndarray) -> SideLines:
    """Side lines of every pose (frames (n, 3, 4), tool to work): the prism's edges along the
    axis that lie furthest toward +omega and toward -omega — from the polygon's vertex on the
    face, so on the tool's surface whatever the polygon's turn about its axis — to where the
    cutter ends (``reach`` (n, 2, 3): the box each pose's cutter is trimmed to); ``blank``
    (g, 4) — the planes of the blank's hull."""
    rot, tips = frames_[:, :, :3], frames_[:, :, 3]
    axes = rot[:, :, 2]
    local = np.einsum("nji,j->ni", rot, omega)                      # omega in each tool frame
    score = local[:, :2] @ tool.ring[:, :2].T                       # (n, s)
    p = []
    for pick in (np.argmax(score, axis=1), np.argmin(score, axis=1)):
        p.append(np.einsum("nij,nj->ni", rot, tool.ring[pick]) + tips)
    p = np.stack(p)
    q = np.stack([pk + axes * _exit_box(pk, axes, reach, tool.length)[:, None] for pk in p])
    inside = np.stack([_exit(pk, axes, blank, tool.length) for pk in p])
    return SideLines(p, q, inside, axes, omega)


def _exit_box(p: np.ndarray, d: np.ndarray, boxes: np.ndarray, limit: float) -> np.ndarray:
    """Distance along unit directions d (m, 3) from points p (m, 3) to where the rays leave
    their boxes (m, 2, 3), clipped to [0, limit]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(d > 1e-15, (boxes[:, 1] - p) / d, np.where(d < -1e-15, (boxes[:, 0] - p) / d, np.inf))
    return np.clip(t.min(axis=1), 0.0, limit)


def side_samples(lines: SideLines, i: int, j: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The surfaces the tool's side sweeps at its ±omega extremes over poses i..j, sampled.

    The side's extreme lines of consecutive poses span a ruled surface — the floor or ceiling
    the side cuts. The lines run from the face to where the cutter ends (its trim box); the
    surface is sampled on the part of the lines inside the blank (overcut elsewhere removes
    nothing), at 7 points along each line, denser toward where it leaves the blank (the hull
    bridges most far out) and with one close to the face (the bridge grows from nothing there;
    see :func:`covered`), and 3 across each step. The true sweep between two poses lies
    beyond the interpolated surface (the side is curved across), so the samples are at or
    inside it.

    Returns, for each of the two sides that moves along omega: (line end points (2m, 3),
    samples (3, m-1, 7, 3) — across each step, step, along the lines —, outward direction
    (3,) — away from the tool)."""
    out = []
    s = np.array([0.0, 0.02, 0.25, 0.5, 0.75, 0.9, 1.0])
    t = np.array([0.0, 0.5, 1.0])[:, None, None, None]
    ax = lines.axes[i : j + 1]
    for side, sign in enumerate((1.0, -1.0)):
        p, q = lines.p[side, i : j + 1], lines.q[side, i : j + 1]
        ends = np.concatenate([p, q])
        if np.ptp(ends @ lines.omega) <= 1e-9:
            continue        # a planar floor: the hull is exact there
        along = p[:, None, :] + ax[:, None, :] * (lines.inside[side, i : j + 1, None] * s)[..., None]
        out.append((ends, along[:-1][None] * (1 - t) + along[1:][None] * t, sign * lines.omega))
    return out


def reaches(planes: np.ndarray, samples: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(k,) mm: for each sample (k, 3), how far the convex solid {x : n·x <= c} (planes
    (f, 4)) reaches beyond it along ``direction`` (0 when the sample is not inside), times
    SAMPLING_MARGIN."""
    toward = planes[:, :3] @ direction
    slack = planes[:, 3][None, :] - samples @ planes[:, :3].T
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(toward[None, :] > 1e-12, slack / toward[None, :], np.inf)
    reach = lam.min(axis=1)
    inside = (slack >= -1e-9).all(axis=1) & np.isfinite(reach)
    return SAMPLING_MARGIN * np.where(inside, reach, 0.0)


def covered(grid: np.ndarray, need: np.ndarray, reach: float, direction: np.ndarray, tips: np.ndarray,
            axes: np.ndarray, tool: Prism, behind: float = 0.0) -> np.ndarray:
    """(a, m, s) bool: the samples ``grid`` (a, m, s, 3) of a sampled surface (:func:`side_samples`)
    around which whatever lies within ``reach`` mm of the surface along ``direction`` (3,) is
    cut anyway by the tool at one of the poses ``tips``, ``axes`` (c, 3; unit axes) — asked
    only for the samples ``need`` (a, m, s) bool.

    The surface between samples is made of patches (a bilinear patch lies in the hull of its
    four corners, so what lies within ``reach`` of it along ``direction`` lies in the hull of
    those corners and the same moved by ``reach``). A patch is covered when those eight
    points lie within the cylinder inscribed in the prism's polygon at one and the same pose —
    so inside the true tool and its polygon both, at a place the path's motion takes. A sample
    is covered when every patch around it is. What a fan takes there beyond its own run's
    sweep is taken by those poses anyway, by the true tool and by the simulated one alike.

    ``behind`` (mm): the cylinders reach that far behind their poses' faces as well. What a
    patch holds there the pose does not cut, but it lies within ``behind`` of what it does:
    a cutter that takes it removes no more than that beyond the true sweep (near its face, a
    helix's next turn stands a little behind or ahead of the face chain where this turn's face
    meets it, the chains of the two differing by their sampling)."""
    out = np.zeros(need.shape, bool)
    if not need.any() or len(tips) == 0 or min(need.shape[0], need.shape[2]) < 2:
        return out
    # patches (a-1, m, s-1) around a needed sample
    want = need[:-1, :, :-1] | need[1:, :, :-1] | need[:-1, :, 1:] | need[1:, :, 1:]
    idx = np.nonzero(want)
    a, k, b = idx
    corners = np.stack([grid[a, k, b], grid[a + 1, k, b], grid[a, k, b + 1], grid[a + 1, k, b + 1]], axis=1)
    corners = np.concatenate([corners, corners + reach * np.asarray(direction, dtype=float)], axis=1)
    inner = tool.inner
    length = tool.length + behind
    tips = tips - behind * axes
    # a pose holds a patch when its eight points are inside: surely when the patch's bounding
    # ball is, possibly when the ball meets the cylinder (tested point by point)
    flat = corners.reshape(-1, 3)
    centre = 0.5 * (flat.min(axis=0) + flat.max(axis=0))
    rho = float(np.linalg.norm(flat - centre, axis=1).max())
    near = _ball_in_cylinder(centre[None], np.array([rho]), tips, axes, length, inner)[1][0]
    tp, ax = tips[near], axes[near]
    patch = np.zeros(want.shape, bool)
    if len(tp):
        mid = corners.mean(axis=1)
        sure, maybe = _ball_in_cylinder(mid, np.linalg.norm(corners - mid[:, None], axis=2).max(axis=1),
                                        tp, ax, length, inner)
        ok = sure.any(axis=1)
        pi_, pj = np.nonzero(maybe & ~ok[:, None])
        d = corners[pi_] - tp[pj][:, None]                                  # (q, 8, 3)
        z = np.einsum("qki,qi->qk", d, ax[pj])
        radial = np.linalg.norm(d - z[..., None] * ax[pj][:, None], axis=2)
        ok[pi_[((z >= 0.0) & (z <= length) & (radial <= inner)).all(axis=1)]] = True
        patch[idx] = ok
    # a sample is covered when every patch around it is (those off the grid do not count)
    full = np.ones((need.shape[0] + 1, need.shape[1], need.shape[2] + 1), bool)
    full[1:-1, :, 1:-1] = patch
    around = full[:-1, :, :-1] & full[1:, :, :-1] & full[:-1, :, 1:] & full[1:, :, 1:]
    return around & need


def _ball_in_cylinder(centres: np.ndarray, radii: np.ndarray, tips: np.ndarray, axes: np.ndarray,
                      length: float, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(inside, meets), each (k, c) bool: whether the ball (centres (k, 3), radii (k,)) lies
    inside, or may meet, the cylinder of the pose (tips, unit axes (c, 3); ``length``,
    ``radius``, from the tip along the axis)."""
    z = centres @ axes.T - np.einsum("ci,ci->c", tips, axes)[None]          # (k, c)
    cc = np.einsum("ki,ki->k", centres, centres)[:, None]
    tt = np.einsum("ci,ci->c", tips, tips)[None]
    radial2 = np.maximum(cc - 2.0 * centres @ tips.T + tt - z * z, 0.0)    # |centre - tip|² - z²
    r = radii[:, None]
    inside = (z >= r) & (z <= length - r) & (radial2 <= np.maximum(radius - r, 0.0) ** 2) & (radius >= r)
    meets = (z >= -r) & (z <= length + r) & (radial2 <= (radius + r) ** 2)
    return inside, meets


def hull_planes(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Face planes (f, 4) ``n·x <= c`` of a convex triangle mesh (outward faces)."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    good = length > 1e-14
    n = n[good] / length[good][:, None]
    return np.column_stack([n, np.einsum("ij,ij->i", n, a[good])])


def basis(omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal u, v with u × v = omega."""
    u = np.cross(omega, [1.0, 0.0, 0.0])
    if np.linalg.norm(u) < 0.5:
        u = np.cross(omega, [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    return u, np.cross(omega, u)


def material_points(tips: np.ndarray, axes: np.ndarray, omega: np.ndarray, around: np.ndarray,
                    margin: float = 1.0, eps: float = EPS) -> np.ndarray | None:
    """Vertices (k, 3) of M — the material below every face plane of a run, moved out by
    ``eps`` — within a box ``margin`` around the points ``around`` (m, 3) (the hull's), so
    that H \\ M is the fan cutter. All face planes contain omega, so M is a prism along it:
    the face lines cut a convex polygon out of a rectangle in the plane perpendicular to
    omega (:func:`vmach.stock.halfplanes.polygon`). None if empty."""
    u, v = basis(omega)
    pu, pv, pw = around @ u, around @ v, around @ omega
    lo, hi = np.array([pu.min(), pv.min()]) - margin, np.array([pu.max(), pv.max()]) + margin
    lines = face_lines(tips, axes, u, v)
    lines[:, 2] += eps
    p = polygon(lines, lo, hi)
    if len(p) < 3 or np.ptp(p[:, 0]) * np.ptp(p[:, 1]) <= 0.0:
        return None
    base = p[:, :1] * u + p[:, 1:] * v
    w0, w1 = pw.min() - margin, pw.max() + margin
    return np.vstack([base + w0 * omega, base + w1 * omega])
