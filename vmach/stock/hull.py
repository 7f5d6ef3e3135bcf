"""The blank's convex hull for the screening tests, kept to a few thousand planes.

The stock stage asks the blank's hull four kinds of question, each only to save work, and each
with one safe direction:

- *does a cylinder lie wholly beyond the blank?* (the verify checks drop such rows) and *where
  does a ray leave the blank?* (the fan's bridge samples): safe with any region that holds the
  blank — the **outer** planes;
- *how far does the blank reach along a direction?* (a fan's back faces must clear it): safe
  with the corners of such a region — the **corners**;
- *is a point inside the blank?* (a part that reaches into it meets it): safe with a region
  inside the blank — the **inner** planes.

A cylinder blank's hull has a few hundred facets (up to ``4 * MAX_PLANES`` triangles), used as
they are (outer = inner = the hull's planes, corners = its vertices: exact). A blank read from a
mesh may have hundreds of thousands (a finely tessellated casting, a CAD cylinder of thin side
strips): every test is points × planes, and a 1.3-million-triangle sphere made the checked run
take minutes in those products alone. Such a hull is reduced:

- outer: the plane of its largest facet in each cell of a grid over the sphere of its normals
  (``BANDS`` × ``SECTORS``; a fine cylinder keeps a side plane every 1.4°) and its bounding
  box's planes — each a supporting plane, so the region they bound holds the hull;
- corners: that region's vertices (:class:`scipy.spatial.HalfspaceIntersection`);
- inner: the hull of about ``INNER_POINTS`` of its vertices, one per cell of a grid, and of its
  extreme points in ``MAX_PLANES / 2`` directions spread over the sphere — a subset of its
  vertices, so inside (its planes serve the few points of one solid at a time, so it may have
  thousands).

The reduced answers are looser, never wrong.

A convex blank read from a mesh is also *cut* as its hull when that has fewer triangles and the
mesh lies on it within ``tol.blank_hull`` (:func:`as_hull`, :func:`lies_on_hull`): a CAD
cylinder's side strips, cut along its length, merge, and the stock's booleans pay per triangle.

Planes are (f, 4) float: unit outward normal n and offset d, the region ``n·x <= d`` (mm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vmach.stock import engine
from vmach.stock.clip import shape

#: a hull of up to 4 * MAX_PLANES triangles is used as it is; MAX_PLANES / 2 directions give
#: the inner region's extreme points
MAX_PLANES = 512
#: the outer planes of a reduced hull: one facet per cell of BANDS x SECTORS on the sphere of
#: its normals (at most 2,048 planes; a cylinder's side every 1.4 degrees)
BANDS, SECTORS = 8, 256
#: hull vertices kept for the inner region (its planes serve few points at a time)
INNER_POINTS = 8192


@dataclass(frozen=True)
class BlankHull:
    """outer, inner : (f, 4) planes (see the module docstring); corners : (v, 3) float, mm;
    exact : True when outer = inner = the hull itself."""

    outer: np.ndarray
    inner: np.ndarray
    corners: np.ndarray
    exact: bool


def box_corners(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(8, 3) float: the corners of the box [lo, hi] ((3,) each, mm)."""
    return np.array(np.meshgrid(*zip(lo, hi, strict=True))).reshape(3, -1).T


