"""Boxes around the stock within ranges of Z: a tighter trim for each cutter.

Only the part of a cutter inside the stock removes anything, and the stock never grows, so a
cutter may be trimmed to any box that holds the stock *within the cutter's own Z range*
(:mod:`vmach.stock.clip` explains why a box, and why exact box coordinates). One box around
the whole stock is loose where the stock has been cut down: on the polygon shaft the end that
the finishing cutter works on is 53.6 mm across while the blank behind the shoulder is still
60. The stock's triangles are binned by Z once (their X/Y extent per bin), and a cutter's box
is the extent of the bins its Z range meets, grown by ``tol.trim_margin``, rounded outward
to a grid, and then moved out by up to JITTER more, by an amount that differs from cutter to
cutter (:func:`jitter`): neighbouring cutters then share no box plane. Exactly coplanar faces
cost manifold3d's union of a batch more (measured: docs/stock-history.md); a larger jitter
makes the boxes, hence the fans' side lines, longer and the fans shorter, which gives the gain
back.

Why that box holds the stock there: a closed surface's points inside a slab lie on triangles
that meet the slab, and the solid's section is bounded by its surface, so the extent of those
triangles bounds the stock within the slab. A stale snapshot (cutters subtracted since) only
makes the box larger. Lengths mm.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from vmach.tol import tol

GRID = 0.5   # box planes rounded outward to multiples of this, mm
JITTER = 0.1  # ... and then moved out by up to this much more, differently for each cutter, mm


def _range_min(nb: int, b0: np.ndarray, b1: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(nb, c) float: for every bin, the least of ``values`` (m, c) over the items whose bin
    range [b0, b1] (m,) holds it (+inf for none). Each range is two overlapping power-of-two
    blocks, marked at its level and pushed down level by level — O(m + nb log nb), whatever
    the ranges' lengths (a CAD blank's cylinder side is long triangles that span every bin)."""
    values = np.asarray(values, dtype=float)
    levels = max(1, int(nb).bit_length())
    tab = np.full((levels, nb, values.shape[1]), np.inf)
    level = np.floor(np.log2(b1 - b0 + 1)).astype(int)
    np.minimum.at(tab, (level, b0), values)
    np.minimum.at(tab, (level, b1 - (1 << level) + 1), values)
    for j in range(levels - 1, 0, -1):
        h = 1 << (j - 1)
        np.minimum(tab[j - 1], tab[j], out=tab[j - 1])
        np.minimum(tab[j - 1, h:], tab[j, : nb - h], out=tab[j - 1, h:])
    return tab[0]


