"""The boolean engine: the only module of vmach that imports ``manifold3d``.

Everything else handles solids as opaque :data:`Solid` handles and numpy arrays, so a change
of manifold3d's API touches this file only (the layering test enforces it). All lengths mm.

manifold3d evaluates lazily; :func:`check` forces evaluation and reads the status, which is
how the stock is *checked* to be a valid manifold after every batch rather than assumed.
"""

from __future__ import annotations

from collections.abc import Sequence

import manifold3d as m3d
import numpy as np

from vmach.errors import VmachError
from vmach.findings import Finding

Solid = m3d.Manifold

__all__ = [
    "EMPTY_BOX", "Solid", "StockError", "box", "box_of", "bounds", "centroid", "check", "cylinder", "empty",
    "extruded", "from_arrays", "from_mesh", "hull", "hull_mesh", "intersect", "is_empty", "min_gap",
    "num_triangles",
    "revolved", "slice_polygons",
    "split", "subtract", "subtract_checked", "to_arrays", "to_mesh", "transform", "trim", "union", "volume",
]


class StockError(VmachError):
    """The stock stopped being a valid manifold, or a mesh is not a closed 2-manifold."""

    exit_code = 1

    def __init__(self, message: str, kind: str = "stock_invalid"):
        super().__init__(message)
        self.kind = kind

    def findings(self) -> list[Finding]:
        return [Finding(self.kind, "error", str(self))]


def empty() -> Solid:
    return m3d.Manifold()


def from_mesh(vertices: np.ndarray, faces: np.ndarray, what: str = "mesh", double: bool = False) -> Solid:
    """Solid from a triangle mesh.

    vertices : (n, 3) float, mm. faces : (m, 3) int, counter-clockwise seen from outside.
    double : keep the vertices in double precision (default: single, as mesh files are). The
        mesh goes in as single precision (manifold3d's 64-bit mesh constructor is not usable
        from Python here) and the vertices are then moved back to their double values, found
        by their single-precision keys; if two vertices share a key the single values stay.
    Raises StockError when the mesh is not a closed, oriented 2-manifold.
    """
    v64 = np.ascontiguousarray(vertices, dtype=np.float64)
    v = np.ascontiguousarray(v64, dtype=np.float32)
    f = np.ascontiguousarray(faces, dtype=np.uint32)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or len(f) < 4:
        raise StockError(f"{what}: not a triangle mesh", kind="stock_mesh")
    solid = m3d.Manifold(m3d.Mesh(vert_properties=v, tri_verts=f))
    status = solid.status()
    if status != m3d.Error.NoError:
        raise StockError(f"{what}: not a closed 2-manifold ({status.name})", kind="stock_mesh")
    if solid.is_empty():
        raise StockError(f"{what}: no volume (empty or degenerate, or its coordinates are out of "
                         "range)", kind="stock_mesh")
    if solid.volume() < 0:  # pragma: no cover - manifold3d orients closed meshes itself
        raise StockError(f"{what}: faces are oriented inward", kind="stock_mesh")
    if double:
        keys = v.view(np.dtype((np.void, 12))).ravel()
        order = np.argsort(keys)
        sorted_keys = keys[order]
        if len(sorted_keys) < 2 or not np.any(sorted_keys[1:] == sorted_keys[:-1]):
            def exact(points):
                q = np.ascontiguousarray(points, dtype=np.float32).view(np.dtype((np.void, 12))).ravel()
                i = np.minimum(np.searchsorted(sorted_keys, q), len(order) - 1)
                return np.where((sorted_keys[i] == q)[:, None], v64[order[i]], points)

            solid = solid.warp_batch(exact)
            check(solid, what)
    return solid


def to_arrays(solid: Solid) -> tuple[np.ndarray, np.ndarray]:
    """A solid as plain arrays, exactly (to send to another process): vertices (n, 3) float64
    as manifold3d holds them and faces (m, 3) uint64. :func:`from_arrays` makes it again."""
    mesh = solid.to_mesh64()
    return (np.array(mesh.vert_properties, dtype=np.float64)[:, :3].copy(),
            np.array(mesh.tri_verts, dtype=np.uint64).reshape(-1, 3))


def from_arrays(vertices: np.ndarray, faces: np.ndarray) -> Solid:
    """The solid of :func:`to_arrays`' arrays (vertices kept in double precision; manifold3d's
    64-bit mesh takes only writable, C-ordered arrays of its exact dtypes, hence the copies)."""
    v = np.array(vertices, dtype=np.float64, order="C", copy=True).reshape(-1, 3)
    f = np.array(faces, dtype=np.uint64, order="C", copy=True).reshape(-1, 3)
    if len(f) == 0:
        return empty()
    return m3d.Manifold(m3d.Mesh64(vert_properties=v, tri_verts=f))


