"""Cutters trimmed to a box around the stock — exactly, and cheaply for the booleans.

Only the part of a cutter inside the stock removes anything, and the stock never grows, so a
cutter may be replaced by its intersection with any box ``Q`` that contains the stock: the
result of the subtraction is the same. The trimmed part of a convex piece ``P`` is convex,
``P ∩ Q = hull(V)`` with V

- the vertices of P inside Q,
- the crossings of P's edges with Q's faces,
- the crossings of Q's edges with P (each edge clipped by P's face planes; this also yields
  the corners of Q inside P).

Points on a face of Q are given that face's coordinate *exactly*, so the caps of all trimmed
cutters lie exactly in the same few axis-aligned planes, outside the stock. That is what makes
it pay: the far ends of overlapping cutters (a radial tool's far face, a face mill's back)
otherwise cross each other in the air in a dense arrangement which manifold3d computes for
every batch union, and which is most of its work (measured: docs/stock-history.md). Exactly coplanar
caps cost manifold3d almost nothing; caps that are only nearly coplanar (an oblique plane
computed in floating point) cost more than no trimming at all — hence the axis-aligned box.

Error: the points are computed in double precision from the placed vertices, so the trimmed
hull differs from ``P ∩ Q`` by rounding (~1e-12 mm), far inside ``tol.tool_chord``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Shape:
    """Edges and face planes of a convex polytope, for clipping.

    vertices : (p, 3) float, mm — hull vertices (tool frame).
    edges : (e, 2) int — vertex index pairs (triangle edges; diagonals of planar faces are
        harmless: their crossings lie on the polytope).
    planes : (f, 4) float — ``n·x <= d`` for every face, unit n.
    edge_normals : (e, 2, 3) float or None — unit normals of the two triangles at each edge
        (NaN next to a sliver; :func:`sweep_shape` keeps the planes of the edges its travel
        sees edge-on).
    """

    vertices: np.ndarray
    edges: np.ndarray
    planes: np.ndarray
    edge_normals: np.ndarray | None = None


def shape(vertices: np.ndarray, faces: np.ndarray) -> Shape:
    """Shape of a convex triangle mesh (vertices (p, 3) float, faces (f, 3) int, outward).
    Edges inside planar faces (the diagonals of a triangulated polygon) are left out: their
    crossings would only add points inside the faces."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    scale = max(1.0, float(np.abs(v).max())) if len(v) else 1.0
    good = length > 1e-12 * scale * scale          # slivers' planes are noise
    unit = np.where(good[:, None], n / np.where(good, length, 1.0)[:, None], 0.0)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    tri = np.tile(np.arange(len(f)), 3)
    key = np.sort(e, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, tri = key[order], tri[order]
    # a closed mesh has every edge twice: pairs (2i, 2i+1) after sorting
    first, second = tri[0::2], tri[1::2]
    bend = np.einsum("ij,ij->i", unit[first], unit[second]) < 1.0 - 1e-12
    kept = bend | ~good[first] | ~good[second]
    edges = key[0::2][kept]
    # an edge next to a sliver has no trustworthy normals: NaN, and it counts as seen edge-on
    normals = np.where((good[first] & good[second])[kept][:, None, None],
                       np.stack([unit[first], unit[second]], axis=1)[kept], np.nan)
    d = np.einsum("ij,ij->i", unit[good], a[good])
    planes = np.column_stack([unit[good], d])
    # one plane per face, not per triangle
    _, first_of = np.unique(np.round(planes / np.array([1e-9, 1e-9, 1e-9, 1e-9 * scale])),
                            axis=0, return_index=True)
    return Shape(v, edges, planes[np.sort(first_of)], normals)


def sweep_shape(sh: Shape, frame_a: np.ndarray, frame_b: np.ndarray) -> Shape:
    """The shape of a convex piece translated from pose a to pose b (frames (3, 4); the same
    axis): its hull, without building it. Vertices: the piece at both poses. Edges: the
    piece's at both poses and the segments joining each vertex to its copy — a superset of
    the hull's edges (the rest lie inside it, and their crossings add nothing). Planes: the
    piece's face normals and, for every edge, the two normals of the plane through it and
    the travel, each at the vertices' support — supporting planes that include every facet
    of the hull, so they cut it out exactly. Only edges the travel sees edge-on (its two
    triangles' normals on either side of it, n₁·d and n₂·d of opposite signs) make facets
    of the hull of their own (the sides of the swept silhouette); the other edges' planes are
    left out, which changes nothing: each only supports the hull at that edge, or is the
    plane of a face parallel to the travel, which the face's own plane gives."""
    p = len(sh.vertices)
    va = sh.vertices @ frame_a[:, :3].T + frame_a[:, 3]
    vb = sh.vertices @ frame_b[:, :3].T + frame_b[:, 3]
    v = np.concatenate([va, vb])
    e = sh.edges
    edges = np.concatenate([e, e + p, np.column_stack([np.arange(p), np.arange(p) + p])])
    d = frame_b[:, 3] - frame_a[:, 3]
    normals = [sh.planes[:, :3] @ frame_a[:, :3].T]
    if sh.edge_normals is not None:
        s = sh.edge_normals @ (frame_a[:, :3].T @ d)                      # (e, 2) in the tool frame
        eps = 1e-12 * max(1.0, float(np.linalg.norm(d)))
        seen = ((s[:, 0] > eps) & (s[:, 1] < -eps)) | ((s[:, 0] < -eps) & (s[:, 1] > eps))
        e = e[seen | np.isnan(s).any(axis=1)]
    side = np.cross(va[e[:, 1]] - va[e[:, 0]], d)
    length = np.linalg.norm(side, axis=1)
    keep = length > 1e-12 * max(1.0, float(np.linalg.norm(d))) * max(1.0, float(np.abs(va).max()))
    side = side[keep] / length[keep][:, None]
    normals += [side, -side]
    n = np.concatenate(normals)
    return Shape(v, edges, np.column_stack([n, (v @ n.T).max(axis=0)]))


def _box_edges(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start points (m, 12, 3) and direction vectors (m, 12, 3) of the edges of boxes
    [lo, hi] (m, 3)."""
    bits = np.arange(8)[:, None] >> np.arange(3)[None, :] & 1                  # (8, 3)
    corner = np.where(bits[None].astype(bool), hi[:, None, :], lo[:, None, :])  # (m, 8, 3)
    pairs = np.array([(i, i | (1 << ax)) for i in range(8) for ax in range(3) if not i & (1 << ax)])
    return corner[:, pairs[:, 0]], corner[:, pairs[:, 1]] - corner[:, pairs[:, 0]]


CHUNK = 128  # copies clipped together (bounds the temporary arrays to a few MB)


def clip(sh: Shape, frames: np.ndarray, lo, hi) -> tuple[list[np.ndarray | None], np.ndarray]:
    """Clip placed copies of a convex shape to boxes [lo, hi].

    sh : the shape in the tool frame. frames : (m, 3, 4) float — rotation | translation.
    lo, hi : (3,) float — one box for all copies — or (m, 3): a box for each.
    Returns (points, inside): points[k] is an (q, 3) array whose hull is copy k ∩ its box, or
    None when copy k misses it (or the box is empty: lo > hi somewhere); inside (m,) bool marks
    copies wholly inside their box (their points are the placed vertices, nothing was cut).
    """
    fr = np.asarray(frames, dtype=float).reshape(-1, 3, 4)
    m = len(fr)
    lo = np.broadcast_to(np.asarray(lo, dtype=float), (m, 3))
    hi = np.broadcast_to(np.asarray(hi, dtype=float), (m, 3))
    if m > CHUNK:
        out: list[np.ndarray | None] = []
        inside = []
        for c0 in range(0, m, CHUNK):
            o, i = clip(sh, fr[c0 : c0 + CHUNK], lo[c0 : c0 + CHUNK], hi[c0 : c0 + CHUNK])
            out += o
            inside.append(i)
        return out, np.concatenate(inside)
    rot, t = fr[:, :, :3], fr[:, :, 3]
    P = sh.vertices @ rot.transpose(0, 2, 1) + t[:, None, :]                  # (m, p, 3)
    plo, phi = P.min(axis=1), P.max(axis=1)
    inside = np.all((plo >= lo) & (phi <= hi), axis=1)
    miss = np.any((phi < lo) | (plo > hi) | (lo > hi), axis=1)
    out = [None] * m
    for k in np.nonzero(inside)[0]:
        out[k] = P[k]
    todo = np.nonzero(~inside & ~miss)[0]
    if len(todo) == 0:
        return out, inside
    Pt = P[todo]                                                              # (c, p, 3)
    c = len(todo)
    blo, bhi = lo[todo], hi[todo]                                             # (c, 3)
    tlo, thi = plo[todo], phi[todo]
    keep = np.all((Pt >= blo[:, None]) & (Pt <= bhi[:, None]), axis=2)         # (c, p)
    which, vert = np.nonzero(keep)
    idx: list[np.ndarray] = [which]
    pts: list[np.ndarray] = [Pt[which, vert]]
    _edge_crossings(sh, Pt, blo, bhi, tlo, thi, idx, pts)
    _box_edges_clipped(sh, rot[todo], t[todo], blo, bhi, tlo, thi, idx, pts)
    allidx = np.concatenate(idx)
    allpts = np.concatenate(pts)
    order = np.argsort(allidx, kind="stable")
    counts = np.bincount(allidx, minlength=c)
    for k, chunk in zip(todo, np.split(allpts[order], np.cumsum(counts)[:-1]), strict=True):
        out[k] = chunk if len(chunk) >= 4 else None
    return out, inside


def _edge_crossings(sh: Shape, Pt: np.ndarray, blo, bhi, tlo, thi, idx: list, pts: list) -> None:
    """Where the copies' (c, p, 3) edges cross their boxes' faces, within the box: appended to
    ``idx`` (copy) and ``pts`` (points)."""
    A, B = Pt[:, sh.edges[:, 0]], Pt[:, sh.edges[:, 1]]                      # (c, e, 3)
    for ax in range(3):
        other = [i for i in range(3) if i != ax]
        for val in (blo[:, ax], bhi[:, ax]):
            # only copies with vertices on both sides of the plane have edges that cross it
            rows = np.nonzero((tlo[:, ax] <= val) & (thi[:, ax] > val))[0]
            if len(rows) == 0:
                continue
            v = val[rows]
            da, db = A[rows, :, ax] - v[:, None], B[rows, :, ax] - v[:, None]
            w, edge = np.nonzero((da > 0) != (db > 0))
            if len(w) == 0:
                continue
            s = da[w, edge] / (da[w, edge] - db[w, edge])
            a, b = A[rows[w], edge], B[rows[w], edge]
            x = a + (b - a) * s[:, None]
            which = rows[w]
            x[:, ax] = val[which]
            ok = np.all((x[:, other] >= blo[which][:, other]) & (x[:, other] <= bhi[which][:, other]), axis=1)
            idx.append(which[ok])
            pts.append(x[ok])


def _box_edges_clipped(sh: Shape, rot: np.ndarray, t: np.ndarray, blo, bhi, tlo, thi, idx: list,
                       pts: list) -> None:
    """The boxes' edges clipped by each copy's face planes (copies' rotations (c, 3, 3) and
    translations (c, 3)): the segments' ends appended to ``idx`` and ``pts``."""
    # the box's edges clipped by each copy's face planes (Cyrus-Beck), for the edges that
    # pass through the copy's bounding box (no other can meet it)
    q0, dq = _box_edges(blo, bhi)                                             # (c, 12, 3)
    near = np.all((dq != 0) | ((q0 >= tlo[:, None]) & (q0 <= thi[:, None])), axis=2)   # (c, 12)
    w, edge = np.nonzero(near)
    if len(w):
        start, step = q0[w, edge], dq[w, edge]                                # (k, 3)
        N = sh.planes[:, :3] @ rot.transpose(0, 2, 1)                   # (c, f, 3)
        D = sh.planes[None, :, 3] + np.matmul(N, t[:, :, None])[:, :, 0]   # (c, f)
        Nk = N[w]                                                             # (k, f, 3)
        nd = np.matmul(Nk, step[:, :, None])[:, :, 0]                         # (k, f)
        num = D[w] - np.matmul(Nk, start[:, :, None])[:, :, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            r = num / nd
        s0 = np.maximum(np.where(nd < 0, r, -np.inf).max(axis=1), 0.0)
        s1 = np.minimum(np.where(nd > 0, r, np.inf).min(axis=1), 1.0)
        blocked = ((nd == 0) & (num < 0)).any(axis=1)
        ok = (s0 <= s1) & ~blocked
        start, step, w = start[ok], step[ok], w[ok]
        fixed = step == 0
        for s_ in (s0[ok], s1[ok]):
            idx.append(w)
            pts.append(np.where(fixed, start, start + step * s_[:, None]))