@dataclass(frozen=True)
class Slabs:
    """X/Y extent of a surface per Z bin.

    z0 : float — bottom of bin 0; step : float — bin height; lo, hi : (b, 2) float — X/Y
    extent of the triangles meeting each bin (+inf/-inf for an empty bin); rmax : (b,) float —
    their largest distance from the Z axis (-inf when empty); top : float — the surface's
    highest Z.
    """

    z0: float
    step: float
    lo: np.ndarray
    hi: np.ndarray
    rmax: np.ndarray
    top: float

    @classmethod
    def from_mesh(cls, vertices: np.ndarray, faces: np.ndarray, step: float = 1.0) -> Slabs:
        tri = vertices[faces]                                   # (m, 3, 3)
        zmin, zmax = tri[:, :, 2].min(axis=1), tri[:, :, 2].max(axis=1)
        z0 = float(zmin.min()) if len(tri) else 0.0
        b0 = np.floor((zmin - z0) / step).astype(int)
        b1 = np.floor((zmax - z0) / step).astype(int)
        nb = int(b1.max()) + 1 if len(tri) else 1
        xy_lo, xy_hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
        r = np.hypot(tri[:, :, 0], tri[:, :, 1]).max(axis=1)
        # the least x, y and the greatest x, y, r per bin, in one pass over the bins
        least = _range_min(nb, b0, b1, np.column_stack([xy_lo, -xy_hi, -r]))
        lo, hi, rmax = least[:, :2], -least[:, 2:4], -least[:, 4]
        return cls(z0, step, lo, hi, rmax, float(zmax.max()) if len(tri) else 0.0)

    def holds(self, points: np.ndarray) -> np.ndarray:
        """(...) bool: points (..., 3) that may lie in the solid — within its Z range, and
        within the X/Y extent and the largest radius about Z of their bin's triangles (a
        superset of the solid, without margin)."""
        p = np.asarray(points, dtype=float)
        b = np.floor((p[..., 2] - self.z0) / self.step).astype(int)
        ok = (p[..., 2] >= self.z0) & (p[..., 2] <= self.top)
        b = np.clip(b, 0, len(self.lo) - 1)
        lo, hi = self.lo[b], self.hi[b]
        ok &= np.all((p[..., :2] >= lo) & (p[..., :2] <= hi), axis=-1)
        return ok & (np.hypot(p[..., 0], p[..., 1]) <= self.rmax[b])

    def support(self, zlo: np.ndarray, zhi: np.ndarray, dirs: np.ndarray) -> np.ndarray:
        """(k,) float, mm: how far the solid reaches along the unit directions ``dirs`` (k, 3)
        within the Z ranges [zlo, zhi] (k,) — at most: the largest support over the bins the
        range meets of each bin's X/Y box and its cylinder of the largest radius about Z
        (the solid lies in both), at the bin's top or bottom; -inf where no bin is met."""
        d = np.asarray(dirs, dtype=float).reshape(-1, 3)
        nb = len(self.lo)
        bottom = self.z0 + self.step * np.arange(nb)
        b0 = np.floor((np.asarray(zlo, dtype=float) - self.z0) / self.step).astype(int)
        b1 = np.floor((np.asarray(zhi, dtype=float) - self.z0) / self.step).astype(int)
        full = np.isfinite(self.rmax)
        box = (np.maximum(d[:, :1] * self.lo[None, :, 0], d[:, :1] * self.hi[None, :, 0])
               + np.maximum(d[:, 1:2] * self.lo[None, :, 1], d[:, 1:2] * self.hi[None, :, 1]))   # (k, b)
        cyl = np.hypot(d[:, 0], d[:, 1])[:, None] * np.where(full, self.rmax, 0.0)[None]
        along = np.maximum(d[:, 2:3] * bottom[None], d[:, 2:3] * (bottom + self.step)[None])
        sup = np.minimum(box, cyl) + along
        bins = np.arange(nb)[None]
        meets = (bins >= b0[:, None]) & (bins <= b1[:, None]) & full[None]
        return np.where(meets, sup, -np.inf).max(axis=1, initial=-np.inf)

    @cached_property
    def _spans(self) -> tuple[np.ndarray, np.ndarray]:
        """Sparse tables (levels, b, 2) of lo and hi: entry [j, i] is the min (max) over bins
        i … i + 2^j − 1 (the bins beyond the last taken as empty)."""
        nb = len(self.lo)
        tab_lo, tab_hi = [self.lo], [self.hi]
        j = 1
        while (1 << j) <= nb:
            h = 1 << (j - 1)
            prev_lo, prev_hi = tab_lo[-1], tab_hi[-1]
            nxt_lo = np.full_like(prev_lo, np.inf)
            nxt_hi = np.full_like(prev_hi, -np.inf)
            nxt_lo[: nb - h] = np.minimum(prev_lo[: nb - h], prev_lo[h:])
            nxt_hi[: nb - h] = np.maximum(prev_hi[: nb - h], prev_hi[h:])
            tab_lo.append(nxt_lo)
            tab_hi.append(nxt_hi)
            j += 1
        return np.stack(tab_lo), np.stack(tab_hi)

    def boxes(self, zlo: np.ndarray, zhi: np.ndarray, outer: np.ndarray) -> np.ndarray:
        """Boxes (k, 2, 3) for Z ranges [zlo, zhi] (k,): the extent of the bins they meet,
        grown by the trim margin, rounded outward to ``GRID`` within ``outer`` (2, 3) (the box
        around the whole stock), and moved out by :func:`jitter` (up to JITTER more). A
        range that meets no material gets an empty box (lo > hi), which culls what is in it."""
        zlo = np.asarray(zlo, dtype=float)
        zhi = np.asarray(zhi, dtype=float)
        nb = len(self.lo)
        b0 = np.clip(np.floor((zlo - self.z0) / self.step).astype(int), 0, nb - 1)
        b1 = np.maximum(np.clip(np.floor((zhi - self.z0) / self.step).astype(int), 0, nb - 1), b0)
        # min/max over the bin ranges: two overlapping power-of-two spans of the sparse tables
        level = np.floor(np.log2(b1 - b0 + 1)).astype(int)
        last = b1 - (1 << level) + 1
        tab_lo, tab_hi = self._spans
        lo = np.minimum(tab_lo[level, b0], tab_lo[level, last])
        hi = np.maximum(tab_hi[level, b0], tab_hi[level, last])
        m = tol.trim_margin
        out = np.empty((len(zlo), 2, 3))
        out[:, 0, :2] = np.maximum(np.floor((lo - m) / GRID) * GRID, outer[0, :2])
        out[:, 1, :2] = np.minimum(np.ceil((hi + m) / GRID) * GRID, outer[1, :2])
        out[:, 0, 2] = outer[0, 2]
        out[:, 1, 2] = outer[1, 2]
        u = jitter(zlo, zhi)
        out[:, 0] -= u[:, :3] * JITTER
        out[:, 1] += u[:, 3:] * JITTER
        return out


def jitter(zlo: np.ndarray, zhi: np.ndarray) -> np.ndarray:
    """(k, 6) float in [0, 1): how far, in grid steps, each box's six planes move out — a
    hash of the cutter's own Z range, so that the same cutter always gets the same box and
    different cutters (almost surely) different ones."""
    k = np.arange(6)
    x = np.sin(np.asarray(zlo, float)[:, None] * (12.9898 + k) + np.asarray(zhi, float)[:, None] * 78.233
               + 37.719 * k) * 43758.5453
    return x - np.floor(x)