#: a folded hull of up to this many points is made again from Qhull's extreme points (Qhull
#: takes a minute on a 40,000-point CAD cylinder); hulls whose check would take more than
#: HULL_CHECK_MOST vertex × face products (a fine blank's) are not checked
HULL_QHULL_MOST = 4096
HULL_CHECK_MOST = 500_000_000


def hull(points: np.ndarray) -> Solid:
    """Convex hull of points (m, 3) float, mm (empty if degenerate).

    manifold3d's QuickHull (3.5.4) sometimes folds the hull of points many of which are nearly
    coplanar or nearly equal — a clipped cutter's corners on a trim box, a subdivided face —
    into a non-convex mesh, its own vertices up to 40 mm beyond one of its faces (20 of the
    polygon-shaft program's 2,464 hulls; 132 of 300 subdivided random polytopes,
    ``tests/stock/test_engine.py``; upstream: elalish/manifold issue 1785, open). The hull of
    the extreme points Qhull (scipy) finds never was, in those cases. So a hull is checked
    (:func:`_folded`) while that costs under ``HULL_CHECK_MOST`` products, and a folded one is
    made again from the points rounded to 1e-9 mm and taken once, which mends most, and if
    that is folded too from Qhull's extreme points (up to ``HULL_QHULL_MOST`` points; scipy's
    import costs half a second, so it comes second)."""
    p = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    h = m3d.Manifold.hull_points(p)
    if h.num_vert() * h.num_tri() <= HULL_CHECK_MOST and _folded(h):
        # the points rounded to 1e-9 mm and taken once mend most folds, without Qhull's import
        again = m3d.Manifold.hull_points(np.ascontiguousarray(np.unique(np.round(p, 9), axis=0)))
        if not _folded(again):
            return again
        if len(p) <= HULL_QHULL_MOST:
            from scipy.spatial import ConvexHull, QhullError  # (only here: its import is slow)

            try:
                p = p[np.sort(ConvexHull(p).vertices)]
            except (QhullError, ValueError):           # flat, or too few points: no solid
                return h
        else:
            p = np.unique(np.round(p, 9), axis=0)
        h = m3d.Manifold.hull_points(np.ascontiguousarray(p))
    return h