def normals(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Triangles (t, 3, 3) float, mm: their normals (t, 3), as long as twice their area (mm²),
    and those lengths (t,)."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n, np.linalg.norm(n, axis=1)


def directions(n: int) -> np.ndarray:
    """(n, 3) unit vectors spread evenly over the sphere (a Fibonacci lattice)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = np.pi * (1.0 + 5.0 ** 0.5) * i
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def _extreme(points: np.ndarray, dirs: np.ndarray, block: int = 1 << 15) -> np.ndarray:
    """(d,) int: the index of the point (p, 3) farthest along each direction (d, 3), taken in
    blocks of points (a 1.3-million-vertex hull times 250 directions would be a 1.3 GB array)."""
    best = np.full(len(dirs), -np.inf)
    where = np.zeros(len(dirs), dtype=np.int64)
    for i in range(0, len(points), block):
        s = dirs @ points[i : i + block].T                         # (d, b)
        k = s.argmax(axis=1)
        top = s[np.arange(len(dirs)), k]
        better = top > best
        best[better], where[better] = top[better], k[better] + i
    return where


def blank_hull(vertices: np.ndarray, faces: np.ndarray, most: int | None = None) -> BlankHull:
    """The hull of a convex triangle mesh (its vertices (p, 3) float, faces (f, 3) int, outward):
    used as it is up to ``4 * most`` triangles (``most``: default ``MAX_PLANES``), else reduced
    (see the module docstring; ``most / 2`` extreme directions for the inner region)."""
    most = MAX_PLANES if most is None else int(most)
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if len(f) <= 4 * most:
        planes = shape(v, f).planes
        return BlankHull(planes, planes, v, True)
    a = v[f[:, 0]]
    n, area = normals(v[f])
    good = area > 1e-12 * max(1.0, float(np.abs(v).max())) ** 2
    unit = n[good] / area[good, None]
    # one facet per cell of the normals' sphere (bands of equal area x sectors), the largest:
    # a fine cylinder keeps one side facet per 360/SECTORS degrees and its caps
    band = np.clip(((unit[:, 2] + 1.0) * 0.5 * BANDS).astype(np.int64), 0, BANDS - 1)
    sector = np.clip(((np.arctan2(unit[:, 1], unit[:, 0]) + np.pi) / (2 * np.pi) * SECTORS).astype(np.int64),
                     0, SECTORS - 1)
    order = np.argsort(-area[good], kind="stable")
    _, first = np.unique((band * SECTORS + sector)[order], return_index=True)
    keep = order[first]
    facets = np.column_stack([unit[keep], np.einsum("ij,ij->i", unit[keep], a[good][keep])])
    u = directions(most // 2)
    extreme = _extreme(v, u)                                     # (d,) the hull's points
    lo, hi = v.min(axis=0), v.max(axis=0)
    eye = np.eye(3)
    box = np.vstack([np.column_stack([eye, hi]), np.column_stack([-eye, -lo])])
    outer = np.vstack([facets, box])
    from scipy.spatial import HalfspaceIntersection, QhullError  # (only here: its import is slow)

    inside = v.mean(axis=0)                   # the mean of a solid hull's vertices is inside it
    try:
        corners = HalfspaceIntersection(np.column_stack([outer[:, :3], -outer[:, 3]]), inside).intersections
    except (QhullError, ValueError):          # degenerate: the bounding box's corners also hold it
        corners = box_corners(lo, hi)
    # inside: the hull of one vertex per cell of a grid (about INNER_POINTS cells hold the
    # surface) and of the extreme ones
    area = 0.5 * float(area.sum())
    cell = (area / INNER_POINTS) ** 0.5
    keys = np.floor((v - lo) / cell).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    pick = np.union1d(first, extreme)
    hv, hf = engine.hull_mesh(v[pick])
    return BlankHull(outer, shape(hv, hf).planes, corners, False)


def lies_on_hull(vertices: np.ndarray, faces: np.ndarray, hull_vertices: np.ndarray,
                 hull_faces: np.ndarray, within: float, block: int = 1 << 16) -> bool:
    """Does every triangle of a closed mesh (vertices (v, 3) float, faces (f, 3) int, mm) lie
    within ``within`` mm of its convex hull's boundary (hull mesh: (h, 3), (g, 3), outward)?

    A triangle passes when its three vertices lie within ``within`` of one face plane of the
    hull — then all of it does (it lies inside the hull, and the plane bounds it). The planes
    tried are those of the hull triangles whose normals are nearest the triangle's own (three)
    and whose centres are nearest its centre (four: a hair-thin strip's own normal is only
    as good as its float32 corners); which planes are tried decides only how often a mesh that
    does lie on its hull is recognised, never whether one that does not passes. A triangle of
    no area (no normal of its own; its points lie on an edge of a neighbour, which is tried)
    passes when its vertices lie within ``within`` of the boundary. A non-convex mesh fails
    even when every vertex lies on the hull (a quad folded inward along the wrong diagonal)."""
    from scipy.spatial import cKDTree

    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    scale = max(1.0, float(np.abs(v).max())) ** 2
    htri = np.asarray(hull_vertices, dtype=float)[np.asarray(hull_faces, dtype=np.int64)]
    hn, hlen = normals(htri)
    good = hlen > 1e-12 * scale                      # a sliver's plane is noise
    unit_h = hn[good] / hlen[good, None]
    planes = np.column_stack([unit_h, np.einsum("ij,ij->i", unit_h, htri[good, 0])])   # one per triangle
    # the distinct planes by normal (a cap fanned into thousands of triangles is one plane: a
    # k-d tree of thousands of equal points is slow), each triangle's by place
    distinct = np.unique(np.round(planes, 9), axis=0, return_index=True)[1]
    by_normal = cKDTree(planes[distinct, :3])
    by_place = cKDTree(htri[good].mean(axis=1))
    kn, kp = min(3, len(distinct)), min(4, len(planes))
    for i in range(0, len(f), block):
        tri = v[f[i : i + block]]                                        # (b, 3, 3)
        n, area = normals(tri)
        flat = area <= 1e-12 * scale
        unit = n[~flat] / area[~flat, None]
        solid_tri = tri[~flat]
        # the plane nearest in normal first; the others only for the triangles it does not hold
        first = distinct[by_normal.query(unit, k=1, workers=-1)[1]].reshape(-1, 1)
        left = ~_held(planes, first, solid_tri, within)
        if left.any():
            centre = solid_tri[left].mean(axis=1)
            near = np.hstack([distinct[by_normal.query(unit[left], k=kn, workers=-1)[1]].reshape(-1, kn),
                              by_place.query(centre, k=kp, workers=-1)[1].reshape(-1, kp)])
            if not _held(planes, near, solid_tri[left], within).all():
                return False
        pts = tri[flat].reshape(-1, 3)
        step = max(1, (1 << 22) // len(planes))           # points × planes of at most 4M at a time
        for j in range(0, len(pts), step):
            if np.any((planes[:, 3] - pts[j : j + step] @ planes[:, :3].T).min(axis=1) > within):
                return False
    return True


def _held(planes: np.ndarray, near: np.ndarray, tri: np.ndarray, within: float) -> np.ndarray:
    """(t,) bool: triangles (t, 3, 3) whose three corners lie within ``within`` of one of the
    planes (f, 4) picked for them (``near`` (t, k) int)."""
    pl = planes[near]                                                    # (t, k, 4)
    gap = np.abs(np.einsum("tkj,tvj->tkv", pl[:, :, :3], tri) - pl[:, :, 3:4])
    return (gap.max(axis=2) <= within).any(axis=1)


_LAST: list = []   # [(solid, its hull_of)]: the last one asked for


def hull_of(solid: engine.Solid) -> tuple[np.ndarray, np.ndarray, engine.Solid, np.ndarray, np.ndarray]:
    """The solid's mesh (vertices (v, 3) float, faces (f, 3) int; double precision), its convex
    hull and the hull's mesh. The last solid's answer is kept (solids do not change): loading a
    mesh blank (:func:`as_hull`) and its stock's screening hull ask in turn — a second hull of a
    finely meshed blank costs seconds."""
    if _LAST and _LAST[0][0] is solid:
        return _LAST[0][1]
    v, f = engine.to_mesh(solid, double=True)
    hull = engine.hull(v)
    hv, hf = engine.to_mesh(hull, double=True)
    _LAST[:] = [(solid, (v, f, hull, hv, hf))]
    return _LAST[0][1]


def as_hull(solid: engine.Solid, within: float) -> engine.Solid:
    """``solid`` (a blank read from a mesh), or its convex hull when that has fewer triangles
    and is the same solid within ``within`` mm (:func:`lies_on_hull`, and the volumes differ by
    no more than a shell that thick): a CAD cylinder of 80,000 triangles (side strips cut along
    its length) has a hull of about 21,000, a convex blank of flat faces a few dozen."""
    v, f, hull, hv, hf = hull_of(solid)
    if len(f) < 8 or len(hf) >= len(f) or len(hf) < 4:
        return solid
    area = 0.5 * float(normals(hv[hf])[1].sum())
    if abs(engine.volume(hull) - engine.volume(solid)) > within * area:   # (a hull is never smaller)
        return solid
    return hull if lies_on_hull(v, f, hv, hf, within) else solid
