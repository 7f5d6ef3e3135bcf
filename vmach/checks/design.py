"""The cut part against its design: gouges and excess as connected regions, with their depth.

    design = load_design("part.stl", offset=(0, 0, 0))          # (vertices, faces), mm
    result = compare(part_solid, design, Band(-0.02, 0.05))

The design is placed in the workpiece frame — the frame of the stock, of ``--export`` and of
every ``at_mm`` in the report (the milling fixture: Z = 0 the blank's top, X and Y from its
centre; the polygon shaft: Z = 0 the shaft's end face on the C axis) — moved by ``offset``
(mm) when given.

- Deviation: the exact signed distance of every vertex of the part to the design's surface
  (:mod:`vmach.checks.distance`), > 0 material outside the design (excess), < 0 inside the
  part's outline where the design has material (gouge).
- Regions: the mesh booleans design − part (material removed that the design keeps) and
  part − design (material left that the design does not have), made by manifold3d through
  :mod:`vmach.stock.engine`, split into connected components by their shared vertices. A
  component's depth is the largest distance of one of its vertices to the other surface (a
  vertex of the component lies on the part or on the design; its distance to the other one is
  the thickness there); components no deeper than the band are within tolerance and dropped.
  Volume and centroid are the component's (the whole connected body of missing or extra
  material, its in-band rim included); ``area_mm2`` is the part's surface in it that lies
  beyond the band.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from vmach.checks.distance import SignedDistance
from vmach.errors import InputError
from vmach.stock import engine

FORMATS = (".stl", ".3mf", ".ply", ".step", ".stp")

#: at most this many points of a region go to the search for the lines that made it
REGION_POINTS = 600
#: mm: a region's faces thinner than this (or than half the band) at their centre lie on a face
#: the part and the design share (its flat rim, which the booleans keep as a sliver of no
#: volume, or the simulation's own error): left out of its bounding box
FLAT = 1e-3


@dataclass(frozen=True)
class Band:
    """Tolerance band about the design's surface, mm: ``lo`` <= 0 (how far the part may lie
    inside) and ``hi`` >= 0 (how far outside)."""

    lo: float = -0.02
    hi: float = 0.05


_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)"


def parse_band(text: str) -> Band:
    """``+0.05/-0.02`` (either order), ``±0.02`` or ``0.02`` (symmetric) → Band."""
    t = text.strip().replace("±", "+-")
    m = re.fullmatch(rf"\+-\s*({_NUMBER})|({_NUMBER})", t)
    if m:
        v = abs(float(m.group(1) or m.group(2)))
        return Band(-v, v)
    m = re.fullmatch(rf"({_NUMBER})\s*/\s*({_NUMBER})", t)
    if not m:
        raise InputError(f"--design-tolerance {text!r}: expected +UPPER/-LOWER in mm, e.g. "
                         "+0.05/-0.02, or ±0.02", kind="usage")
    a, b = float(m.group(1)), float(m.group(2))
    lo, hi = min(a, b), max(a, b)
    if not (lo <= 0 <= hi and math.isfinite(lo) and math.isfinite(hi)):
        raise InputError(f"--design-tolerance {text!r}: the band must hold the design's surface "
                         "(an upper bound >= 0 and a lower one <= 0)", kind="usage")
    return Band(lo, hi)


def parse_offset(text: str | None) -> np.ndarray:
    """``"x,y,z"`` mm → (3,) float (zeros for None)."""
    if not text:
        return np.zeros(3)
    try:
        v = np.array([float(p) for p in text.split(",")], dtype=float)
    except ValueError:
        v = np.zeros(0)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InputError(f"--design-offset {text!r}: expected X,Y,Z in mm, e.g. 0,0,-10", kind="usage")
    return v


def load_design(path: str | Path, offset: np.ndarray | None = None, chord: float = 0.001
                ) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) float, mm (moved by ``offset``) and faces (m, 3) int of a design file:
    STL, 3MF or PLY through trimesh; STEP through trimesh and cascadio (OpenCASCADE), when
    installed (``pip install vmach[step]``), tessellated within ``chord`` mm. A file that is
    not a closed 2-manifold is an InputError (kind ``design_mesh``)."""
    import trimesh

    p = Path(path)
    ext = p.suffix.lower()
    if ext not in FORMATS:
        raise InputError(f"{path}: a design is read from {', '.join(FORMATS)}", kind="design_format")
    if not p.is_file():
        raise InputError(f"{path}: no such file", kind="unreadable")
    kwargs = {}
    if ext in (".step", ".stp"):
        try:
            import cascadio  # noqa: F401  (trimesh's STEP loader needs it)
        except ImportError:
            raise InputError(f"{path}: reading STEP needs cascadio (OpenCASCADE): pip install "
                             "'vmach[step]', or export the design as STL/3MF/PLY",
                             kind="design_format") from None
        kwargs = {"tol_linear": chord, "tol_angular": 0.5, "tol_relative": False}  # mm, radians
    try:
        mesh = trimesh.load(str(p), force="mesh", process=True, **kwargs)
    except Exception as exc:  # trimesh raises many kinds on a broken file
        raise InputError(f"{path}: cannot read the design: {exc}", kind="unreadable") from None
    if getattr(mesh, "units", None) not in (None, "mm", "millimeters", "millimeter"):
        mesh.convert_units("millimeters")    # STEP comes through glTF, which is in metres
    if hasattr(mesh, "merge_vertices"):      # by position only: a STEP's faces come apart by normals
        mesh.merge_vertices(merge_tex=True, merge_norm=True)
    v = np.asarray(getattr(mesh, "vertices", np.zeros((0, 3))), dtype=float)
    f = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), dtype=np.int64)
    if len(f) < 4:
        raise InputError(f"{path}: no triangles in the design", kind="design_mesh")
    if offset is not None:
        v = v + np.asarray(offset, dtype=float)
    try:
        solid = engine.from_mesh(v, f, what=str(path), double=True)
    except engine.StockError as exc:
        raise InputError(f"{exc} — a design must be a closed solid", kind="design_mesh") from None
    return engine.to_mesh(solid, double=True)


