"""Convex polygons cut out by half-planes, in 2D (the plane perpendicular to a fan's or a
column's rotation axis, where every face plane of its poses is a line).

:func:`polygon` gives the corners of {x : a·x + b·y <= c for every line} inside a box in
O(m log m) through the lines' dual (:func:`_hull2d`), or by clipping the box line by line
(:func:`clip_box`) when no point strictly inside every half-plane is found. Used for the
material M below a fan's or a column's face planes (:func:`vmach.stock.fan_measure.material_points`)
and for how deep a column's face chain lies below a turn's own
(:func:`vmach.stock.column.chain_depth`).

Lengths mm.
"""

from __future__ import annotations

import numpy as np


def face_lines(tips: np.ndarray, axes: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Face lines (m, 3) ``(a, b, c)``: a·x + b·y <= c in the plane (u, v) perpendicular to a
    rotation axis omega — the material side of each pose's face plane (tips, outward unit
    axes (m, 3), both planes containing omega)."""
    return np.column_stack([axes @ u, axes @ v, np.einsum("ij,ij->i", tips, axes)])


def polygon(lines: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Vertices (k, 2) of the convex polygon {x : a·x + b·y <= c for every line (m, 3)} inside
    the box [lo, hi] (2,); (0, 2) when empty.

    The lines' region is found through its dual: with a point p0 strictly inside every
    half-plane, line (n, c) maps to the point n / (c − n·p0), and the region's corners are the
    crossings of the lines whose dual points are neighbours on the dual points' convex hull
    (:func:`_hull2d`). p0 is sought where the lines' normals agree (behind their mean normal);
    if none is found strictly inside, the box is clipped by each half-plane in turn instead
    (Sutherland–Hodgman)."""
    lines = np.asarray(lines, dtype=float).reshape(-1, 3)
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    box = np.array([[-1.0, 0.0, -lo[0]], [1.0, 0.0, hi[0]], [0.0, -1.0, -lo[1]], [0.0, 1.0, hi[1]]])
    every = np.vstack([lines, box])
    p0 = _inside(every, lo, hi)
    if p0 is None:
        return clip_box(lines, lo, hi)
    slack = every[:, 2] - every[:, :2] @ p0
    ring = _hull2d(every[:, :2] / slack[:, None])
    a, b = every[ring], every[np.roll(ring, -1)]
    det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    good = np.abs(det) > 1e-15
    a, b, det = a[good], b[good], det[good]
    return np.column_stack([(a[:, 2] * b[:, 1] - b[:, 2] * a[:, 1]) / det,
                            (a[:, 0] * b[:, 2] - b[:, 0] * a[:, 2]) / det])


def _hull2d(points: np.ndarray) -> np.ndarray:
    """Indices of the points (m, 2) on their convex hull, counter-clockwise (Andrew's monotone
    chain; points on an edge left out)."""
    order = np.lexsort((points[:, 1], points[:, 0]))
    p = points[order]

    def half(idx):
        out: list[int] = []
        for i in idx:
            while len(out) >= 2:
                o, a = p[out[-2]], p[out[-1]]
                if (a[0] - o[0]) * (p[i][1] - o[1]) - (a[1] - o[1]) * (p[i][0] - o[0]) > 0:
                    break
                out.pop()
            out.append(i)
        return out

    lower = half(range(len(p)))
    upper = half(range(len(p) - 1, -1, -1))
    return order[np.array(lower[:-1] + upper[:-1], dtype=int)]


def _inside(lines: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray | None:
    """A point strictly inside every half-plane of ``lines`` (m, 3) — tried along the mean
    normal behind the centre of the box's face-line feet, and at the box's centre — or None."""
    n = lines[:, :2]
    mean = n[:-4].sum(axis=0) if len(n) > 4 else np.zeros(2)
    tries = [0.5 * (lo + hi)]
    norm = float(np.linalg.norm(mean))
    if norm > 1e-12:
        m = mean / norm
        foot = (lines[:-4, 2:3] * n[:-4]).mean(axis=0)          # near the lines
        along = n[:-4] @ m
        if np.all(along > 1e-6):
            need = float(np.max((n[:-4] @ foot - lines[:-4, 2]) / along))
            tries.insert(0, foot - (max(need, 0.0) + 1.0) * m)
    scale = max(1.0, float(np.abs(lines[:, 2]).max()))
    for p in tries:
        if np.all(lines[:, :2] @ p - lines[:, 2] < -1e-9 * scale):
            return p
    return None


def clip_box(lines: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The box [lo, hi] clipped by each half-plane of ``lines`` (m, 3) in turn."""
    poly = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]], dtype=float)
    for a, b, c in lines:
        s = poly @ np.array([a, b]) - c                 # > 0: outside
        if np.all(s <= 0):
            continue
        if np.all(s > 0):
            return np.zeros((0, 2))
        nxt, sn = np.roll(poly, -1, axis=0), np.roll(s, -1)
        out = []
        for p, q, sp, sq in zip(poly, nxt, s, sn, strict=True):
            if sp <= 0:
                out.append(p)
            if (sp <= 0) != (sq <= 0):
                out.append(p + (q - p) * (sp / (sp - sq)))
        poly = np.array(out)
    return poly