def _folded(solid: Solid, block: int = 1 << 22) -> bool:
    """Does a hull's mesh have a vertex beyond the plane of one of its faces (by more than
    1e-6 of its size; faces of under 1e-9 of the largest one's area, whose planes are noise,
    left out)? A convex mesh has none; a fold need not show at any one edge, so every vertex
    is tried against every face (``block`` products at a time)."""
    mesh = solid.to_mesh64()
    v = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    f = np.asarray(mesh.tri_verts, dtype=np.int64).reshape(-1, 3)
    if len(f) == 0:
        return False
    a = v[f[:, 0]]
    b, c = v[f[:, 1]] - a, v[f[:, 2]] - a
    n = np.empty_like(a)                      # b × c, written out (np.cross's overhead is
    n[:, 0] = b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1]   # most of its cost on a few hundred rows)
    n[:, 1] = b[:, 2] * c[:, 0] - b[:, 0] * c[:, 2]
    n[:, 2] = b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]
    length = np.sqrt(np.einsum("ij,ij->i", n, n))
    big = length > 1e-9 * length.max()
    if not big.all():
        n, a, length = n[big], a[big], length[big]
    d = np.einsum("ij,ij->i", n, a)
    limit = 1e-6 * max(1.0, float(np.abs(v).max())) * length
    # each face's farthest vertex, a block of vertices at a time (one (block, f) product and
    # its reduction: a comparison of the whole product costs eight times as much here)
    step = max(1, block // len(n))
    reach = np.full(len(n), -np.inf)
    for i in range(0, len(v), step):
        np.maximum(reach, (v[i : i + step] @ n.T).max(axis=0), out=reach)
    return bool(np.any(reach - d > limit))                       # beyond a plane, times |n|


def hull_mesh(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Convex hull of points (m, 3) as a triangle mesh in double precision: vertices (n, 3)
    float (a subset of the points, bit for bit) and faces (f, 3) int64, outward."""
    mesh = hull(points).to_mesh64()
    v = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    f = np.asarray(mesh.tri_verts, dtype=np.int64).reshape(-1, 3)
    return v, f


def cylinder(radius: float, z0: float, z1: float, segments: int) -> Solid:
    """Cylinder on the Z axis from z0 to z1, a ``segments``-gon with circumradius ``radius``."""
    return m3d.Manifold.cylinder(z1 - z0, radius, radius, int(segments)).translate((0, 0, z0))


def box(lo: Sequence[float], hi: Sequence[float]) -> Solid:
    """Axis-aligned box from corner ``lo`` to corner ``hi`` (mm)."""
    lo = np.asarray(lo, dtype=float)
    size = np.asarray(hi, dtype=float) - lo
    return m3d.Manifold.cube(tuple(size)).translate(tuple(lo))


def transform(solid: Solid, matrix: np.ndarray) -> Solid:
    """Rigid transform; ``matrix`` (3, 4) or (4, 4) float — rotation | translation (mm)."""
    mat = np.asarray(matrix, dtype=np.float64)[:3, :4]
    return solid.transform(np.ascontiguousarray(mat))


def subtract(solid: Solid, cutters: Sequence[Solid]) -> Solid:
    """``solid`` minus the union of ``cutters``, in one batch boolean (lazy)."""
    if not cutters:
        return solid
    return m3d.Manifold.batch_boolean([solid, *cutters], m3d.OpType.Subtract)


def union(solids: Sequence[Solid]) -> Solid:
    """Union of solids in one batch boolean."""
    solids = [s for s in solids if not s.is_empty()]
    if not solids:
        return empty()
    if len(solids) == 1:
        return solids[0]
    return m3d.Manifold.batch_boolean(list(solids), m3d.OpType.Add)


def intersect(a: Solid, b: Solid) -> Solid:
    return a ^ b


def trim(solid: Solid, plane: np.ndarray) -> Solid:
    """``solid`` ∩ {x : n·x <= c} for ``plane`` (4,) = (unit n, c), mm (lazy)."""
    n = np.asarray(plane[:3], dtype=float)
    return solid.trim_by_plane((-float(n[0]), -float(n[1]), -float(n[2])), -float(plane[3]))


def split(solid: Solid, cutters: Sequence[Solid]) -> tuple[Solid, Solid]:
    """(``solid`` ∩ union of ``cutters``, ``solid`` minus it), in one boolean (lazy)."""
    cut = union(cutters)
    if cut.is_empty():
        return empty(), solid
    inside, outside = solid.split(cut)
    return inside, outside


def min_gap(a: Solid, b: Solid, search: float) -> float:
    """Smallest distance between two solids, mm, looked for up to ``search`` mm (``search`` when
    they are farther apart; 0 when they touch or overlap)."""
    if a.is_empty() or b.is_empty():
        return float(search)
    return float(a.min_gap(b, float(search)))


def check(solid: Solid, what: str = "stock") -> None:
    """Evaluate ``solid`` and raise StockError unless it is a valid manifold."""
    status = solid.status()
    if status != m3d.Error.NoError:
        raise StockError(f"{what} is no longer a valid manifold ({status.name})")


def subtract_checked(solid: Solid, volume_: float, cutters: Sequence[Solid]) -> tuple[Solid, float]:
    """``solid`` minus ``cutters``, evaluated and checked: (the result, its volume mm³).
    Raises StockError unless it is a valid manifold whose volume did not grow."""
    new = subtract(solid, cutters)
    check(new, "stock")
    vol = volume(new)
    if vol > volume_ * (1 + 1e-9) + 1e-9:
        raise StockError(f"stock volume grew from {volume_:.6f} to {vol:.6f} mm³")
    return new, vol


#: (2, 3) the bounds of nothing: every box test against it fails
EMPTY_BOX = np.array([[np.inf] * 3, [-np.inf] * 3])


def box_of(solid: Solid) -> np.ndarray:
    """(2, 3) float, mm: the solid's bounds (EMPTY_BOX when empty)."""
    return bounds(solid) if not is_empty(solid) else EMPTY_BOX.copy()


def is_empty(solid: Solid) -> bool:
    return bool(solid.is_empty())


def volume(solid: Solid) -> float:
    """Volume, mm³."""
    return float(solid.volume())


def area(solid: Solid) -> float:
    """Surface area, mm²."""
    return float(solid.surface_area())


def centroid(solid: Solid) -> np.ndarray | None:
    """(3,) float, mm: the centre of mass of the solid's volume (None when empty or flat).
    Unlike its box's centre, slivers of no volume do not move it."""
    if solid.is_empty():
        return None
    v, f = to_mesh(solid, double=True)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    o = v.mean(axis=0)                      # tetrahedra from a point near the solid: less rounding
    vol = np.einsum("ij,ij->i", a - o, np.cross(b - o, c - o)) / 6.0
    total = vol.sum()
    if total <= 0.0:
        return None
    return o + (vol[:, None] * (a + b + c - 3.0 * o)).sum(axis=0) / (4.0 * total)


def num_triangles(solid: Solid) -> int:
    return int(solid.num_tri())


def bounds(solid: Solid) -> np.ndarray:
    """Axis-aligned bounds (2, 3) float, mm: [min, max] (NaN-free; zeros when empty)."""
    if solid.is_empty():
        return np.zeros((2, 3))
    return np.asarray(solid.bounding_box(), dtype=float).reshape(2, 3)


def to_mesh(solid: Solid, double: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Triangle mesh: vertices (n, 3) float, mm; faces (m, 3) int64. ``double``: the vertices
    as manifold3d holds them (else rounded to single precision, as mesh files keep them)."""
    mesh = solid.to_mesh64() if double else solid.to_mesh()
    v = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    f = np.asarray(mesh.tri_verts, dtype=np.int64).reshape(-1, 3)
    return v, f


def slice_polygons(solid: Solid, z: float) -> list[np.ndarray]:
    """Section by the plane Z = z: closed contours, each (k, 2) float, mm (outer contours
    counter-clockwise, holes clockwise)."""
    return [np.asarray(p, dtype=float) for p in solid.slice(float(z)).to_polygons()]


def revolved(hulls: Sequence[np.ndarray], segments: int, box: Sequence[float] | None = None,
             scale: float = 1.0) -> Solid:
    """The solid of revolution about Z of the union of the convex hulls of ``hulls``, each
    (k, 2) float points ``(r, z)`` mm (a turning tool's 2-D sweep; what lies at r < 0 is
    mirrored onto r > 0 — the far side of the axis turns through the same circles).

    segments : polygon count of the revolution (vertices at angles 2πi/segments from +X, as
        :func:`cylinder`'s). box : (r_max, z_min, z_max) — the section is clipped to it first
        (the stock's extent: what lies outside removes nothing). scale : radial factor applied
        to the section (the straddling polygon's vertex radius over the true radius).
    Empty when nothing is left in the half-plane.
    """
    parts = [m3d.CrossSection.hull_points(np.ascontiguousarray(h, dtype=np.float64)) for h in hulls
             if len(h) >= 3]
    if not parts:
        return empty()
    cs = m3d.CrossSection.batch_boolean(parts, m3d.OpType.Add) if len(parts) > 1 else parts[0]
    lo = cs.bounds()[0]
    if lo < 0:                      # what lies across the axis turns there too: mirrored onto r >= 0
        far = max(abs(lo), abs(cs.bounds()[2])) + 1.0
        y0, y1 = cs.bounds()[1] - 1.0, cs.bounds()[3] + 1.0
        neg = cs ^ m3d.CrossSection.square((far, y1 - y0)).translate((-far, y0))
        cs = cs + neg.mirror((1.0, 0.0))
    if box is not None:
        r_max, z0, z1 = (float(v) for v in box)
        if r_max <= 0 or z1 <= z0:
            return empty()
        cs = cs ^ m3d.CrossSection.square((r_max, z1 - z0)).translate((0.0, z0))
    if scale != 1.0:
        cs = cs.scale((float(scale), 1.0))
    if cs.is_empty() or cs.area() <= 0:
        return empty()
    return m3d.Manifold.revolve(cs, int(segments))


def extruded(hulls: Sequence[np.ndarray], z0: float, z1: float, half: float | None = None) -> Solid:
    """The union of the convex hulls of ``hulls``, each (k, 2) float points ``(x, y)`` mm (a
    polygonal-turning cross-section: :mod:`vmach.stock.strategies.polygonal`), extruded along Z
    from ``z0`` to ``z1`` mm; ``half`` (mm): the section is first clipped to the square
    ``|x|, |y| <= half`` (the stock's extent). Empty when nothing is left or z1 <= z0."""
    parts = [m3d.CrossSection.hull_points(np.ascontiguousarray(h, dtype=np.float64)) for h in hulls
             if len(h) >= 3]
    if not parts or not z1 > z0:
        return empty()
    cs = m3d.CrossSection.batch_boolean(parts, m3d.OpType.Add) if len(parts) > 1 else parts[0]
    if half is not None:
        cs = cs ^ m3d.CrossSection.square((2.0 * half, 2.0 * half), True)
    if cs.is_empty() or cs.area() <= 0:
        return empty()
    return m3d.Manifold.extrude(cs, float(z1 - z0)).translate((0.0, 0.0, float(z0)))