@dataclass
class Region:
    """One connected body of material removed inside the design (``gouge``) or left outside
    it (``excess``), mm and mm³; ``points`` (k, 3) spread over the surface beyond the band
    that a tool crossed (a gouge: the design's) or stopped at (excess: the part's)."""

    kind: str
    volume: float
    depth: float
    area: float
    centroid: np.ndarray
    bounds: np.ndarray
    deepest: np.ndarray
    points: np.ndarray = field(repr=False)


@dataclass
class Comparison:
    """The outcome: part mesh (vertices (n, 3), faces (m, 3)), its signed deviation (n,) mm,
    the band, and the regions beyond it, deepest first within each kind."""

    vertices: np.ndarray
    faces: np.ndarray
    deviation: np.ndarray
    band: Band
    regions: list[Region]
    seconds: float = 0.0

    def region_of_vertex(self) -> np.ndarray:
        """(n,) int: the number (1-based, as the regions list) of the region nearest each part
        vertex beyond the band, 0 for vertices within it."""
        out = np.zeros(len(self.vertices), dtype=np.int32)
        beyond = (self.deviation < self.band.lo) | (self.deviation > self.band.hi)
        if not self.regions or not beyond.any():
            return out
        from scipy.spatial import cKDTree

        pts = np.vstack([r.points for r in self.regions])
        label = np.concatenate([np.full(len(r.points), i + 1) for i, r in enumerate(self.regions)])
        d, j = cKDTree(pts).query(self.vertices[beyond])
        out[np.flatnonzero(beyond)] = np.where(np.isfinite(d), label[np.minimum(j, len(label) - 1)], 0)
        return out


def compare(part: engine.Solid, design: tuple[np.ndarray, np.ndarray], band: Band) -> Comparison:
    """Compare the part (a solid of :mod:`vmach.stock.engine`) with the design (vertices,
    faces in the workpiece frame); see the module docstring."""
    import time

    t0 = time.perf_counter()
    dv, df = design
    dsolid = engine.from_mesh(dv, df, what="design", double=True)
    pv, pf = engine.to_mesh(part, double=True)
    to_design = SignedDistance(dv, df)
    deviation = to_design(pv)
    to_part = SignedDistance(pv, pf)
    regions: list[Region] = []
    for kind, body, limit in (("gouge", engine.subtract(dsolid, [part]), -band.lo),
                              ("excess", engine.subtract(part, [dsolid]), band.hi)):
        regions.extend(_regions(kind, body, limit, to_design, to_part))
    return Comparison(pv, pf, deviation, band, regions, time.perf_counter() - t0)


