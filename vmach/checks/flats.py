"""The flats of a polygonal cross-section: how many, and how flat each flank is.

    fl = flanks(contour)          # contour (k, 2) mm about the work's axis at (0, 0)
    len(fl), fl[0].flatness, fl[0].bulge

A polygon-like section's distance from its axis, r(θ), has one minimum per flat (its middle)
and one maximum per corner. The flats are the minima that stand at least ``prominence`` times
the mean radius below the corners on both sides. Each flank is the contour between two
neighbouring corners, trimmed to its middle ``span`` (the corners' rounding left out, as a
measuring machine's evaluation length does); against the chord through its two ends:

- ``bulge`` : the signed deviation of largest size, mm — positive outward (a convex flank,
  away from the axis), negative inward (concave);
- ``flatness`` : the width of the zone between the two parallel lines to the chord that hold
  the trimmed flank, mm (for an arc-like flank, which lies on one side of the chord, this is
  |bulge| and the minimum-zone flatness of ISO 1101);
- ``angle`` : direction of the flat's middle (its nearest point to the axis), degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: samples of r(θ) over a turn
SAMPLES = 7200


@dataclass(frozen=True)
class Flank:
    """One flat: ``angle`` degrees, ``radius`` mm (its middle's distance from the axis),
    ``bulge`` and ``flatness`` mm (module docstring), ``width`` mm (the trimmed chord's length)."""

    angle: float
    radius: float
    bulge: float
    flatness: float
    width: float


def dense(contour: np.ndarray, step: float) -> np.ndarray:
    """(p, 2): the closed contour's points with points at most ``step`` mm apart along each edge."""
    c = np.asarray(contour, dtype=float).reshape(-1, 2)
    closed = np.vstack([c, c[:1]])
    seg = np.diff(closed, axis=0)
    n = np.maximum(1, np.ceil(np.linalg.norm(seg, axis=1) / step).astype(int))
    t = np.concatenate([np.arange(k) / k for k in n])
    return np.repeat(closed[:-1], n, axis=0) + np.repeat(seg, n, axis=0) * t[:, None]


def radius_profile(contour: np.ndarray, samples: int = SAMPLES) -> tuple[np.ndarray, np.ndarray]:
    """(θ (s,) rad, r (s,) mm): the contour's distance from the origin on a uniform grid of
    angles (the contour star-shaped about the origin, as a turned part's section is)."""
    pts = dense(contour, 0.01)        # so that r(θ) follows straight edges between vertices
    th = np.arctan2(pts[:, 1], pts[:, 0])
    r = np.hypot(pts[:, 0], pts[:, 1])
    order = np.argsort(th)
    th, r = th[order], r[order]
    grid = np.linspace(-math.pi, math.pi, samples, endpoint=False)
    return grid, np.interp(grid, th, r, period=2.0 * math.pi)


def flanks(contour: np.ndarray, span: float = 0.8, prominence: float = 0.002) -> list[Flank]:
    """The flats of a closed ``contour`` (k, 2) mm about the origin, in order of angle
    (module docstring). ``span``: the middle fraction of each flank measured; ``prominence``:
    the least depth of a flat below its corners, as a fraction of the mean radius."""
    c = np.asarray(contour, dtype=float).reshape(-1, 2)
    th, r = radius_profile(c)
    s = len(r)
    depth = prominence * float(r.mean())
    # candidate middles: the least r within ±1° (wrapping), then kept where both corners stand higher
    w = max(1, s // 360)
    ext = np.r_[r[-w:], r, r[:w]]
    window = np.lib.stride_tricks.sliding_window_view(ext, 2 * w + 1)
    low = np.nonzero((r <= window.min(axis=1)) & (np.r_[r[1:], r[:1]] > r - 1e-12))[0]
    if len(low) == 0:
        return []
    keep = []
    for i, a in enumerate(low):
        b = low[(i + 1) % len(low)]
        between = _arc(r, a, b)
        if len(low) == 1 or between.max() - r[a] >= depth:
            keep.append(a)
    mids = _merge(r, keep, depth)
    if len(mids) < 2:
        return []
    corners = []
    for i, a in enumerate(mids):
        b = mids[(i + 1) % len(mids)]
        idx = _arc_index(a, b, s)
        corners.append(int(idx[np.argmax(r[idx])]))
    out = []
    for i, m in enumerate(mids):
        a, b = corners[i - 1], corners[i]
        lo, hi = th[a], th[a] + ((th[b] - th[a]) % (2.0 * math.pi))
        mid = (lo + hi) / 2.0
        half = (hi - lo) * span / 2.0
        out.append(_flank(c, mid - half, mid + half, th[m], r[m]))
    return out


def _arc(r: np.ndarray, a: int, b: int) -> np.ndarray:
    return r[_arc_index(a, b, len(r))]


def _arc_index(a: int, b: int, s: int) -> np.ndarray:
    """Indices from a to b going up (wrapping), both included."""
    return np.arange(a, a + ((b - a) % s) + 1) % s


def _merge(r: np.ndarray, keep: list, depth: float) -> list[int]:
    """Kept minima with no corner of ``depth`` between two of them merged into the lower."""
    mids = list(keep)
    changed = True
    while changed and len(mids) > 1:
        changed = False
        for i in range(len(mids)):
            a, b = mids[i], mids[(i + 1) % len(mids)]
            top = _arc(r, a, b).max()
            if top - max(r[a], r[b]) < depth:
                lose = a if r[a] > r[b] else b
                mids.remove(lose)
                changed = True
                break
    return sorted(mids)


def _flank(contour: np.ndarray, t0: float, t1: float, at: float, radius: float) -> Flank:
    """The flank of the contour between the angles t0 < t1 (rad, t1 - t0 < 2π)."""
    pts = dense(contour, 0.005)
    th = np.arctan2(pts[:, 1], pts[:, 0])
    rel = (th - t0) % (2.0 * math.pi)
    sel = pts[rel <= (t1 - t0)]
    ends = [np.array([math.cos(t), math.sin(t)]) for t in (t0, t1)]
    # the chord's ends: where the contour crosses the rays at t0 and t1
    a, b = (_on_ray(pts, e) for e in ends)
    d = b - a
    length = float(np.linalg.norm(d))
    nrm = np.array([d[1], -d[0]]) / max(length, 1e-12)
    if nrm @ (a + b) < 0:
        nrm = -nrm                                   # outward: away from the axis
    dev = (sel - a) @ nrm
    big = dev[np.argmax(np.abs(dev))] if len(dev) else 0.0
    return Flank(math.degrees(at), radius, float(big), float(dev.max() - min(dev.min(), 0.0))
                 if big >= 0 else float(max(dev.max(), 0.0) - dev.min()), length)


def _on_ray(pts: np.ndarray, e: np.ndarray) -> np.ndarray:
    """The point of the dense contour ``pts`` nearest the ray from the origin along ``e``."""
    along = pts @ e
    off = np.abs(pts[:, 0] * e[1] - pts[:, 1] * e[0])
    off[along <= 0] = np.inf
    return pts[int(np.argmin(off))]


__all__ = ["Flank", "dense", "flanks", "radius_profile"]