def _regions(kind: str, body: engine.Solid, limit: float, to_design: SignedDistance,
             to_part: SignedDistance) -> list[Region]:
    if engine.is_empty(body):
        return []
    v, f = engine.to_mesh(body, double=True)
    if len(f) == 0:
        return []
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    centre = (a + b + c) / 3.0
    # a vertex lies on one surface; its distance to the other is the body's thickness there
    # (the faces' centres asked at the same time: one search of each mesh)
    n = len(v)
    both = np.vstack([v, centre])
    on_design, on_part = np.abs(to_design(both)), np.abs(to_part(both))
    thick = np.maximum(on_design[:n], on_part[:n])
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]]])
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    count, label = connected_components(graph, directed=False)
    deep = np.zeros(count)
    np.maximum.at(deep, label, thick)
    keep = np.flatnonzero(deep > limit + 1e-9)
    if not len(keep):
        return []
    face_label = label[f[:, 0]]
    o = v.mean(axis=0)
    cross = np.cross(b - o, c - o)
    tet = np.einsum("ij,ij->i", a - o, cross) / 6.0
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    sel = np.isin(face_label, keep)
    beyond = np.zeros(len(f), dtype=bool)
    thick_face = np.zeros(len(f), dtype=bool)
    at_design, at_part = on_design[n:][sel], on_part[n:][sel]
    beyond[sel] = at_design > limit
    thick_face[sel] = np.maximum(at_design, at_part) > max(FLAT, limit / 2)
    # the surface a tool should not have crossed (a gouge: the design's, its distance to the
    # part beyond the band) or should have reached (excess: the part's, left by the tool)
    tool_side = np.zeros(len(f), dtype=bool)
    tool_side[sel] = ((at_design <= at_part) & (at_part > limit) if kind == "gouge"
                      else (at_part <= at_design) & (at_design > limit))
    out = []
    for k in keep:
        fk = face_label == k
        vol = float(tet[fk].sum())
        cen = o + (tet[fk, None] * (a[fk] + b[fk] + c[fk] - 3 * o)).sum(axis=0) / (4 * vol) \
            if vol > 0 else v[label == k].mean(axis=0)
        idx = np.flatnonzero(label == k)
        order = idx[np.argsort(-thick[idx])]
        # the corners of faces that have depth: not the flat rims along shared faces
        near = f[(face_label == k) & thick_face].ravel()
        box = v[near if len(near) else idx]
        side = fk & tool_side
        if side.any():
            pts = surface_points(a[side], b[side], c[side], REGION_POINTS)
        else:
            pts = v[order[:: max(1, len(order) // REGION_POINTS)]]
        out.append(Region(kind, abs(vol), float(deep[k]), float(area[fk & beyond].sum()), cen,
                          np.stack([box.min(axis=0), box.max(axis=0)]), v[order[0]], pts))
    out.sort(key=lambda r: -r.depth)
    return out


def surface_points(a: np.ndarray, b: np.ndarray, c: np.ndarray, most: int) -> np.ndarray:
    """About ``most`` points (k, 3) spread evenly over triangles (a, b, c) (m, 3) mm: the
    centroids of each triangle's sub-triangles in an m-fold subdivision, m from its longest
    edge and one spacing for all."""
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    spacing = max(math.sqrt(max(float(area.sum()), 1e-12) * 2.0 / most), 1e-3)
    longest = np.max([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                      np.linalg.norm(a - c, axis=1)], axis=0)
    m = np.clip(np.ceil(longest / spacing), 1, 64).astype(int)
    out = []
    for k in np.unique(m):
        i, j = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
        ok = i + j <= k - 1
        u = (i[ok] + 1 / 3) / k
        w = (j[ok] + 1 / 3) / k
        t = m == k
        out.append((a[t, None, :] + (b - a)[t, None, :] * u[None, :, None]
                    + (c - a)[t, None, :] * w[None, :, None]).reshape(-1, 3))
    pts = np.vstack(out)
    step = max(1, len(pts) // most)
    return pts[::step]
